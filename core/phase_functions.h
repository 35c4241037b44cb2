#pragma once
// Phase functions of sea water and of the particles in it.
//
// Conventions (all types below):
//   * cosTheta is the cosine of the scattering angle Theta between the incident propagation
//     direction and the scattered propagation direction: 1 = straight on, -1 = straight back.
//   * Every phase function is normalised over the sphere, Int_{4 pi} p dOmega = 1, so eval() is
//     in sr^-1 and is also the pdf (per unit solid angle) of the direction its sampler draws:
//     sampling is exact, pdf == eval.
//   * Sampling comes as a triple. sampleCos(u) inverts the cumulative distribution counted from
//     straight back, F(c) = P(cos Theta <= c); invertCos(c) = F(c) is its inverse; pdf(c) = eval(c).
//     u in [0, 1).
//   * Forward precision. cos Theta rounds to 1 for angles below ~1.5e-8 rad, yet the Petzold and
//     Fournier-Forand functions put percents of their scattering there. Each type therefore also
//     works in t = 1 - cos Theta = 2 sin^2(Theta/2), which stays exact for tiny angles:
//     evalOneMinusCos(t) and sampleOneMinusCos(u) (== 1 - sampleCos(u), to rounding).
//   * Petzold and Fournier-Forand have an integrable power-law singularity straight forward:
//     eval(1) is +infinity (any t > 0 gives a finite value). A renderer that can hit exactly
//     cos Theta = 1 (e.g. next-event estimation along an unscattered, refracted sun beam) must
//     treat the forward cone as unscattered, which is what forwardConeFraction() is for (the
//     dissertation's "effective scattering coefficient", spec/seed-ch06-07-appA.md section 2.4).
//
// PhaseFunction is the type the renderer holds per medium: a value type holding a mixture of up
// to four of the components below, weighted by their scattering coefficients. It allocates
// nothing on eval/sample/pdf; copying it copies at most four small structs and one shared
// pointer per tabulated component.
#include <array>
#include <memory>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "core/kinds.h"
#include "core/vec.h"

