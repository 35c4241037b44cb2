#include "render/film.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"

namespace littoral::render {

namespace {
void validateBands(const std::vector<Band>& bands) {
    if (bands.empty()) throw InputError("film: at least one spectral band is required");
    for (std::size_t i = 0; i < bands.size(); ++i) {
        const Band& b = bands[i];
        if (!(std::isfinite(b.lo) && std::isfinite(b.hi)) || !(b.hi > b.lo) || b.lo <= 0.0)
            throw InputError("film: band " + std::to_string(i) + " [" + std::to_string(b.lo) + ", " +
                             std::to_string(b.hi) + "] um is not a valid interval (need 0 < lo < hi)");
    }
}
}  // namespace

Film::Film(int w, int h, std::vector<Band> bands_) : width(w), height(h), bands(std::move(bands_)) {
    if (w <= 0 || h <= 0)
        throw InputError("film: image size " + std::to_string(w) + " x " + std::to_string(h) +
                         " px is invalid (width and height must be positive)");
    validateBands(bands);
    pixels.assign(pixelCount() * bands.size(), 0.0f);
}

float& Film::at(int x, int y, int b) {
    LITTORAL_CHECK(x >= 0 && x < width && y >= 0 && y < height && b >= 0 && b < bandCount());
    return pixels[(static_cast<std::size_t>(y) * width + x) * bands.size() + b];
}

float Film::at(int x, int y, int b) const {
    LITTORAL_CHECK(x >= 0 && x < width && y >= 0 && y < height && b >= 0 && b < bandCount());
    return pixels[(static_cast<std::size_t>(y) * width + x) * bands.size() + b];
}

int Film::nearestBand(double wavelengthUm) const {
    if (bands.empty()) throw InputError("film: no bands to choose from");
    int best = 0;
    double bestD = std::abs(bands[0].center() - wavelengthUm);
    for (int b = 1; b < bandCount(); ++b) {
        const double d = std::abs(bands[b].center() - wavelengthUm);
        if (d < bestD) { best = b; bestD = d; }
    }
    return best;
}

int Film::bandContaining(double wavelengthUm) const {
    for (int b = 0; b < bandCount(); ++b) {
        const bool last = b + 1 == bandCount();
        if (wavelengthUm >= bands[b].lo && (wavelengthUm < bands[b].hi || (last && wavelengthUm == bands[b].hi)))
            return b;
    }
    return -1;
}

std::vector<float> Film::bandPlane(int b) const {
    LITTORAL_CHECK(b >= 0 && b < bandCount());
    std::vector<float> plane(pixelCount());
    const std::size_t nb = bands.size();
    for (std::size_t p = 0; p < plane.size(); ++p) plane[p] = pixels[p * nb + b];
    return plane;
}

void Film::setBandPlane(int b, const std::vector<float>& plane) {
    LITTORAL_CHECK(b >= 0 && b < bandCount());
    LITTORAL_CHECK_EQ(plane.size(), pixelCount());
    const std::size_t nb = bands.size();
    for (std::size_t p = 0; p < plane.size(); ++p) pixels[p * nb + b] = plane[p];
}

BandStats bandStats(const Film& film, int b) {
    LITTORAL_CHECK(b >= 0 && b < film.bandCount());
    BandStats s;
    // Welford's running mean and sum of squared deviations: stable for the 10^6-pixel images
    // a float accumulator would round badly.
    double mean = 0.0, m2 = 0.0;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    const std::size_t nb = film.bands.size();
    for (std::size_t p = 0; p < film.pixelCount(); ++p) {
        const double v = film.pixels[p * nb + b];
        if (!std::isfinite(v)) { ++s.nonFinite; continue; }
        ++s.finite;
        const double d = v - mean;
        mean += d / static_cast<double>(s.finite);
        m2 += d * (v - mean);
        lo = std::min(lo, v);
        hi = std::max(hi, v);
    }
    if (s.finite > 0) {
        s.min = lo;
        s.max = hi;
        s.mean = mean;
        s.stddev = std::sqrt(m2 / static_cast<double>(s.finite));
    }
    return s;
}

double bandQuantile(const Film& film, int b, double q) {
    if (!(q >= 0.0 && q <= 1.0))
        throw InputError("film: quantile " + std::to_string(q) + " is outside [0, 1]");
    LITTORAL_CHECK(b >= 0 && b < film.bandCount());
    std::vector<float> v;
    v.reserve(film.pixelCount());
    const std::size_t nb = film.bands.size();
    for (std::size_t p = 0; p < film.pixelCount(); ++p) {
        const float x = film.pixels[p * nb + b];
        if (std::isfinite(x)) v.push_back(x);
    }
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    // Hyndman & Fan (1996) definition 7: h = (N - 1) q, interpolate between floor(h) and floor(h) + 1.
    const double h = (static_cast<double>(v.size()) - 1.0) * q;
    const std::size_t k = static_cast<std::size_t>(std::floor(h));
    if (k + 1 >= v.size()) return v.back();
    return v[k] + (h - static_cast<double>(k)) * (static_cast<double>(v[k + 1]) - v[k]);
}

TruthImages::TruthImages(int w, int h) : width(w), height(h) {
    if (w <= 0 || h <= 0)
        throw InputError("truth images: image size " + std::to_string(w) + " x " + std::to_string(h) +
                         " px is invalid (width and height must be positive)");
    const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    materialId.assign(n, -1);
    surfaceId.assign(n, -1);
    range.assign(n, std::numeric_limits<float>::infinity());
    hitDepth.assign(n, std::numeric_limits<float>::quiet_NaN());
}

}  // namespace littoral::render
