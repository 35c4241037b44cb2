#include "render/cox_munk.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "core/units.h"

namespace littoral::render {

namespace {
constexpr double kInvSqrtPi = 0.56418958354775628695;  // 1 / sqrt(pi)

// Int phi(xi) phi(eta) max(-P, 0) dxi deta: the mass the clipping at zero adds back. P is a
// polynomial whose Gaussian-weighted integral is exactly 1 (Hermite orthogonality: every term but
// the 1 has zero mean), so Z = 1 + this. For fixed xi, P is a quartic in eta: its sign changes are
// bracketed on a 0.01 grid over [-12, 12] and bisected, and Int phi(eta) eta^k over each interval
// where P < 0 is exact (erf and the recursion M_k = (k-1) M_{k-2} + [-eta^{k-1} phi]). The outer
// integral over xi is a trapezoidal sum with step 0.01 on [-9, 9]; the integrand is smooth except
// where a negative interval is born (it grows as (xi - xi*)^{3/2}). Halving the step changes the
// result by 4e-13 at 10 m/s and 1e-15 at 14 m/s (absolute). Beyond |xi| = 9 the weight is below
// e^-40. About 4 million quartic evaluations: some 20 ms.
double clippedMass(const GramCharlierCoefficients& c) {
    constexpr double kInvSqrt2Pi = 0.39894228040143267794;
    auto phi = [](double x) { return kInvSqrt2Pi * std::exp(-0.5 * x * x); };
    auto Phi = [](double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); };
    double outer = 0;
    constexpr double hx = 0.01, Lx = 9.0, he = 0.01, Le = 12.0;
    constexpr int nx = static_cast<int>(2 * Lx / hx + 0.5), ne = static_cast<int>(2 * Le / he + 0.5);
    for (int i = 0; i <= nx; ++i) {
        const double xi = -Lx + i * hx, x2 = xi * xi;
        // P(eta) = a0 + a1 eta + a2 eta^2 + a3 eta^3 + a4 eta^4 (the series of cox_munk.h at this xi).
        const double a[5] = {1.0 + c.c40 / 24.0 * (x2 * x2 - 6.0 * x2 + 3.0) - 0.25 * c.c22 * (x2 - 1.0) + c.c04 / 8.0,
                             -0.5 * c.c21 * (x2 - 1.0) + 0.5 * c.c03, 0.25 * c.c22 * (x2 - 1.0) - 0.25 * c.c04,
                             -c.c03 / 6.0, c.c04 / 24.0};
        auto P = [&](double e) { return a[0] + e * (a[1] + e * (a[2] + e * (a[3] + e * a[4]))); };
        auto root = [&](double lo, double hi) {
            const bool loNeg = P(lo) < 0;
            for (int it = 0; it < 80 && hi - lo > 1e-15; ++it) {
                const double mid = 0.5 * (lo + hi);
                ((P(mid) < 0) == loNeg ? lo : hi) = mid;
            }
            return 0.5 * (lo + hi);
        };
        // Int_lo^hi phi(eta) (-P(eta)) d eta from the exact moments M_0..M_4.
        auto negativePart = [&](double lo, double hi) {
            double M[5];
            M[0] = Phi(hi) - Phi(lo);
            M[1] = phi(lo) - phi(hi);
            for (int k = 2; k <= 4; ++k)
                M[k] = (k - 1) * M[k - 2] + std::pow(lo, k - 1) * phi(lo) - std::pow(hi, k - 1) * phi(hi);
            double s = 0;
            for (int k = 0; k <= 4; ++k) s += a[k] * M[k];
            return std::max(0.0, -s);
        };
        double inner = 0, start = 0;
        bool neg = P(-Le) < 0;
        if (neg) start = -Le;
        double prev = -Le;
        for (int j = 1; j <= ne; ++j) {
            const double e = -Le + j * he;
            const bool n = P(e) < 0;
            if (n != neg) {
                const double r = root(prev, e);
                if (n) start = r;
                else inner += negativePart(start, r);
                neg = n;
            }
            prev = e;
        }
        if (neg) inner += negativePart(start, Le);
        outer += (i == 0 || i == nx ? 0.5 : 1.0) * phi(xi) * inner;
    }
    return outer * hx;
}
}  // namespace

