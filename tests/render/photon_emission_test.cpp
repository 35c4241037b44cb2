// Photon emission (render/photon_pass.h: PhotonSource, emitPhoton) through the shared chi-square
// harness (issue 17), and the emission's normalisation: the density of emitted power must integrate
// to the sources' flux.
//
// The scene: a flat Lambertian floor at z = 0 that covers the domain [0, 4] x [0, 2] m exactly
// (photons starting near its edges reach it through the periodic-air wrap), lit by a sun at 35 deg
// from the zenith and a uniform sky, in two bands whose sun and sky spectra differ. What the test
// expects is derived here from the source model, never from the sampler:
//  * landing points uniform over the floor, i.e. the domain (cells of equal area): the periodic
//    air wraps a photon that would leave the plan view before its first hit;
//  * sun photons travel along -w, w uniform over the disc's cone (equal-solid-angle rings);
//  * sky photons travel along -w, w cosine-weighted over the upper hemisphere: P(theta < x) =
//    sin^2 x;
//  * the source is chosen with P(sun) = Phi_sun / (Phi_sun + Phi_sky), both band-averaged, with
//    Phi_sun,b = E_sun,b cos(theta_sun) A and Phi_sky,b = pi L_sky,b A;
//  * each photon carries power_b = Phi_source,b / (P(source) Phi_mean), so that
//    E[power_b] Phi_mean = Phi_sun,b + Phi_sky,b: the emitted power integrates to the flux.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

#include "core/frame.h"
#include "core/rng.h"
#include "core/units.h"
#include "render/photon_pass.h"
#include "render/scene.h"
#include "tests/render/render_test_scenes.h"
#include "tests/support/chi_square.h"

using namespace littoral;
using namespace littoral::render;
using namespace littoral::render::testing;
namespace chi2 = littoral::testing_support::chi2;

namespace {

// Family-wise false-alarm probability 1 % over this file's four acceptance tests (positions, sun
// directions, sky directions, the sun fraction): Sidak's level 1 - 0.99^(1/4) = 2.5e-3 each.
const double kEmissionAlpha = chi2::sidakLevel(0.01, 4);
constexpr double kSunZenith = 35.0 * kPi / 180.0;
constexpr double kHalfAngle = 0.5 * 0.53 * kPi / 180.0;
const double kSunE[2] = {1.6, 0.9};     // W m^-2 um^-1 on a plane normal to the beam
const double kSkyL[2] = {0.05, 0.12};   // W m^-2 sr^-1 um^-1

struct Fixture {
    ir::SceneIR ir;
    std::unique_ptr<Scene> scene;
    PhotonSource src;
    BandGroup g{0, 2};
    Fixture() {
        ir.name = "emission";
        ir.render.bands = {Band{0.40, 0.50}, Band{0.50, 0.60}};
        ir.domain = {0, 4, 0, 2, false};
        ir.sun.enabled = true;
        ir.sun.zenith = kSunZenith;
        ir.sun.azimuth = 0.7;
        ir.sun.halfAngle = kHalfAngle;
        ir.sun.irradiance = Spectrum::tabulated({0.40, 0.60}, {kSunE[0], kSunE[1]}, "sun");
        ir.sky.radiance = Spectrum::tabulated({0.40, 0.60}, {kSkyL[0], kSkyL[1]}, "sky");
        ir.materials.push_back(material("floor", ir::Material::Type::Lambertian, ir::Material::Solver::SurfacePM, 0.5));
        ir.meshes.push_back(meshOf("floor", grid(0, 4, 0, 2, 0.0, 4, 2, [](int, int) { return uint16_t{0}; }), {"floor"}));
        scene = std::make_unique<Scene>(ir, ".");
        src = PhotonSource::of(*scene, g);
    }
    EmittedPhoton emit(uint64_t seed, uint64_t i) const {
        RandomStream rng(seed, 7, i);
        return emitPhoton(*scene, src, rng);
    }
};

const Fixture& fixture() {
    static const Fixture f;
    return f;
}

}  // namespace