namespace littoral {

// p = 1 / (4 pi).
struct IsotropicPhase {
    double eval(double cosTheta) const;
    double evalOneMinusCos(double t) const;
    double sampleCos(double u) const;
    double sampleOneMinusCos(double u) const;
    double invertCos(double c) const;
    double pdf(double c) const { return eval(c); }
    double meanCosine() const { return 0.0; }
    double backscatterFraction() const { return 0.5; }
    double forwardConeFraction(double cosTheta0) const;
    double forwardFraction(double t) const;  // scattered within the cone 1 - cos <= t
};

// Henyey-Greenstein (1941): p = (1 - g^2) / (4 pi (1 + g^2 - 2 g cos)^{3/2}); g in (-1, 1) is the
// mean cosine. The inverse CDF is written so that it has no cancellation for g near 0 and none
// near the forward or backward peak for |g| up to 0.999 (see phase_functions.cpp).
struct HenyeyGreenstein {
    double g = 0.0;
    double eval(double cosTheta) const;
    double evalOneMinusCos(double t) const;
    double sampleCos(double u) const;
    double sampleOneMinusCos(double u) const;
    double invertCos(double c) const;
    double pdf(double c) const { return eval(c); }
    double meanCosine() const { return g; }
    // B(g) = (1 - g)/(2 g) [(1 + g)/sqrt(1 + g^2) - 1], written without the 1/g cancellation.
    double backscatterFraction() const;
    // ((1 + g)/(2 g)) [1 - (1 - g)/sqrt(1 + g^2 - 2 g cos t0)], likewise.
    double forwardConeFraction(double cosTheta0) const;
    double forwardFraction(double t) const;  // the same in t = 1 - cos t0
};

// Rayleigh-like: p = (1 + k cos^2) / (4 pi (1 + k/3)). k = 1 is Mobley et al. (1993) problem 1's
// (3 / (16 pi))(1 + cos^2); k = 0.835 is Morel's (1974) molecular scattering of water
// (depolarisation ratio 0.09). The inverse CDF is the one real root of a cubic, taken in its
// hyperbolic-sine form, which is exact and free of cancellation.
struct RayleighLikePhase {
    double k = 1.0;
    double eval(double cosTheta) const;
    double evalOneMinusCos(double t) const;
    double sampleCos(double u) const;
    double sampleOneMinusCos(double u) const;
    double invertCos(double c) const;
    double pdf(double c) const { return eval(c); }
    double meanCosine() const { return 0.0; }
    double backscatterFraction() const { return 0.5; }
    double forwardConeFraction(double cosTheta0) const;
    double forwardFraction(double t) const;
};

// Fournier-Forand phase function in the form of Mobley, Sundman and Boss (2002), Appl. Opt. 41,
// eq. (5):
//   p = 1/(4 pi (1-d)^2 d^nu) { nu (1-d) - (1 - d^nu) + [d (1 - d^nu) - nu (1-d)] / sin^2(psi/2) }
//     + (1 - d180^nu) / (16 pi (d180 - 1) d180^nu) (3 cos^2 psi - 1),
//   nu = (3 - mu)/2, d = 4 sin^2(psi/2) / (3 (n - 1)^2), d180 = d at psi = 180 deg,
// with n the particles' real index relative to water and mu the slope of the hyperbolic (Junge)
// size distribution. Its CDF is the closed form of Fournier and Jonasz (1999); its backscatter
// fraction is
//   B = 1 - [1 - d90^(nu+1) - (1 - d90^nu)/2] / [(1 - d90) d90^nu].
// Both d -> 1 (a removable singularity near psi ~ 10 deg for n = 1.10) and d -> 0 are evaluated
// without cancellation. Sampling inverts the CDF by safeguarded Newton iteration on the log of
// the smaller tail, from a tabulated starting point, to 1e-14 in the cumulative probability.
class FournierForand {
public:
    // Solves B(mu, n) = backscatterFraction for mu in (3, 5]. Throws InputError when B or n is
    // outside the supported range (n in [1.01, 1.30]; B such that mu >= 3.11, i.e. B >~ 0.002 for
    // n = 1.10, and B <= 0.5).
    static FournierForand fromBackscatterFraction(double backscatterFraction, double n = 1.10);
    static FournierForand fromSlope(double mu, double n = 1.10);
    // Closed-form backscatter fraction B(mu, n), Mobley et al. (2002) eq. (6).
    static double backscatterFractionOf(double mu, double n);

    double eval(double cosTheta) const;
    double evalOneMinusCos(double t) const;
    double sampleCos(double u) const;
    double sampleOneMinusCos(double u) const;
    double invertCos(double c) const;
    double pdf(double c) const { return eval(c); }
    double meanCosine() const { return meanCosine_; }  // by quadrature of the CDF at construction
    double backscatterFraction() const { return backscatter_; }
    double forwardConeFraction(double cosTheta0) const;

    double slope() const { return mu_; }
    double particleIndex() const { return n_; }
    // Cumulative fractions at t = 1 - cos: scattered within the cone t' <= t (forward) and
    // beyond it (backward); their sum is 1. Each is computed where it is small, to full
    // relative precision.
    double forwardFraction(double t) const;
    double backwardFraction(double t) const;

private:
    FournierForand(double mu, double n);
    double backwardFraction(double t, double twoMinusT) const;
    double solveOneMinusCos(bool forward, double logTarget, double v0) const;
    double initialGuess(bool forward, double logTarget) const;
    double n_ = 1.10, mu_ = 3.5, nu_ = -0.25, delta180_ = 1, logHalfDelta180_ = 0, kappa_ = 0;
    double backscatter_ = 0, meanCosine_ = 0;
    // The solution at 129 equally spaced log-targets: ln d for ln(1-u) in [-37, ln(1-B)]
    // (forward) and ln(2 - t) for ln u in [-37, ln B] (backward). Built once; Newton starts from
    // its interpolant.
    static constexpr int kGuessNodes = 129;
    std::shared_ptr<const std::array<double, 2 * kGuessNodes>> guess_;
};

// A phase function tabulated in scattering angle psi (degrees) with sr^-1 values, e.g. Petzold's.
// The input table is interpolated as stated (linear in psi by default) and, below its first
// angle psi_0 > 0, extended by the power law value(psi_0) (psi_0/psi)^m.
//
// The internal representation on which eval and sampling both operate (so pdf == eval exactly):
//   * each input interval is cut into `subdivisions` equal steps in psi; at these nodes the
//     value is the input interpolant's; between nodes the density is linear in t = 1 - cos psi,
//     whose CDF is a quadratic with a closed-form root;
//   * below psi_0 the density is p_0 (t/t_0)^(-m/2), i.e. the stated power law with psi^2
//     replaced by 2(1 - cos psi) (relative difference < psi_0^2/12 = 4e-7 for Petzold), whose
//     CDF inverts in closed form;
//   * the whole is renormalised to 1 (to rounding).
// Segment lookup is a binary search over at most 4096 nodes.
class TabulatedPhase {
public:
    enum class Interpolation { LinearInPsi, LogLog };
    // psiDegValue: strictly increasing psi from psi_0 >= 0 to exactly 180; values > 0.
    // forwardExponent m in [0, 2) (ignored when psi_0 = 0). Throws InputError on a malformed table.
    TabulatedPhase(std::vector<std::pair<double, double>> psiDegValue, double forwardExponent,
                   Interpolation interpolation = Interpolation::LinearInPsi, int subdivisions = 32,
                   std::string name = "tabulated");

