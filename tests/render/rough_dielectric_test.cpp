// The rough (Cox-Munk) dielectric BxDF: its f against the dissertation's closed forms (Eq. 5.4 and
// the Walter-consistent BTDF of tests/support/glint.h), reciprocity and the adjoint, chi-square of
// sample() against pdf() for both lobes from above and below (total internal reflection
// included), energy (white furnace) against an independent quadrature over the slopes, the limit
// of a calm sea, and its input errors.
#include "render/rough_dielectric.h"

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/frame.h"
#include "core/rng.h"
#include "core/units.h"
#include "render/bxdf.h"
#include "tests/support/chi_square.h"
#include "tests/support/glint.h"

using namespace littoral;
using namespace littoral::render;
namespace chi2 = littoral::testing_support::chi2;
namespace glint = littoral::testing_support::glint;

namespace {

constexpr double kWater = 1.34;

RoughDielectricBxDF rough(double U, CoxMunkSea sea, double azimuth = 0.0,
                          MicrofacetShadowing shadowing = MicrofacetShadowing::None, bool gc = false) {
    return RoughDielectricBxDF(1.0, kWater, CoxMunkDistribution(CoxMunkParams{U, azimuth, sea, gc}), shadowing);
}

// Unit direction at polar angle theta from +z (theta > pi/2: below the surface) and azimuth phi.
Vec3 dir(double theta, double phi) {
    return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

glint::Dir toGlint(const Vec3& v) { return {v.x, v.y, v.z}; }

std::string label(double U, CoxMunkSea sea, double thetaDeg, bool above) {
    return fmt::format("U {} {} wo {} deg {}", U, nameOf(sea), thetaDeg, above ? "above" : "below");
}

}  // namespace

// With G = 1, f_r cos(theta_i) is the dissertation's Eq. 5.4 and f_t cos(theta_i) (Radiance mode)
// the Walter-consistent closed form of digest section 1.6, both written independently in
// tests/support/glint.h. Same numbers, two derivations: agreement to 1e-12 relative (rounding).
// The wind azimuth rotates the pattern: glint.h's x axis is the wind axis.
TEST(RoughDielectric, MatchesClosedFormsOfTheDissertation) {
    for (double W : {0.5, 2.0, 5.0, 8.0})
        for (double az : {0.0, 0.7, 2.4}) {
            const RoughDielectricBxDF b = rough(W, CoxMunkSea::Dissertation, az);
            const glint::SlopeVariances v = glint::dissertationSlopes(W);
            for (const auto& [thSun, phSun] : {std::pair{0.0, 0.0}, std::pair{24.0, 180.0}, std::pair{50.0, 30.0}})
                for (double thView : {0.0, 3.0, 10.0, 25.0, 60.0})
                    for (double phView : {0.0, 45.0, 90.0, 200.0}) {
                        // Directions in glint.h's wind frame, then rotated by the wind azimuth.
                        const Vec3 sunW = dir(deg2rad(thSun), deg2rad(phSun)), viewW = dir(deg2rad(thView), deg2rad(phView));
                        const Vec3 sun = dir(deg2rad(thSun), deg2rad(phSun) + az);
                        const Vec3 view = dir(deg2rad(thView), deg2rad(phView) + az);
                        const double ref = glint::reflected(v, toGlint(sunW), toGlint(viewW), kWater);
                        const double fr = b.f(view, sun) * sun.z;
                        EXPECT_NEAR(fr, ref, 1e-12 * ref + 1e-300) << W << " " << thSun << " " << thView;
                        // A submerged receiver at in-water angle thView from nadir.
                        const Vec3 recW{viewW.x, viewW.y, -viewW.z}, rec{view.x, view.y, -view.z};
                        const double tref = glint::transmitted(v, toGlint(sunW), toGlint(recW), kWater);
                        const double ft = b.f(rec, sun, TransportMode::Radiance) * sun.z;
                        EXPECT_NEAR(ft, tref, 1e-11 * tref + 1e-300) << W << " " << thSun << " " << thView;
                    }
        }
    // Digest section 1.6: at nadir, sun at zenith, t(0) = 982.4 / W.
    const RoughDielectricBxDF b = rough(2.0, CoxMunkSea::Dissertation);
    EXPECT_NEAR(b.f({0, 0, -1}, {0, 0, 1}) * 2.0, 982.4, 0.06);  // 982.45, printed truncated
}

// Generalised reciprocity of a refracting BSDF: f_rad(wo, wi) / eta_o^2 = f_rad(wi, wo) / eta_i^2
// (Veach 1997, eq. 5.14) for the symmetric shadowing terms; and for every term the adjoint
// f_imp(wo, wi) = f_rad(wi, wo). pdf does not depend on the mode. Relative tolerance 1e-9: the
// half vector, built from the pair in either order, differs in its last bits, and D's exponent
// x = (slope / sigma)^2 / 2 (up to ~500 for these random pairs) magnifies that by x.
TEST(RoughDielectric, ReciprocityAndAdjoint) {
    for (MicrofacetShadowing s :
         {MicrofacetShadowing::None, MicrofacetShadowing::SmithLight, MicrofacetShadowing::SmithSeparable}) {
        const RoughDielectricBxDF b = rough(9.0, CoxMunkSea::Clean, 0.4, s, true);
        int nonzero = 0;
        for (int i = 0; i < 4000; ++i) {
            RandomStream rs(5, 0, static_cast<uint64_t>(i));
            const Vec3 wo = dir(std::acos(1 - 2 * rs.uniform()), 2 * kPi * rs.uniform());
            const Vec3 wi = dir(std::acos(1 - 2 * rs.uniform()), 2 * kPi * rs.uniform());
            const double eo = wo.z > 0 ? 1.0 : kWater, ei = wi.z > 0 ? 1.0 : kWater;
            const double a = b.f(wo, wi, TransportMode::Radiance), c = b.f(wi, wo, TransportMode::Radiance);
            if (a > 0) ++nonzero;
            if (s != MicrofacetShadowing::SmithLight) {
                EXPECT_NEAR(a / (eo * eo), c / (ei * ei), 1e-9 * (a + c));
            }
            EXPECT_NEAR(b.f(wo, wi, TransportMode::Importance), c, 1e-9 * c);
            EXPECT_EQ(b.pdf(wo, wi, TransportMode::Importance), b.pdf(wo, wi, TransportMode::Radiance));
        }
        EXPECT_GT(nonzero, 1000);  // the check saw both lobes, not only zeros
    }
}

// The variant wrapper: the rough interface is glossy and transmissive, not delta, and dispatches.
TEST(RoughDielectric, HeldByTheBxDFVariant) {
    const RoughDielectricBxDF r = rough(5.0, CoxMunkSea::Clean, 0.2);
    const BxDF b = r;
    EXPECT_FALSE(b.isDelta());
    EXPECT_TRUE(b.isGlossy());
    EXPECT_TRUE(b.isTransmissive());
    EXPECT_FALSE(b.isDiffuse());
    const Vec3 wo = normalize(Vec3{0.3, 0.1, 0.9}), wi = normalize(Vec3{-0.25, -0.05, 0.95});
    EXPECT_EQ(b.f(wo, wi), r.f(wo, wi));
    EXPECT_EQ(b.pdf(wo, wi), r.pdf(wo, wi));
    const auto s = b.sample(wo, 0.001, {0.3, 0.6});
    ASSERT_TRUE(s);
    EXPECT_TRUE(s->flags & kGlossy);
    EXPECT_FALSE(s->isSpecular());
    EXPECT_EQ(s->pdf, r.pdf(wo, s->wi));
    BSDFSample x, y;
    bool can = false;
    EXPECT_FALSE(b.specularPair(wo, TransportMode::Radiance, &x, &y, &can));
    // evaluate() reports the lobe and the relative index.
    const auto e = r.evaluate(wo, {0, 0, -1});
    EXPECT_TRUE(e.flags & kTransmission);
    EXPECT_NEAR(e.etap, kWater, 1e-15);
}

// sample() draws directions distributed as pdf() says, on both lobes: chi-square through the
// shared harness. Each case is binned twice, with theta measured from the mirror direction and
// from the flat-surface refracted direction (when there is one), geometric theta bins inside the
// lobe (scale: the larger RMS slope) and 10 azimuth bins; samples that fail (facets seen from
// behind, light sent to the wrong side) are the harness's remainder cell, expected N (1 - Int pdf).
// Winds 2 (dissertation), 8 and 14 m/s (clean, the latter with Gram-Charlier terms: sampling and
// pdf are the Gaussian part's); incidence 0, 45 and 80 deg from the air, and 20, 45 and 70 deg
// from the water (70 deg: beyond the 48.3 deg critical angle, total internal reflection of the
// flat interface; only steep facets transmit).
TEST(RoughDielectric, SamplingMatchesPdf) {
    struct Case { double U; CoxMunkSea sea; bool gc; };
    const Case cases[] = {
        {2.0, CoxMunkSea::Dissertation, false}, {8.0, CoxMunkSea::Clean, false}, {14.0, CoxMunkSea::Clean, true}};
    const double above[] = {0.0, 45.0, 80.0}, below[] = {20.0, 45.0, 70.0};
    // Tests: per wind 3 above x 2 frames + 2 below x 2 + 1 below (TIR, mirror frame only) = 11.
    const int tests = 3 * 11;
    const double alpha = chi2::sidakLevel(0.01, tests);
    int run = 0;
    for (const Case& c : cases) {
        const RoughDielectricBxDF b = rough(c.U, c.sea, 0.8, MicrofacetShadowing::None, c.gc);
        const double s = std::atan(std::sqrt(std::max(b.slopes.varianceUpwind(), b.slopes.varianceCrosswind())));
        for (int side = 0; side < 2; ++side)
            for (double thDeg : side == 0 ? above : below) {
                const double th = deg2rad(thDeg);
                const Vec3 wo = side == 0 ? dir(th, 0.3) : dir(kPi - th, 0.3);
                std::vector<Vec3> centres{Vec3{-wo.x, -wo.y, wo.z}};
                Vec3 wt;
                const double eta = side == 0 ? 1.0 / kWater : kWater;
                if (refract(wo, Vec3{0, 0, wo.z > 0 ? 1.0 : -1.0}, eta, &wt)) centres.push_back(wt);
                for (const Vec3& centre : centres) {
                    // Transmitted lobes are narrower than reflected ones by up to ~8 (1 - 1/n vs 2).
                    auto edges = chi2::forwardPeakedThetaEdges(0.01 * s, 14, std::min(1.0, 6.0 * s), 8);
                    chi2::Options o;
                    o.samples = 200000;
                    o.seed = 17 + run;
                    // Expected counts to 1e-4 relative: an error dE = 1e-4 E shifts a cell's term by
                    // at most (dE)^2 / E + 2 |O - E| dE / E ~ 1e-8 E + 2e-4 sqrt(E) < 0.1 for the
                    // largest cells here (E < 3e4), nothing beside the statistic's dof of 100-200.
                    o.relTol = 1e-4;
                    const Frame frame = Frame::fromNormal(centre);
                    const auto r = chi2::testSphere(
                        edges, 10, frame,
                        [&](RandomStream& rs) -> std::optional<Vec3> {
                            const double uc = rs.uniform(), u1 = rs.uniform(), u2 = rs.uniform();
                            const auto smp = b.sample(wo, uc, {u1, u2}, TransportMode::Radiance);
                            if (!smp) return std::nullopt;
                            return smp->wi;
                        },
                        [&](double t, double p) { return b.pdf(wo, frame.toWorld(dir(t, p))); }, o);
                    ++run;
                    std::printf("[ info ] chi2 %s, frame on %s: p = %.3g (dof %d, %lld failed, pdf mass %.4f)\n",
                                label(c.U, c.sea, thDeg, side == 0).c_str(), centre.z * wo.z > 0 ? "mirror" : "refracted",
                                r.pValue, r.dof, r.failures, r.expectedInBins);
                    EXPECT_FALSE(r.rejectedAt(alpha)) << label(c.U, c.sea, thDeg, side == 0) << ": " << r.summary();
                }
            }
    }
    EXPECT_EQ(run, tests);
}

// The transmission-only sampler (sampleTransmission / pdfTransmission, used for the sun seen from
// under a rough surface) against its own pdf, through the same harness: from above and from below
// (where total internal reflection removes part of the lobe, so the pdf integrates to the success
// probability and the remainder cell counts the failures). Sidak-corrected 1 % family level.
TEST(RoughDielectric, TransmissionSamplerMatchesItsPdf) {
    struct Case {
        double U;
        double thetaDeg;
        bool above;
    };
    const Case cases[] = {{2.0, 0.0, true}, {8.0, 40.0, true}, {14.0, 75.0, true},
                          {2.0, 10.0, false}, {8.0, 35.0, false}, {14.0, 45.0, false}};
    const int tests = 6;
    const double alpha = chi2::sidakLevel(0.01, tests);
    int run = 0;
    for (const Case& c : cases) {
        const RoughDielectricBxDF b = rough(c.U, CoxMunkSea::Clean, 0.8);
        const double s = std::atan(std::sqrt(std::max(b.slopes.varianceUpwind(), b.slopes.varianceCrosswind())));
        const double th = deg2rad(c.thetaDeg);
        const Vec3 wo = c.above ? dir(th, 0.3) : dir(kPi - th, 0.3);
        Vec3 wt;
        const double eta = c.above ? 1.0 / kWater : kWater;
        if (!refract(wo, Vec3{0, 0, wo.z > 0 ? 1.0 : -1.0}, eta, &wt)) wt = Vec3{0, 0, wo.z > 0 ? -1.0 : 1.0};
        auto edges = chi2::forwardPeakedThetaEdges(0.01 * s, 14, std::min(1.0, 6.0 * s), 8);
        chi2::Options o;
        o.samples = 200000;
        o.seed = 91 + run;
        o.relTol = 1e-4;  // as in the sampling test above
        const Frame frame = Frame::fromNormal(wt);
        const auto r = chi2::testSphere(
            edges, 10, frame,
            [&](RandomStream& rs) -> std::optional<Vec3> {
                const double u1 = rs.uniform(), u2 = rs.uniform();
                return b.sampleTransmission(wo, {u1, u2});
            },
            [&](double t, double p) { return b.pdfTransmission(wo, frame.toWorld(dir(t, p))); }, o);
        ++run;
        std::printf("[ info ] chi2 transmission only, U %g, wo %g deg %s: p = %.3g (dof %d, %lld failed, pdf mass %.4f)\n",
                    c.U, c.thetaDeg, c.above ? "above" : "below", r.pValue, r.dof, r.failures, r.expectedInBins);
        EXPECT_FALSE(r.rejectedAt(alpha)) << c.U << " " << c.thetaDeg << ": " << r.summary();
        // The lobe choice aside, it is the BxDF's own transmission density: pdf = (1 - F) pdfTransmission.
        for (int k = 0; k < 20; ++k) {
            RandomStream rs(5, 1, static_cast<uint64_t>(k));
            const auto wi = b.sampleTransmission(wo, {rs.uniform(), rs.uniform()});
            if (!wi) continue;
            const auto e = b.evaluate(wo, *wi);
            const Vec3 h = normalize(-((wo.z > 0 ? 1.0 : kWater) * wo + (wo.z > 0 ? kWater : 1.0) * *wi));
            const double F = fresnelDielectric(std::abs(dot(wo, h)), wo.z > 0 ? 1.0 : kWater, wo.z > 0 ? kWater : 1.0);
            EXPECT_NEAR(e.pdf, (1 - F) * b.pdfTransmission(wo, *wi), 1e-12 * e.pdf);
        }
    }
    EXPECT_EQ(run, tests);
}

namespace {

// Flux fraction scattered by single microfacet interactions, for light arriving from `l`
// (Importance transport), by quadrature over the slopes: each facet m, of density p_s, offers the
// beam the area |l.m| / (m_z |l.z|) per unit beam cross-section and reflects r_f(|l.m|) of what
// reaches it (G1(l, m) of it under Smith shadowing) and transmits the rest; a lobe counts as kept
// if its direction leaves on the side a single-scattering BxDF can represent, else as `lost`.
// Written from the microfacet picture, not from RoughDielectricBxDF::f. The integrand jumps where
// a facet stops being lit, where a reflected or refracted ray crosses the horizon and at total
// internal reflection, so the quadrature follows those curves explicitly (an adaptive rule that
// sees only zeros on a narrow band of lost light would stop early). Its accuracy is judged by
// Smith's identity, kept + lost = 1 for smith-light, which it reproduces to 1e-6 (asserted).
struct EnergyQuadrature {
    double reflected = 0, transmitted = 0, lost = 0;
    double total() const { return reflected + transmitted; }
};

// 16-point Gauss-Legendre on [lo, hi] of a function returning three values (accumulated into out).
template <class F> void gaussLegendre16(F&& f, double lo, double hi, double out[3]) {
    static constexpr double x[8] = {0.0950125098376374, 0.2816035507792589, 0.4580167776572274, 0.6178762444026438,
                                    0.7554044083550030, 0.8656312023878318, 0.9445750230732326, 0.9894009349916499};
    static constexpr double w[8] = {0.1894506104550685, 0.1826034150449236, 0.1691565193950025, 0.1495959888165767,
                                    0.1246289712555339, 0.0951585116824928, 0.0622535239386479, 0.0271524594117541};
    const double c = 0.5 * (lo + hi), h = 0.5 * (hi - lo);
    for (int k = 0; k < 8; ++k)
        for (double sgn : {-1.0, 1.0}) {
            double v[3] = {0, 0, 0};
            f(c + sgn * h * x[k], v);
            for (int i = 0; i < 3; ++i) out[i] += w[k] * h * v[i];
        }
}

EnergyQuadrature energyQuadrature(const RoughDielectricBxDF& b, const Vec3& l) {
    const CoxMunkDistribution& d = b.slopes;
    const double su = std::sqrt(d.varianceUpwind()), sc = std::sqrt(d.varianceCrosswind());
    const bool above = l.z > 0;
    const double n1 = above ? b.nOut : b.nIn, n2 = above ? b.nIn : b.nOut;
    auto G = [&](const Vec3& out, const Vec3& m) {
        switch (b.shadowing) {
        case MicrofacetShadowing::None: return 1.0;
        case MicrofacetShadowing::SmithLight: return d.G1(l, m);
        case MicrofacetShadowing::SmithSeparable: return d.G1(l, m) * d.G1(out, m);
        }
        return 1.0;
    };
    // At whitened slopes (eta, xi): v = {reflected kept, transmitted kept, lost} per unit d eta d xi,
    // and the regime (which of those terms are present), whose changes are the integrand's jumps.
    auto point = [&](double eta, double xi, double* v) {
        const Vec2 g = d.fromWindSlopes({su * eta, sc * xi});
        const Vec3 m = normalize(Vec3{-g.x, -g.y, 1.0});
        const double lm = dot(l, m);
        if (lm * l.z <= 0) return 0;  // facet not lit
        const double F = fresnelDielectric(std::abs(lm), n1, n2);
        const double weight = d.slopePdf(g) * su * sc * std::abs(lm) / m.z / std::abs(l.z);
        int regime = 1;
        const Vec3 r = reflect(l, m);
        if (r.z * l.z > 0) {
            regime |= 2;
            if (v) v[0] += weight * F * G(r, m);
        } else if (v) {
            v[2] += weight * F * G(r, m);
        }
        Vec3 t;
        if (F < 1.0 && refract(l, lm > 0 ? m : -m, n1 / n2, &t)) {
            regime |= 4;
            if (t.z * l.z < 0) {
                regime |= 8;
                if (v) v[1] += weight * (1.0 - F) * G(t, m);
            } else if (v) {
                v[2] += weight * (1.0 - F) * G(t, m);
            }
        }
        return regime;
    };
    constexpr double L = 7.0;  // whitened slopes beyond 7 carry < 3e-12 of the mass
    // Inner integral over xi at fixed eta: the regime is scanned on a 0.1 grid, each change is
    // bisected to 1e-12, and each piece of constant regime (a smooth integrand) gets Gauss-Legendre
    // on sub-panels no wider than 1.
    auto inner = [&](double eta, double* out) {
        std::vector<double> cuts{-L};
        int prevRegime = point(eta, -L, nullptr);
        double prevXi = -L;
        for (int j = 1; j <= 140; ++j) {
            const double xi = -L + 0.1 * j;
            const int reg = point(eta, xi, nullptr);
            if (reg != prevRegime) {
                double lo = prevXi, hi = xi;
                while (hi - lo > 1e-12) {
                    const double mid = 0.5 * (lo + hi);
                    (point(eta, mid, nullptr) == prevRegime ? lo : hi) = mid;
                }
                cuts.push_back(0.5 * (lo + hi));
            }
            prevRegime = reg;
            prevXi = xi;
        }
        cuts.push_back(L);
        for (size_t k = 0; k + 1 < cuts.size(); ++k) {
            const int panels = std::max(1, static_cast<int>(std::ceil(cuts[k + 1] - cuts[k])));
            for (int p = 0; p < panels; ++p) {
                const double lo = cuts[k] + (cuts[k + 1] - cuts[k]) * p / panels;
                const double hi = cuts[k] + (cuts[k + 1] - cuts[k]) * (p + 1) / panels;
                gaussLegendre16([&](double xi, double* v) { point(eta, xi, v); }, lo, hi, out);
            }
        }
    };
    // Outer integral over eta: composite Gauss-Legendre on 0.5-wide panels. The inner integral is
    // continuous in eta, with kinks where the regime pieces are born or vanish.
    double sum[3] = {0, 0, 0};
    for (int p = 0; p < 28; ++p) gaussLegendre16(inner, -L + 0.5 * p, -L + 0.5 * (p + 1), sum);
    EnergyQuadrature e;
    e.reflected = sum[0];
    e.transmitted = sum[1];
    e.lost = sum[2];
    return e;
}

constexpr long long kEnergySamples = 100000;

struct EnergyMC {
    double mean = 0, se = 0;            // R + T and its standard error
    double reflected = 0, seReflected = 0, transmitted = 0, seTransmitted = 0;
};

// Mean of f |cos(theta_i)| / pdf over the BxDF's own samples (0 for a failed sample), Importance
// mode: an unbiased estimate of Int f |cos| d omega_i, with its standard error from the sample
// variance.
EnergyMC energyMC(const RoughDielectricBxDF& b, const Vec3& wo, long long n, uint64_t seed) {
    double s = 0, s2 = 0, r = 0, r2 = 0, t = 0, t2 = 0;
    for (long long i = 0; i < n; ++i) {
        RandomStream rs(seed, 0, static_cast<uint64_t>(i));
        const double uc = rs.uniform(), u1 = rs.uniform(), u2 = rs.uniform();
        const auto smp = b.sample(wo, uc, {u1, u2}, TransportMode::Importance);
        if (!smp) continue;
        const double w = smp->f * std::abs(smp->wi.z) / smp->pdf;
        s += w;
        s2 += w * w;
        (smp->isTransmission() ? t : r) += w;
        (smp->isTransmission() ? t2 : r2) += w * w;
    }
    const double N = static_cast<double>(n);
    auto se = [N](double sum, double sum2) { return std::sqrt(std::max(0.0, sum2 / N - sqr(sum / N)) / (N - 1)); };
    EnergyMC e;
    e.mean = s / N;
    e.se = se(s, s2);
    e.reflected = r / N;
    e.seReflected = se(r, r2);
    e.transmitted = t / N;
    e.seTransmitted = se(t, t2);
    return e;
}

}  // namespace

// White furnace. For each wind, incidence (from the air and from the water) and shadowing term,
// the Monte Carlo albedo Int (f_r + f_t) |cos(theta_i)| d omega_i (the BxDF's own sampler and pdf,
// Importance mode, 1e5 samples) must equal the quadrature over the slopes (EnergyQuadrature), and
// so must its reflected and transmitted parts. Each difference is a normal deviate of standard
// error SE (from the sample variance), rejected beyond
// z SE + 3/N + 1e-6: z at the Sidak level of the whole set (1 % family); 3/N (the rule of three)
// for events rarer than the sample shows, e.g. at normal incidence, where the smith-light weights
// are exactly 1 unless light is lost (SE = 0 when no sample saw a loss of 1e-6); 1e-6 for the
// quadrature.
// What each shadowing term conserves, from the quadrature:
//   smith-light: reflected + transmitted + wrong-side loss = 1 to 1e-6 (rough_dielectric.h's
//                derivation, Smith's identity); so R + T = 1 exactly wherever nothing is lost,
//                e.g. at normal incidence, and the loss is reported;
//   none:        R + T > 1 at 88 degrees from the air (gains energy at grazing incidence);
//   smith-separable: R + T < 1 off normal incidence (loses energy).
TEST(RoughDielectric, WhiteFurnace) {
    struct Case { double U; CoxMunkSea sea; };
    const Case cases[] = {{2.0, CoxMunkSea::Dissertation}, {6.0, CoxMunkSea::Clean}, {14.0, CoxMunkSea::Clean}};
    struct Term { MicrofacetShadowing s; std::vector<double> above, below; };
    const Term terms[] = {
        {MicrofacetShadowing::SmithLight, {0.0, 30.0, 60.0, 80.0, 88.0}, {0.0, 30.0, 45.0, 60.0, 85.0}},
        {MicrofacetShadowing::None, {0.0, 60.0, 88.0}, {30.0, 60.0, 85.0}},
        {MicrofacetShadowing::SmithSeparable, {0.0, 60.0, 88.0}, {30.0, 60.0, 85.0}}};
    const int tests = 3 * 3 * (10 + 6 + 6);  // R, T and R + T of each case
    // z with P(|N(0,1)| > z) = Sidak level: bisection on the chi-square(1) survival function.
    const double alpha = chi2::sidakLevel(0.01, tests);
    double zlo = 0, zhi = 10;
    for (int i = 0; i < 100; ++i) {
        const double mid = 0.5 * (zlo + zhi);
        (chi2::chiSquareSurvival(mid * mid, 1) > alpha ? zlo : zhi) = mid;
    }
    const double z = zhi;
    for (const Case& c : cases)
        for (const Term& term : terms) {
            const RoughDielectricBxDF b = rough(c.U, c.sea, 1.1, term.s);
            for (int side = 0; side < 2; ++side)
                for (double thDeg : side == 0 ? term.above : term.below) {
                    const double th = deg2rad(thDeg);
                    const Vec3 wo = side == 0 ? dir(th, 0.5) : dir(kPi - th, 0.5);
                    const EnergyQuadrature q = energyQuadrature(b, wo);
                    const EnergyMC mc = energyMC(b, wo, kEnergySamples, 101);
                    const std::string what = label(c.U, c.sea, thDeg, side == 0) + " " + std::string(nameOf(term.s));
                    std::printf("[ info ] energy %-44s MC R %.5f T %.5f R+T %.5f +- %.5f | quadrature R+T %.6f (R %.5f "
                                "T %.5f) lost %.2e\n",
                                what.c_str(), mc.reflected, mc.transmitted, mc.mean, mc.se, q.total(), q.reflected,
                                q.transmitted, q.lost);
                    const double slack = 3.0 / kEnergySamples + 1e-6;
                    EXPECT_LE(std::abs(mc.mean - q.total()), z * mc.se + slack) << what;
                    EXPECT_LE(std::abs(mc.reflected - q.reflected), z * mc.seReflected + slack) << what << " (R)";
                    EXPECT_LE(std::abs(mc.transmitted - q.transmitted), z * mc.seTransmitted + slack) << what << " (T)";
                    switch (term.s) {
                    case MicrofacetShadowing::SmithLight: EXPECT_NEAR(q.total() + q.lost, 1.0, 1e-6) << what; break;
                    case MicrofacetShadowing::None:
                        if (side == 0 && thDeg >= 88.0) {
                            EXPECT_GT(q.total(), 1.0) << what;
                        }
                        break;
                    case MicrofacetShadowing::SmithSeparable:
                        if (thDeg > 0.0) {
                            EXPECT_LT(q.total(), 1.0) << what;
                        }
                        break;
                    }
                }
        }
}

// With Gram-Charlier terms (10 m/s, clean sea, smith-light) the sampler still draws the Gaussian
// part and the weights carry D / D_gauss: the Monte Carlo albedo must still equal the quadrature
// over the (clipped Gram-Charlier) slopes, same rule as the white furnace (6 cases, 1 % family).
// Smith's identity is no longer exact, because the masking keeps the Gaussian Lambda: kept + lost
// is reported, not asserted.
TEST(RoughDielectric, GramCharlierWeightsAreUnbiased) {
    const RoughDielectricBxDF b = rough(10.0, CoxMunkSea::Clean, 0.3, MicrofacetShadowing::SmithLight, true);
    const double alpha = chi2::sidakLevel(0.01, 6);
    double zlo = 0, zhi = 10;
    for (int i = 0; i < 100; ++i) {
        const double mid = 0.5 * (zlo + zhi);
        (chi2::chiSquareSurvival(mid * mid, 1) > alpha ? zlo : zhi) = mid;
    }
    for (int side = 0; side < 2; ++side)
        for (double thDeg : {0.0, 30.0, 60.0}) {
            const double th = deg2rad(thDeg);
            const Vec3 wo = side == 0 ? dir(th, 1.0) : dir(kPi - th, 1.0);
            const EnergyQuadrature q = energyQuadrature(b, wo);
            const EnergyMC mc = energyMC(b, wo, kEnergySamples, 303);
            const std::string what = label(10.0, CoxMunkSea::Clean, thDeg, side == 0) + " gram-charlier";
            std::printf("[ info ] energy %-44s MC R+T %.5f +- %.5f | quadrature R+T %.6f, kept + lost %.6f\n",
                        what.c_str(), mc.mean, mc.se, q.total(), q.total() + q.lost);
            EXPECT_LE(std::abs(mc.mean - q.total()), zhi * mc.se + 3.0 / kEnergySamples + 1e-6) << what;
        }
}

// A calm sea (0.01 m/s, the dissertation's coefficients: RMS slopes 0.006 and 0.004) is the flat
// interface (digest CH5-F): the reflected fraction equals the flat Fresnel reflectance, and a
// submerged receiver looking straight up sees L_t = n^2 (1 - rho) L for a uniform sky (Radiance
// mode), 1.7577 L. Tolerance: 4 Monte Carlo standard errors plus the O(sigma^2) effect of the
// slopes on r_f (|d^2 r_f / d theta^2| < 1 for theta <= 60 deg on water, sigma^2 < 4e-5: 1e-4).
TEST(RoughDielectric, CalmSeaIsTheFlatInterface) {
    const RoughDielectricBxDF b = rough(0.01, CoxMunkSea::Dissertation, 0.0, MicrofacetShadowing::SmithLight);
    for (double thDeg : {0.0, 30.0, 60.0}) {
        const Vec3 wo = dir(deg2rad(thDeg), 0.0);
        const EnergyMC e = energyMC(b, wo, 100000, 7);
        const double F = fresnelDielectric(std::cos(deg2rad(thDeg)), 1.0, kWater);
        EXPECT_NEAR(e.reflected, F, 4 * e.seReflected + 1e-4) << thDeg;
        EXPECT_NEAR(e.transmitted, 1 - F, 4 * e.seTransmitted + 1e-4) << thDeg;
    }
    // Radiance seen from below, looking up: Int f_rad(wo, wi) |wi.z| d omega_i by the sampler.
    const Vec3 wo{0, 0, -1};
    double s = 0, s2 = 0;
    const int n = 100000;
    for (int i = 0; i < n; ++i) {
        RandomStream rs(9, 0, static_cast<uint64_t>(i));
        const double uc = rs.uniform(), u1 = rs.uniform(), u2 = rs.uniform();
        const auto smp = b.sample(wo, uc, {u1, u2}, TransportMode::Radiance);
        if (!smp || !smp->isTransmission()) continue;
        const double w = smp->f * std::abs(smp->wi.z) / smp->pdf;
        s += w;
        s2 += w * w;
    }
    const double mean = s / n, se = std::sqrt((s2 / n - mean * mean) / (n - 1));
    EXPECT_NEAR(mean, kWater * kWater * (1 - fresnelDielectric(1.0, kWater, 1.0)), 4 * se + 1e-4);
    EXPECT_NEAR(kWater * kWater * (1 - fresnelDielectric(1.0, kWater, 1.0)), 1.7577, 0.00005);
}

// Input errors: equal indices, and (through the distribution) winds outside the Cox-Munk range.
TEST(RoughDielectric, RefusesBadInput) {
    const CoxMunkDistribution d(CoxMunkParams{5.0, 0.0, CoxMunkSea::Clean, false});
    EXPECT_THROW(RoughDielectricBxDF(1.34, 1.34, d), InputError);
    EXPECT_THROW(RoughDielectricBxDF(1.0, -1.0, d), InputError);
    try {
        rough(20.0, CoxMunkSea::Clean);
        ADD_FAILURE();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("Cox-Munk range"), std::string::npos) << e.what();
    }
    // Degenerate directions give zero, not NaN.
    const RoughDielectricBxDF b = rough(5.0, CoxMunkSea::Clean);
    EXPECT_EQ(b.f({1, 0, 0}, {0, 0, 1}), 0.0);
    EXPECT_EQ(b.pdf({0, 0, 1}, {1, 0, 0}), 0.0);
    EXPECT_FALSE(b.sample({1, 0, 0}, 0.5, {0.5, 0.5}));
}
