// Cox-Munk slope distribution: the published coefficients and the dissertation's figure labels,
// normalisation of p_s and of D over solid angle, Smith's projected-area identity, the
// Gram-Charlier moments, the sampler triple and its chi-square test, and the wind-range errors.
#include "render/cox_munk.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "core/cox_munk_fit.h"
#include "core/error.h"
#include "core/frame.h"
#include "core/rng.h"
#include "core/units.h"
#include "tests/support/chi_square.h"

using namespace littoral;
using namespace littoral::render;
namespace chi2 = littoral::testing_support::chi2;

namespace {

// Chi-square tests in this file: 6 (three winds x two seas/azimuths); family false-alarm 1 %.
const double kCoxMunkAlpha = chi2::sidakLevel(0.01, 6);

CoxMunkDistribution dist(double U, CoxMunkSea sea, double azimuth = 0.0, bool gc = false) {
    return CoxMunkDistribution(CoxMunkParams{U, azimuth, sea, gc});
}

// Int over the upper hemisphere of g(m) d omega_m, adaptive (chi_square.h), to relTol.
template <class G> double hemisphere(G&& g, double relTol = 1e-7) {
    return chi2::sphereIntegral(
        [&](double th, double ph) {
            return g(Vec3{std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)});
        },
        0.5 * kPi, relTol);
}

// Int over slope space of g(eta, xi) p in the wind-normalised variables eta = z_u/sigma_u,
// xi = z_c/sigma_c, on [-10, 10]^2 (the Gaussian weight beyond is below e^-50), by the trapezoidal
// rule. For a smooth integrand (Gaussian times a polynomial) step 0.025 is exact to rounding (the
// error falls as exp(-2 pi^2 / h^2)); a Gram-Charlier density clipped at zero has a kink along
// P = 0, where the rule's error is O(h^2) of the clipped mass: `kinked` uses step 0.01, for an
// error near 1e-8 (the code's own, different, quadrature of the clipped mass is exact to 1e-12).
template <class G> double slopeMoment(const CoxMunkDistribution& d, G&& g, bool kinked = false) {
    const double su = std::sqrt(d.varianceUpwind()), sc = std::sqrt(d.varianceCrosswind());
    auto f = [&](double eta, double xi) { return g(eta, xi) * d.slopePdf(d.fromWindSlopes({su * eta, sc * xi})) * su * sc; };
    const double h = kinked ? 0.01 : 0.025;
    const int n = static_cast<int>(std::lround(20.0 / h));
    double sum = 0;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j)
            sum += (i == 0 || i == n ? 0.5 : 1.0) * (j == 0 || j == n ? 0.5 : 1.0) * f(-10.0 + i * h, -10.0 + j * h);
    return sum * h * h;
}

}  // namespace

// TEST CH5-A (digest section 2): the dissertation's Fig. 5.1 labels, to their 3 printed decimals,
// from the no-offset ("dissertation") coefficients. The fit itself has no range check (30 and
// 40 m/s are beyond what a surface accepts).
TEST(CoxMunkFit, DissertationFigureLabels) {
    struct Row { double W, su, sc; };
    for (const Row r : {Row{5, 0.126, 0.098}, Row{10, 0.178, 0.139}, Row{30, 0.308, 0.240}, Row{40, 0.356, 0.277},
                        Row{2, 0.079, 0.062}, Row{4, 0.112, 0.088}, Row{6, 0.138, 0.107}, Row{8, 0.159, 0.124}}) {
        const SlopeVariances v = coxMunkSlopeVariances(r.W, CoxMunkSea::Dissertation);
        EXPECT_NEAR(std::sqrt(v.upwind), r.su, 0.0005 + 1e-12) << r.W;
        EXPECT_NEAR(std::sqrt(v.crosswind), r.sc, 0.0005 + 1e-12) << r.W;
    }
    // The printed labels do NOT follow the clean fit's crosswind offset (digest table): at 2 m/s
    // sqrt(0.003 + 0.00192 W) = 0.0827, not the printed 0.062.
    EXPECT_GT(std::abs(std::sqrt(coxMunkSlopeVariances(2, CoxMunkSea::Clean).crosswind) - 0.062), 0.02);
}

