#pragma once
// Films: the images the renderer produces.
//
//   Film         – a multi-band float image of band-averaged spectral radiance,
//                  W m^-2 sr^-1 um^-1, one value per (pixel, band).
//   TruthImages  – per-pixel geometric truth of the first hit along each pixel's centre ray
//                  (material id, range, depth of the first opaque surface below the water).
//
// Pixel (x, y): x = column from the left, y = row from the top (y = 0 is the top row), the same
// convention as the camera (see docs/outputs.md and render-core's camera code).
// Storage is band-interleaved by pixel: pixels[(y * width + x) * bands.size() + b].
#include <cstdint>
#include <vector>

#include "core/spectrum.h"

namespace littoral::render {

// A multi-band float image; pixel (x, y), y = 0 is the top row; value per band in
// W m^-2 sr^-1 um^-1 (band-averaged spectral radiance).
struct Film {
    int width = 0, height = 0;
    std::vector<Band> bands;
    std::vector<float> pixels;  // (y * width + x) * bands.size() + b

    Film() = default;
    // Zero-filled. InputError if w or h is not positive, bands is empty, or a band has hi <= lo.
    Film(int w, int h, std::vector<Band> bands);

    float& at(int x, int y, int b);
    float at(int x, int y, int b) const;

    int bandCount() const { return static_cast<int>(bands.size()); }
    std::size_t pixelCount() const { return static_cast<std::size_t>(width) * static_cast<std::size_t>(height); }
    bool empty() const { return pixels.empty(); }

    // Index of the band whose centre is nearest to `wavelengthUm` (ties: the lower index).
    // InputError if the film has no bands.
    int nearestBand(double wavelengthUm) const;
    // Index of the band with lo <= wavelengthUm < hi (the last band also accepts wavelengthUm == hi),
    // or -1 if no band contains it.
    int bandContaining(double wavelengthUm) const;

    // One band as a width*height plane (row-major, y = 0 first).
    std::vector<float> bandPlane(int b) const;
    void setBandPlane(int b, const std::vector<float>& plane);
};

// Statistics of one band over all pixels. Non-finite values (NaN, +-inf) are counted in
// `nonFinite` and excluded from the other figures.
struct BandStats {
    double min = 0, max = 0, mean = 0, stddev = 0;  // stddev: population (divide by N)
    std::size_t finite = 0, nonFinite = 0;
};
BandStats bandStats(const Film& film, int b);

// The q-quantile (q in [0, 1]) of the finite values of band b, by linear interpolation between
// order statistics (Hyndman & Fan 1996 type 7, the numpy default). InputError if q is outside
// [0, 1]; returns 0 if the band has no finite value.
double bandQuantile(const Film& film, int b, double q);

// Per-pixel truth of the first hit along the centre ray of each pixel.
struct TruthImages {
    int width = 0, height = 0;
    std::vector<int32_t> materialId;  // index into ir materials of the first hit, -1 = nothing hit / sky
    std::vector<int32_t> surfaceId;   // material of the first opaque surface reached through the
                                      // interfaces (the seabed's class under water), -1 if none
    std::vector<float> range;         // metres along the ray to the first hit, +inf if none
    std::vector<float> hitDepth;      // metres below z = 0 of the first opaque surface reached
                                      // (through refraction), 0 if above water, NaN if none
    TruthImages() = default;
    // Initialised to "nothing hit": materialId and surfaceId -1, range +inf, hitDepth NaN.
    TruthImages(int w, int h);

    std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x); }
};

}  // namespace littoral::render