double beckmannLambda(double a) {
    if (!(a < 1e8)) return 0.0;  // normal incidence (a = +inf): nothing is masked
    if (a <= 0.0) return std::numeric_limits<double>::infinity();
    // Smith (1967) for a Gaussian slope distribution: Lambda = (erf(a) - 1)/2 + exp(-a^2)/(2 a sqrt(pi)).
    // (erf(a) - 1) = -erfc(a) keeps precision where both terms are small (a >> 1).
    return 0.5 * (std::exp(-a * a) * kInvSqrtPi / a - std::erfc(a));
}

CoxMunkDistribution::CoxMunkDistribution(const CoxMunkParams& p, const SourceLoc& where, std::string_view windKey) {
    checkCoxMunkWind(p.windSpeed, where, windKey);
    if (!std::isfinite(p.windAzimuth))
        throw InputError(where, fmt::format("wind azimuth {} is not a finite angle", p.windAzimuth));
    if (p.gramCharlier && p.sea != CoxMunkSea::Clean)
        throw InputError(where, fmt::format("Gram-Charlier terms are published for the clean sea only (Cox & Munk "
                                            "1954); they cannot be used with the {} coefficients; allowed with: clean",
                                            nameOf(p.sea)));
    if (const std::string why = coxMunkSlopesProblem(p.slopes, p.sea, p.gramCharlier); !why.empty())
        throw InputError(where, why);
    const SlopeVariances v = coxMunkSlopeVariances(p.windSpeed, p.sea, p.slopes);
    *this = fromVariances(v.upwind, v.crosswind, p.windAzimuth);
    if (p.gramCharlier) {
        gc_ = true;
        c_ = coxMunkCleanGramCharlier(p.windSpeed);
        z_ = 1.0 + clippedMass(c_);
    }
}

CoxMunkDistribution CoxMunkDistribution::fromVariances(double varUpwind, double varCrosswind, double windAzimuth) {
    if (!(varUpwind > 0) || !(varCrosswind > 0) || !std::isfinite(varUpwind) || !std::isfinite(varCrosswind))
        throw InputError(fmt::format("slope variances must be finite and > 0 (got upwind {}, crosswind {})", varUpwind,
                                     varCrosswind));
    CoxMunkDistribution d;
    d.varU_ = varUpwind;
    d.varC_ = varCrosswind;
    d.sigU_ = std::sqrt(varUpwind);
    d.sigC_ = std::sqrt(varCrosswind);
    d.phiW_ = windAzimuth;
    d.cosW_ = std::cos(windAzimuth);
    d.sinW_ = std::sin(windAzimuth);
    return d;
}

Vec2 CoxMunkDistribution::toWindSlopes(const Vec2& g) const {
    // z_u = -grad z . e_down, z_c = grad z . e_cross (see the header).
    return {-(g.x * cosW_ + g.y * sinW_), -g.x * sinW_ + g.y * cosW_};
}

Vec2 CoxMunkDistribution::fromWindSlopes(const Vec2& w) const {
    // grad z = -z_u e_down + z_c e_cross.
    return {-w.x * cosW_ - w.y * sinW_, -w.x * sinW_ + w.y * cosW_};
}

double CoxMunkDistribution::gcFactor(double xi, double eta) const {
    const double x2 = xi * xi, e2 = eta * eta;
    // Cox & Munk (1954) Gram-Charlier series (header); clipped at 0 and renormalised by Z.
    const double P = 1.0 - 0.5 * c_.c21 * (x2 - 1.0) * eta - c_.c03 / 6.0 * (e2 * eta - 3.0 * eta) +
                     c_.c40 / 24.0 * (x2 * x2 - 6.0 * x2 + 3.0) + 0.25 * c_.c22 * (x2 - 1.0) * (e2 - 1.0) +
                     c_.c04 / 24.0 * (e2 * e2 - 6.0 * e2 + 3.0);
    return std::max(P, 0.0) / z_;
}

