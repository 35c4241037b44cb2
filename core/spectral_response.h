#pragma once
// Output bands with a spectral response (scene files' render.bands; docs/scene-format.md): a
// rectangle [lo, hi], a Gaussian given by centre and FWHM, or a tabulated response function. The
// renderer renders fine internal sub-bands (the IR's render.bands) and each output band is the
// response-weighted mean of them:
//
//   L_out = sum_i w_i L_i,  w_i = int_{sub-band i} R(l) dl / int R(l) dl,
//
// the band average of the radiance weighted by R when L is constant within each sub-band. The
// sub-bands tile the union of the responses' supports (a Gaussian's is centre +- 2 FWHM, which
// holds 99.997 % of it; a table's, its first to last wavelength; a rectangle's, itself) with
// breaks at every support edge, each at most min(5 nm, FWHM / 4) wide.
#include <string>
#include <vector>

#include "core/scene_ir.h"
#include "core/spectrum.h"

namespace littoral {

struct ResponseSpec {
    enum class Kind { Rectangle, Gaussian, Table };
    Kind kind = Kind::Rectangle;
    double lo = 0, hi = 0;          // rectangle, um
    double centre = 0, fwhm = 0;    // gaussian, um
    std::vector<double> wl, value;  // table: um (increasing), response (>= 0)
};

inline constexpr double kGaussianSupportFwhm = 2.0;  // a Gaussian's support: centre +- 2 FWHM
inline constexpr double kMaxSubBandUm = 0.005;
inline constexpr int kMaxInternalBands = 1000;

// The response at `um` (a Gaussian's peak is 1; a table's, its own values).
double responseAt(const ResponseSpec& r, double um);

struct ResponseGrid {
    std::vector<Band> internal;               // the bands to render
    std::vector<ir::ResponseBand> outputs;    // one per ResponseSpec, weights over `internal`
};
// InputError (without a location: the caller names the key) if the sub-bands would exceed
// kMaxInternalBands.
ResponseGrid responseGrid(const std::vector<ResponseSpec>& specs);

// A table's nominal band: centroid +- FWHM / 2, the FWHM from the half-maximum crossings
// (linear between samples).
Band tableNominalBand(const std::vector<double>& wl, const std::vector<double>& value);

}  // namespace littoral
