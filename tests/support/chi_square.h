#pragma once
// Chi-square goodness-of-fit harness for direction samplers: every phase function now, every
// BxDF sampler later. A sampler passes when the directions it draws are distributed as the pdf
// it reports, judged by Pearson's chi-square test on binned counts whose expected values come
// from integrating that pdf numerically (never from the sampler).
//
// API, namespace littoral::testing_support::chi2 (header-only):
//
//  Special functions
//    regularizedGammaP(a, x), regularizedGammaQ(a, x)  P = gamma(a,x)/Gamma(a), Q = 1 - P; Q is
//        computed directly (continued fraction) where it is small, so tiny p-values are exact.
//    chiSquareSurvival(statistic, dof)   the p-value P(X^2_dof >= statistic) = Q(dof/2, stat/2).
//    sidakLevel(familyAlpha, tests)      per-test significance level 1 - (1 - alpha)^(1/m).
//        We use Sidak's correction (exact for independent tests; Bonferroni's alpha/m is its
//        first-order approximation and slightly more conservative): if each of m independent
//        tests of correct samplers rejects with probability sidakLevel(alpha, m), the whole
//        suite has a false-alarm probability of exactly alpha.
//
//  Quadrature (independent of any sampler)
//    integrate(f, a, b, relTol, singular)   adaptive: Gauss-Kronrod 7/15 on interior panels,
//        tanh-sinh on panels touching an end flagged in `singular` (integrable endpoint
//        singularities such as the theta^-0.35 of Petzold's forward power law times sin theta).
//    axialSphereIntegral(pdf(theta), thetaHi = pi)   2 pi Int_0^thetaHi pdf sin(theta) dtheta.
//    sphereIntegral(pdf(theta, phi), thetaHi = pi)   Int Int pdf sin(theta) dphi dtheta.
//        The normalisation check: 1 for a sampler that always returns a direction, less for one
//        that can fail (its pdf then integrates to the success probability).
//
//  Bins
//    uniformEdges(lo, hi, n); forwardPeakedThetaEdges(thetaMin, nLog, thetaSplit, nLinear):
//        {0, thetaMin .. thetaSplit geometric (nLog bins), .. pi linear (nLinear bins)}, so a
//        forward-peaked pdf (HG g = 0.97, Petzold) is resolved inside its peak.
//
//  Tests. A sampler is called as sampler(RandomStream&) with a stream unique to (seed, sample
//  index) and returns std::optional (std::nullopt = the sampler failed to produce a direction).
//    testTheta(thetaEdges, sampler -> optional<double theta>, pdf(theta), options)
//        1-D in the polar (e.g. scattering) angle, for pdfs that do not depend on phi.
//    testSphere(thetaEdges, phiBins, frame, sampler -> optional<Vec3>, pdf(theta, phi), options)
//        2-D in (theta, phi) about frame.n, phi measured from frame.s toward frame.t.
//    testCells(observed, expected, labels, options)   the pooled statistic on given cells.
//    Cells are the bins plus one "remainder" cell: failed samples and samples outside the
//    edges, expected N (1 - sum of bin probabilities). Cells whose expected count is below
//    options.minExpected (5) are pooled into one; if the pool stays below it, it joins the
//    smallest other cell. A sample in a cell of (numerically) zero expected count rejects at
//    once. dof = cells - 1.
//
//  ChiSquareResult: statistic, dof, pValue, cells, samples, failures, outside, expectedInBins,
//    worst (the cells that contribute most, for the failure message); rejectedAt(alpha);
//    summary().
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numeric>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "core/frame.h"
#include "core/rng.h"
#include "core/units.h"
#include "core/vec.h"

