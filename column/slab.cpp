#include "column/slab.h"

#include <cmath>
#include <limits>

#include "column/legendre.h"
#include "core/error.h"
#include "core/units.h"

namespace littoral::column {

double modeKernel(const std::vector<double>& chi, int m, double x, double y) {
    const int lmax = static_cast<int>(chi.size()) - 1;
    if (m > lmax) return 0.0;
    const auto lx = normalizedAssociatedLegendre(m, lmax, x), ly = normalizedAssociatedLegendre(m, lmax, y);
    double s = 0;
    for (int l = m; l <= lmax; ++l) s += (2 * l + 1) * chi[static_cast<size_t>(l)] * lx[static_cast<size_t>(l)] * ly[static_cast<size_t>(l)];
    return s;
}

namespace {

// Int_0^d e^{-a s} ds = (1 - e^{-a d}) / a, without cancellation for small a d.
double expIntegral(double a, double d) {
    const double ad = a * d;
    return std::abs(ad) < 1e-8 ? d * (1.0 - 0.5 * ad) : -std::expm1(-ad) / a;
}

// Exact single scattering of a slab of optical thickness d (the start of doubling).
SlabOperators thinSlab(const Streams& s, const ScaledOptics& o, int m, double mu0, double d) {
    const int n = s.size();
    SlabOperators op{Matrix(n, n), Matrix(n, n), std::vector<double>(static_cast<size_t>(n)),
                     std::vector<double>(static_cast<size_t>(n)), std::exp(-d / mu0)};
    const double beamFactor = o.omega / (4 * kPi) * (m == 0 ? 1.0 : 2.0) / mu0;
    std::vector<std::vector<double>> lp(static_cast<size_t>(n)), lm(static_cast<size_t>(n));
    const int lmax = static_cast<int>(o.chi.size()) - 1;
    for (int i = 0; i < n; ++i) {
        lp[static_cast<size_t>(i)] = normalizedAssociatedLegendre(m, lmax, s.mu[static_cast<size_t>(i)]);
        lm[static_cast<size_t>(i)] = normalizedAssociatedLegendre(m, lmax, -s.mu[static_cast<size_t>(i)]);
    }
    auto kernel = [&](const std::vector<double>& a, const std::vector<double>& b) {
        double k = 0;
        for (int l = m; l <= lmax; ++l)
            k += (2 * l + 1) * o.chi[static_cast<size_t>(l)] * a[static_cast<size_t>(l)] * b[static_cast<size_t>(l)];
        return k;
    };
    const auto l0 = normalizedAssociatedLegendre(m, lmax, mu0);
    for (int i = 0; i < n; ++i) {
        const double mi = s.mu[static_cast<size_t>(i)], ei = std::exp(-d / mi);
        for (int j = 0; j < n; ++j) {
            const double mj = s.mu[static_cast<size_t>(j)], wj = s.w[static_cast<size_t>(j)];
            const double back = kernel(lm[static_cast<size_t>(i)], lp[static_cast<size_t>(j)]);
            const double fwd = kernel(lp[static_cast<size_t>(i)], lp[static_cast<size_t>(j)]);
            op.R(i, j) = 0.5 * o.omega * wj * back / mi * expIntegral(1 / mi + 1 / mj, d);
            op.T(i, j) = 0.5 * o.omega * wj * fwd / mi * ei * expIntegral(1 / mj - 1 / mi, d) + (i == j ? ei : 0.0);
        }
        op.su[static_cast<size_t>(i)] = beamFactor * kernel(lm[static_cast<size_t>(i)], l0) / mi * expIntegral(1 / mu0 + 1 / mi, d);
        op.sd[static_cast<size_t>(i)] = beamFactor * kernel(lp[static_cast<size_t>(i)], l0) / mi * ei * expIntegral(1 / mu0 - 1 / mi, d);
    }
    return op;
}

// Two copies of `a` stacked (the doubling step in the header).
SlabOperators doubled(const SlabOperators& a) {
    const int n = a.R.rows();
    const Matrix g = Matrix::identity(n) - a.R * a.R;
    const Matrix rt = a.R * a.T;
    const std::vector<double> rhsSource = a.sd + a.beamT * (a.R * a.su);
    Matrix rhs(n, 2 * n + 1);
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            rhs(i, j) = a.T(i, j);
            rhs(i, n + j) = rt(i, j);
        }
        rhs(i, 2 * n) = rhsSource[static_cast<size_t>(i)];
    }
    const Matrix sol = solve(g, rhs);
    Matrix gt(n, n), grt(n, n);
    std::vector<double> x(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            gt(i, j) = sol(i, j);
            grt(i, j) = sol(i, n + j);
        }
        x[static_cast<size_t>(i)] = sol(i, 2 * n);
    }
    SlabOperators b;
    b.T = a.T * gt;
    b.R = a.R + a.T * grt;
    const std::vector<double> y = a.R * x + a.beamT * a.su;
    b.su = a.su + a.T * y;
    b.sd = a.beamT * a.sd + a.T * x;
    b.beamT = a.beamT * a.beamT;
    return b;
}

double maxDiff(const std::vector<double>& a, const std::vector<double>& b) {
    double m = 0;
    for (size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
    return m;
}

}  // namespace

SlabOperators slabOperators(const Streams& s, const ScaledOptics& optics, int m, double mu0, double tau) {
    LITTORAL_CHECK_GT(tau, 0.0);
    constexpr double kStart = 1e-6;
    if (std::isinf(tau)) {
        // Semi-infinite: double until R and su stop changing (T, sd, t vanish geometrically).
        SlabOperators op = thinSlab(s, optics, m, mu0, kStart);
        for (int k = 0; k < 200; ++k) {
            SlabOperators next = doubled(op);
            const bool done = (next.R - op.R).maxAbs() < 1e-14 && maxDiff(next.su, op.su) < 1e-14 * (1 + op.su.size()) &&
                              next.T.maxAbs() < 1e-14 && next.beamT < 1e-14;
            op = std::move(next);
            if (done) break;
        }
        op.T = Matrix(s.size(), s.size());
        op.sd.assign(op.sd.size(), 0.0);
        op.beamT = 0;
        return op;
    }
    int k = 0;
    while (tau / std::ldexp(1.0, k) > kStart && k < 60) ++k;
    SlabOperators op = thinSlab(s, optics, m, mu0, tau / std::ldexp(1.0, k));
    for (int i = 0; i < k; ++i) op = doubled(op);
    return op;
}

}  // namespace littoral::column