    double eval(double cosTheta) const;
    double evalOneMinusCos(double t) const;
    double sampleCos(double u) const;
    double sampleOneMinusCos(double u) const;
    double invertCos(double c) const;
    double pdf(double c) const { return eval(c); }
    double meanCosine() const { return meanCosine_; }
    double backscatterFraction() const;
    double forwardConeFraction(double cosTheta0) const;
    double forwardFraction(double t) const;  // scattered within the cone t' <= t

    const std::string& name() const { return name_; }
    Interpolation interpolation() const { return interpolation_; }
    // 2 pi Int beta(psi) sin(psi) dpsi of the input table itself under its interpolation and
    // power law, before renormalisation: how far the published numbers are from normalised.
    double tableNormalization() const { return tableNormalization_; }
    // The input interpolant (not renormalised), sr^-1, at psi in degrees.
    double tableValue(double psiDeg) const;
    // Internal nodes (t ascending, values normalised): between two nodes the density is linear in t.
    const std::vector<double>& nodesOneMinusCos() const { return t_; }
    const std::vector<double>& nodeValues() const { return p_; }
    size_t segmentOfT(double t) const;    // j with t_[j] <= t < t_[j + 1], t in [t_[0], 2)

private:
    std::vector<double> psiDeg_, value_;  // the input table
    Interpolation interpolation_;
    double exponent_ = 0, halfExponent_ = 0;
    std::vector<double> t_, p_, cdf_;  // fine nodes, normalised density, forward fraction at t_
    double powerLawMass_ = 0;          // forward fraction below t_[0]
    // Search accelerators: bin k of kLookupBins, uniform in sqrt(t / 2) = sin(psi / 2) (tLookup_)
    // or in the forward fraction q (cdfLookup_), starts in node segment lookup[k]; a search is then
    // a walk over the few nodes in bin k (a bisection between lookup[k - 1] and lookup[k + 2] took
    // 50 % longer: its branches are unpredictable).
    static constexpr int kLookupBins = 2048;
    std::vector<uint32_t> tLookup_, cdfLookup_;
    void buildLookups();                  // from t_ and cdf_ (the constructor)
    size_t segmentOfCdf(double q) const;  // j with cdf_[j] <= q < cdf_[j + 1] (clamped to the last)
    double tableNormalization_ = 1, meanCosine_ = 0;
    std::string name_;
};

// Petzold's average-particle phase function (San Diego Harbor), Mobley et al. (1993) Table 2, as
// given in spec/reference-data.md, interpolated log-log (ln value linear in ln psi) between its
// rows, value(0.12589 deg) x (0.12589/psi)^1.346 below 0.12589 deg. Built once; every call
// returns the same table.
std::shared_ptr<const TabulatedPhase> petzoldAverageParticleTable();
TabulatedPhase petzoldAverageParticle();

class PhaseFunction {
public:
    static constexpr int kMaxComponents = 4;