TEST(PhotonEmission, SourceFluxesAndSunProbabilityFromTheSourceModel) {
    const Fixture& f = fixture();
    const double A = 8.0;
    // The spectra are linear over [0.40, 0.60]: the band averages over [0.40, 0.50] and
    // [0.50, 0.60] are their values at 0.45 and 0.55, (3 v0 + v1) / 4 and (v0 + 3 v1) / 4.
    const double sunB[2] = {(3 * kSunE[0] + kSunE[1]) / 4, (kSunE[0] + 3 * kSunE[1]) / 4};
    const double skyB[2] = {(3 * kSkyL[0] + kSkyL[1]) / 4, (kSkyL[0] + 3 * kSkyL[1]) / 4};
    double sumSun = 0, sumSky = 0;
    for (int b = 0; b < 2; ++b) {
        const double phiSun = sunB[b] * std::cos(kSunZenith) * A, phiSky = kPi * skyB[b] * A;
        EXPECT_NEAR(f.src.sunFlux[b], phiSun, 1e-12 * phiSun) << b;
        EXPECT_NEAR(f.src.skyFlux[b], phiSky, 1e-12 * phiSky) << b;
        sumSun += phiSun;
        sumSky += phiSky;
    }
    EXPECT_NEAR(f.src.pSun, sumSun / (sumSun + sumSky), 1e-12);
    EXPECT_NEAR(f.src.meanFlux, (sumSun + sumSky) / 2, 1e-12);
}

TEST(PhotonEmission, LandingPointsAreUniformOverTheDomain) {
    // The sources light an infinite plane of which the domain is one period: a photon that would
    // leave the domain's plan view before its first hit continues from the opposite side, so the
    // points where photons land on the floor (z = 0, covering the domain) are uniform over it.
    const Fixture& f = fixture();
    // 8 x 4 cells of 0.5 m: each holds 1/32 of the photons. 256 000 photons: 8000 expected per cell.
    constexpr int kN = 256000, kX = 8, kY = 4;
    std::vector<double> observed(kX * kY + 1, 0), expected(kX * kY + 1, kN / double(kX * kY));
    expected.back() = 0;  // a start outside the domain's plan view is impossible
    std::vector<std::string> labels;
    for (int k = 0; k <= kX * kY; ++k) labels.push_back(k < kX * kY ? "cell " + std::to_string(k) : "outside");
    for (int i = 0; i < kN; ++i) {
        const Ray r = f.emit(11, i).ray;
        ASSERT_LT(r.d.z, 0);
        const double t = -r.o.z / r.d.z;
        const Point3 o = r.at(t);
        const int cx = static_cast<int>(std::floor(o.x / 0.5)), cy = static_cast<int>(std::floor(o.y / 0.5));
        if (cx < 0 || cx >= kX || cy < 0 || cy >= kY) observed.back() += 1;
        else observed[cy * kX + cx] += 1;
    }
    const auto res = chi2::testCells(observed, expected, labels, chi2::Options{});
    std::printf("[ info ] emission landing points: p = %.3g (dof %d)\n", res.pValue, res.dof);
    EXPECT_FALSE(res.rejectedAt(kEmissionAlpha)) << res.summary();
}

