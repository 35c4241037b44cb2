// Self-tests of the analytic references the renderer's tests use: the Appendix A two-stream model
// (tests/support/two_stream.h), the Mobley et al. (1993) table (pipelines/reference/mobley1993.h) and
// the Gordon and Ding (1992) self-shading error (pipelines/reference/gordon_ding.h).
#include <gtest/gtest.h>

#include <cmath>

#include "core/units.h"
#include "tests/support/chi_square.h"
#include "pipelines/reference/gordon_ding.h"
#include "pipelines/reference/mobley1993.h"
#include "tests/support/two_stream.h"

using namespace littoral;
namespace ts = littoral::testing_support::two_stream;
namespace m93 = littoral::reference::mobley1993;
namespace gd = littoral::reference::gordon_ding;
namespace chi2 = littoral::testing_support::chi2;

namespace {
// Half a unit in the last of `digits` significant digits of `printed`: the tolerance of a value
// that is given "to the digits given".
double halfUnit(double printed, int digits) {
    return 0.5 * std::pow(10.0, std::floor(std::log10(std::abs(printed))) - digits + 1);
}
struct Printed {
    double v;
    int digits;
};
}  // namespace

// spec/seed-ch06-07-appA.md section 3.9, check values (L_n = 1, mu = 1): all four rows, every
// column, each to half a unit of its last printed digit.
TEST(TwoStream, ReproducesDigestCheckValues) {
    struct Row {
        double w0, mubar, tauStar, r, rb;
        Printed gamma, rho, a, d, lPlus0, lMinusStar, lAngular, inscatter, ed;
    };
    const Row rows[] = {
        {0.5, 0.5, 2, 0, 0, {1.41421, 6}, {0.171573, 6}, {-0.00059945, 5}, {1.0001, 5}, {0.170991, 6}, {0.0573717, 6},
         {0.188023, 6}, {0.119816, 6}, {0.326817, 6}},
        {0.5, 0.5, 2, 0.5, 0.5, {1.41421, 6}, {0.171573, 6}, {0.00125475, 6}, {0.999785, 6}, {0.172791, 6},
         {0.0627353, 6}, {0.191781, 6}, {0.121468, 6}, {0.342105, 6}},
        {0.9, 0.6, 1, 1.0, 1.2, {0.527046, 6}, {0.519494, 6}, {0.474503, 6}, {0.753499, 6}, {0.865941, 6},
         {0.862379, 6}, {0.891972, 6}, {0.52264, 5}, {2.72739, 6}},
        {0.952381, 0.5446, 1.47, 1.0, 1.0892, {0.400694, 6}, {0.641743, 6}, {0.353764, 6}, {0.772974, 6},
         {0.849815, 6}, {0.838051, 6}, {0.868027, 6}, {0.646639, 6}, {2.66253, 6}},
    };
    for (const Row& r : rows) {
        ts::Params p;
        p.w0 = r.w0;
        p.mubar = r.mubar;
        p.tauStar = r.tauStar;
        p.bottomReflectance = r.r;  // R_b defaults to 2 r mubar, which the table's R_b column equals
        const ts::Solution s(p);
        EXPECT_NEAR(s.Rb(), r.rb, 1e-12);
        auto check = [&](double ours, Printed ref, const char* what) {
            EXPECT_NEAR(ours, ref.v, halfUnit(ref.v, ref.digits)) << what << " (w0 " << r.w0 << ")";
        };
        check(s.gamma(), r.gamma, "Gamma");
        check(s.rho(), r.rho, "rho_inf");
        check(s.A(), r.a, "A");
        check(s.D(), r.d, "D");
        check(s.LplusDave(0), r.lPlus0, "L+_dave(0)");
        check(s.LminusDave(r.tauStar), r.lMinusStar, "L-_dave(tau*)");
        check(s.LminusAngular(r.tauStar, 1.0), r.lAngular, "L-(tau*, 1) (A.42)");
        check(s.inscatterUp(0, 1.0), r.inscatter, "in-scatter up (A.44)");
        check(s.Ed(r.tauStar), r.ed, "E_d(tau*)");
    }
}