// spec/reference-data.md: clean upwind 3.16e-3 U, crosswind 0.003 + 1.92e-3 U and the separately
// fitted total 0.003 + 5.12e-3 U, which exceeds the sum of the components by 4e-5 U; slick upwind
// 0.005 + 0.78e-3 U and crosswind 0.003 + 0.84e-3 U.
TEST(CoxMunkFit, PublishedCoefficients) {
    for (double U : {0.7, 3.0, 7.23, 14.0}) {
        const SlopeVariances c = coxMunkSlopeVariances(U, CoxMunkSea::Clean);
        EXPECT_NEAR(coxMunkCleanTotalMss(U), 0.003 + 5.12e-3 * U, 1e-15);
        EXPECT_NEAR(coxMunkCleanTotalMss(U) - c.total(), 4e-5 * U, 1e-15);
        EXPECT_NEAR(c.upwind, 3.16e-3 * U, 1e-15);
        EXPECT_NEAR(c.crosswind, 0.003 + 1.92e-3 * U, 1e-15);
        const SlopeVariances s = coxMunkSlopeVariances(U, CoxMunkSea::Slick);
        EXPECT_NEAR(s.upwind, 0.005 + 0.78e-3 * U, 1e-15);
        EXPECT_NEAR(s.crosswind, 0.003 + 0.84e-3 * U, 1e-15);
    }
    const GramCharlierCoefficients g = coxMunkCleanGramCharlier(10.0);
    EXPECT_NEAR(g.c21, 0.01 - 0.086, 1e-15);
    EXPECT_NEAR(g.c03, 0.04 - 0.33, 1e-15);
    EXPECT_EQ(g.c40, 0.40);
    EXPECT_EQ(g.c22, 0.12);
    EXPECT_EQ(g.c04, 0.23);
    EXPECT_EQ(nameOf(CoxMunkSea::Dissertation), "dissertation");
    EXPECT_EQ(parseName<CoxMunkSea>("slick"), CoxMunkSea::Slick);
}

// Digest section 1.2: peak density p_s(0, 0) = 64.614 / W and glint ellipse aspect 1.2829.
TEST(CoxMunkDistribution, PeakDensityAndAspect) {
    for (double W : {0.5, 1.0, 2.0, 3.0, 5.0, 8.0}) {
        const CoxMunkDistribution d = dist(W, CoxMunkSea::Dissertation, 0.7);
        EXPECT_NEAR(d.slopePdf({0, 0}) * W, 64.614, 0.0005) << W;  // 5 printed digits
        EXPECT_NEAR(std::sqrt(d.varianceUpwind() / d.varianceCrosswind()), 1.2829, 0.00005);
    }
}

// p_s and D are normalised: Int p_s dzx dzy = 1 and Int D(m) cos(theta_m) d omega_m = 1 (the second
// is the Jacobian d omega = cos^3 dzx dzy at work), for Gaussian and Gram-Charlier densities, in any
// wind azimuth. Over slopes (slopeMoment): asserted to 1e-9 for the smooth densities and to 1e-7
// for the clipped Gram-Charlier ones (far below the clipped masses 8e-6 and 4e-4 being
// renormalised). Over solid angle: adaptive quadrature at 1e-7, asserted to 1e-6 (a wrong Jacobian
// would be off by O(sigma^2) > 1e-3).
TEST(CoxMunkDistribution, NormalisedOverSlopesAndSolidAngle) {
    // solidAngle: also integrate over solid angle (the narrowest and widest lobes, and a clipped
    // Gram-Charlier density; the Jacobian does not depend on the coefficient set).
    struct Case { double U; CoxMunkSea sea; double az; bool gc, solidAngle; };
    for (const Case c :
         {Case{0.5, CoxMunkSea::Dissertation, 0.0, false, true}, Case{2, CoxMunkSea::Dissertation, 0.3, false, false},
          Case{6, CoxMunkSea::Clean, 1.2, false, false}, Case{14, CoxMunkSea::Clean, -2.0, false, true},
          Case{5, CoxMunkSea::Slick, 0.5, false, false}, Case{5, CoxMunkSea::Clean, 0.4, true, false},
          Case{10, CoxMunkSea::Clean, 2.5, true, false}, Case{14, CoxMunkSea::Clean, 0.0, true, true}}) {
        const CoxMunkDistribution d = dist(c.U, c.sea, c.az, c.gc);
        const bool kinked = c.gc && c.U > 9.0;  // clipped (cox_munk.h)
        EXPECT_NEAR(slopeMoment(d, [](double, double) { return 1.0; }, kinked), 1.0, kinked ? 1e-7 : 1e-9) << c.U;
        if (c.solidAngle) {
            EXPECT_NEAR(hemisphere([&](const Vec3& m) { return d.D(m) * m.z; }), 1.0, 1e-6) << c.U << " gc " << c.gc;
            // The sampling density (the Gaussian part) is normalised too.
            EXPECT_NEAR(hemisphere([&](const Vec3& m) { return d.pdfNormal(m); }), 1.0, 1e-6) << c.U;
        }
    }
}

