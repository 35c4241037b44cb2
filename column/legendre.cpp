#include "column/legendre.h"

#include <cmath>

#include "core/error.h"
#include "core/quadrature.h"

namespace littoral::column {

std::vector<double> legendreMoments(const PhaseFunction& p, int count) {
    LITTORAL_CHECK_GE(count, 1);
    std::vector<double> chi(static_cast<size_t>(count), 0.0);
    const double tMin = 1e-12;
    // The cone t < tMin: all of it scatters at P_l ~ 1.
    const double cone = p.forwardConeFraction(1.0 - tMin);
    for (double& c : chi) c = cone;
    const GaussLegendre g(16);
    const int panels = 240;
    const double l0 = std::log(tMin), l1 = std::log(2.0);
    std::vector<double> pl(static_cast<size_t>(count));
    for (int k = 0; k < panels; ++k) {
        const double ta = std::exp(l0 + (l1 - l0) * k / panels), tb = std::exp(l0 + (l1 - l0) * (k + 1) / panels);
        for (size_t q = 0; q < g.x.size(); ++q) {
            const double t = 0.5 * (ta + tb) + 0.5 * (tb - ta) * g.x[q], wt = 0.5 * (tb - ta) * g.w[q];
            const double x = 1.0 - t, f = 2 * kPi * p.evalOneMinusCos(t) * wt;  // dx = -dt; the sign flips the limits
            double a = 1, b = x;
            for (int l = 0; l < count; ++l) {
                chi[static_cast<size_t>(l)] += f * a;
                const double c = ((2 * l + 3) * x * b - (l + 1) * a) / (l + 2);  // P_{l+2}
                a = b;
                b = c;
            }
        }
    }
    const double norm = chi[0];  // 1 to the table's and the quadrature's precision
    LITTORAL_CHECK(std::abs(norm - 1.0) < 1e-3);
    for (double& c : chi) c /= norm;
    return chi;
}

std::vector<double> normalizedAssociatedLegendre(int m, int lmax, double x) {
    std::vector<double> v(static_cast<size_t>(lmax + 1), 0.0);
    if (m > lmax) return v;
    const double s = std::sqrt(std::max(0.0, 1.0 - x * x));
    double lmm = 1.0;  // L_m^m = sqrt((2m-1)!!/(2m)!!) s^m
    for (int k = 1; k <= m; ++k) lmm *= std::sqrt((2.0 * k - 1.0) / (2.0 * k)) * s;
    v[static_cast<size_t>(m)] = lmm;
    if (m + 1 <= lmax) v[static_cast<size_t>(m + 1)] = x * std::sqrt(2.0 * m + 1.0) * lmm;
    for (int l = m + 2; l <= lmax; ++l)
        v[static_cast<size_t>(l)] = ((2.0 * l - 1.0) * x * v[static_cast<size_t>(l - 1)] -
                                     std::sqrt(double(l - 1) * (l - 1) - double(m) * m) * v[static_cast<size_t>(l - 2)]) /
                                    std::sqrt(double(l) * l - double(m) * m);
    return v;
}

}  // namespace littoral::column