// The closed forms against brute-force numerical integration of their defining integrals (the
// harness's adaptive quadrature, relative accuracy ~1e-12): A.31 for L-(tau, mu), A.32/A.44 for
// the in-scatter, the mu-integral for E_d. Tolerance 1e-10 relative. Includes mu = 1/Gamma,
// where the printed A.42/A.44 have removable singularities, and anisotropic scattering (b != 1/2).
TEST(TwoStream, ClosedFormsMatchNumericalIntegration) {
    for (double b : {0.5, 0.3}) {
        for (const ts::Params& base : {ts::Params{0.5, 0.5, 2, 0, NAN, 1, 0.5}, ts::Params{0.9, 0.6, 1, 1.0, NAN, 1, 0.5},
                                       ts::Params{0.2, 0.7, 5, 0.5, NAN, 2.5, 0.5}}) {
            ts::Params p = base;
            p.backscatter = b;
            const ts::Solution s(p);
            for (double tau : {0.3 * p.tauStar, p.tauStar})
                for (double mu : {0.05, 0.3, 1.0 / s.gamma(), 0.8, 1.0}) {
                    if (mu > 1) continue;
                    auto down = [&](double t) { return s.sourceDown(t) / mu * std::exp(-(tau - t) / mu); };
                    const double lMinus = p.Ln * std::exp(-tau / mu) + chi2::integrate(down, 0.0, tau, 1e-13);
                    EXPECT_NEAR(s.LminusAngular(tau, mu) / lMinus, 1.0, 1e-10) << "b " << b << " tau " << tau << " mu " << mu;
                    auto up = [&](double t) { return s.sourceUp(t) / mu * std::exp(-(t - tau) / mu); };
                    const double in = chi2::integrate(up, tau, p.tauStar, 1e-13);
                    EXPECT_NEAR(s.inscatterUp(tau, mu), in, 1e-10 * in + 1e-15) << "b " << b << " tau " << tau << " mu " << mu;
                }
            auto edIntegrand = [&](double mu) { return s.LminusAngular(p.tauStar, mu) * mu; };
            EXPECT_NEAR(s.Ed(p.tauStar) / (2 * kPi * chi2::integrate(edIntegrand, 0.0, 1.0, 1e-13)), 1.0, 1e-10);
            // Continuity through mu = 1/Gamma (the removable singularity), where it lies in (0, 1).
            const double mu0 = 1.0 / s.gamma();
            if (mu0 < 1) {
                EXPECT_NEAR(s.LminusAngular(p.tauStar, mu0 * (1 + 1e-9)) / s.LminusAngular(p.tauStar, mu0), 1.0, 1e-8);
                EXPECT_NEAR(s.inscatterUp(0, mu0 * (1 - 1e-9)) / s.inscatterUp(0, mu0), 1.0, 1e-8);
            }
        }
    }
}

// The stream solution satisfies the two-stream equations (7.12, 7.13 with S* = 0) and both
// boundary conditions. Central differences with h = 1e-4 carry a truncation error of
// h^2 Gamma^3 L / 6 < 1e-8 for these parameters and a rounding error of ~1e-12: tolerance 1e-7.
TEST(TwoStream, SatisfiesEquationsAndBoundaryConditions) {
    for (double b : {0.5, 0.2}) {
        ts::Params p{0.8, 0.55, 3, 0.7, NAN, 1.3, b};
        const ts::Solution s(p);
        EXPECT_NEAR(s.LminusDave(0), p.Ln, 1e-14);
        EXPECT_NEAR(s.LplusDave(p.tauStar), s.Rb() * s.LminusDave(p.tauStar), 1e-14);
        const double h = 1e-4;
        for (double tau : {0.1, 1.0, 2.9}) {
            const double dMinus = (s.LminusDave(tau + h) - s.LminusDave(tau - h)) / (2 * h);
            const double dPlus = (s.LplusDave(tau + h) - s.LplusDave(tau - h)) / (2 * h);
            const double lm = s.LminusDave(tau), lp = s.LplusDave(tau);
            EXPECT_NEAR(-p.mubar * dMinus, lm - p.w0 * (1 - b) * lm - p.w0 * b * lp, 1e-7) << tau;
            EXPECT_NEAR(p.mubar * dPlus, lp - p.w0 * (1 - b) * lp - p.w0 * b * lm, 1e-7) << tau;
        }
        // Irradiance in the two-stream sense: E = 2 pi mubar L_dave.
        EXPECT_NEAR(s.EdTwoStream(0), 2 * kPi * p.mubar * p.Ln, 1e-14);
    }
}

