#pragma once
// Where vertical sunlight refracted by a sinusoidal gravity wave lands on a flat floor, and where
// the bright caustic lines are: the analytic model of Schenck (1957) used by the dissertation
// (spec/seed-ch05-10.md section 1.8, Eqs. 5.21-5.26), for the lead's caustic image tests.
//
// Profile. The wave runs along X (metres); heights are measured from the mean water level, the
// floor lies at depth D below it. We use the convention of surfaces/synthesis.h (and DIRSIG's
// SINUSOID): Y(X) = -A cos(k (X - X0)), k = 2 pi / lambda, a trough at X0. The digest's literal
// Eq. 5.21, Y = A sin(k X), is the same curve with X0 = -lambda / 4.
//
// Landing (Eqs. 5.22-5.26): a vertical ray meets the surface at P = (X, Y(X)); the slope s = dY/dX
// gives the incidence angle theta_i = atan|s| (5.23); Snell n_i sin theta_i = n_t sin theta_r; the
// refracted ray leans theta_i - theta_r from the vertical (5.24) toward the uphill side (sign of s);
// H = D + Y(X) (5.25) and
//   X_d = X + sign(s) H tan(theta_i - theta_r)                          (5.26)
// It is exact for a vertical ray and one refraction: the ray leans toward the rising surface, so it
// never meets the surface again (the tests check this by marching along the ray).
//
// Caustics. With rays arriving at every X, the irradiance on the floor, relative to a flat surface
// (and ignoring Fresnel losses), is I(x_d) = Sum over the rays landing at x_d of 1 / |dX_d/dX|. The
// bright lines are the folds of the landing map, dX_d/dX = 0, where I diverges; causticLines()
// finds them by bracketing sign changes of the analytic derivative and bisecting. Under a crest
// (s = 0) the derivative is exactly 1 - H (1 - n_i/n_t) A k^2, so the rays next to the crest focus
// at the depth H = 1 / ((1 - n_i/n_t) A k^2) below it (digest: about 1.25 m for A = 2, lambda = 5).
//
// API, namespace littoral::testing_support::sinusoid (header-only): struct Wave with height,
// slope, landing, landingDerivative, causticLines, crestFocalDepth; landingHistogram (the
// dissertation's binning of the landing points of given rays into GSD-wide bins).
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/units.h"

namespace littoral::testing_support::sinusoid {

using littoral::kPi;  // the same constant (one entity, so files that also use namespace littoral agree)

struct Wave {
    double amplitude = 2.0;    // A, m
    double wavelength = 5.0;   // lambda, m
    double trough = 0.0;       // X0, m: position of a trough
    double depth = 6.0;        // D, m: mean water depth (floor at Y = -D)
    double nAir = 1.0, nWater = 1.34;

    double k() const { return 2.0 * kPi / wavelength; }
    double height(double X) const { return -amplitude * std::cos(k() * (X - trough)); }     // Eq. 5.21
    double slope(double X) const { return amplitude * k() * std::sin(k() * (X - trough)); }  // Eq. 5.22
    double slopeDerivative(double X) const { return amplitude * k() * k() * std::cos(k() * (X - trough)); }

    // Signed deviation of the refracted ray from the vertical, theta_i - theta_r, as an odd
    // function of the slope (Eqs. 5.23-5.24); positive leans toward +X.
    double deviation(double s) const {
        const double ti = std::atan(std::abs(s));
        const double tr = std::asin(nAir / nWater * std::sin(ti));
        return std::copysign(ti - tr, s);
    }
    // d(deviation)/ds: 1/(1 + s^2) - (1 + s^2)^(-3/2) n_i / (n_t cos theta_r); even in s.
    double deviationDerivative(double s) const {
        const double q = 1.0 + s * s;
        const double ti = std::atan(std::abs(s));
        const double tr = std::asin(nAir / nWater * std::sin(ti));
        return 1.0 / q - nAir / (nWater * std::cos(tr) * q * std::sqrt(q));
    }
    // Eq. 5.26: landing position on the floor of the vertical ray through X.
    double landing(double X) const {
        const double H = depth + height(X);  // Eq. 5.25
        return X + H * std::tan(deviation(slope(X)));
    }
    // dX_d/dX = 1 + H' tan(delta) + H sec^2(delta) delta'(s) s', with H' = s.
    double landingDerivative(double X) const {
        const double s = slope(X), d = deviation(s);
        const double H = depth + height(X);
        const double sec2 = 1.0 / (std::cos(d) * std::cos(d));
        return 1.0 + s * std::tan(d) + H * sec2 * deviationDerivative(s) * slopeDerivative(X);
    }
    // Depth below a crest at which the rays next to it focus (exact at the crest, see above).
    double crestFocalDepth() const { return 1.0 / ((1.0 - nAir / nWater) * amplitude * k() * k()); }

    struct Caustic {
        double X = 0;        // where the rays forming it enter the surface, m
        double landing = 0;  // where the bright line is on the floor, m
    };
    // Folds of the landing map for rays entering in [X0, X0 + lambda) (one period; the pattern
    // repeats every lambda), sorted by entry position. `steps` brackets per period.
    std::vector<Caustic> causticLines(int steps = 20000) const {
        std::vector<Caustic> out;
        const double a = trough, h = wavelength / steps;
        double xPrev = a, dPrev = landingDerivative(a);
        for (int i = 1; i <= steps; ++i) {
            const double x = a + i * h, d = landingDerivative(x);
            if ((dPrev < 0) != (d < 0)) {
                double lo = xPrev, hi = x;
                const bool loNeg = dPrev < 0;
                for (int it = 0; it < 100 && hi - lo > 1e-13; ++it) {
                    const double mid = 0.5 * (lo + hi);
                    ((landingDerivative(mid) < 0) == loNeg ? lo : hi) = mid;
                }
                const double xr = 0.5 * (lo + hi);
                if (xr < a + wavelength) out.push_back({xr, landing(xr)});
            }
            xPrev = x;
            dPrev = d;
        }
        return out;
    }
};

// The dissertation's binning: landing points of the rays entering at `entries` counted in bins of
// width gsd covering [x0, x1). Returns counts per bin.
inline std::vector<int> landingHistogram(const Wave& w, const std::vector<double>& entries, double x0, double x1,
                                         double gsd) {
    const int n = static_cast<int>(std::ceil((x1 - x0) / gsd - 1e-9));
    std::vector<int> counts(static_cast<size_t>(std::max(n, 0)), 0);
    for (double X : entries) {
        const double xd = w.landing(X);
        const double b = std::floor((xd - x0) / gsd);
        if (b >= 0 && b < n) ++counts[static_cast<size_t>(b)];
    }
    return counts;
}

}  // namespace littoral::testing_support::sinusoid