// The clipped mass Z - 1 stated in cox_munk.h: 0 below about 9 m/s, then growing.
TEST(CoxMunkDistribution, GramCharlierClipping) {
    EXPECT_EQ(dist(5, CoxMunkSea::Clean, 0, true).gramCharlierNormalization(), 1.0);
    const double z10 = dist(10, CoxMunkSea::Clean, 0, true).gramCharlierNormalization() - 1.0;
    const double z14 = dist(14, CoxMunkSea::Clean, 0, true).gramCharlierNormalization() - 1.0;
    std::printf("[ info ] Gram-Charlier clipped mass: 10 m/s %.3g, 14 m/s %.3g\n", z10, z14);
    EXPECT_NEAR(z10, 8.4e-6, 0.3e-6);
    EXPECT_NEAR(z14, 4.0e-4, 0.1e-4);
}

// With no clipping (5 m/s) the Gram-Charlier density has the moments that define its coefficients
// (Hermite orthogonality): E[eta] = E[xi] = 0, E[eta^2] = E[xi^2] = 1, skewness E[eta^3] = -c03,
// E[xi^2 eta] = -c21, excess kurtoses E[xi^4] - 3 = c40, E[eta^4] - 3 = c04,
// E[xi^2 eta^2] - 1 = c22. Quadrature: 1e-9.
TEST(CoxMunkDistribution, GramCharlierMoments) {
    const double U = 5.0;
    const CoxMunkDistribution d = dist(U, CoxMunkSea::Clean, 0.9, true);
    const GramCharlierCoefficients c = coxMunkCleanGramCharlier(U);
    auto m = [&](int pe, int px) {
        return slopeMoment(d, [&](double e, double x) { return std::pow(e, pe) * std::pow(x, px); });
    };
    EXPECT_NEAR(m(1, 0), 0.0, 1e-9);
    EXPECT_NEAR(m(0, 1), 0.0, 1e-9);
    EXPECT_NEAR(m(2, 0), 1.0, 1e-9);
    EXPECT_NEAR(m(0, 2), 1.0, 1e-9);
    EXPECT_NEAR(m(3, 0), -c.c03, 1e-9);
    EXPECT_NEAR(m(1, 2), -c.c21, 1e-9);
    EXPECT_NEAR(m(0, 4) - 3.0, c.c40, 1e-9);
    EXPECT_NEAR(m(4, 0) - 3.0, c.c04, 1e-9);
    EXPECT_NEAR(m(2, 2) - 1.0, c.c22, 1e-9);
    // Positive skewness of z_u (up-slope toward upwind) at this wind: the long tail of steep
    // downwind-facing facets (the sign convention of cox_munk.h).
    EXPECT_GT(m(3, 0), 0.1);
}

