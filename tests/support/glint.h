#pragma once
// Closed-form glint and transmitted-sun predictions for a Cox-Munk sea (spec/seed-ch05-10.md
// sections 1.2-1.7): the analytic curves the dissertation's Figs. 5.5-5.8 compare DIRSIG with, for
// the lead's image tests (rendered transects against these) and for the BxDF's own tests.
//
// Deliberately self-contained: its own Fresnel (the sin/tan form of Eq. 4.2), its own Gaussian
// slope density and the digest's closed forms written as printed, so that a test comparing the
// renderer's RoughDielectricBxDF with these compares two independent derivations.
//
// Geometry. Local frame: x upwind axis (the digest's z_x slope), y crosswind, z up; the surface
// is horizontal at z = 0 with air (n_i) above and water (n_t) below. Directions are unit vectors
// pointing AWAY from the surface: `toSun` (in air, z > 0), `toViewer` (z > 0 for a sensor in air,
// z < 0 for a submerged receiver). All results are ratios to E_perp, the solar irradiance on a
// plane normal to the beam (sr^-1), for a point sun; sunDiscAverage() averages over a finite disc.
//
// API, namespace littoral::testing_support::glint (header-only):
//   fresnelSinTan(cosI, n1, n2)       Eq. 4.2 as printed (normal incidence: Eq. 4.3)
//   SlopeVariances{upwind, crosswind}, dissertationSlopes(W): 0.00316 W, 0.00192 W (section 1.2)
//   slopePdf(v, zx, zy)               p_s, zero-mean Gaussian
//   reflected(v, toSun, toViewer)     Eq. 5.4 with Eqs. 5.7-5.10: rho(alpha) p_s / (4 cos^4 beta cos theta_r)
//   transmitted(v, toSun, toViewer)   section 1.6 closed form (Walter-consistent):
//                                     n_t^2 (1 - rho(alpha)) p_s cos(alpha) cos(gamma)
//                                     / (cos^4 beta cos theta_t |n_i i + n_t o|^2)
//   Sun at zenith, nadir viewer / upward-looking receiver (section 1.7):
//     nadirGlint(W, viewZenith, Axis)            L_r / E_perp along the upwind or crosswind transect
//     nadirGlintAtGround(v, x, y, H)            the same for ground point (x, y) seen from height H
//     submergedTransmitted(W, inWaterZenith, Axis)  L_t / E_perp at in-water zenith angle from nadir
//   halfMaximumAngle(f, hi)           where a decreasing transect first falls to half its peak
//   sunDiscAverage(g, toSun, radius)  average of g(sun direction) over a uniform solar disc
#include <algorithm>
#include <cmath>
#include <functional>

#include "core/units.h"