// Importance emission (render/photon_pass.h): a pilot in which only the western half of the
// cells stored photons gives those cells p_c = 0.9 / 512 + 0.1 / 1024 each, so 95 % of the photons
// start there, with weight (1 / N) / p_c = 1 / 1.9; the others weigh 10. The mean weight is 1
// whatever the pilot said (sum_c p_c w_c = 1): the estimate is unchanged. 200 000 photons: the
// western share and the mean weight each within 4 of their standard errors (binomial, and the
// weights' spread over sqrt(n)).
TEST(PhotonEmission, ImportanceFollowsThePilotAndKeepsTheMeanWeight) {
    const Fixture& f = fixture();
    constexpr int K = EmissionImportance::kCells, N = EmissionImportance::N;
    // A long pilot (10^6 photons per cell), so that the 16-photon prior that shrinks each cell's
    // share toward the mean moves the weights by under 2e-4 of themselves.
    std::vector<uint64_t> emitted(2 * N, 1000000), stored(2 * N, 0);
    for (int s = 0; s < 2; ++s)
        for (int c = 0; c < N; ++c)
            if (c % K < K / 2) stored[s * N + c] = 312500;
    const EmissionImportance imp = EmissionImportance::fromPilot(emitted, stored);
    EXPECT_NEAR(imp.weight[0][0], 1 / 1.9, 2e-4 / 1.9);
    EXPECT_NEAR(imp.weight[0][K - 1], 10.0, 2e-3);
    constexpr int n = 200000;
    double west = 0, sumW = 0, sumW2 = 0;
    for (int i = 0; i < n; ++i) {
        RandomStream a(5, 7, i), b(5, 7, i);
        const EmittedPhoton e = emitPhoton(*f.scene, f.src, a, &imp), u = emitPhoton(*f.scene, f.src, b);
        ASSERT_EQ(e.fromSun, u.fromSun);
        const double w = e.power[0] / u.power[0];
        EXPECT_NEAR(e.power[1] / u.power[1], w, 1e-12 * w);
        west += (e.cell % K) < K / 2;
        sumW += w, sumW2 += w * w;
    }
    const double share = west / n, seShare = std::sqrt(0.95 * 0.05 / n);
    const double meanW = sumW / n, seW = std::sqrt((sumW2 / n - meanW * meanW) / (n - 1));
    EXPECT_NEAR(share, 0.95, 4 * seShare);
    EXPECT_NEAR(meanW, 1.0, 4 * seW);
    std::printf("[ info ] importance emission: %.4f of the photons start in the storing half (0.95), mean weight "
                "%.4f +- %.4f\n", share, meanW, seW);
}

namespace {
// Directions of the photons emitted from one source (the travel direction reversed: toward the
// source), as chi-square results of the sun disc and of the sky hemisphere.
struct DirectionTests {
    chi2::ChiSquareResult sun, sky;
    long long sunCount = 0, total = 0;
};
DirectionTests directionTests(long long n, uint64_t seed, double skyWrongPower = 1.0) {
    const Fixture& f = fixture();
    const Vec3 toSun = f.scene->sun().direction;
    const Frame sunFrame = Frame::fromNormal(toSun);
    // Sun: 10 rings of equal solid angle in the cone, 12 azimuth sectors: equal probabilities.
    constexpr int kRings = 10, kSectors = 12;
    const double cosMax = std::cos(kHalfAngle);
    std::vector<double> sunObs(kRings * kSectors + 1, 0), skyObs;
    // Sky: theta bins of the cosine-weighted hemisphere, P(theta < x) = sin^2 x.
    const std::vector<double> skyEdges = chi2::uniformEdges(0, 0.5 * kPi, 18);
    skyObs.assign(skyEdges.size(), 0);  // bins + remainder (below the horizon: impossible)
    DirectionTests out;
    for (long long i = 0; i < n; ++i) {
        const EmittedPhoton e = f.emit(seed, static_cast<uint64_t>(i));
        const Vec3 w = -e.ray.d;
        ++out.total;
        if (e.fromSun) {
            ++out.sunCount;
            const Vec3 l = sunFrame.toLocal(w);
            const double u = (1.0 - std::min(1.0, l.z)) / (1.0 - cosMax);  // uniform in [0, 1) inside the cone
            const double phi = std::atan2(l.y, l.x) + kPi;
            const int ring = static_cast<int>(u * kRings), sector = std::min(kSectors - 1, static_cast<int>(phi / (2 * kPi) * kSectors));
            if (ring < 0 || ring >= kRings) sunObs.back() += 1;
            else sunObs[ring * kSectors + sector] += 1;
        } else {
            const double th = std::acos(std::clamp(w.z, -1.0, 1.0));
            size_t k = 0;
            while (k + 1 < skyEdges.size() && th >= skyEdges[k + 1]) ++k;
            if (w.z <= 0 || k + 1 >= skyEdges.size()) skyObs.back() += 1;
            else skyObs[k] += 1;
        }
    }
    std::vector<double> sunExp(sunObs.size(), static_cast<double>(out.sunCount) / (kRings * kSectors));
    sunExp.back() = 0;
    std::vector<double> skyExp(skyObs.size(), 0);
    const double nSky = static_cast<double>(out.total - out.sunCount);
    for (size_t k = 0; k + 1 < skyEdges.size(); ++k)
        skyExp[k] = nSky * (std::pow(std::sin(skyEdges[k + 1]), 2 * skyWrongPower) -
                            std::pow(std::sin(skyEdges[k]), 2 * skyWrongPower));
    std::vector<std::string> sunLabels(sunObs.size(), "sun cell"), skyLabels(skyObs.size(), "sky bin");
    out.sun = chi2::testCells(sunObs, sunExp, sunLabels, chi2::Options{});
    out.sky = chi2::testCells(skyObs, skyExp, skyLabels, chi2::Options{});
    return out;
}
}  // namespace