// Smith: Int G1(w, m) |w.m| [m faces w] D(m) d omega_m = |w.z| (the visible facets project onto
// the plane normal to w like the macrosurface), for directions above and below, along and across
// the wind, up to 89 degrees. Integrated over the slopes (D d omega = p_s dzx dzy / m_z, and
// |w.m| / m_z = |w_z - w_h . grad z|, whose zero line is the only kink), nested adaptive quadrature
// in the whitened slopes with the inner integral split at that line; quadrature relative 1e-10,
// asserted to 1e-8.
TEST(CoxMunkDistribution, SmithProjectedAreaIdentity) {
    for (double U : {1.0, 7.0, 14.0}) {
        const CoxMunkDistribution d = dist(U, CoxMunkSea::Clean, 0.6);
        const double su = std::sqrt(d.varianceUpwind()), sc = std::sqrt(d.varianceCrosswind());
        for (double thDeg : {0.0, 30.0, 60.0, 80.0, 89.0})
            for (double phi : {0.6, 0.6 + kPi / 2, 2.0})
                for (double side : {1.0, -1.0}) {
                    const double th = deg2rad(thDeg);
                    const Vec3 w{std::sin(th) * std::cos(phi), std::sin(th) * std::sin(phi), side * std::cos(th)};
                    auto f = [&](double eta, double xi) {
                        const Vec2 g = d.fromWindSlopes({su * eta, sc * xi});
                        const Vec3 m = normalize(Vec3{-g.x, -g.y, 1.0});
                        return d.G1(w, m) * std::abs(dot(w, m)) / m.z * d.slopePdf(g) * su * sc;
                    };
                    // grad z = eta A + xi B; the kink is where w_z = w_h . grad z.
                    const Vec2 A = d.fromWindSlopes({su, 0.0}), B = d.fromWindSlopes({0.0, sc});
                    const double wa = w.x * A.x + w.y * A.y, wb = w.x * B.x + w.y * B.y;
                    auto inner = [&](double eta) {
                        auto g = [&](double xi) { return f(eta, xi); };
                        const double k = wb != 0.0 ? (w.z - eta * wa) / wb : 1e300;
                        if (!(k > -9.0 && k < 9.0)) return chi2::integrate(g, -9.0, 9.0, 1e-11);
                        return chi2::integrate(g, -9.0, k, 1e-11) + chi2::integrate(g, k, 9.0, 1e-11);
                    };
                    const double I = chi2::integrate(inner, -9.0, 9.0, 1e-10);
                    EXPECT_NEAR(I / std::abs(w.z), 1.0, 1e-8)
                        << "U " << U << " theta " << thDeg << " phi " << phi << " side " << side;
                }
    }
}

// Smith's Lambda: 0 at normal incidence; against its derivation from the slope component s along
// w's azimuth (variance sigma^2, a = cot(theta) / (sqrt(2) sigma)): 1 + Lambda =
// E[max(0, cot(theta) - s)] / cot(theta) = Phi(sqrt(2) a) + phi(sqrt(2) a) / (sqrt(2) a), with the
// standard normal Phi and phi; the effective roughness is the slope variance along w's azimuth.
TEST(CoxMunkDistribution, LambdaValues) {
    EXPECT_EQ(beckmannLambda(std::numeric_limits<double>::infinity()), 0.0);
    for (double a : {0.05, 0.3, 1.0, 2.0, 4.0}) {
        const double x = std::sqrt(2.0) * a;
        const double Phi = 0.5 * std::erfc(-x / std::sqrt(2.0)), phi = std::exp(-0.5 * x * x) / std::sqrt(2 * kPi);
        EXPECT_NEAR(beckmannLambda(a), Phi + phi / x - 1.0, 1e-13 * (1 + 1 / a)) << a;
    }
    EXPECT_NEAR(beckmannLambda(1.0), 0.0251273, 1e-7);
    const CoxMunkDistribution d = dist(8, CoxMunkSea::Clean, 0.0);
    const double th = deg2rad(70);
    // Along the wind axis (x): a = cot(theta) / sqrt(2 sigma_u^2).
    EXPECT_NEAR(d.lambda({std::sin(th), 0, std::cos(th)}),
                beckmannLambda(1.0 / std::tan(th) / std::sqrt(2 * d.varianceUpwind())), 1e-14);
    EXPECT_NEAR(d.lambda({0, std::sin(th), -std::cos(th)}),
                beckmannLambda(1.0 / std::tan(th) / std::sqrt(2 * d.varianceCrosswind())), 1e-14);
    EXPECT_NEAR(d.varianceAlong(0.0), d.varianceUpwind(), 1e-16);
    EXPECT_NEAR(d.varianceAlong(kPi / 2), d.varianceCrosswind(), 1e-16);
}

