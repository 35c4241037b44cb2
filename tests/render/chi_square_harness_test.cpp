// Self-tests of the shared chi-square harness (tests/support/chi_square.h): its special
// functions against known values, its quadrature against closed forms, and proof that it can
// fail: it must reject deliberately wrong samplers.
#include <gtest/gtest.h>

#include <cmath>

#include "core/frame.h"
#include "core/phase_functions.h"
#include "core/rng.h"
#include "core/units.h"
#include "render/sampling.h"
#include "tests/support/chi_square.h"

using namespace littoral;
namespace chi2 = littoral::testing_support::chi2;

namespace {
// The acceptance tests below (correct samplers) are 4 tests: a 1 % family-wise false alarm.
const double kHarnessAlpha = chi2::sidakLevel(0.01, 4);

Vec3 uniformSphere(RandomStream& rs) {
    const double z = 1.0 - 2.0 * rs.uniform(), phi = 2.0 * kPi * rs.uniform();
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return {r * std::cos(phi), r * std::sin(phi), z};
}
}  // namespace

// Q(1, x) = e^-x; Q(n, x) = e^-x Sum_{k<n} x^k/k!; Q(1/2, x) = erfc(sqrt x); other values from
// mpmath at 30 digits. The series and continued fraction converge to ~1e-16 relative; lgamma
// and exp add a few ulps per unit of the exponent's size, hence 1e-13 (1e-11 where the
// exponent is ~100).
TEST(ChiSquareHarness, IncompleteGammaMatchesKnownValues) {
    for (double x : {0.1, 1.0, 5.0, 50.0}) EXPECT_NEAR(chi2::regularizedGammaQ(1, x) / std::exp(-x), 1.0, 1e-13) << x;
    for (int n = 2; n <= 20; ++n)
        for (double x : {0.5, 3.0, 10.0, 40.0}) {
            double s = 0, term = 1;
            for (int k = 0; k < n; ++k) {
                s += term;
                term *= x / (k + 1);
            }
            EXPECT_NEAR(chi2::regularizedGammaQ(n, x) / (std::exp(-x) * s), 1.0, 1e-12) << n << " " << x;
            EXPECT_NEAR(chi2::regularizedGammaP(n, x) + chi2::regularizedGammaQ(n, x), 1.0, 1e-14);
        }
    for (double x : {0.01, 0.7, 2.0, 9.0}) EXPECT_NEAR(chi2::regularizedGammaQ(0.5, x) / std::erfc(std::sqrt(x)), 1.0, 1e-13);
    EXPECT_NEAR(chi2::regularizedGammaQ(7.5, 3.2) / 0.972217381418685559, 1.0, 1e-13);
    EXPECT_NEAR(chi2::regularizedGammaQ(0.3, 0.01) / 0.720759003640985154, 1.0, 1e-13);
    EXPECT_NEAR(chi2::regularizedGammaQ(250, 260) / 0.259389482607647268, 1.0, 1e-11);
    EXPECT_NEAR(chi2::regularizedGammaQ(2.5, 40) / 8.39182511483161009e-16, 1.0, 1e-12);
    // Tiny p-values stay exact (Q computed directly, not as 1 - P): chi2 = 200 with 10 dof.
    EXPECT_NEAR(chi2::chiSquareSurvival(200, 10) / 1.61393053369773048e-37, 1.0, 1e-11);
}

// Critical values of the chi-square distribution (mpmath, 30 digits).
TEST(ChiSquareHarness, ChiSquareQuantiles) {
    EXPECT_NEAR(chi2::chiSquareSurvival(3.84145882069412587, 1), 0.05, 1e-14);
    EXPECT_NEAR(chi2::chiSquareSurvival(18.3070380532751467, 10), 0.05, 1e-14);
    EXPECT_NEAR(chi2::chiSquareSurvival(124.342113404004081, 100), 0.05, 1e-13);
    EXPECT_NEAR(chi2::chiSquareSurvival(59.7030643044299308, 30), 0.001, 1e-15);
    EXPECT_NEAR(chi2::chiSquareSurvival(9.21034037197618, 2), 0.01, 1e-15);  // dof 2: Q = e^{-x/2}
}

TEST(ChiSquareHarness, SidakLevel) {
    EXPECT_NEAR(chi2::sidakLevel(0.01, 1), 0.01, 1e-17);
    EXPECT_NEAR(chi2::sidakLevel(0.05, 10), 1 - std::pow(0.95, 0.1), 1e-16);
    // Slightly less conservative than Bonferroni, never more than it.
    EXPECT_GT(chi2::sidakLevel(0.01, 20), 0.01 / 20);
    EXPECT_LT(chi2::sidakLevel(0.01, 20), 0.01 / 20 * 1.01);
}