TEST(PhotonEmission, DirectionsFollowTheSunDiscAndTheCosineWeightedSky) {
    // 300 000 photons: pSun is 0.79 here, so ~238 000 sun photons over 120 cells (~2000 each)
    // and ~62 000 sky photons over 18 bins.
    const DirectionTests t = directionTests(300000, 12);
    std::printf("[ info ] emission directions: sun p = %.3g (dof %d), sky p = %.3g (dof %d)\n", t.sun.pValue, t.sun.dof,
                t.sky.pValue, t.sky.dof);
    EXPECT_FALSE(t.sun.rejectedAt(kEmissionAlpha)) << t.sun.summary();
    EXPECT_FALSE(t.sky.rejectedAt(kEmissionAlpha)) << t.sky.summary();
    // The source choice is binomial: the two-sided level kEmissionAlpha (2.5e-3) is 3.02 standard deviations.
    const double p = fixture().src.pSun, n = static_cast<double>(t.total);
    const double z = (static_cast<double>(t.sunCount) - n * p) / std::sqrt(n * p * (1 - p));
    std::printf("[ info ] emission: %lld of %lld from the sun, expected %.1f (z = %.2f)\n", t.sunCount, t.total, n * p, z);
    EXPECT_LT(std::abs(z), 3.02);
}

TEST(PhotonEmission, RejectsAWrongSkyDistribution) {
    // Power: the same directions judged against P(theta < x) = sin^2.2 x (a slightly more
    // zenith-heavy sky) must be rejected at the acceptance level.
    const DirectionTests t = directionTests(300000, 12, 1.1);
    std::printf("[ info ] emission, wrong sky: p = %.3g\n", t.sky.pValue);
    EXPECT_TRUE(t.sky.rejectedAt(kEmissionAlpha)) << t.sky.summary();
}

TEST(PhotonEmission, EmittedPowerIntegratesToTheSourceFlux) {
    // E[power_b] Phi_mean = Phi_sun,b + Phi_sky,b. The per-photon power takes two values per band
    // (one per source), so the estimate's standard error is known from the sample variance; the
    // tolerance is 4 standard errors.
    const Fixture& f = fixture();
    constexpr int kN = 200000;
    double sum[2] = {0, 0}, sum2[2] = {0, 0};
    for (int i = 0; i < kN; ++i) {
        const EmittedPhoton e = f.emit(13, i);
        for (int b = 0; b < 2; ++b) {
            const double v = e.power[b] * f.src.meanFlux;
            sum[b] += v;
            sum2[b] += v * v;
        }
    }
    for (int b = 0; b < 2; ++b) {
        const double mean = sum[b] / kN, var = sum2[b] / kN - mean * mean;
        const double se = std::sqrt(var / kN), flux = f.src.sunFlux[b] + f.src.skyFlux[b];
        std::printf("[ info ] emission band %d: emitted %.5f +- %.5f W um^-1, source flux %.5f\n", b, mean, se, flux);
        EXPECT_NEAR(mean, flux, 4 * se) << b;
    }
}