namespace littoral::testing_support::chi2 {

// ---------------------------------------------------------------------------------------------
// Special functions (Numerical Recipes, 3rd ed., section 6.2: series for x < a + 1, Lentz's
// continued fraction otherwise).

inline double gammaSeriesP(double a, double x) {
    double ap = a, del = 1.0 / a, sum = del;
    for (int n = 0; n < 100000; ++n) {
        ap += 1.0;
        del *= x / ap;
        sum += del;
        if (std::abs(del) < std::abs(sum) * 1e-17) break;
    }
    return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

inline double gammaContinuedFractionQ(double a, double x) {
    constexpr double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 100000; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1.0 / d;
        const double del = d * c;
        h *= del;
        if (std::abs(del - 1.0) < 1e-16) break;
    }
    return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

inline double regularizedGammaP(double a, double x) {
    if (!(a > 0) || x < 0) return std::numeric_limits<double>::quiet_NaN();
    if (x == 0) return 0.0;
    return x < a + 1.0 ? gammaSeriesP(a, x) : 1.0 - gammaContinuedFractionQ(a, x);
}

inline double regularizedGammaQ(double a, double x) {
    if (!(a > 0) || x < 0) return std::numeric_limits<double>::quiet_NaN();
    if (x == 0) return 1.0;
    return x < a + 1.0 ? 1.0 - gammaSeriesP(a, x) : gammaContinuedFractionQ(a, x);
}

inline double chiSquareSurvival(double statistic, int dof) {
    if (dof < 1 || !(statistic >= 0)) return std::numeric_limits<double>::quiet_NaN();
    if (std::isinf(statistic)) return 0.0;
    return regularizedGammaQ(0.5 * dof, 0.5 * statistic);
}

inline double sidakLevel(double familyAlpha, int tests) { return -std::expm1(std::log1p(-familyAlpha) / tests); }

// ---------------------------------------------------------------------------------------------
// Quadrature

struct QuadratureEstimate {
    double value = 0, error = 0;
};

// Gauss-Kronrod 7/15 (QUADPACK's qk15 nodes and weights); error = |K15 - G7|.
template <class F> QuadratureEstimate gaussKronrod15(F& f, double a, double b) {
    static constexpr double xgk[8] = {0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
                                      0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
                                      0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
                                      0.207784955007898467600689403773245, 0.0};
    static constexpr double wgk[8] = {0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
                                      0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
                                      0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
                                      0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
    static constexpr double wg[4] = {0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
                                     0.381830050505118944950369775488975, 0.417959183673469387755102040816327};
    const double c = 0.5 * (a + b), h = 0.5 * (b - a);
    const double fc = f(c);
    double k = fc * wgk[7], g = fc * wg[3];
    for (int j = 0; j < 7; ++j) {
        const double fsum = f(c - h * xgk[j]) + f(c + h * xgk[j]);
        k += wgk[j] * fsum;
        if (j % 2 == 1) g += wg[j / 2] * fsum;
    }
    return {k * h, std::abs((k - g) * h)};
}

// Tanh-sinh (double-exponential) quadrature: x = (a+b)/2 + (b-a)/2 tanh(pi/2 sinh t). Abscissae
// are generated as distances from the ends, a + (b-a) d and b - (b-a) d with
// d = 1/(1 + e^{pi sinh t}), so f is evaluated accurately arbitrarily close to an end. The rule
// is refined by halving the step (up to 7 times); error = difference of the last two levels.
template <class F> QuadratureEstimate tanhSinh(F& f, double a, double b, int maxLevels = 7) {
    constexpr double tMax = 5.3;  // d(tMax) ~ 1e-137: below that no integrable end matters here
    const double w = b - a;
    auto level = [&](double h) {
        const double mid = f(0.5 * (a + b));
        double s = 0.25 * kPi * w * mid;
        for (double t = h; t <= tMax; t += h) {
            const double d = 1.0 / (1.0 + std::exp(kPi * std::sinh(t)));
            const double weight = w * kPi * std::cosh(t) * d * (1.0 - d);
            if (weight == 0.0) break;
            const double fl = f(a + w * d), fu = f(b - w * d);
            s += weight * ((std::isfinite(fl) || weight > 1e-100 ? fl : 0.0) + (std::isfinite(fu) || weight > 1e-100 ? fu : 0.0));
        }
        return s * h;
    };
    double h = 0.5, prev = level(h), cur = prev, err = std::numeric_limits<double>::infinity();
    for (int l = 0; l < maxLevels; ++l) {
        h *= 0.5;
        cur = level(h);
        err = std::abs(cur - prev);
        if (err <= 1e-15 * std::abs(cur)) break;
        prev = cur;
    }
    return {cur, err};
}

enum class Singular { None, Lower, Upper, Both };

// Adaptive integral of f over [a, b], globally adaptive in the manner of QUADPACK's QAG: the
// panel with the largest error estimate is halved until the summed estimate is at most
// max(absTol, relTol |I|) (or 200000 panels exist). Panels touching an end flagged `singular`
// use tanh-sinh, the others Gauss-Kronrod 7/15.
template <class F>
double integrate(F&& f, double a, double b, double relTol = 1e-11, Singular singular = Singular::None,
                 double absTol = 0.0) {
    if (!(b > a)) return 0.0;
    const bool lowerSing = singular == Singular::Lower || singular == Singular::Both;
    const bool upperSing = singular == Singular::Upper || singular == Singular::Both;
    struct Panel {
        double a, b, value, error;
        bool operator<(const Panel& o) const { return error < o.error; }
    };
    auto evaluate = [&](double pa, double pb) {
        const bool endPanel = (lowerSing && pa == a) || (upperSing && pb == b);
        const QuadratureEstimate r = endPanel ? tanhSinh(f, pa, pb) : gaussKronrod15(f, pa, pb);
        return Panel{pa, pb, r.value, r.error};
    };
    std::vector<Panel> heap{evaluate(a, b)};
    double total = heap.front().value, error = heap.front().error;
    for (int n = 0; n < 200000; ++n) {
        if (error <= std::max(absTol, relTol * std::abs(total))) break;
        std::pop_heap(heap.begin(), heap.end());
        const Panel p = heap.back();
        heap.pop_back();
        const double m = 0.5 * (p.a + p.b);
        if (!(m > p.a && m < p.b)) {  // cannot split further: keep it, stop refining
            heap.push_back({p.a, p.b, p.value, 0.0});
            std::push_heap(heap.begin(), heap.end());
            error -= p.error;
            continue;
        }
        const Panel l = evaluate(p.a, m), r = evaluate(m, p.b);
        total += l.value + r.value - p.value;
        error += l.error + r.error - p.error;
        heap.push_back(l);
        std::push_heap(heap.begin(), heap.end());
        heap.push_back(r);
        std::push_heap(heap.begin(), heap.end());
    }
    double sum = 0;
    for (const Panel& p : heap) sum += p.value;
    return sum;
}

// 2 pi Int_0^thetaHi pdf(theta) sin(theta) dtheta for a pdf over solid angle that does not
// depend on phi.
template <class Pdf> double axialSphereIntegral(Pdf&& pdfTheta, double thetaHi = kPi, double relTol = 1e-12) {
    auto f = [&](double th) { return pdfTheta(th) * std::sin(th); };
    return 2.0 * kPi * integrate(f, 0.0, thetaHi, relTol, Singular::Both);
}

// Int_0^thetaHi Int_0^2pi pdf(theta, phi) sin(theta) dphi dtheta.
template <class Pdf> double sphereIntegral(Pdf&& pdf, double thetaHi = kPi, double relTol = 1e-11) {
    auto outer = [&](double th) {
        auto inner = [&](double ph) { return pdf(th, ph); };
        return integrate(inner, 0.0, 2.0 * kPi, relTol) * std::sin(th);
    };
    return integrate(outer, 0.0, thetaHi, relTol, Singular::Both);
}

// ---------------------------------------------------------------------------------------------
// Bins

inline std::vector<double> uniformEdges(double lo, double hi, int n) {
    std::vector<double> e(static_cast<size_t>(n) + 1);
    for (int i = 0; i <= n; ++i) e[static_cast<size_t>(i)] = lo + (hi - lo) * i / n;
    e.back() = hi;
    return e;
}

inline std::vector<double> forwardPeakedThetaEdges(double thetaMin, int nLog, double thetaSplit, int nLinear) {
    std::vector<double> e{0.0};
    for (int i = 0; i <= nLog; ++i) e.push_back(thetaMin * std::pow(thetaSplit / thetaMin, static_cast<double>(i) / nLog));
    e.back() = thetaSplit;
    for (int i = 1; i <= nLinear; ++i) e.push_back(thetaSplit + (kPi - thetaSplit) * i / nLinear);
    e.back() = kPi;
    return e;
}

// Scattering angle from t = 1 - cos(theta) and back, both exact for tiny angles.
inline double thetaFromOneMinusCos(double t) { return 2.0 * std::asin(std::sqrt(std::clamp(0.5 * t, 0.0, 1.0))); }
inline double oneMinusCosFromTheta(double theta) { return 2.0 * sqr(std::sin(0.5 * theta)); }

// ---------------------------------------------------------------------------------------------
// Tests

struct Options {
    long long samples = 200000;
    uint64_t seed = 1;
    double minExpected = 5.0;  // the usual validity condition of Pearson's approximation
    double relTol = 1e-10;     // quadrature of each bin: far below the relative Poisson noise 1/sqrt(E)
};

struct ChiSquareResult {
    double statistic = 0;
    int dof = 0;
    double pValue = std::numeric_limits<double>::quiet_NaN();
    int cells = 0;
    long long samples = 0, failures = 0, outside = 0;
    double expectedInBins = 0;  // sum of bin probabilities (the pdf's integral over the bins)
    std::string worst;           // largest contributions, for messages
    bool rejectedAt(double alpha) const { return !(pValue >= alpha); }
    std::string summary() const {
        std::ostringstream os;
        os << "chi2 = " << statistic << ", dof = " << dof << ", p = " << pValue << " (" << cells << " cells, " << samples
           << " samples, " << failures << " failed, " << outside << " outside the bins, pdf mass in bins "
           << expectedInBins << ")" << worst;
        return os.str();
    }
};

// Pearson's statistic on cells (observed counts, expected counts), with the pooling described at
// the top of this header. `labels` name the cells for the message (may be empty).
inline ChiSquareResult testCells(const std::vector<double>& observed, const std::vector<double>& expected,
                                 const std::vector<std::string>& labels, const Options& opt) {
    ChiSquareResult r;
    struct Cell {
        double o, e;
        std::string label;
    };
    std::vector<Cell> cells;
    constexpr double zeroExpected = 1e-6;  // counts; quadrature error of a truly empty cell is far below
    for (size_t i = 0; i < observed.size(); ++i) {
        const std::string label = i < labels.size() ? labels[i] : "cell " + std::to_string(i);
        if (expected[i] <= zeroExpected) {
            if (observed[i] > 0) {
                r.statistic = std::numeric_limits<double>::infinity();
                r.pValue = 0.0;
                r.worst = "; " + std::to_string(static_cast<long long>(observed[i])) + " samples in " + label +
                          ", where the pdf integrates to " + std::to_string(expected[i]) + " samples";
                return r;
            }
            continue;
        }
        cells.push_back({observed[i], expected[i], label});
    }
    std::sort(cells.begin(), cells.end(), [](const Cell& a, const Cell& b) { return a.e < b.e; });
    std::vector<Cell> kept;
    Cell pool{0, 0, "pooled small cells"};
    int pooled = 0;
    for (const Cell& c : cells) {
        if (c.e < opt.minExpected) {
            pool.o += c.o;
            pool.e += c.e;
            ++pooled;
        } else {
            kept.push_back(c);
        }
    }
    if (pooled > 0) {
        pool.label = "pool of " + std::to_string(pooled) + " cells";
        if (pool.e >= opt.minExpected || kept.empty()) {
            kept.push_back(pool);
        } else {
            kept.front().o += pool.o;  // smallest kept cell (cells were sorted by expected count)
            kept.front().e += pool.e;
            kept.front().label += " + " + pool.label;
        }
    }
    r.cells = static_cast<int>(kept.size());
    r.dof = r.cells - 1;
    std::vector<std::pair<double, size_t>> contrib;
    for (size_t i = 0; i < kept.size(); ++i) {
        const double c = sqr(kept[i].o - kept[i].e) / kept[i].e;
        r.statistic += c;
        contrib.push_back({c, i});
    }
    r.pValue = chiSquareSurvival(r.statistic, r.dof);
    std::sort(contrib.begin(), contrib.end(), std::greater<>());
    std::ostringstream os;
    os << "; largest terms:";
    for (size_t k = 0; k < std::min<size_t>(4, contrib.size()); ++k) {
        const Cell& c = kept[contrib[k].second];
        os << " [" << c.label << ": observed " << c.o << ", expected " << c.e << "]";
    }
    r.worst = os.str();
    return r;
}

// 1-D test in theta. thetaEdges ascending within [0, pi]; pdfTheta(theta) is the pdf per unit
// solid angle (phi-independent), so bin i expects N 2 pi Int pdf sin(theta) dtheta.
template <class Sampler, class Pdf>
ChiSquareResult testTheta(const std::vector<double>& edges, Sampler&& sampler, Pdf&& pdfTheta, const Options& opt) {
    const size_t nb = edges.size() - 1;
    const double n = static_cast<double>(opt.samples);
    std::vector<double> expected(nb + 1, 0.0), observed(nb + 1, 0.0);
    std::vector<std::string> labels(nb + 1);
    double inBins = 0;
    auto f = [&](double th) { return pdfTheta(th) * std::sin(th); };
    for (size_t i = 0; i < nb; ++i) {
        const bool lo = edges[i] == 0.0, hi = edges[i + 1] >= kPi;
        const Singular s = lo && hi ? Singular::Both : lo ? Singular::Lower : hi ? Singular::Upper : Singular::None;
        const double p = 2.0 * kPi * integrate(f, edges[i], edges[i + 1], opt.relTol, s);
        inBins += p;
        expected[i] = n * p;
        std::ostringstream os;
        os << "theta [" << edges[i] << ", " << edges[i + 1] << ")";
        labels[i] = os.str();
    }
    expected[nb] = std::max(0.0, n * (1.0 - inBins));
    labels[nb] = "failed or outside the bins";
    long long failures = 0, outside = 0;
    for (long long k = 0; k < opt.samples; ++k) {
        RandomStream rs(opt.seed, 0, static_cast<uint64_t>(k));
        const std::optional<double> th = sampler(rs);
        if (!th) {
            ++failures;
            observed[nb] += 1;
            continue;
        }
        if (!(*th >= edges.front() && *th <= edges.back())) {
            ++outside;
            observed[nb] += 1;
            continue;
        }
        size_t i = static_cast<size_t>(std::upper_bound(edges.begin(), edges.end(), *th) - edges.begin());
        i = std::min(std::max<size_t>(i, 1), nb) - 1;
        observed[i] += 1;
    }
    ChiSquareResult r = testCells(observed, expected, labels, opt);
    r.samples = opt.samples;
    r.failures = failures;
    r.outside = outside;
    r.expectedInBins = inBins;
    return r;
}

// 2-D test in (theta, phi) about `frame` (theta from frame.n, phi from frame.s toward frame.t).
// pdf(theta, phi) is per unit solid angle.
template <class Sampler, class Pdf>
ChiSquareResult testSphere(const std::vector<double>& thetaEdges, int phiBins, const Frame& frame, Sampler&& sampler,
                           Pdf&& pdf, const Options& opt) {
    const size_t nt = thetaEdges.size() - 1, np = static_cast<size_t>(phiBins), nb = nt * np;
    const double n = static_cast<double>(opt.samples);
    std::vector<double> expected(nb + 1, 0.0), observed(nb + 1, 0.0);
    std::vector<std::string> labels(nb + 1);
    double inBins = 0;
    for (size_t i = 0; i < nt; ++i) {
        const bool lo = thetaEdges[i] == 0.0, hi = thetaEdges[i + 1] >= kPi;
        const Singular s = lo && hi ? Singular::Both : lo ? Singular::Lower : hi ? Singular::Upper : Singular::None;
        for (size_t j = 0; j < np; ++j) {
            const double p0 = 2.0 * kPi * j / np, p1 = 2.0 * kPi * (j + 1) / np;
            auto outer = [&](double th) {
                auto inner = [&](double ph) { return pdf(th, ph); };
                return integrate(inner, p0, p1, opt.relTol) * std::sin(th);
            };
            const double p = integrate(outer, thetaEdges[i], thetaEdges[i + 1], opt.relTol, s);
            inBins += p;
            expected[i * np + j] = n * p;
            std::ostringstream os;
            os << "theta [" << thetaEdges[i] << ", " << thetaEdges[i + 1] << ") phi [" << p0 << ", " << p1 << ")";
            labels[i * np + j] = os.str();
        }
    }
    expected[nb] = std::max(0.0, n * (1.0 - inBins));
    labels[nb] = "failed or outside the bins";
    long long failures = 0, outside = 0;
    for (long long k = 0; k < opt.samples; ++k) {
        RandomStream rs(opt.seed, 0, static_cast<uint64_t>(k));
        const std::optional<Vec3> w = sampler(rs);
        if (!w) {
            ++failures;
            observed[nb] += 1;
            continue;
        }
        const Vec3 l = frame.toLocal(*w);
        const double th = std::atan2(std::hypot(l.x, l.y), l.z);
        double ph = std::atan2(l.y, l.x);
        if (ph < 0) ph += 2.0 * kPi;
        if (!(th >= thetaEdges.front() && th <= thetaEdges.back()) || !std::isfinite(ph)) {
            ++outside;
            observed[nb] += 1;
            continue;
        }
        size_t i = static_cast<size_t>(std::upper_bound(thetaEdges.begin(), thetaEdges.end(), th) - thetaEdges.begin());
        i = std::min(std::max<size_t>(i, 1), nt) - 1;
        const size_t j = std::min(np - 1, static_cast<size_t>(ph / (2.0 * kPi) * static_cast<double>(np)));
        observed[i * np + j] += 1;
    }
    ChiSquareResult r = testCells(observed, expected, labels, opt);
    r.samples = opt.samples;
    r.failures = failures;
    r.outside = outside;
    r.expectedInBins = inBins;
    return r;
}

}  // namespace littoral::testing_support::chi2
