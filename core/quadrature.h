#pragma once
// Gauss–Legendre quadrature: the n nodes and weights on [-1, 1], found by Newton's method on
// the Legendre polynomial P_n (exact to rounding), and the n-point rule on [a, b].
#include <cmath>
#include <cstddef>
#include <vector>

#include "core/units.h"

namespace littoral {

struct GaussLegendre {
    std::vector<double> x, w;  // nodes (descending) and weights on [-1, 1]

    explicit GaussLegendre(int n) : x(static_cast<size_t>(n)), w(static_cast<size_t>(n)) {
        for (int i = 0; i < n; ++i) {
            double z = std::cos(kPi * (i + 0.75) / (n + 0.5));
            double dp = 1;
            for (int it = 0; it < 100; ++it) {
                double p0 = 1, p1 = z;
                for (int k = 2; k <= n; ++k) {
                    const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n * (z * p1 - p0) / (z * z - 1);
                const double dz = p1 / dp;
                z -= dz;
                if (std::abs(dz) < 1e-16) break;
            }
            x[static_cast<size_t>(i)] = z;
            w[static_cast<size_t>(i)] = 2.0 / ((1 - z * z) * dp * dp);
        }
    }

    // Int_a^b f.
    template <class F> double integrate(F&& f, double a, double b) const {
        const double m = 0.5 * (a + b), h = 0.5 * (b - a);
        double s = 0;
        for (size_t i = 0; i < x.size(); ++i) s += w[i] * f(m + h * x[i]);
        return s * h;
    }
};

}  // namespace littoral