// Splitting by depth (render/photon_pass.h, DepthImportance): the importance from a pilot's scalar
// irradiance profile is Eo(shallowest) / Eo(z), log-linear between the planes (exact for an
// exponential profile), constant beyond them, clamped, and empty when fewer than two planes saw
// light. Values derived by hand from the profile below.
TEST(DepthImportance, FollowsTheInverseProfileBetweenThePlanes) {
    // Eo = e^{0.2 z} down to 10 m (K = 0.2 m^-1), then e^{-2 - 0.05 (|z| - 10)}; one plane saw nothing.
    const DepthImportance d = DepthImportance::fromProfile(
        {{-10, std::exp(-2.0)}, {-1, std::exp(-0.2)}, {-30, std::exp(-3.0)}, {-20, 0.0}});
    ASSERT_EQ(d.z.size(), 3u);
    EXPECT_DOUBLE_EQ(d.at(0.0), 1.0);   // above the shallowest plane: its importance, 1
    EXPECT_DOUBLE_EQ(d.at(-1.0), 1.0);
    EXPECT_NEAR(d.at(-5.5), std::exp(0.2 * 4.5), 1e-12);              // within the first span: e^{K dz}
    EXPECT_NEAR(d.at(-10.0), std::exp(1.8), 1e-12);
    EXPECT_NEAR(d.at(-20.0), std::exp(1.8 + 0.05 * 10), 1e-12);         // the empty plane was left out
    EXPECT_NEAR(d.at(-60.0), std::exp(2.8), 1e-12);                     // below the deepest: constant
    // The exponent and the clamp.
    const DepthImportance h = DepthImportance::fromProfile({{-1, 1.0}, {-50, 1e-12}}, 0.5, 1e4);
    EXPECT_NEAR(h.at(-50.0), 1e4, 1e-6);
    const DepthImportance up = DepthImportance::fromProfile({{-1, 1.0}, {-5, 1e6}});  // a bright floor below
    EXPECT_NEAR(up.at(-5.0), 1e-2, 1e-15);
    EXPECT_TRUE(DepthImportance::fromProfile({{-1, 1.0}, {-5, 0.0}}).empty());
    EXPECT_DOUBLE_EQ(DepthImportance{}.at(-3.0), 1.0);
}

// The forward tallies' importance below the deepest plane (fromProfile's fallBelowDeepest): it falls
// at the attenuation of the last two points' Eo, a photon there being as unlikely to come back up to
// the deepest plane as the light is to get down that far, and at most by a factor 100. Values by
// hand from the profile of the test above.
TEST(DepthImportance, FallsBelowTheDeepestPlaneAtTheLastAttenuation) {
    const DepthImportance d = DepthImportance::fromProfile(
        {{-10, std::exp(-2.0)}, {-1, std::exp(-0.2)}, {-30, std::exp(-3.0)}}, 1.0, 1e4, true);
    EXPECT_NEAR(d.fallBelow, 0.05, 1e-12);                         // ln(e^-2 / e^-3) / 20 m
    EXPECT_NEAR(d.at(-20.0), std::exp(2.3), 1e-12);                 // between the planes: unchanged
    EXPECT_NEAR(d.at(-30.0), std::exp(2.8), 1e-12);
    EXPECT_NEAR(d.at(-40.0), std::exp(2.8 - 0.05 * 10), 1e-12);     // 10 m below: e^{-K 10}
    EXPECT_NEAR(d.at(-1000.0), std::exp(2.8) / 100, 1e-12);         // the floor: 1 / 100 of the deepest
    // A profile that brightens with depth (a bright floor below) does not fall.
    const DepthImportance up = DepthImportance::fromProfile({{-1, 1.0}, {-5, 2.0}}, 1.0, 1e4, true);
    EXPECT_DOUBLE_EQ(up.fallBelow, 0.0);
    EXPECT_NEAR(up.at(-9.0), up.at(-5.0), 1e-15);
}
