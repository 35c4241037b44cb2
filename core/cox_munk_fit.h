#pragma once
// Cox and Munk's (1954) fits of sea-surface slope statistics to wind speed: the coefficients
// shared by the rough air-water interface (render/cox_munk.h) and by the wave surface whose
// facet slopes follow them (surfaces/, model `cox-munk`). It sits in core because both of those
// modules need it and neither may include the other.
//
// Wind speed U in m/s at 12.5 m above mean sea level (Cox and Munk's anemometer height).
// Slopes are dimensionless (dz/dx); variances are of the slope components along (upwind) and
// across (crosswind) the wind.
//
// Three coefficient sets (spec/reference-data.md; spec/seed-ch05-10.md section 1.2):
//   clean        Cox & Munk (1954), clean sea:  sigma_u^2 = 3.16e-3 U,          sigma_c^2 = 0.003 + 1.92e-3 U
//   slick        Cox & Munk (1954), oil slick:  sigma_u^2 = 0.005 + 0.78e-3 U,  sigma_c^2 = 0.003 + 0.84e-3 U
//   dissertation the clean fit without the 0.003 crosswind offset, sigma_c^2 = 1.92e-3 U: the values
//                every label of the dissertation's Figs. 5.1-5.3 prints (digest section 1.2), so
//                the thesis' glint and transmission tests are reproduced with it.
//
// Optional Gram-Charlier terms (Cox & Munk 1954, clean sea only): skewness c21 = 0.01 - 0.0086 U,
// c03 = 0.04 - 0.033 U; peakedness c40 = 0.40, c22 = 0.12, c04 = 0.23 (render/cox_munk.h says
// how they enter the density).
#include <cmath>
#include <string>
#include <string_view>

#include <fmt/format.h>

#include "core/error.h"
#include "core/names.h"