TEST(ChiSquareHarness, QuadratureMatchesClosedForms) {
    // An integrable end singularity: Int_0^1 x^-0.9 dx = 10.
    EXPECT_NEAR(chi2::integrate([](double x) { return std::pow(x, -0.9); }, 0.0, 1.0, 1e-13, chi2::Singular::Lower), 10.0,
                1e-11);
    // A narrow interior peak (Lorentzian of width 1e-4 at 0.3): Int = atan-difference / w.
    const double w = 1e-4;
    auto lor = [&](double x) { return 1.0 / (1.0 + sqr((x - 0.3) / w)); };
    EXPECT_NEAR(chi2::integrate(lor, 0.0, 1.0, 1e-13) / (w * (std::atan(0.7 / w) + std::atan(0.3 / w))), 1.0, 1e-11);
    // A kink: Int_0^2 |x - 0.7| dx = 0.245 + 0.845.
    EXPECT_NEAR(chi2::integrate([](double x) { return std::abs(x - 0.7); }, 0.0, 2.0, 1e-13), 1.09, 1e-12);
    // Normalisation checks on the sphere: uniform sphere and cosine-weighted hemisphere.
    EXPECT_NEAR(chi2::sphereIntegral([](double, double) { return 1.0 / (4 * kPi); }), 1.0, 1e-12);
    EXPECT_NEAR(chi2::sphereIntegral([](double th, double) { return std::cos(th) / kPi; }, 0.5 * kPi), 1.0, 1e-12);
    EXPECT_NEAR(chi2::axialSphereIntegral([](double) { return 1.0 / (4 * kPi); }), 1.0, 1e-13);
}

TEST(ChiSquareHarness, PoolsSmallCells) {
    chi2::Options o;
    // Three cells of expected count 1 pool into one of expected 3, still below 5, which joins
    // the smallest other cell (expected 97 -> 100, observed 100 -> 103): two cells, dof 1.
    const auto r = chi2::testCells({1, 0, 2, 100, 95}, {1, 1, 1, 97, 100}, {}, o);
    EXPECT_EQ(r.cells, 2);
    EXPECT_EQ(r.dof, 1);
    EXPECT_NEAR(r.statistic, sqr(103 - 100.0) / 100 + sqr(95 - 100.0) / 100, 1e-12);
    // Zero-expected cells without samples are dropped; with samples they reject.
    EXPECT_EQ(chi2::testCells({50, 0, 50}, {50, 0, 50}, {}, o).cells, 2);
    EXPECT_EQ(chi2::testCells({50, 1, 49}, {50, 0, 50}, {}, o).pValue, 0.0);
}

// Correct samplers pass.
TEST(ChiSquareHarness, AcceptsCorrectSamplers) {
    chi2::Options o;
    o.samples = 200000;
    o.seed = 3;
    const auto sphere = chi2::testSphere(
        chi2::uniformEdges(0, kPi, 12), 8, Frame{}, [](RandomStream& rs) -> std::optional<Vec3> { return uniformSphere(rs); },
        [](double, double) { return 1.0 / (4 * kPi); }, o);
    EXPECT_FALSE(sphere.rejectedAt(kHarnessAlpha)) << sphere.summary();

    // A cosine-weighted hemisphere sampler about a tilted normal, binned on the hemisphere only.
    const Frame f = Frame::fromNormal(normalize(Vec3{1, 2, 3}));
    o.seed = 4;
    const auto cosine = chi2::testSphere(
        chi2::uniformEdges(0, 0.5 * kPi, 10), 12, f,
        [&](RandomStream& rs) -> std::optional<Vec3> {
            const double u1 = rs.uniform(), u2 = rs.uniform();
            return f.toWorld(render::sampleCosineHemisphere(u1, u2));
        },
        [](double th, double) { return std::cos(th) / kPi; }, o);
    EXPECT_FALSE(cosine.rejectedAt(kHarnessAlpha)) << cosine.summary();

    // A sampler that fails 10 % of the time; its pdf integrates to 0.9.
    o.seed = 5;
    auto failing = [](RandomStream& rs) -> std::optional<Vec3> {
        if (rs.uniform() < 0.1) return std::nullopt;
        return uniformSphere(rs);
    };
    const auto fr = chi2::testSphere(chi2::uniformEdges(0, kPi, 10), 6, Frame{}, failing,
                                     [](double, double) { return 0.9 / (4 * kPi); }, o);
    EXPECT_FALSE(fr.rejectedAt(kHarnessAlpha)) << fr.summary();
    EXPECT_GT(fr.failures, 19000);
    EXPECT_NEAR(chi2::sphereIntegral([](double, double) { return 0.9 / (4 * kPi); }), 0.9, 1e-12);

    // 1-D in theta.
    o.seed = 6;
    const HenyeyGreenstein hg{0.5};
    const auto r1 = chi2::testTheta(
        chi2::uniformEdges(0, kPi, 30),
        [&](RandomStream& rs) -> std::optional<double> { return chi2::thetaFromOneMinusCos(hg.sampleOneMinusCos(rs.uniform())); },
        [&](double th) { return hg.eval(std::cos(th)); }, o);
    EXPECT_FALSE(r1.rejectedAt(kHarnessAlpha)) << r1.summary();
}

