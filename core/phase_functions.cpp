#include "core/phase_functions.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include "core/error.h"
#include "core/frame.h"
#include "core/quadrature.h"
#include "core/units.h"

namespace littoral {

namespace {

constexpr double kInv4Pi = 1.0 / (4.0 * kPi);
constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kGuessLogLo = -37.0;  // ~ ln 2^-53: the smallest sampling target u or 1 - u

double clamp01(double u) { return std::clamp(u, 0.0, 1.0); }

const GaussLegendre& gauss20() {
    static const GaussLegendre g(20);
    return g;
}

// Solves f(x) = 0 for an increasing f on [lo, hi] with f(lo) < 0 < f(hi) by Newton steps that
// fall back to bisection whenever a step leaves the bracket (Numerical-Recipes "rtsafe" logic).
template <class F> double safeguardedNewton(F&& f, double lo, double hi, double x) {
    for (int it = 0; it < 200; ++it) {
        double fx, dfx;
        f(x, &fx, &dfx);
        if (fx == 0) return x;
        if (fx > 0) hi = x;
        else lo = x;
        if (std::abs(fx) < 1e-14) return x;
        double xn = x - fx / dfx;
        if (!(xn > lo && xn < hi)) xn = 0.5 * (lo + hi);
        if (std::abs(xn - x) <= 1e-14 * std::max(1.0, std::abs(x)) || hi - lo <= 1e-14 * std::max(1.0, std::abs(x)))
            return xn;
        x = xn;
    }
    return x;
}


// Pure water (Morel 1974): p proportional to 1 + (1 - delta)/(1 + delta) cos^2 psi, delta the
// depolarisation ratio of its molecular scattering; delta = 0.09 gives 1 + 0.835 cos^2. delta in
// [0, 1] keeps the coefficient in [0, 1], the rayleigh kind's range.
constexpr double kPureWaterDepolarization = 0.09;
PhaseKind pureWaterKind() {
    return {{"phase function", "pure-water",
             "molecular scattering of pure (and sea) water, Morel (1974): p proportional to 1 + (1 - delta)/(1 + delta) "
             "cos^2",
             {{"depolarization_ratio", "", ParamType::Real, kPureWaterDepolarization, 0.0, 1.0, "",
               "delta; 0.09 (Morel 1974) gives 1 + 0.835 cos^2"}}},
            [](const ParamValues& v) {
                const double d = v.number("depolarization_ratio");
                return PhaseFunction::molecularWater((1.0 - d) / (1.0 + d));
            }};
}
}  // namespace

// ---------------------------------------------------------------------------------------------
// Isotropic

double IsotropicPhase::eval(double) const { return kInv4Pi; }
double IsotropicPhase::evalOneMinusCos(double) const { return kInv4Pi; }
double IsotropicPhase::sampleCos(double u) const { return 2.0 * clamp01(u) - 1.0; }
double IsotropicPhase::sampleOneMinusCos(double u) const { return 2.0 * (1.0 - clamp01(u)); }
double IsotropicPhase::invertCos(double c) const { return 0.5 * (1.0 + std::clamp(c, -1.0, 1.0)); }
double IsotropicPhase::forwardConeFraction(double c0) const { return 0.5 * (1.0 - std::clamp(c0, -1.0, 1.0)); }
double IsotropicPhase::forwardFraction(double t) const { return 0.5 * std::clamp(t, 0.0, 2.0); }

namespace {
PhaseKind isotropicKind() {
    return {{"phase function", "isotropic", "the same in every direction, p = 1 / (4 pi)", {}},
            [](const ParamValues&) { return PhaseFunction::isotropic(); }};
}
}  // namespace

// ---------------------------------------------------------------------------------------------
// Henyey-Greenstein

// 1 + g^2 - 2 g cos written as a sum of non-negative terms: (1 - g)^2 + 2 g (1 - cos) for g >= 0
// and (1 + g)^2 + 2 |g| (1 + cos) for g < 0, so the peak (forward or backward) loses nothing.
double HenyeyGreenstein::eval(double cosTheta) const {
    const double c = std::clamp(cosTheta, -1.0, 1.0);
    const double q = g >= 0 ? sqr(1.0 - g) + 2.0 * g * (1.0 - c) : sqr(1.0 + g) - 2.0 * g * (1.0 + c);
    return (1.0 - g * g) * kInv4Pi / (q * std::sqrt(q));
}

double HenyeyGreenstein::evalOneMinusCos(double t) const {
    t = std::clamp(t, 0.0, 2.0);
    const double q = g >= 0 ? sqr(1.0 - g) + 2.0 * g * t : sqr(1.0 + g) - 2.0 * g * (2.0 - t);
    return (1.0 - g * g) * kInv4Pi / (q * std::sqrt(q));
}

// The textbook inverse, cos = [1 + g^2 - ((1 - g^2)/(1 - g + 2 g u))^2] / (2 g), divides a
// difference of O(1) terms by g. Expanding it with d = 1 + g (2u - 1) gives exactly
//   1 - cos = 2 (1 - g)^2 (1 - u) (1 + g u) / d^2,
//   1 + cos = 2 (1 + g)^2 u (1 - g (1 - u)) / d^2,
// products of factors that we write as sums of non-negative terms (d = (1 - g) + 2 g u for
// g >= 0, (1 + g) + 2 |g| (1 - u) for g < 0, and likewise 1 + g u and 1 - g (1 - u)). The smaller
// of the two is then accurate to a few ulps for every g in (-1, 1), including g = 0
// (cos = 2u - 1) and both peaks as |g| -> 1.
namespace {
struct HgFactors {
    double d, onePlusGu, oneMinusGv;
};
HgFactors hgFactors(double g, double u) {
    const double v = 1.0 - u;
    if (g >= 0) return {(1.0 - g) + 2.0 * g * u, 1.0 + g * u, (1.0 - g) + g * u};
    return {(1.0 + g) - 2.0 * g * v, (1.0 + g) - g * v, 1.0 - g * v};
}
}  // namespace

double HenyeyGreenstein::sampleOneMinusCos(double u) const {
    u = clamp01(u);
    const HgFactors f = hgFactors(g, u);
    return std::min(2.0, 2.0 * sqr(1.0 - g) * (1.0 - u) * f.onePlusGu / (f.d * f.d));
}

double HenyeyGreenstein::sampleCos(double u) const {
    u = clamp01(u);
    const HgFactors f = hgFactors(g, u);
    const double d2 = f.d * f.d;
    const double oneMinus = 2.0 * sqr(1.0 - g) * (1.0 - u) * f.onePlusGu / d2;
    if (oneMinus <= 1.0) return 1.0 - oneMinus;
    const double onePlus = 2.0 * sqr(1.0 + g) * u * f.oneMinusGv / d2;
    return std::clamp(onePlus - 1.0, -1.0, 1.0);
}

// F(c) = (1 - g^2)/(2 g) [1/sqrt(q) - 1/(1 + g)], q = 1 + g^2 - 2 g c, rationalised:
// F(c) = (1 - g)(1 + c) / (sqrt(q) (1 + g + sqrt(q))).
double HenyeyGreenstein::invertCos(double c) const {
    c = std::clamp(c, -1.0, 1.0);
    const double q = g >= 0 ? sqr(1.0 - g) + 2.0 * g * (1.0 - c) : sqr(1.0 + g) - 2.0 * g * (1.0 + c);
    const double sq = std::sqrt(q);
    return (1.0 - g) * (1.0 + c) / (sq * (1.0 + g + sq));
}

double HenyeyGreenstein::backscatterFraction() const { return invertCos(0.0); }

// 1 - F(c0) = (1 + g)(1 - c0) / (sqrt(q) (1 - g + sqrt(q))): the rationalised form of
// ((1 + g)/(2 g)) [1 - (1 - g)/sqrt(q)] (spec/seed-ch06-07-appA.md section 2.4).
double HenyeyGreenstein::forwardConeFraction(double c0) const { return forwardFraction(1.0 - std::clamp(c0, -1.0, 1.0)); }

double HenyeyGreenstein::forwardFraction(double t) const {
    t = std::clamp(t, 0.0, 2.0);
    const double q = g >= 0 ? sqr(1.0 - g) + 2.0 * g * t : sqr(1.0 + g) - 2.0 * g * (2.0 - t);
    const double sq = std::sqrt(q);
    return (1.0 + g) * t / (sq * (1.0 - g + sq));
}

namespace {
// |g| up to 0.999: the sampler is free of cancellation there (phase_functions.h).
PhaseKind henyeyGreensteinKind() {
    return {{"phase function", "henyey-greenstein", "Henyey and Greenstein (1941), one forward (g > 0) or backward lobe",
             {{"g", "", ParamType::Real, std::nullopt, -0.999, 0.999, "", "asymmetry parameter (mean cosine)"}}},
            [](const ParamValues& v) { return PhaseFunction::henyeyGreenstein(v.number("g")); }};
}
}  // namespace

// ---------------------------------------------------------------------------------------------
// Rayleigh-like

double RayleighLikePhase::eval(double c) const { return (1.0 + k * c * c) * kInv4Pi / (1.0 + k / 3.0); }
double RayleighLikePhase::evalOneMinusCos(double t) const { return eval(1.0 - t); }

// F(c) = [3 (1 + c) + k (1 + c^3)] / (2 (3 + k)). F(c) = u is the depressed cubic
// c^3 + (3/k) c + (3 + k)(1 - 2u)/k = 0 with one real root (p = 3/k > 0), which the hyperbolic
// form of Cardano's formula gives without cancellation:
//   c = -(2/sqrt(k)) sinh( asinh( (3 + k)(1 - 2u) sqrt(k) / 2 ) / 3 ).
// k = 1: c = 2 sinh(asinh(4u - 2)/3).
double RayleighLikePhase::sampleCos(double u) const {
    u = clamp01(u);
    if (k <= 0.0) return 2.0 * u - 1.0;
    const double sk = std::sqrt(k);
    const double c = -(2.0 / sk) * std::sinh(std::asinh(0.5 * (3.0 + k) * (1.0 - 2.0 * u) * sk) / 3.0);
    return std::clamp(c, -1.0, 1.0);
}
double RayleighLikePhase::sampleOneMinusCos(double u) const { return 1.0 - sampleCos(u); }
double RayleighLikePhase::invertCos(double c) const {
    c = std::clamp(c, -1.0, 1.0);
    return (3.0 * (1.0 + c) + k * (1.0 + c * c * c)) / (2.0 * (3.0 + k));
}
double RayleighLikePhase::forwardConeFraction(double c0) const {
    c0 = std::clamp(c0, -1.0, 1.0);
    return (3.0 * (1.0 - c0) + k * (1.0 - c0 * c0 * c0)) / (2.0 * (3.0 + k));
}
// 1 - c^3 = t (1 + c + c^2) with c = 1 - t: exact for small t.
double RayleighLikePhase::forwardFraction(double t) const {
    t = std::clamp(t, 0.0, 2.0);
    const double c = 1.0 - t;
    return t * (3.0 + k * (1.0 + c + c * c)) / (2.0 * (3.0 + k));
}

namespace {
// k = (1 - rho) / (1 + rho) for depolarisation ratio rho in [0, 1]: k in [0, 1].
constexpr double kRayleighKMin = 0.0, kRayleighKMax = 1.0;
PhaseKind rayleighKind() {
    return {{"phase function", "rayleigh",
             "Rayleigh-like, p proportional to 1 + k cos^2 (k = 1: Mobley et al. 1993 problem 1; 0.835: molecular water)",
             {{"k", "", ParamType::Real, 1.0, kRayleighKMin, kRayleighKMax, "",
               "the cos^2 coefficient (Morel 1974: 0.835 for pure water)"}}},
            [](const ParamValues& v) {
                const double k = v.number("k");
                return k == 1.0 ? PhaseFunction::rayleighLike() : PhaseFunction::molecularWater(k);
            }};
}
}  // namespace

// ---------------------------------------------------------------------------------------------
// Fournier-Forand

namespace {

// The two brackets of Mobley et al. (2002) eq. (5), as functions of x = ln d, divided by x^2:
//   n1 = [nu (1 - d) - (1 - d^nu)] / x^2,  n2 = [d (1 - d^nu) - nu (1 - d)] / x^2,
// and (1 - d)^2 / x^2. Both brackets vanish to second order at d = 1 (x = 0), so near there
// they come from their Taylor series, Sum_{k>=2} c_k x^(k-2)/k! with
//   c_k = nu^k - nu   and   c_k = (1 + nu) - (1 + nu)^k.
struct FFBrackets {
    double n1, n2, oneMinusD2;
};
FFBrackets ffBrackets(double x, double nu) {
    if (std::abs(x) < 0.5) {
        double term = 0.5;  // x^(k-2)/k! at k = 2
        double nuk = nu * nu, mk = sqr(1.0 + nu);
        double s1 = 0, s2 = 0;
        double e = 1.0, eterm = 1.0;  // expm1(x)/x = Sum_{k>=1} x^(k-1)/k!
        for (int k = 2; k < 26; ++k) {
            s1 += (nuk - nu) * term;
            s2 += ((1.0 + nu) - mk) * term;
            eterm *= x / k;
            e += eterm;
            term *= x / (k + 1);
            nuk *= nu;
            mk *= 1.0 + nu;
        }
        return {s1, s2, e * e};
    }
    const double e1 = std::expm1(x), env = std::expm1(nu * x);
    const double x2 = x * x;
    return {(env - nu * e1) / x2, (-std::exp(x) * env + nu * e1) / x2, e1 * e1 / x2};
}

}  // namespace

double FournierForand::backscatterFractionOf(double mu, double n) {
    const double nu = 0.5 * (3.0 - mu);
    const double d90 = 2.0 / (3.0 * sqr(n - 1.0));  // 4 sin^2(45 deg) / (3 (n - 1)^2)
    const double d90nu = std::pow(d90, nu);
    return 1.0 - (1.0 - d90nu * d90 - 0.5 * (1.0 - d90nu)) / ((1.0 - d90) * d90nu);
}

FournierForand::FournierForand(double mu, double n) : n_(n), mu_(mu) {
    nu_ = 0.5 * (3.0 - mu);
    delta180_ = 4.0 / (3.0 * sqr(n - 1.0));
    logHalfDelta180_ = std::log(0.5 * delta180_);
    const double d180nu = std::pow(delta180_, nu_);
    kappa_ = (1.0 - d180nu) / ((delta180_ - 1.0) * d180nu);
    backscatter_ = backscatterFractionOf(mu, n);
    // Mean cosine = Int_{-1}^{1} c dF = 1 - Int_0^2 G(t) dt = Int_0^2 Q(t) dt - 1 with Q the
    // forward fraction. With t = 2 e^y the integrand Q(2e^y) 2e^y is smooth and decays like
    // e^{(1 - nu) y}; 60 unit panels of 20-point Gauss-Legendre reach rounding.
    double s = 0;
    for (int i = 0; i < 60; ++i)
        s += gauss20().integrate([&](double y) { return forwardFraction(2.0 * std::exp(y)) * 2.0 * std::exp(y); },
                                 -60.0 + i, -59.0 + i);
    meanCosine_ = s - 1.0;
    // Starting points for sampling (see initialGuess).
    auto table = std::make_shared<std::array<double, 2 * kGuessNodes>>();
    for (int branch = 0; branch < 2; ++branch)
        for (int i = 0; i < kGuessNodes; ++i) {
            const bool forward = branch == 0;
            const double top = forward ? std::log1p(-backscatter_) : std::log(backscatter_);
            const double logTarget = kGuessLogLo + (top - kGuessLogLo) * i / (kGuessNodes - 1);
            const double t = solveOneMinusCos(forward, logTarget, initialGuess(forward, logTarget));
            (*table)[static_cast<size_t>(branch * kGuessNodes + i)] =
                forward ? logHalfDelta180_ + std::log(t) : std::log(2.0 - t);
        }
    guess_ = std::move(table);
}

FournierForand FournierForand::fromSlope(double mu, double n) {
    if (!(n >= 1.01 && n <= 1.30))
        throw InputError(fmt::format("Fournier-Forand particle index n = {} is outside the supported range [1.01, 1.30]", n));
    if (!(mu >= 3.11 && mu <= 5.0))
        throw InputError(fmt::format(
            "Fournier-Forand slope mu = {} is outside the supported range [3.11, 5]; below 3.11 the function is so "
            "forward-peaked that its cumulative distribution cannot be resolved in double precision",
            mu));
    return FournierForand(mu, n);
}

FournierForand FournierForand::fromBackscatterFraction(double b, double n) {
    if (!(n >= 1.01 && n <= 1.30))
        throw InputError(fmt::format("Fournier-Forand particle index n = {} is outside the supported range [1.01, 1.30]", n));
    const double bMin = backscatterFractionOf(3.11, n);
    if (!(b >= bMin && b <= 0.5))
        throw InputError(fmt::format(
            "Fournier-Forand backscatter fraction {} is outside the supported range [{:.6f}, 0.5] for n = {}", b, bMin, n));
    // B(mu) increases monotonically on (3, 5] (B -> 0 as mu -> 3, B(5) = 1/2 for every n).
    double lo = 3.11, hi = 5.0;
    for (int i = 0; i < 200 && hi - lo > 1e-15; ++i) {
        const double mid = 0.5 * (lo + hi);
        (backscatterFractionOf(mid, n) < b ? lo : hi) = mid;
    }
    return FournierForand(0.5 * (lo + hi), n);
}

double FournierForand::eval(double c) const { return evalOneMinusCos(1.0 - c); }

double FournierForand::evalOneMinusCos(double t) const {
    if (!(t > 0.0)) return kInfinity;
    t = std::min(t, 2.0);
    const double s = 0.5 * t;  // sin^2(psi/2)
    const double x = logHalfDelta180_ + std::log(t);  // ln d
    const FFBrackets br = ffBrackets(x, nu_);
    const double p1 = (br.n1 + br.n2 / s) * kInv4Pi / (br.oneMinusD2 * std::exp(nu_ * x));
    const double c = 1.0 - t;
    return p1 + kappa_ * kInv4Pi * 0.25 * (3.0 * c * c - 1.0);
}

// Fournier and Jonasz (1999): the fraction scattered within psi is
//   Q = [1 - d^(nu+1) - (1 - d^nu) s] / ((1 - d) d^nu) + (kappa/8) cos(psi) sin^2(psi),
// s = sin^2(psi/2). Rearranged, the fraction beyond psi is
//   G = 1 - Q = (1 - s) (1 - d^-nu)/(1 - d) - (kappa/8) cos(psi) sin^2(psi),
// whose ratio is expm1(-nu x)/expm1(x) (limit -nu at x = 0). Q is taken from its own form where
// it is small (d < 1/e) and G from its own elsewhere, so each keeps full relative precision.
double FournierForand::forwardFraction(double t) const {
    if (!(t > 0.0)) return 0.0;
    if (t >= 2.0) return 1.0;
    const double x = logHalfDelta180_ + std::log(t);
    const double s = 0.5 * t, c = 1.0 - t;
    const double tail = 0.125 * kappa_ * c * t * (2.0 - t);  // (kappa/8) cos sin^2
    if (x < -1.0) {
        const double d = std::exp(x);
        return ((s - d) + std::exp(-nu_ * x) * (1.0 - s)) / (1.0 - d) + tail;
    }
    const double e = x == 0.0 ? -nu_ : std::expm1(-nu_ * x) / std::expm1(x);
    return 1.0 - ((1.0 - s) * e - tail);
}

double FournierForand::backwardFraction(double t) const { return backwardFraction(t, 2.0 - t); }

// The same with 2 - t given separately (exact when it comes from the sampler's w = ln(2 - t)),
// so that G ~ (2 - t) keeps its relative precision next to straight back.
double FournierForand::backwardFraction(double t, double twoMinusT) const {
    if (!(t > 0.0)) return 1.0;
    if (!(twoMinusT > 0.0)) return 0.0;
    const double x = logHalfDelta180_ + std::log(t);
    if (x < -1.0) return 1.0 - forwardFraction(t);
    const double oneMinusS = 0.5 * twoMinusT, c = twoMinusT - 1.0;
    const double tail = 0.125 * kappa_ * c * t * twoMinusT;
    const double e = x == 0.0 ? -nu_ : std::expm1(-nu_ * x) / std::expm1(x);
    return oneMinusS * e - tail;
}

double FournierForand::forwardConeFraction(double c0) const { return forwardFraction(1.0 - std::clamp(c0, -1.0, 1.0)); }
double FournierForand::invertCos(double c) const { return backwardFraction(1.0 - std::clamp(c, -1.0, 1.0)); }

// Solves G(t) = u, i.e. P(cos <= c) = u, by Newton iteration on the log of the smaller tail:
//  * forward targets (u > B, so cos > 0): ln Q = ln(1 - u) in x = ln d = ln(d180 t / 2); Q
//    behaves like e^{-nu x} as x -> -inf, so ln Q is nearly linear in x; dQ/dx = 2 pi p(t) t;
//  * backward targets (u <= B, cos <= 0): ln G = ln u in w = ln(2 - t); G behaves like (2 - t)
//    near straight back, so ln G is nearly linear in w; dG/dw = 2 pi p(t) (2 - t).
// The forward search stops at t = 1e-300, below which Q < 2^-53 for mu >= 3.11. Starting points
// come from a 129-node table of the solution against the log-target (built at construction);
// from there two or three safeguarded Newton steps reach the 1e-14 stopping tolerance.
double FournierForand::initialGuess(bool forward, double logTarget) const {
    const double xHi = std::log(delta180_), xLo = logHalfDelta180_ + std::log(1e-300);
    const double wLo = std::log(1e-300), wHi = std::log(2.0);
    const double lo = forward ? xLo : wLo, hi = forward ? xHi : wHi;
    double v;
    if (guess_) {
        const double top = forward ? std::log1p(-backscatter_) : std::log(backscatter_);
        const double pos = std::clamp((logTarget - kGuessLogLo) / (top - kGuessLogLo) * (kGuessNodes - 1), 0.0,
                                      kGuessNodes - 1.0);
        const int i = std::min(static_cast<int>(pos), kGuessNodes - 2);
        const double* g = guess_->data() + (forward ? 0 : kGuessNodes);
        v = g[i] + (pos - i) * (g[i + 1] - g[i]);
    } else if (forward) {
        v = logTarget / -nu_;  // Q ~ d^-nu far forward
    } else {
        // Near straight back G ~ (1 - s)(E(x_max) + kappa/2) = (2 - t)(E(x_max) + kappa/2)/2.
        const double slopeBack = 0.5 * (std::expm1(-nu_ * xHi) / std::expm1(xHi) + 0.5 * kappa_);
        v = std::min(logTarget - std::log(slopeBack), wHi - 1e-3);
    }
    return std::clamp(v, lo + 1e-9, hi - 1e-12);
}

double FournierForand::solveOneMinusCos(bool forward, double logTarget, double v0) const {
    if (forward) {
        const double xHi = std::log(delta180_), xLo = logHalfDelta180_ + std::log(1e-300);
        auto tOf = [&](double x) { return std::min(2.0, std::exp(x - logHalfDelta180_)); };
        if (std::log(forwardFraction(tOf(xLo))) >= logTarget) return tOf(xLo);
        auto f = [&](double x, double* fx, double* dfx) {
            const double t = tOf(x), q = forwardFraction(t);
            *fx = std::log(q) - logTarget;
            *dfx = 2.0 * kPi * evalOneMinusCos(t) * t / q;
        };
        return tOf(safeguardedNewton(f, xLo, xHi, v0));
    }
    const double wLo = std::log(1e-300), wHi = std::log(2.0);
    auto tOf = [](double w) { return std::clamp(2.0 - std::exp(w), 0.0, 2.0); };
    auto f = [&](double w, double* fx, double* dfx) {
        const double t = tOf(w), g = backwardFraction(t, std::exp(w));
        *fx = std::log(g) - logTarget;
        *dfx = 2.0 * kPi * evalOneMinusCos(t) * std::exp(w) / g;
    };
    return tOf(safeguardedNewton(f, wLo, wHi, v0));
}

double FournierForand::sampleOneMinusCos(double u) const {
    u = clamp01(u);
    if (u <= 0.0) return 2.0;
    const bool forward = u > backscatter_;
    const double logTarget = forward ? std::log1p(-u) : std::log(u);
    return solveOneMinusCos(forward, logTarget, initialGuess(forward, logTarget));
}

double FournierForand::sampleCos(double u) const {
    const double t = sampleOneMinusCos(u);
    return std::clamp(1.0 - t, -1.0, 1.0);
}

namespace {
// From B = 0.002 (slope mu = 3.11 at n = 1.10, the most forward-peaked function whose cumulative
// distribution resolves in double precision; fromBackscatterFraction) to just below 1/2.
PhaseKind fournierForandKind() {
    return {{"phase function", "fournier-forand",
             "Fournier and Forand (1994) in the form of Mobley et al. (2002), particle index n = 1.10",
             {{"backscatter_fraction", "", ParamType::Real, std::nullopt, 0.002, 0.4999, "",
               "B = b_b / b, the fraction scattered backward"}}},
            [](const ParamValues& v) { return PhaseFunction::fournierForand(v.number("backscatter_fraction")); }};
}
}  // namespace

// ---------------------------------------------------------------------------------------------
// Tabulated

namespace {
double oneMinusCosDeg(double psiDeg) { return 2.0 * sqr(std::sin(0.5 * deg2rad(psiDeg))); }
}  // namespace

TabulatedPhase::TabulatedPhase(std::vector<std::pair<double, double>> table, double m, Interpolation interp,
                               int subdivisions, std::string name)
    : interpolation_(interp), exponent_(m), halfExponent_(0.5 * m), name_(std::move(name)) {
    const std::string what = "phase function table '" + name_ + "'";
    if (table.size() < 2) throw InputError(what + ": needs at least two (angle, value) rows");
    for (size_t i = 0; i < table.size(); ++i) {
        const auto [psi, v] = table[i];
        if (!std::isfinite(psi) || !std::isfinite(v) || v <= 0)
            throw InputError(fmt::format("{}: row {} ({}, {}) must have a finite angle and a positive value", what, i + 1, psi, v));
        if (i > 0 && !(psi > table[i - 1].first))
            throw InputError(fmt::format("{}: angles must increase strictly (row {}: {} after {})", what, i + 1, psi,
                                         table[i - 1].first));
    }
    if (table.front().first < 0) throw InputError(what + ": angles start below 0 deg");
    if (std::abs(table.back().first - 180.0) > 1e-9)
        throw InputError(fmt::format("{}: the last angle must be 180 deg, not {}", what, table.back().first));
    table.back().first = 180.0;
    if (!(m >= 0.0 && m < 2.0)) throw InputError(fmt::format("{}: forward exponent {} must lie in [0, 2)", what, m));
    const size_t intervals = table.size() - 1;
    if (subdivisions < 1 || intervals * static_cast<size_t>(subdivisions) + 1 > 4096)
        throw InputError(fmt::format("{}: {} intervals x {} subdivisions exceed 4096 nodes", what, intervals, subdivisions));
    for (const auto& [psi, v] : table) {
        psiDeg_.push_back(psi);
        value_.push_back(v);
    }

    // Fine nodes: `subdivisions` equal steps in psi per input interval.
    for (size_t i = 0; i < intervals; ++i)
        for (int j = 0; j < subdivisions; ++j) {
            const double psi = psiDeg_[i] + (psiDeg_[i + 1] - psiDeg_[i]) * j / subdivisions;
            t_.push_back(j == 0 ? oneMinusCosDeg(psiDeg_[i]) : oneMinusCosDeg(psi));
            p_.push_back(j == 0 ? value_[i] : tableValue(psi));
        }
    t_.push_back(2.0);
    p_.push_back(value_.back());

    // Mass below t_0 under p_0 (t/t_0)^(-m/2): 2 pi p_0 t_0 / (1 - m/2); each segment: pi h (p_j + p_j+1).
    const bool tableStartsAtZero = psiDeg_.front() == 0.0;
    powerLawMass_ = tableStartsAtZero ? 0.0 : 2.0 * kPi * p_[0] * t_[0] / (1.0 - halfExponent_);
    double total = powerLawMass_;
    for (size_t j = 0; j + 1 < t_.size(); ++j) total += kPi * (t_[j + 1] - t_[j]) * (p_[j] + p_[j + 1]);
    for (double& p : p_) p /= total;
    powerLawMass_ /= total;
    cdf_.resize(t_.size());
    cdf_[0] = powerLawMass_;
    for (size_t j = 0; j + 1 < t_.size(); ++j) cdf_[j + 1] = cdf_[j] + kPi * (t_[j + 1] - t_[j]) * (p_[j] + p_[j + 1]);

    buildLookups();

    // Mean cosine = 1 - E[t]; per segment Int t 2 pi p dt in closed form, below t_0
    // Int_0^t0 t 2 pi p_0 (t/t_0)^(-a) dt = 2 pi p_0 t_0^2 / (2 - a).
    double meanT = tableStartsAtZero ? 0.0 : 2.0 * kPi * p_[0] * t_[0] * t_[0] / (2.0 - halfExponent_);
    for (size_t j = 0; j + 1 < t_.size(); ++j) {
        const double h = t_[j + 1] - t_[j], dp = p_[j + 1] - p_[j];
        meanT += 2.0 * kPi * h * (p_[j] * (t_[j] + 0.5 * h) + dp * (0.5 * t_[j] + h / 3.0));
    }
    meanCosine_ = 1.0 - meanT;

    // The input table's own normalisation, 2 pi Int beta sin(psi) dpsi (psi in radians):
    // below psi_0 the power law integrates term by term, sin psi = Sum (-1)^k psi^(2k+1)/(2k+1)!;
    // each interval by 20-point Gauss-Legendre (exact for the linear interpolant, ~1e-15 for
    // the log-log one, whose intervals span a ratio of at most a few in psi).
    double norm = 0;
    if (!tableStartsAtZero) {
        const double psi0 = deg2rad(psiDeg_[0]);
        double series = 0, fact = 1, sign = 1;
        for (int k = 0; k < 12; ++k) {
            if (k > 0) fact *= (2.0 * k) * (2.0 * k + 1.0);
            series += sign * std::pow(psi0, 2.0 * k + 2.0 - m) / (fact * (2.0 * k + 2.0 - m));
            sign = -sign;
        }
        norm += 2.0 * kPi * value_[0] * std::pow(psi0, m) * series;
    }
    for (size_t i = 0; i < intervals; ++i)
        norm += gauss20().integrate(
            [&](double psi) { return 2.0 * kPi * tableValue(rad2deg(psi)) * std::sin(psi); }, deg2rad(psiDeg_[i]),
            deg2rad(psiDeg_[i + 1]));
    tableNormalization_ = norm;
}

double TabulatedPhase::tableValue(double psiDeg) const {
    if (psiDeg <= psiDeg_.front()) {
        if (psiDeg == psiDeg_.front() || psiDeg_.front() == 0.0) return value_.front();
        return value_.front() * std::pow(psiDeg_.front() / psiDeg, exponent_);
    }
    if (psiDeg >= 180.0) return value_.back();
    const size_t i = static_cast<size_t>(std::upper_bound(psiDeg_.begin(), psiDeg_.end(), psiDeg) - psiDeg_.begin()) - 1;
    const double a = psiDeg_[i], b = psiDeg_[i + 1];
    if (interpolation_ == Interpolation::LinearInPsi) return value_[i] + (value_[i + 1] - value_[i]) * (psiDeg - a) / (b - a);
    return std::exp(std::log(value_[i]) +
                    (std::log(value_[i + 1]) - std::log(value_[i])) * std::log(psiDeg / a) / std::log(b / a));
}

double TabulatedPhase::eval(double c) const { return evalOneMinusCos(1.0 - c); }

void TabulatedPhase::buildLookups() {
    // For each bin's lower edge, the segment holding it.
    tLookup_.resize(kLookupBins + 1);
    cdfLookup_.resize(kLookupBins + 1);
    auto seg = [](const std::vector<double>& v, double x) {
        const size_t j = static_cast<size_t>(std::upper_bound(v.begin(), v.end(), x) - v.begin());
        return static_cast<uint32_t>(std::min(j > 0 ? j - 1 : 0, v.size() - 2));
    };
    for (int k = 0; k <= kLookupBins; ++k) {
        const double u = static_cast<double>(k) / kLookupBins;
        tLookup_[static_cast<size_t>(k)] = seg(t_, 2.0 * u * u);  // t = 2 sin^2(psi / 2)
        cdfLookup_[static_cast<size_t>(k)] = seg(cdf_, u);
    }
}

namespace {
// The segment j of sorted nodes v (v[j] <= x < v[j + 1], clamped to [0, v.size() - 2]): from the
// segment holding bin k's lower edge, a walk forward over the few nodes in the bin (and back by
// one where rounding in k put x just below the bin).
size_t segmentNear(const std::vector<double>& v, const std::vector<uint32_t>& lookup, int bins, double x, double u) {
    const int k = std::clamp(static_cast<int>(u * bins), 0, bins - 1);
    size_t j = lookup[static_cast<size_t>(k)];
    const size_t last = v.size() - 2;
    while (j > 0 && v[j] > x) --j;
    while (j < last && v[j + 1] <= x) ++j;
    return j;
}
}  // namespace

size_t TabulatedPhase::segmentOfT(double t) const {
    return segmentNear(t_, tLookup_, kLookupBins, t, std::sqrt(0.5 * t));
}

size_t TabulatedPhase::segmentOfCdf(double q) const { return segmentNear(cdf_, cdfLookup_, kLookupBins, q, q); }

double TabulatedPhase::evalOneMinusCos(double t) const {
    if (t < t_.front()) {
        if (halfExponent_ == 0.0) return p_.front();
        if (!(t > 0.0)) return kInfinity;
        return p_.front() * std::pow(t / t_.front(), -halfExponent_);
    }
    if (t >= 2.0) return p_.back();
    const size_t j = segmentOfT(t);
    return p_[j] + (p_[j + 1] - p_[j]) * (t - t_[j]) / (t_[j + 1] - t_[j]);
}

double TabulatedPhase::forwardFraction(double t) const {
    if (!(t > 0.0)) return 0.0;
    if (t < t_.front()) return powerLawMass_ * std::pow(t / t_.front(), 1.0 - halfExponent_);
    if (t >= 2.0) return 1.0;
    const size_t j = segmentOfT(t);
    const double s = t - t_[j];
    return cdf_[j] + kPi * s * (2.0 * p_[j] + (p_[j + 1] - p_[j]) * s / (t_[j + 1] - t_[j]));
}

// Inverse of the forward fraction Q(t) = 1 - u: the power law inverts as a power; on a segment
// 2 pi [p_j s + (p_j+1 - p_j) s^2 / (2h)] = r is a quadratic whose root is taken in the form
// s = 2r / (b + sqrt(b^2 + 4ar)), free of cancellation whatever the sign of the slope.
double TabulatedPhase::sampleOneMinusCos(double u) const {
    const double q = 1.0 - clamp01(u);
    if (q <= powerLawMass_) {
        if (powerLawMass_ <= 0.0) return t_.front();
        return t_.front() * std::pow(q / powerLawMass_, 1.0 / (1.0 - halfExponent_));
    }
    const size_t j = segmentOfCdf(q);
    const double h = t_[j + 1] - t_[j];
    const double r = std::max(0.0, q - cdf_[j]);
    const double a = kPi * (p_[j + 1] - p_[j]) / h, b = 2.0 * kPi * p_[j];
    const double s = 2.0 * r / (b + std::sqrt(std::max(0.0, b * b + 4.0 * a * r)));
    return t_[j] + std::clamp(s, 0.0, h);
}

double TabulatedPhase::sampleCos(double u) const { return std::clamp(1.0 - sampleOneMinusCos(u), -1.0, 1.0); }
double TabulatedPhase::invertCos(double c) const { return 1.0 - forwardFraction(1.0 - std::clamp(c, -1.0, 1.0)); }
double TabulatedPhase::backscatterFraction() const { return 1.0 - forwardFraction(1.0); }
double TabulatedPhase::forwardConeFraction(double c0) const { return forwardFraction(1.0 - std::clamp(c0, -1.0, 1.0)); }

// Mobley et al. (1993) Table 2, from psi = 0.12589 deg (the 0.1 deg row, 1.76661e3, lies in the
// power-law range and is implied by it: 1.29564e3 x 1.2589^1.346 = 1.76633e3, 1.6e-4 below the
// printed value, i.e. the printed row implies an exponent of 1.3467).
std::shared_ptr<const TabulatedPhase> petzoldAverageParticleTable() {
    static const std::shared_ptr<const TabulatedPhase> table = std::make_shared<const TabulatedPhase>(
        std::vector<std::pair<double, double>>{
            {0.12589, 1.29564e3}, {0.15849, 9.50172e2}, {0.19953, 6.99092e2}, {0.25119, 5.13687e2},
            {0.31623, 3.76373e2}, {0.39811, 2.76318e2}, {0.50119, 2.18839e2}, {0.63096, 1.44369e2},
            {0.79433, 1.02241e2}, {1.0000, 7.16082e1},  {1.2589, 4.95803e1},  {1.5849, 3.39511e1},
            {1.9953, 2.28129e1},  {2.5119, 1.51622e1},  {3.1623, 1.00154e1},  {3.9811, 6.57957},
            {5.0119, 4.29530},    {6.3096, 2.80690},    {7.9433, 1.81927},    {10, 1.15257},
            {15, 4.89344e-1},     {20, 2.44424e-1},     {25, 1.47151e-1},     {30, 8.60848e-2},
            {35, 5.93075e-2},     {40, 4.20985e-2},     {45, 3.06722e-2},     {50, 2.27533e-2},
            {55, 1.69904e-2},     {60, 1.31254e-2},     {65, 1.04625e-2},     {70, 8.48826e-3},
            {75, 6.97601e-3},     {80, 5.84232e-3},     {85, 4.95306e-3},     {90, 4.29232e-3},
            {95, 3.78161e-3},     {100, 3.40405e-3},    {105, 3.11591e-3},    {110, 2.91222e-3},
            {115, 2.79696e-3},    {120, 2.68568e-3},    {125, 2.57142e-3},    {130, 2.47603e-3},
            {135, 2.37667e-3},    {140, 2.32898e-3},    {145, 2.31308e-3},    {150, 2.36475e-3},
            {155, 2.50584e-3},    {160, 2.66183e-3},    {165, 2.83472e-3},    {170, 3.03046e-3},
            {175, 3.09206e-3},    {180, 3.15366e-3}},
        1.346, TabulatedPhase::Interpolation::LogLog, 32, "Petzold average particle (Mobley et al. 1993, Table 2)");
    return table;
}

TabulatedPhase petzoldAverageParticle() { return *petzoldAverageParticleTable(); }

namespace {
PhaseKind petzoldKind() {
    return {{"phase function", "petzold", "Petzold's average particle (San Diego Harbor), Mobley et al. (1993) Table 2",
             {}},
            [](const ParamValues&) { return PhaseFunction::petzold(); }};
}
}  // namespace

// ---------------------------------------------------------------------------------------------
// PhaseFunction

namespace {

template <class F> double visitPart(const PhaseFunction::Component& c, F&& f) {
    return std::visit(
        [&](const auto& p) -> double {
            using T = std::decay_t<decltype(p)>;
            if constexpr (std::is_same_v<T, std::shared_ptr<const TabulatedPhase>>) return f(*p);
            else return f(p);
        },
        c);
}

std::string describePart(const PhaseFunction::Component& c) {
    return std::visit(
        [](const auto& p) -> std::string {
            using T = std::decay_t<decltype(p)>;
            if constexpr (std::is_same_v<T, IsotropicPhase>) return "isotropic";
            else if constexpr (std::is_same_v<T, HenyeyGreenstein>) return fmt::format("Henyey-Greenstein g={}", p.g);
            else if constexpr (std::is_same_v<T, RayleighLikePhase>) return fmt::format("Rayleigh-like (1 + {} cos^2)", p.k);
            else if constexpr (std::is_same_v<T, FournierForand>)
                return fmt::format("Fournier-Forand B={:.6g} (n={}, mu={:.6f})", p.backscatterFraction(), p.particleIndex(),
                                   p.slope());
            else return p->name();
        },
        c);
}

}  // namespace

PhaseFunction::PhaseFunction() : PhaseFunction(Component{IsotropicPhase{}}) {}

PhaseFunction::PhaseFunction(Component c) {
    parts_[0] = std::move(c);
    weight_[0] = 1.0;
    cumulative_[0] = 1.0;
    count_ = 1;
}

PhaseFunction PhaseFunction::isotropic() { return PhaseFunction(); }

PhaseFunction PhaseFunction::henyeyGreenstein(double g) {
    if (!(g > -1.0 && g < 1.0))
        throw InputError(fmt::format("Henyey-Greenstein g = {} is outside the allowed range (-1, 1)", g));
    return PhaseFunction(Component{HenyeyGreenstein{g}});
}

PhaseFunction PhaseFunction::rayleighLike() { return PhaseFunction(Component{RayleighLikePhase{1.0}}); }

PhaseFunction PhaseFunction::molecularWater(double k) {
    if (!(k >= kRayleighKMin && k <= kRayleighKMax))
        throw InputError(fmt::format("molecular phase function coefficient k = {} is outside the allowed range [{}, {}]", k,
                                     kRayleighKMin, kRayleighKMax));
    return PhaseFunction(Component{RayleighLikePhase{k}});
}

PhaseFunction PhaseFunction::fournierForand(double b, double n) {
    return PhaseFunction(Component{FournierForand::fromBackscatterFraction(b, n)});
}

PhaseFunction PhaseFunction::petzold() { return PhaseFunction(Component{petzoldAverageParticleTable()}); }

PhaseFunction PhaseFunction::tabulated(std::shared_ptr<const TabulatedPhase> table) {
    if (!table) throw InputError("tabulated phase function: no table given");
    return PhaseFunction(Component{std::move(table)});
}

PhaseFunction PhaseFunction::mixture(const std::vector<std::pair<double, PhaseFunction>>& parts) {
    PhaseFunction out;
    out.count_ = 0;
    double sum = 0;
    for (const auto& [b, pf] : parts) {
        if (!std::isfinite(b) || b < 0)
            throw InputError(fmt::format("phase-function mixture: scattering weight {} must be finite and >= 0", b));
        for (int i = 0; i < pf.count_; ++i) {
            const double w = b * pf.weight_[static_cast<size_t>(i)];
            if (w <= 0) continue;
            if (out.count_ == kMaxComponents)
                throw InputError(fmt::format("phase-function mixture: more than {} components with non-zero scattering",
                                             kMaxComponents));
            out.parts_[static_cast<size_t>(out.count_)] = pf.parts_[static_cast<size_t>(i)];
            out.weight_[static_cast<size_t>(out.count_)] = w;
            ++out.count_;
            sum += w;
        }
    }
    if (out.count_ == 0 || !(sum > 0))
        throw InputError("phase-function mixture: the scattering weights sum to zero, so no phase function is defined");
    double cum = 0;
    for (int i = 0; i < out.count_; ++i) {
        out.weight_[static_cast<size_t>(i)] /= sum;
        cum += out.weight_[static_cast<size_t>(i)];
        out.cumulative_[static_cast<size_t>(i)] = cum;
    }
    out.cumulative_[static_cast<size_t>(out.count_ - 1)] = 1.0;
    return out;
}

PhaseFunction PhaseFunction::component(int i) const { return PhaseFunction(parts_.at(static_cast<size_t>(i))); }

int PhaseFunction::pick(double u1) const {
    for (int i = 0; i + 1 < count_; ++i)
        if (u1 < cumulative_[static_cast<size_t>(i)]) return i;
    return count_ - 1;
}

double PhaseFunction::eval(double cosTheta) const { return evalOneMinusCos(1.0 - cosTheta); }

double PhaseFunction::evalOneMinusCos(double t) const {
    double s = 0;
    for (int i = 0; i < count_; ++i)
        s += weight_[static_cast<size_t>(i)] *
             visitPart(parts_[static_cast<size_t>(i)], [t](const auto& p) { return p.evalOneMinusCos(t); });
    return s;
}

double PhaseFunction::evalDirections(const Vec3& incident, const Vec3& scattered) const {
    return evalOneMinusCos(std::clamp(0.5 * lengthSquared(scattered - incident), 0.0, 2.0));
}

double PhaseFunction::sampleCos(double u1, double u2) const {
    return visitPart(parts_[static_cast<size_t>(pick(u1))], [u2](const auto& p) { return p.sampleCos(u2); });
}

double PhaseFunction::sampleOneMinusCos(double u1, double u2) const {
    return visitPart(parts_[static_cast<size_t>(pick(u1))], [u2](const auto& p) { return p.sampleOneMinusCos(u2); });
}

double PhaseFunction::invertCos(double c) const {
    double s = 0;
    for (int i = 0; i < count_; ++i)
        s += weight_[static_cast<size_t>(i)] *
             visitPart(parts_[static_cast<size_t>(i)], [c](const auto& p) { return p.invertCos(c); });
    return s;
}

Vec3 PhaseFunction::sample(const Vec3& dir, double u1, double u2, double u3, double* pdfOut) const {
    const double t = std::clamp(sampleOneMinusCos(u1, u2), 0.0, 2.0);
    const double sinTheta = std::sqrt(std::max(0.0, t * (2.0 - t)));
    const CosSin phi = cosSinTurns(u3);
    const Frame f = Frame::fromNormal(dir);
    if (pdfOut) *pdfOut = evalOneMinusCos(t);
    return f.toWorld({sinTheta * phi.c, sinTheta * phi.s, 1.0 - t});
}

double PhaseFunction::meanCosine() const {
    double s = 0;
    for (int i = 0; i < count_; ++i)
        s += weight_[static_cast<size_t>(i)] *
             visitPart(parts_[static_cast<size_t>(i)], [](const auto& p) { return p.meanCosine(); });
    return s;
}

double PhaseFunction::backscatterFraction() const {
    double s = 0;
    for (int i = 0; i < count_; ++i)
        s += weight_[static_cast<size_t>(i)] *
             visitPart(parts_[static_cast<size_t>(i)], [](const auto& p) { return p.backscatterFraction(); });
    return s;
}

double PhaseFunction::forwardConeFraction(double cosTheta0) const {
    double s = 0;
    for (int i = 0; i < count_; ++i)
        s += weight_[static_cast<size_t>(i)] *
             visitPart(parts_[static_cast<size_t>(i)], [cosTheta0](const auto& p) { return p.forwardConeFraction(cosTheta0); });
    return s;
}

std::string PhaseFunction::describe() const {
    if (count_ == 1) return describePart(parts_[0]);
    std::string s = "mixture of ";
    for (int i = 0; i < count_; ++i) {
        if (i > 0) s += " + ";
        s += fmt::format("{:.6g} x {}", weight_[static_cast<size_t>(i)], describePart(parts_[static_cast<size_t>(i)]));
    }
    return s;
}

// ---------------------------------------------------------------------------------------------
// The phase-function kinds: one registration line per kind.

const KindRegistry<PhaseKind>& phaseFunctionKinds() {
    static const KindRegistry<PhaseKind> registry = [] {
        KindRegistry<PhaseKind> r("phase function");
        r.add(isotropicKind());
        r.add(henyeyGreensteinKind());
        r.add(petzoldKind());
        r.add(fournierForandKind());
        r.add(rayleighKind());
        r.add(pureWaterKind());
        return r;
    }();
    return registry;
}

ParamValues resolvePhaseParams(std::string_view type, const ParamValues& params, const std::string& who) {
    return resolveParams(phaseFunctionKinds().get(type, who).info, params, who);
}

PhaseFunction makePhaseFunction(std::string_view type, const ParamValues& params, const std::string& who) {
    const PhaseKind& kind = phaseFunctionKinds().get(type, who);
    return kind.make(resolveParams(kind.info, params, who));
}

}  // namespace littoral
