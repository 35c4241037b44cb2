#pragma once
// Gordon and Ding (1992), "Self-shading of in-water optical instruments", Limnol. Oceanogr.
// 37(3), 491-500: the relative error epsilon = 1 - exp(-k' a R) that an opaque instrument of
// radius R (m) causes in upwelling radiance (Lu) or irradiance (Eu) in water of absorption a
// (m^-1). Coefficients as in spec/reference-data.md (header-only).
//   Sun:  k' = k''/tan(theta_w), theta_w = asin(sin(theta_0)/1.33) the refracted solar zenith
//         angle, k'' tabulated at theta_0 = 0, 10, ..., 90 deg and interpolated linearly in
//         theta_0 here.
//   Sky:  k' = 4.61 (Lu), 2.70 (Eu).
//   Both: epsilon = (epsilon_sun + f epsilon_sky)/(1 + f), f = E_sky/E_sun.
// At theta_0 = 0 the sun term's k' is infinite (the shadow lies straight under the instrument),
// so epsilon_sun = 1 for any a R > 0.
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/units.h"

namespace littoral::reference::gordon_ding {

enum class Quantity { Lu, Eu };

inline constexpr double kWaterIndex = 1.33;  // Gordon and Ding's refraction of the sun
inline constexpr double kSunKpp[2][10] = {
    {2.17, 2.17, 2.23, 2.23, 2.29, 2.37, 2.41, 2.45, 2.45, 2.45},  // Lu
    {3.14, 3.14, 3.05, 2.94, 2.80, 2.64, 2.47, 2.33, 2.33, 2.33},  // Eu
};
inline constexpr double kSkyKp[2] = {4.61, 2.70};

// k''(theta_0), linear in theta_0 between the 10-deg nodes.
inline double kDoublePrimeSun(Quantity q, double theta0Deg) {
    const double x = std::clamp(theta0Deg / 10.0, 0.0, 9.0);
    const int i = std::min(static_cast<int>(x), 8);
    const double* k = kSunKpp[q == Quantity::Lu ? 0 : 1];
    return k[i] + (x - i) * (k[i + 1] - k[i]);
}

inline double refractedZenithRad(double theta0Deg) { return std::asin(std::sin(deg2rad(theta0Deg)) / kWaterIndex); }

inline double kPrimeSun(Quantity q, double theta0Deg) {
    const double t = std::tan(refractedZenithRad(theta0Deg));
    return t > 0 ? kDoublePrimeSun(q, theta0Deg) / t : std::numeric_limits<double>::infinity();
}

inline double kPrimeSky(Quantity q) { return kSkyKp[q == Quantity::Lu ? 0 : 1]; }

// epsilon = 1 - exp(-k' a R), written with expm1 so that small a R keeps its precision.
inline double epsilonSun(Quantity q, double theta0Deg, double absorption, double radius) {
    const double k = kPrimeSun(q, theta0Deg);
    if (std::isinf(k)) return absorption * radius > 0 ? 1.0 : 0.0;
    return -std::expm1(-k * absorption * radius);
}

inline double epsilonSky(Quantity q, double absorption, double radius) {
    return -std::expm1(-kPrimeSky(q) * absorption * radius);
}

// Sun and sky combined; skyToSun = f = E_sky / E_sun.
inline double epsilon(Quantity q, double theta0Deg, double absorption, double radius, double skyToSun) {
    return (epsilonSun(q, theta0Deg, absorption, radius) + skyToSun * epsilonSky(q, absorption, radius)) / (1.0 + skyToSun);
}

}  // namespace littoral::reference::gordon_ding
