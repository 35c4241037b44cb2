#pragma once
// The image-quality study of the dissertation's Chapter 9 (`littoral study image-quality`,
// docs/image-quality.md): a submerged slanted step target (a bright and a dark half) seen from
// nadir, rendered with the photon-map solvers (MediumPM in the water, SurfacePM on the target and
// the seabed) for a grid of search radii and photon densities; for each render the SNR on each
// side of the edge and the edge and line spread functions (ESF by the slanted-edge method, LSF by
// differentiating it, its FWHM and its tails).
//
// Chapter 9's findings (digest seed-ch08-09.md, Sec. 3.7-3.8), which the study reproduces:
//   * SNR = mean / standard deviation over a side; it grows with the photon density (variance
//     ~ 1/N, Fig. 9.6) and with the search radius (variance ~ SR^-p, p about 2.4-3.0, Fig. 9.5);
//   * the FWHM of the LSF stays nearly constant with SR (within the 0.25 m GSD); a larger SR
//     shows first in the LSF's tails ("edge bias", Fig. 9.12).
#include <filesystem>
#include <string>
#include <vector>

namespace littoral::pipelines {

// A straight edge in plan view: unit normal n (pointing into the dark side) through point c.
// The signed distance of p is (p - c) . n; `along` is the coordinate along the edge.
struct EdgeGeometry {
    double cx = 0, cy = 0;        // a point on the edge, m
    double nx = 1, ny = 0;        // unit normal, toward the dark half
    double halfLength = 1;        // pixels with |along| beyond this are not used, m
};

// Pixel centres of a nadir orthographic image: column i, row j (row 0 at the top, +y) map to
// x = x0 + (i + 0.5) pixel, y = y0 - (j + 0.5) pixel.
struct PixelGrid {
    int width = 0, height = 0;
    double pixel = 1;     // m
    double x0 = 0, y0 = 0;  // world position of the image's top-left corner
};

struct RegionStats {
    double mean = 0, stddev = 0, snr = 0;
    int pixels = 0;
};

struct EdgeMeasures {
    RegionStats bright, dark;         // pixels with margin <= |distance| <= margin + width on each side
    std::vector<double> esfX, esf;    // oversampled ESF: bin centres (m, + toward dark) and means
    std::vector<double> lsfX, lsf;    // LSF (derivative of the smoothed ESF, normalised to a unit area)
    double fwhm = 0;                  // FWHM of the LSF, m
    double width1090 = 0;             // distance between the 10% and 90% points of the ESF, m
    double tailFraction = 0;          // share of the step still missing, on average, from tailFrom to
                                      // 2 tailFrom on either side of the LSF's peak (the LSF's tails)
    // Why some of fwhm, width1090 and tailFraction are undefined (they are then NaN, and empty in
    // the study's CSV): the step is not resolved above the noise, or the noisy ESF never crosses a
    // level. Empty when all are defined.
    std::string undefined;
};

struct EdgeAnalysisOptions {
    double margin = 0.5;     // m: side regions start this far from the edge
    double regionWidth = 3;  // m: and are this wide
    double binWidth = 0.0625;  // m: ESF bin (a quarter of the study's 0.25 m GSD)
    double esfHalfRange = 3;   // m: ESF from -range to +range
    int smoothBins = 3;        // box-car width of the ESF smoothing, bins (odd)
    double tailFrom = 0.5;     // m: the tails window starts this far from the LSF's peak
};

// The ESF/LSF/SNR measures of one band plane (row-major, width x height) of a nadir image.
// InputError if a side region or an ESF bin near the edge holds no pixel.
EdgeMeasures analyseEdge(const std::vector<float>& plane, const PixelGrid& grid, const EdgeGeometry& edge,
                         const EdgeAnalysisOptions& options = {});

struct ImageQualityOptions {
    std::string out;                                  // output folder
    std::vector<double> depths{1.0, 2.5};             // target depths, m
    std::vector<double> radii{0.25, 0.5, 1.0};        // search radii (surface = volume), m
    std::vector<double> densities{1000, 3000};        // volume photons per m^3
    double surfacePerVolume = 5.5;                    // surface photons per m^2 for each volume photon per m^3
    std::string water = "coastal";                    // coastal, bay or turbid (Table 9.6 coefficients)
    double g = 0.92;                                  // Henyey-Greenstein asymmetry
    int pixels = 64;                                  // image width = height (GSD 0.25 m)
    int samplesPerPixel = 4;
    uint64_t seed = 1;
    int threads = 0;
    bool progress = true;
};

struct ImageQualityRow {
    double depth, radius, density;
    long long surfacePhotons, volumePhotons;
    EdgeMeasures m;
    double seconds;
};

// Runs the study: one scene per (depth, radius, density) under OUT/runs/, then OUT/image_quality.csv,
// OUT/esf_*.csv and the SVG figures. Returns the rows (also for tests) and a summary in *summary.
std::vector<ImageQualityRow> runImageQualityStudy(const ImageQualityOptions& options, std::string* summary = nullptr);

}  // namespace littoral::pipelines