// The sampler triple: invertSlope(sampleSlope(u)) = u, sampleNormal(invertNormal(m)) = m.
TEST(CoxMunkDistribution, SamplerInverts) {
    const CoxMunkDistribution d = dist(6, CoxMunkSea::Clean, 2.2);
    for (int i = 0; i < 2000; ++i) {
        RandomStream rs(3, 0, static_cast<uint64_t>(i));
        const Vec2 u{rs.uniform(), rs.uniform()};
        const Vec2 back = d.invertSlope(d.sampleSlope(u));
        EXPECT_NEAR(back.x, u.x, 1e-12);
        EXPECT_NEAR(std::fmod(back.y - u.y + 1.5, 1.0) - 0.5, 0.0, 1e-12);
        const Vec3 m = d.sampleNormal(u);
        const Vec3 m2 = d.sampleNormal(d.invertNormal(m));
        EXPECT_NEAR(length(m2 - m), 0.0, 1e-12);
    }
}

// Sampled normals follow pdfNormal = D_gauss(m) cos(theta_m): chi-square through the shared
// harness, theta bins geometric inside the lobe (scale = the larger RMS slope), 16 azimuth bins to
// see the anisotropy and the wind azimuth.
TEST(CoxMunkDistribution, NormalSamplingMatchesPdf) {
    struct Case { double U; CoxMunkSea sea; double az; };
    for (const Case c : {Case{0.5, CoxMunkSea::Dissertation, 0.0}, Case{3, CoxMunkSea::Dissertation, 1.0},
                         Case{8, CoxMunkSea::Clean, 2.0}, Case{14, CoxMunkSea::Clean, -0.5},
                         Case{6, CoxMunkSea::Slick, 0.3}, Case{10, CoxMunkSea::Clean, 0.8}}) {
        const CoxMunkDistribution d = dist(c.U, c.sea, c.az);
        const double s = std::atan(std::sqrt(std::max(d.varianceUpwind(), d.varianceCrosswind())));
        auto edges = chi2::forwardPeakedThetaEdges(0.05 * s, 12, std::min(4.0 * s, 1.2), 6);
        edges.back() = 0.5 * kPi;  // normals stay in the upper hemisphere
        chi2::Options o;
        o.samples = 200000;
        o.seed = 11;
        o.relTol = 1e-8;
        const auto r = chi2::testSphere(
            edges, 16, Frame{},
            [&](RandomStream& rs) -> std::optional<Vec3> {
                const double u1 = rs.uniform(), u2 = rs.uniform();
                return d.sampleNormal({u1, u2});
            },
            [&](double th, double ph) {
                return d.pdfNormal({std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)});
            },
            o);
        std::printf("[ info ] chi2 normals U %.1f %s: p = %.3g (dof %d)\n", c.U, std::string(nameOf(c.sea)).c_str(),
                    r.pValue, r.dof);
        EXPECT_FALSE(r.rejectedAt(kCoxMunkAlpha)) << r.summary();
    }
}

// Winds outside [0.01, 14] m/s, and Gram-Charlier terms with other than the clean fit, are input
// errors that say what is allowed.
TEST(CoxMunkDistribution, RefusesBadInput) {
    for (double U : {0.0, 0.005, 14.5, 40.0, std::nan("")}) {
        try {
            dist(U, CoxMunkSea::Clean);
            ADD_FAILURE() << "accepted " << U;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("allowed 0.01 to 14 m/s"), std::string::npos) << e.what();
        }
    }
    try {
        dist(5, CoxMunkSea::Slick, 0.0, true);
        ADD_FAILURE();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("clean"), std::string::npos) << e.what();
    }
    EXPECT_THROW(CoxMunkDistribution::fromVariances(0.0, 0.01, 0.0), InputError);
    EXPECT_NO_THROW(dist(0.01, CoxMunkSea::Dissertation));
    EXPECT_NO_THROW(dist(14, CoxMunkSea::Slick));
}