// The printed A.36 coupling 2 pi r mubar gives negative radiances for bright bottoms: with
// w0 = 0.9, mubar = 0.6, tau* = 1, r = 1, L+(0) = -1.716 (digest, 4 digits). The default, corrected
// coupling 2 r mubar gives the positive 0.865941 of the check table.
TEST(TwoStream, LiteralA36CouplingIsNotTheDefault) {
    ts::Params p{0.9, 0.6, 1, 1.0, NAN, 1, 0.5};
    EXPECT_GT(ts::Solution(p).LplusDave(0), 0.0);
    p.Rb = 2 * kPi * 1.0 * 0.6;
    EXPECT_NEAR(ts::Solution(p).LplusDave(0), -1.716, halfUnit(1.716, 4));
}

// ---------------------------------------------------------------------------------------------
// Mobley et al. (1993)

TEST(Mobley1993, TableAndTolerance) {
    EXPECT_EQ(std::size(m93::kRows), 8u);
    const m93::Row* r = m93::find(1, 0.9, 5);
    ASSERT_NE(r, nullptr);
    EXPECT_DOUBLE_EQ(r->Ed.mean, 4.33e-2);
    EXPECT_DOUBLE_EQ(r->Lu.sOverMean, 0.052);
    EXPECT_EQ(m93::find(2, 0.9, 5), nullptr);
    // max(3 s/m, 3 se/mean): the published spread dominates a precise run, the run's own error
    // an imprecise one.
    EXPECT_DOUBLE_EQ(m93::tolerance(r->Ed, 0.0), 3 * 0.003);
    EXPECT_NEAR(m93::tolerance(r->Ed, 0.01 * 4.33e-2), 0.03, 1e-15);
    // Problem 6, tau = 1, Ed: s/mean printed 0.000; the mean 1.62e-1 is rounded by up to 0.31 %.
    const m93::Row* p6 = m93::find(6, 0.2, 1);
    ASSERT_NE(p6, nullptr);
    EXPECT_NEAR(m93::roundingHalfUnit(p6->Ed), 0.0005 / 0.162, 1e-15);
    EXPECT_NEAR(m93::toleranceWithRounding(p6->Ed, 1e-4), 3e-4 / 0.162 + 0.0005 / 0.162, 1e-15);
}

// The table is physically consistent: (1) at the problem-6 bottom (Lambertian, R = 0.5) the
// reflected field is isotropic, so Eu = R Ed, Eou = 2 Eu = Ed and Lu = Eu/pi, within the printed
// spreads (3 s/mean of each cell, plus rounding); (2) Ed is never below the unscattered sun beam,
// E_d0 (1 - r_F) exp(-tau/mu_w), with r_F the Fresnel reflectance of unpolarised light at 60 deg
// (n = 1.34) and mu_w the cosine of the refracted angle; (3) Ed decreases with depth.
TEST(Mobley1993, TableIsPhysicallyConsistent) {
    const m93::Row* bottom = m93::find(6, 0.2, 5);
    ASSERT_NE(bottom, nullptr);
    const double ed = bottom->Ed.mean, eu = m93::kProblem6BottomReflectance * ed;
    EXPECT_NEAR(bottom->Eou.mean / (2 * eu), 1.0,
                3 * (bottom->Eou.sOverMean + bottom->Ed.sOverMean) + m93::roundingHalfUnit(bottom->Eou) +
                    m93::roundingHalfUnit(bottom->Ed));
    EXPECT_NEAR(bottom->Lu.mean / (eu / kPi), 1.0,
                3 * (bottom->Lu.sOverMean + bottom->Ed.sOverMean) + m93::roundingHalfUnit(bottom->Lu) +
                    m93::roundingHalfUnit(bottom->Ed));

    const double n = m93::kWaterIndex, ti = deg2rad(m93::kSunZenithDeg);
    const double tt = std::asin(std::sin(ti) / n);
    const double rs = sqr((std::cos(ti) - n * std::cos(tt)) / (std::cos(ti) + n * std::cos(tt)));
    const double rp = sqr((n * std::cos(ti) - std::cos(tt)) / (n * std::cos(ti) + std::cos(tt)));
    const double transmitted = m93::kEdAboveSurface * (1 - 0.5 * (rs + rp));
    double previous = 1e9;
    int lastProblem = 0;
    double lastW0 = 0;
    for (const m93::Row& r : m93::kRows) {
        const double direct = transmitted * std::exp(-r.tau / std::cos(tt));
        EXPECT_GE(r.Ed.mean * (1 + m93::roundingHalfUnit(r.Ed)), direct) << r.problem << " " << r.w0 << " " << r.tau;
        if (r.problem == lastProblem && r.w0 == lastW0) {
            EXPECT_LT(r.Ed.mean, previous);
        }
        previous = r.Ed.mean;
        lastProblem = r.problem;
        lastW0 = r.w0;
    }
}