    PhaseFunction();  // isotropic
    static PhaseFunction isotropic();
    static PhaseFunction henyeyGreenstein(double g);  // |g| < 1, else InputError
    static PhaseFunction rayleighLike();              // k = 1, Mobley problem 1
    static PhaseFunction molecularWater(double k = 0.835);  // Morel (1974) 1 + 0.835 cos^2
    static PhaseFunction fournierForand(double backscatterFraction, double n = 1.10);
    static PhaseFunction petzold();
    static PhaseFunction tabulated(std::shared_ptr<const TabulatedPhase> table);
    // p = sum b_i p_i / sum b_i. Nested mixtures are flattened; zero weights are dropped; at most
    // kMaxComponents remain. Throws InputError for negative or non-finite weights, an all-zero
    // weight sum, or too many components.
    static PhaseFunction mixture(const std::vector<std::pair<double /*b weight*/, PhaseFunction>>& parts);

    double eval(double cosTheta) const;  // sr^-1
    double evalOneMinusCos(double t) const;
    // Value for two unit propagation directions; 1 - cos is taken as |b - a|^2 / 2, which keeps
    // its precision for nearly parallel directions.
    double evalDirections(const Vec3& incident, const Vec3& scattered) const;
    double pdf(double cosTheta) const { return eval(cosTheta); }
    // u1 picks the mixture component (ignored for a single component), u2 the angle.
    double sampleCos(double u1, double u2) const;
    double sampleOneMinusCos(double u1, double u2) const;
    // CDF of the mixture counted from straight back: P(cos Theta <= c).
    double invertCos(double c) const;
    // A direction scattered from the unit propagation direction `dir`: u1 component, u2 polar
    // angle, u3 azimuth (uniform). *pdfOut (if given) receives the pdf per unit solid angle.
    Vec3 sample(const Vec3& dir, double u1, double u2, double u3, double* pdfOut) const;

    double meanCosine() const;
    double backscatterFraction() const;
    // Fraction of scattering into the cone of half-angle acos(cosTheta0) about forward.
    double forwardConeFraction(double cosTheta0) const;
    std::string describe() const;

    int componentCount() const { return count_; }
    double componentWeight(int i) const { return weight_[static_cast<size_t>(i)]; }
    PhaseFunction component(int i) const;
    const auto& part(int i) const { return parts_[static_cast<size_t>(i)]; }  // the component itself

    using Component = std::variant<IsotropicPhase, HenyeyGreenstein, RayleighLikePhase, FournierForand,
                                   std::shared_ptr<const TabulatedPhase>>;

private:
    explicit PhaseFunction(Component c);
    int pick(double u1) const;

    std::array<Component, kMaxComponents> parts_;
    std::array<double, kMaxComponents> weight_{}, cumulative_{};
    int count_ = 0;
};

// ---- the phase-function kinds -----------------------------------------------------------------
// Each kind a scene file or an IR can name ("isotropic", "henyey-greenstein", "petzold",
// "fournier-forand", "rayleigh"), described once in phase_functions.cpp beside its implementation:
// its parameters (name, default or required, the one range, unit, doc) and its factory. The
// scene-file parser, the IR writer and reader, docs/scene-format.md (checked by a test) and the
// renderer's media all read these descriptors.
struct PhaseKind {
    KindInfo info;  // family "phase function"
    PhaseFunction (*make)(const ParamValues& resolved);
};
inline const KindInfo& kindInfo(const PhaseKind& k) { return k.info; }

const KindRegistry<PhaseKind>& phaseFunctionKinds();

// The phase function of kind `type` with parameters `params` (e.g. an IR scatterer's), after
// checking both against the descriptor. InputError "{who}: ..." on an unknown type or a missing,
// unknown, mistyped or out-of-range parameter.
PhaseFunction makePhaseFunction(std::string_view type, const ParamValues& params, const std::string& who);
// The same check; returns every parameter of the kind, defaults filled in, in descriptor order.
ParamValues resolvePhaseParams(std::string_view type, const ParamValues& params, const std::string& who);

}  // namespace littoral