double CoxMunkDistribution::gaussianSlopePdf(const Vec2& g) const {
    const Vec2 w = toWindSlopes(g);
    const double eta = w.x / sigU_, xi = w.y / sigC_;
    return std::exp(-0.5 * (eta * eta + xi * xi)) / (2.0 * kPi * sigU_ * sigC_);
}

double CoxMunkDistribution::slopePdf(const Vec2& g) const {
    if (!gc_) return gaussianSlopePdf(g);
    const Vec2 w = toWindSlopes(g);
    const double eta = w.x / sigU_, xi = w.y / sigC_;
    return std::exp(-0.5 * (eta * eta + xi * xi)) / (2.0 * kPi * sigU_ * sigC_) * gcFactor(xi, eta);
}

Vec2 CoxMunkDistribution::sampleSlope(const Vec2& u) const {
    // Box-Muller: (eta, xi) = r (cos psi, sin psi) is a standard bivariate normal.
    const double r = std::sqrt(-2.0 * std::log1p(-u.x));
    const double psi = 2.0 * kPi * u.y;
    return fromWindSlopes({sigU_ * r * std::cos(psi), sigC_ * r * std::sin(psi)});
}

Vec2 CoxMunkDistribution::invertSlope(const Vec2& g) const {
    const Vec2 w = toWindSlopes(g);
    const double eta = w.x / sigU_, xi = w.y / sigC_;
    double psi = std::atan2(xi, eta);
    if (psi < 0) psi += 2.0 * kPi;
    double u2 = psi / (2.0 * kPi);
    if (u2 >= 1.0) u2 = 0.0;
    return {-std::expm1(-0.5 * (eta * eta + xi * xi)), u2};
}

double CoxMunkDistribution::D(const Vec3& m) const {
    if (!(m.z > 0)) return 0.0;
    const double c2 = m.z * m.z;
    return slopePdf({-m.x / m.z, -m.y / m.z}) / (c2 * c2);  // digest section 1.2: p_s / cos^4
}

double CoxMunkDistribution::gaussianD(const Vec3& m) const {
    if (!(m.z > 0)) return 0.0;
    const double c2 = m.z * m.z;
    return gaussianSlopePdf({-m.x / m.z, -m.y / m.z}) / (c2 * c2);
}

Vec3 CoxMunkDistribution::sampleNormal(const Vec2& u) const {
    const Vec2 z = sampleSlope(u);
    return normalize(Vec3{-z.x, -z.y, 1.0});  // Eq. 5.5
}

Vec2 CoxMunkDistribution::invertNormal(const Vec3& m) const { return invertSlope({-m.x / m.z, -m.y / m.z}); }

double CoxMunkDistribution::varianceAlong(double phi) const {
    const double c = std::cos(phi - phiW_), s = std::sin(phi - phiW_);
    return varU_ * c * c + varC_ * s * s;
}

double CoxMunkDistribution::lambda(const Vec3& w) const {
    const double sin2 = w.x * w.x + w.y * w.y;
    if (sin2 <= 0.0) return 0.0;
    if (w.z == 0.0) return std::numeric_limits<double>::infinity();
    // a = cot(theta) / (sqrt(2) sigma(phi)), sigma(phi)^2 the slope variance along w's azimuth:
    // sigma(phi)^2 = (var_u (w_h . e_down)^2 + var_c (w_h . e_cross)^2) / |w_h|^2.
    const double d = w.x * cosW_ + w.y * sinW_, c = -w.x * sinW_ + w.y * cosW_;
    const double var = (varU_ * d * d + varC_ * c * c) / sin2;
    const double a = std::abs(w.z) / std::sqrt(2.0 * var * sin2);
    return beckmannLambda(a);
}

double CoxMunkDistribution::G1(const Vec3& w, const Vec3& m) const {
    // chi+: the facet must face w from w's side of the surface.
    if (dot(w, m) * w.z <= 0.0) return 0.0;
    return 1.0 / (1.0 + lambda(w));
}

}  // namespace littoral::render