// ---------------------------------------------------------------------------------------------
// Gordon and Ding (1992)

TEST(GordonDing, CoefficientsAndInterpolation) {
    EXPECT_DOUBLE_EQ(gd::kDoublePrimeSun(gd::Quantity::Lu, 30), 2.23);
    EXPECT_DOUBLE_EQ(gd::kDoublePrimeSun(gd::Quantity::Eu, 60), 2.47);
    EXPECT_NEAR(gd::kDoublePrimeSun(gd::Quantity::Eu, 45), 0.5 * (2.80 + 2.64), 1e-15);
    EXPECT_NEAR(gd::kDoublePrimeSun(gd::Quantity::Lu, 37), 2.23 + 0.7 * (2.29 - 2.23), 1e-15);
    EXPECT_DOUBLE_EQ(gd::kDoublePrimeSun(gd::Quantity::Lu, 90), 2.45);
    EXPECT_DOUBLE_EQ(gd::kPrimeSky(gd::Quantity::Lu), 4.61);
    EXPECT_DOUBLE_EQ(gd::kPrimeSky(gd::Quantity::Eu), 2.70);
    // theta_w = asin(sin 30 / 1.33) = 22.0824 deg.
    EXPECT_NEAR(rad2deg(gd::refractedZenithRad(30)), 22.0824, 5e-5);
}

// epsilon = 1 - exp(-k' a R) written out: Lu, theta_0 = 30 deg, a = 0.1 m^-1, R = 0.05 m gives
// k' = 2.23/tan(22.08 deg) = 5.4966 and epsilon = 0.027109; the sun/sky blend is a weighted mean.
TEST(GordonDing, SelfShadingError) {
    const double a = 0.1, r = 0.05;
    const double kp = 2.23 / std::tan(std::asin(0.5 / 1.33));
    EXPECT_NEAR(gd::epsilonSun(gd::Quantity::Lu, 30, a, r), 1 - std::exp(-kp * a * r), 1e-15);
    EXPECT_NEAR(gd::epsilonSun(gd::Quantity::Lu, 30, a, r), 0.027109, 5e-7);
    EXPECT_NEAR(gd::epsilonSky(gd::Quantity::Eu, a, r), 1 - std::exp(-2.70 * a * r), 1e-15);
    const double es = gd::epsilonSun(gd::Quantity::Eu, 50, a, r), ek = gd::epsilonSky(gd::Quantity::Eu, a, r);
    EXPECT_DOUBLE_EQ(gd::epsilon(gd::Quantity::Eu, 50, a, r, 0.0), es);
    EXPECT_NEAR(gd::epsilon(gd::Quantity::Eu, 50, a, r, 1.0), 0.5 * (es + ek), 1e-16);
    EXPECT_NEAR(gd::epsilon(gd::Quantity::Eu, 50, a, r, 1e12), ek, 1e-12);
    // Small a R: epsilon ~ k' a R (second-order term k'^2 (aR)^2 / 2, relative 3e-7 here).
    EXPECT_NEAR(gd::epsilonSun(gd::Quantity::Lu, 40, 1e-7, 1.0) / (gd::kPrimeSun(gd::Quantity::Lu, 40) * 1e-7), 1.0, 1e-6);
    // Zenith sun: the shadow lies straight below, k' -> infinity.
    EXPECT_EQ(gd::epsilonSun(gd::Quantity::Lu, 0, a, r), 1.0);
    EXPECT_EQ(gd::epsilonSun(gd::Quantity::Lu, 0, 0.0, r), 0.0);
    EXPECT_LT(gd::epsilonSun(gd::Quantity::Lu, 60, a, r), gd::epsilonSun(gd::Quantity::Lu, 20, a, r));
}
