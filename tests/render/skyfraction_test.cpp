// Skyfraction (seed-ch06-07-appA.md §3.1, Eq. 6.1; T6.2 with r_b = 0): a Lambertian ground
// (r_g = 1) under a uniform sky (E_h = 1) beside a black obstruction returns L = F E_h r_g / pi,
// F the cosine-weighted visible sky fraction, for both the Classic and the Generic solvers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/units.h"
#include "render/renderer.h"
#include "tests/render/render_test_scenes.h"

namespace littoral::render {
namespace {

using namespace testing;
using M = ir::Material;

// Eq. 6.1 closed form for an obstruction of constant elevation theta_h over azimuth width phi_w.
double skyFractionEq61(double phiW, double thetaH) { return 1.0 - phiW * sqr(std::sin(thetaH)) / (2 * kPi); }

// The exact cosine-weighted fraction of the hemisphere above a horizontal point (normal +z)
// covered by a planar polygon, by Lambert's contour integral:
// (1/2pi) | sum_i gamma_i z . (v_i x v_{i+1}) / |v_i x v_{i+1}| |, gamma_i the angle between
// consecutive vertex directions v_i (relative to the point).
double polygonProjectedFraction(const Point3& p, const std::vector<Point3>& poly) {
    double sum = 0;
    for (size_t i = 0; i < poly.size(); ++i) {
        const Vec3 a = normalize(poly[i] - p), b = normalize(poly[(i + 1) % poly.size()] - p);
        const Vec3 c = cross(a, b);
        const double lc = length(c);
        if (lc < 1e-15) continue;
        sum += std::acos(std::clamp(dot(a, b), -1.0, 1.0)) * c.z / lc;
    }
    return std::abs(sum) / (2 * kPi);
}

// The dirsig estimator's Classic and Generic solvers, and the path estimator (which has no
// per-material solver; each pixel then takes `samples` paths instead of hemisphere samples).
enum class Mode { Classic, Generic, Path };
const char* modeName(Mode m) { return m == Mode::Classic ? "Classic" : m == Mode::Generic ? "Generic" : "Path"; }

// A scene for `mode` with N hemisphere samples (dirsig) or N samples per pixel (path) and GRS
// bounce limit 2 (sky fraction plus the neighbours' sky fraction; the neighbours here are black).
ir::SceneIR skyScene(Mode mode, int N) {
    ir::SceneIR s = uniformSkyScene();
    s.render.settings.set("max_bounces", 2);
    if (const char* e = std::getenv("LITTORAL_TEST_SEED")) s.render.seed = std::stoull(e);
    if (mode == Mode::Path) s.render.estimator = ir::Estimator::Path;
    else s.render.settings.set("hemisphere_samples", N);
    const M::Solver solver = mode == Mode::Classic ? M::Solver::Classic : M::Solver::Generic;
    ir::Material ground = material("ground", M::Type::Lambertian, solver, 1.0);
    if (mode == Mode::Path) ground.solver.reset();
    s.materials.push_back(ground);
    s.materials.push_back(material("black", M::Type::Black, M::Solver::Classic));
    return s;
}

class SkyFraction : public ::testing::TestWithParam<Mode> {};

// A single-sheet arc wall of radius 2 m centred on the test point gives an obstruction of exactly
// constant elevation theta_h over azimuth width phi_w: Eq. 6.1 is exact there.
TEST_P(SkyFraction, ArcWallMatchesEq61) {
    const Mode mode = GetParam();
    struct Case { double phiW, thetaH; };
    for (const Case cs : {Case{kPi, deg2rad(45)}, Case{0.5 * kPi, deg2rad(60)}, Case{1.5 * kPi, deg2rad(30)}}) {
        ir::SceneIR s = skyScene(mode, 1024);
        const double rho = 2.0;
        s.meshes.push_back(meshOf("ground", plane(-100, 100, -100, 100, 0), {"ground"}));
        s.meshes.push_back(meshOf("wall", arcWall(0, 0, rho, 0, cs.phiW, rho * std::tan(cs.thetaH), 512), {"black"}));
        // 4 x 4 pixels 0.1 mm apart around the centre: the same F to < 1e-5.
        s.sensors.push_back(ortho("o", {0, 0, 20}, {0, 0, -1}, {0, 1, 0}, 4, 4, 1e-4));
        if (mode == Mode::Path) s.sensors.back().samplesPerPixel = 1024;
        const Scene scene(s, ".");
        const SensorImage img = renderSensor(scene, s.sensors[0], quiet());
        double sum = 0, sum2 = 0;
        const int np = 16;
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) {
                const double F = img.film.at(i, j, 0) * kPi;  // L = F E_h r_g / pi with E_h = r_g = 1
                sum += F;
                sum2 += F * F;
            }
        const double mean = sum / np;
        const double sd = std::sqrt(std::max(0.0, (sum2 - np * mean * mean) / (np - 1)));
        const double pred = skyFractionEq61(cs.phiW, cs.thetaH);
        // Tolerance: 4 standard errors of the 16-pixel mean (each pixel is an independent
        // estimate, its spread measured), with a floor of 1/(4 N) for the case where stratification
        // leaves almost no spread, plus 1e-4 for the 512-segment arc (its chords sit at
        // rho cos(dphi/2), raising the elevation by < 2e-5 rad).
        const double tol = 4 * sd / std::sqrt(np) + 0.25 / 1024 + 1e-4;
        EXPECT_NEAR(mean, pred, tol) << "phi_w " << cs.phiW << " theta_h " << cs.thetaH;
        std::printf("[ skyfraction arc %s ] phi_w %.3f theta_h %.1f deg: F = %.5f +- %.5f (Eq. 6.1: %.5f)\n",
                    modeName(mode), cs.phiW, rad2deg(cs.thetaH), mean, sd / std::sqrt(np), pred);
    }
}

// Ground transect beside a black box (x in [0, 2], y in [-1, 1], height 1.5 m): the box face
// x = 0 is the obstruction; F = 1 - (its projected fraction) exactly (polygon view factor, the
// finite-box form of Eq. 6.1 recommended in §3.1). Each pixel's estimate from N stratified
// hemisphere samples has a standard deviation below the binomial sqrt(F (1 - F) / N).
TEST_P(SkyFraction, GroundBesideBoxMatchesPolygonViewFactor) {
    const Mode mode = GetParam();
    const int N = 1024;
    ir::SceneIR s = skyScene(mode, N);
    s.meshes.push_back(meshOf("ground", plane(-100, 100, -100, 100, 0), {"ground"}));
    s.meshes.push_back(meshOf("box", box({0, -1, 0}, {2, 1, 1.5}), {"black"}, "", "", true));
    const int W = 24, H = 4;
    s.sensors.push_back(ortho("o", {-1.2, 0, 10}, {0, 0, -1}, {0, 1, 0}, W, H, 0.1));
    // The path estimator jitters its samples over the 0.1 m pixel, where F is nearly linear in x:
    // the pixel average differs from the centre value by F'' (0.1 m)^2 / 24 < 1e-4.
    if (mode == Mode::Path) s.sensors.back().samplesPerPixel = N;
    const Scene scene(s, ".");
    const SensorImage img = renderSensor(scene, s.sensors[0], quiet());
    double sumErr = 0, sumVar = 0, minF = 1;
    int count = 0;
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            const Point3 p{-1.2 + (i + 0.5 - W / 2.0) * 0.1, -(j + 0.5 - H / 2.0) * 0.1, 0};
            const std::vector<Point3> face{{0, -1, 0}, {0, 1, 0}, {0, 1, 1.5}, {0, -1, 1.5}};
            const double F = 1.0 - polygonProjectedFraction(p, face);
            const double est = img.film.at(i, j, 0) * kPi;
            const double sigma = std::sqrt(F * (1 - F) / N);
            EXPECT_NEAR(est, F, 4 * sigma + 1e-4) << "pixel " << i << "," << j;
            sumErr += est - F;
            sumVar += sigma * sigma;
            minF = std::min(minF, F);
            ++count;
        }
    // The mean error over all pixels: standard error sqrt(sum sigma^2)/count.
    const double meanErr = sumErr / count, se = std::sqrt(sumVar) / count;
    EXPECT_LT(std::abs(meanErr), 4 * se + 1e-4);
    EXPECT_LT(minF, 0.6);  // the transect reaches the wall, where F approaches 1/2
    std::printf("[ skyfraction box %s ] %d pixels, F from %.4f, mean error %.2e (se %.2e)\n", modeName(mode), count,
                minF, meanErr, se);
}

INSTANTIATE_TEST_SUITE_P(Solvers, SkyFraction, ::testing::Values(Mode::Classic, Mode::Generic, Mode::Path),
                         [](const ::testing::TestParamInfo<Mode>& i) { return std::string(modeName(i.param)); });

}  // namespace
}  // namespace littoral::render