namespace littoral {

enum class CoxMunkSea { Clean, Slick, Dissertation };

template <> struct EnumNames<CoxMunkSea> {
    static constexpr std::string_view what = "Cox-Munk surface";
    static constexpr EnumName<CoxMunkSea> table[] = {
        {CoxMunkSea::Clean, "clean"}, {CoxMunkSea::Slick, "slick"}, {CoxMunkSea::Dissertation, "dissertation"}};
};

// The microfacet shadowing-masking term of the rough interface (render/rough_dielectric.h says what
// each does). It sits here, beside the slope statistics, so that the Scene IR (core/) can carry it.
enum class MicrofacetShadowing { None, SmithLight, SmithSeparable };

template <> struct EnumNames<MicrofacetShadowing> {
    using M = MicrofacetShadowing;
    static constexpr std::string_view what = "microfacet shadowing";
    static constexpr EnumName<M> table[] = {
        {M::None, "none"}, {M::SmithLight, "smith-light"}, {M::SmithSeparable, "smith-separable"}};
};

// Which form of Cox and Munk's clean-sea fit gives the slopes: the anisotropic upwind/crosswind
// variances (the default), or the isotropic Gaussian of their separate fit to the total mean-square
// slope, sigma^2 = 0.003 + 5.12e-3 U, shared equally between any two perpendicular directions
// (which keeps the azimuthal Fourier modes of a plane-parallel solver uncoupled). The isotropic
// form is published for the clean sea only.
enum class CoxMunkSlopes { Anisotropic, Isotropic };

template <> struct EnumNames<CoxMunkSlopes> {
    static constexpr std::string_view what = "Cox-Munk slope distribution";
    static constexpr EnumName<CoxMunkSlopes> table[] = {{CoxMunkSlopes::Anisotropic, "anisotropic"},
                                                        {CoxMunkSlopes::Isotropic, "isotropic"}};
};

struct SlopeVariances {
    double upwind = 0, crosswind = 0;  // sigma_u^2, sigma_c^2
    double total() const { return upwind + crosswind; }
};

// The linear fits themselves, evaluated at any U >= 0 without a range check (the dissertation's
// Fig. 5.1 tabulates them up to 40 m/s). Anything that builds a surface or an interface from them
// calls checkCoxMunkWind first.
inline SlopeVariances coxMunkSlopeVariances(double windSpeed, CoxMunkSea sea) {
    const double U = windSpeed;
    switch (sea) {
    case CoxMunkSea::Clean: return {3.16e-3 * U, 0.003 + 1.92e-3 * U};
    case CoxMunkSea::Slick: return {0.005 + 0.78e-3 * U, 0.003 + 0.84e-3 * U};
    case CoxMunkSea::Dissertation: return {3.16e-3 * U, 1.92e-3 * U};
    }
    return {};
}

// Cox and Munk's separate fit to the clean sea's total mean-square slope, 0.003 + 5.12e-3 U
// (spec/reference-data.md). It is not the sum of the component fits above (0.003 + 5.08e-3 U):
// each of the three was fitted to the data on its own. The dissertation's Beaufort "RMS slope"
// (surfaces/beaufort.h) is this total.
inline double coxMunkCleanTotalMss(double windSpeed) { return 0.003 + 5.12e-3 * windSpeed; }

// "" if the slope form can be used with this sea and Gram-Charlier choice; otherwise why not.
inline std::string coxMunkSlopesProblem(CoxMunkSlopes slopes, CoxMunkSea sea, bool gramCharlier) {
    if (slopes != CoxMunkSlopes::Isotropic) return "";
    if (sea != CoxMunkSea::Clean)
        return fmt::format("the isotropic form (sigma^2 = 0.003 + 0.00512 U) is Cox and Munk's clean-sea fit; it cannot "
                           "be used with sea: {}", nameOf(sea));
    if (gramCharlier) return "the Gram-Charlier terms are upwind/crosswind terms; the isotropic form has none";
    return "";
}

// The variances of the chosen form: the isotropic one splits the total equally.
inline SlopeVariances coxMunkSlopeVariances(double windSpeed, CoxMunkSea sea, CoxMunkSlopes slopes) {
    if (slopes == CoxMunkSlopes::Anisotropic) return coxMunkSlopeVariances(windSpeed, sea);
    const double half = 0.5 * coxMunkCleanTotalMss(windSpeed);
    return {half, half};
}

// Gram-Charlier coefficients of the clean-sea fit (Cox & Munk 1954); no others are published here.
struct GramCharlierCoefficients {
    double c21 = 0, c03 = 0;            // skewness (odd in the upwind slope)
    double c40 = 0, c22 = 0, c04 = 0;   // peakedness
};
inline GramCharlierCoefficients coxMunkCleanGramCharlier(double windSpeed) {
    return {0.01 - 0.0086 * windSpeed, 0.04 - 0.033 * windSpeed, 0.40, 0.12, 0.23};
}

// The winds a Cox-Munk surface accepts.
//  * Upper limit 14 m/s: Cox and Munk's photographs span winds of about 0.7 to 14 m/s; above that
//    the linear fits are extrapolations into seas with whitecaps, which the slope statistics of a
//    continuous surface do not describe.
//  * Lower limit 0.01 m/s: below 0.7 m/s the fits are extrapolated linearly toward their calm
//    intercepts (a flat sea for the dissertation's coefficients). We accept that extrapolation down
//    to 0.01 m/s because the dissertation uses 0.5 m/s (glint images) and 0.01 m/s (convergence of
//    the rough interface to the flat one, Fig. 5.9); a calmer sea is the smooth dielectric.
struct CoxMunkLimits {
    static constexpr double kMinWind = 0.01;  // m/s
    static constexpr double kMaxWind = 14.0;  // m/s
};

// Throws InputError at `where` unless kMinWind <= U <= kMaxWind. `key` names the setting in the
// message (a scene key or a command-line option).
inline void checkCoxMunkWind(double windSpeed, const SourceLoc& where, std::string_view key) {
    if (std::isfinite(windSpeed) && windSpeed >= CoxMunkLimits::kMinWind && windSpeed <= CoxMunkLimits::kMaxWind)
        return;
    throw InputError(where, fmt::format("{}: {} m/s is outside the Cox-Munk range; allowed {} to {} m/s (wind at "
                                        "12.5 m; Cox and Munk measured about 0.7 to 14 m/s)",
                                        key, windSpeed, CoxMunkLimits::kMinWind, CoxMunkLimits::kMaxWind));
}

}  // namespace littoral