namespace littoral::testing_support::glint {

using littoral::kPi;  // the same constant (one entity, so files that also use namespace littoral agree)
inline constexpr double kWaterIndex = 1.34;  // n_w of the dissertation (Ch. 4)

struct Dir {
    double x = 0, y = 0, z = 1;
};
inline double dotd(const Dir& a, const Dir& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Dir normalized(double x, double y, double z) {
    const double l = std::sqrt(x * x + y * y + z * z);
    return {x / l, y / l, z / l};
}
// Direction at zenith angle theta from +z and azimuth phi from +x (Eq. 5.8).
inline Dir fromAngles(double theta, double phi) {
    return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// Eq. 4.2: r = 1/2 [sin^2(ti - tr)/sin^2(ti + tr) + tan^2(ti - tr)/tan^2(ti + tr)], Snell n1 sin ti =
// n2 sin tr; ((n2 - n1)/(n2 + n1))^2 at normal incidence (Eq. 4.3); 1 beyond the critical angle.
inline double fresnelSinTan(double cosI, double n1, double n2) {
    cosI = std::clamp(cosI, 0.0, 1.0);
    const double ti = std::acos(cosI);
    const double st = n1 / n2 * std::sin(ti);
    if (st >= 1.0) return 1.0;
    const double tr = std::asin(st);
    if (ti < 1e-7) return ((n2 - n1) / (n2 + n1)) * ((n2 - n1) / (n2 + n1));
    const double a = std::sin(ti - tr) / std::sin(ti + tr);
    const double b = std::tan(ti - tr) / std::tan(ti + tr);
    return 0.5 * (a * a + b * b);
}

struct SlopeVariances {
    double upwind = 0, crosswind = 0;
};
// The dissertation's figure labels (digest section 1.2): no 0.003 crosswind offset.
inline SlopeVariances dissertationSlopes(double W) { return {0.00316 * W, 0.00192 * W}; }

inline double slopePdf(const SlopeVariances& v, double zx, double zy) {
    return std::exp(-0.5 * (zx * zx / v.upwind + zy * zy / v.crosswind)) /
           (2.0 * kPi * std::sqrt(v.upwind * v.crosswind));
}

// Eq. 5.4 with the facet slopes of Eqs. 5.7-5.8 (normal ~ toSun + toViewer) and cos(alpha) of Eq. 5.9.
inline double reflected(const SlopeVariances& v, const Dir& toSun, const Dir& toViewer, double nWater = kWaterIndex) {
    const double den = toSun.z + toViewer.z;
    const double zx = -(toSun.x + toViewer.x) / den, zy = -(toSun.y + toViewer.y) / den;
    const double cosBeta = 1.0 / std::sqrt(1.0 + zx * zx + zy * zy);
    const Dir N{-zx * cosBeta, -zy * cosBeta, cosBeta};
    const double cosAlpha = dotd(toViewer, N);
    const double rho = fresnelSinTan(cosAlpha, 1.0, nWater);
    const double c2 = cosBeta * cosBeta;
    return slopePdf(v, zx, zy) * rho / (4.0 * c2 * c2 * toViewer.z);
}

// Digest section 1.6, closed form with G = 1 (t = f_t cos(theta_i) of Walter et al. 2007):
// h = -(n_i i + n_t o)/|..| (turned up), alpha = angle(i, h), gamma = angle(o, -h), beta = angle(h, z).
inline double transmitted(const SlopeVariances& v, const Dir& toSun, const Dir& toViewer, double nWater = kWaterIndex) {
    const double ni = 1.0, nt = nWater;
    const double sx = ni * toSun.x + nt * toViewer.x, sy = ni * toSun.y + nt * toViewer.y,
                 sz = ni * toSun.z + nt * toViewer.z;
    const double s2 = sx * sx + sy * sy + sz * sz;
    Dir h = normalized(-sx, -sy, -sz);
    if (h.z < 0) h = {-h.x, -h.y, -h.z};
    const double cosAlpha = dotd(toSun, h), cosGamma = -dotd(toViewer, h), cosBeta = h.z;
    if (cosAlpha <= 0 || cosGamma <= 0) return 0.0;
    const double zx = -h.x / h.z, zy = -h.y / h.z;
    const double rho = fresnelSinTan(cosAlpha, ni, nt);
    const double c2 = cosBeta * cosBeta;
    return nt * nt * (1.0 - rho) * slopePdf(v, zx, zy) * cosAlpha * cosGamma / (c2 * c2 * std::abs(toViewer.z) * s2);
}

enum class Axis { Upwind, Crosswind };

// Sun at zenith, viewer in air at zenith angle viewZenith along the upwind (x) or crosswind (y) axis.
inline double nadirGlint(double W, double viewZenith, Axis axis, double nWater = kWaterIndex) {
    return reflected(dissertationSlopes(W), {0, 0, 1}, fromAngles(viewZenith, axis == Axis::Upwind ? 0.0 : 0.5 * kPi),
                     nWater);
}

// Nadir sensor at height H above the sea, sun at zenith, ground point (x, y) (x upwind): section 1.7,
// z_x = x / (R + H), z_y = y / (R + H), R = sqrt(x^2 + y^2 + H^2).
inline double nadirGlintAtGround(const SlopeVariances& v, double x, double y, double H, double nWater = kWaterIndex) {
    const double R = std::sqrt(x * x + y * y + H * H);
    return reflected(v, {0, 0, 1}, {-x / R, -y / R, H / R}, nWater);
}

// Submerged receiver looking up; in-water zenith angle measured from nadir along an axis; sun at zenith.
inline double submergedTransmitted(double W, double inWaterZenith, Axis axis, double nWater = kWaterIndex) {
    const Dir up = fromAngles(inWaterZenith, axis == Axis::Upwind ? 0.0 : 0.5 * kPi);
    return transmitted(dissertationSlopes(W), {0, 0, 1}, {up.x, up.y, -up.z}, nWater);
}

// The angle in (0, hi) at which a transect f(angle), largest at 0 and decreasing, falls to f(0)/2.
// Bisection to 1e-12 rad.
inline double halfMaximumAngle(const std::function<double(double)>& f, double hi) {
    const double half = 0.5 * f(0.0);
    double lo = 0.0;
    for (int i = 0; i < 200 && hi - lo > 1e-12; ++i) {
        const double mid = 0.5 * (lo + hi);
        (f(mid) > half ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

// Average of g(sun direction) over a sun disc of angular radius `radius` (uniform radiance) centred
// on toSun: 16-point Gauss-Legendre in the disc's area coordinate rho^2 times 64 azimuths, on the
// small-angle tangent plane (relative error ~ radius^2, 2e-5 for the 0.265 deg sun).
inline double sunDiscAverage(const std::function<double(const Dir&)>& g, const Dir& toSun, double radius) {
    static constexpr double x[8] = {0.0950125098376374, 0.2816035507792589, 0.4580167776572274, 0.6178762444026438,
                                    0.7554044083550030, 0.8656312023878318, 0.9445750230732326, 0.9894009349916499};
    static constexpr double w[8] = {0.1894506104550685, 0.1826034150449236, 0.1691565193950025, 0.1495959888165767,
                                    0.1246289712555339, 0.0951585116824928, 0.0622535239386479, 0.0271524594117541};
    // Tangent basis (e1, e2) of toSun.
    const Dir a = std::abs(toSun.z) < 0.9 ? Dir{0, 0, 1} : Dir{1, 0, 0};
    Dir e1 = normalized(a.y * toSun.z - a.z * toSun.y, a.z * toSun.x - a.x * toSun.z, a.x * toSun.y - a.y * toSun.x);
    const Dir e2{toSun.y * e1.z - toSun.z * e1.y, toSun.z * e1.x - toSun.x * e1.z, toSun.x * e1.y - toSun.y * e1.x};
    constexpr int nPhi = 64;
    double sum = 0;
    for (int k = 0; k < 16; ++k) {
        const double t = k < 8 ? 0.5 * (1 - x[7 - k]) : 0.5 * (1 + x[k - 8]);  // node in (0, 1)
        const double wt = 0.5 * (k < 8 ? w[7 - k] : w[k - 8]);
        const double r = radius * std::sqrt(t);  // area coordinate t = (r / radius)^2
        for (int j = 0; j < nPhi; ++j) {
            const double p = 2.0 * kPi * (j + 0.5) / nPhi;
            const double cx = r * std::cos(p), cy = r * std::sin(p);
            sum += wt / nPhi * g(normalized(toSun.x + cx * e1.x + cy * e2.x, toSun.y + cx * e1.y + cy * e2.y,
                                            toSun.z + cx * e1.z + cy * e2.z));
        }
    }
    return sum;
}

}  // namespace littoral::testing_support::glint