// The harness can fail: each of these samplers is wrong, and the test must reject it at the
// suite's per-test level. The errors are small on purpose (a 0.02 shift of g; a 5 % error in the
// success probability), so they also show the power of 200000 samples: the p-values are
// far below any level we use.
TEST(ChiSquareHarness, RejectsWrongSamplers) {
    const double alpha = chi2::sidakLevel(0.01, 20);
    chi2::Options o;
    o.samples = 200000;
    o.seed = 7;
    // Henyey-Greenstein sampled with g + 0.02 but judged against the pdf with g.
    for (double g : {0.5, 0.92}) {
        const HenyeyGreenstein pdf{g}, wrong{g + 0.02};
        const auto r = chi2::testTheta(
            chi2::forwardPeakedThetaEdges(1e-3, 20, 0.5, 20),
            [&](RandomStream& rs) -> std::optional<double> {
                return chi2::thetaFromOneMinusCos(wrong.sampleOneMinusCos(rs.uniform()));
            },
            [&](double th) { return pdf.eval(std::cos(th)); }, o);
        EXPECT_TRUE(r.rejectedAt(alpha)) << "g " << g << ": " << r.summary();
        EXPECT_LT(r.pValue, 1e-10) << r.summary();
        // The same error seen through directions.
        const Vec3 dir = normalize(Vec3{0.2, 0.1, -1});
        const auto r2 = chi2::testSphere(
            chi2::forwardPeakedThetaEdges(1e-3, 12, 0.5, 10), 6, Frame::fromNormal(dir),
            [&](RandomStream& rs) -> std::optional<Vec3> {
                const double t = wrong.sampleOneMinusCos(rs.uniform()), phi = 2 * kPi * rs.uniform();
                const double s = std::sqrt(t * (2 - t));
                return Frame::fromNormal(dir).toWorld({s * std::cos(phi), s * std::sin(phi), 1 - t});
            },
            [&](double th, double) { return pdf.eval(std::cos(th)); }, o);
        EXPECT_TRUE(r2.rejectedAt(alpha)) << r2.summary();
    }
    // Azimuth drawn from [0, 1.9 pi) instead of [0, 2 pi): only the 2-D test can see it.
    {
        const auto r = chi2::testSphere(
            chi2::uniformEdges(0, kPi, 8), 10, Frame{},
            [](RandomStream& rs) -> std::optional<Vec3> {
                const double z = 1.0 - 2.0 * rs.uniform(), phi = 1.9 * kPi * rs.uniform();
                const double s = std::sqrt(1 - z * z);
                return Vec3{s * std::cos(phi), s * std::sin(phi), z};
            },
            [](double, double) { return 1.0 / (4 * kPi); }, o);
        EXPECT_TRUE(r.rejectedAt(alpha)) << r.summary();
    }
    // A sampler that fails 10 % of the time while its pdf claims 95 % success.
    {
        const auto r = chi2::testSphere(
            chi2::uniformEdges(0, kPi, 10), 6, Frame{},
            [](RandomStream& rs) -> std::optional<Vec3> {
                if (rs.uniform() < 0.1) return std::nullopt;
                return uniformSphere(rs);
            },
            [](double, double) { return 0.95 / (4 * kPi); }, o);
        EXPECT_TRUE(r.rejectedAt(alpha)) << r.summary();
    }
    // Directions where the pdf is zero (a hemisphere pdf, a sampler leaking below the horizon)
    // reject at once, whatever the counts.
    {
        const auto r = chi2::testSphere(
            chi2::uniformEdges(0, kPi, 8), 4, Frame{},
            [](RandomStream& rs) -> std::optional<Vec3> {
                Vec3 w = uniformSphere(rs);
                if (w.z < 0 && rs.uniform() < 0.999) w.z = -w.z;
                return w;
            },
            [](double th, double) { return th < 0.5 * kPi ? 1.0 / (2 * kPi) : 0.0; }, o);
        EXPECT_EQ(r.pValue, 0.0) << r.summary();
    }
}
