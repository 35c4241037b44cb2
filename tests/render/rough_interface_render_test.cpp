// The rough (Cox-Munk) air-water interface rendered end to end: glint and transmitted-sun
// transects in images against the dissertation's closed forms (Eq. 5.4 and the Walter-consistent
// BTDF of digest section 1.6, tests/support/glint.h), sun next-event estimation against BSDF
// sampling and their MIS combination, probes and the photon pass under a rough surface.
//
// Scenes: a flat sea (a water box whose top face is the rough interface, every other face black)
// under a black sky and a sun at the zenith, pure non-attenuating water (n = 1.34). Light that
// enters the water ends on the black floor, so a camera above sees only the glint and a camera
// below only the transmitted sun: the closed forms are the whole answer, exactly (G = 1, the
// dissertation's slope variances 0.00316 W and 0.00192 W, digest section 1.2).
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "core/rng.h"
#include "core/units.h"
#include "render/estimator.h"
#include "render/probes.h"
#include "render/renderer.h"
#include "tests/render/render_test_scenes.h"
#include "tests/support/glint.h"

namespace littoral::render {
namespace {

using namespace testing;
namespace glint = littoral::testing_support::glint;
using M = ir::Material;

constexpr double kRoughE = 1000.0;     // sun irradiance normal to the beam, W m^-2 um^-1
constexpr double kRoughN = 1.34;       // water index (Ch. 4)
constexpr double kSunDeg = 0.53;  // solar disc diameter

ir::Material roughMaterial(double W, CoxMunkSea sea, double windAzimuth = 0.0) {
    ir::Material m;
    m.name = "sea";
    m.type = M::Type::RoughDielectric;
    m.windSpeed = W;
    m.windAzimuth = windAzimuth;
    m.sea = sea;
    return m;
}

// A flat rough sea: a 100 m x 100 m x 10 m water box, rough top, black sides and floor; sun at the
// zenith (diameter `sunDeg`), black sky, one band.
ir::SceneIR roughSea(double W, ir::Estimator estimator, double sunDeg = kSunDeg) {
    ir::SceneIR s;
    s.name = "rough";
    s.render.bands = {Band{0.4, 0.6}};
    s.render.estimator = estimator;
    s.sun.enabled = true;
    s.sun.zenith = 0.0;
    s.sun.azimuth = 0.0;
    s.sun.halfAngle = 0.5 * deg2rad(sunDeg);
    s.sun.irradiance = Spectrum::constant(kRoughE);
    s.sky.radiance = Spectrum::constant(0.0);
    s.media.push_back(water(0, 0, kRoughN));
    s.materials.push_back(roughMaterial(W, CoxMunkSea::Dissertation));
    s.materials.push_back(material("black", M::Type::Black, M::Solver::Classic));
    s.meshes.push_back(meshOf("water", box({-50, -50, -10}, {50, 50, 0}, 0, 1), {"sea", "black"}, "water", "", true));
    return s;
}

// Per-pixel mean and standard error over independent renders (seeds), each one sample per pixel
// through the pixel centre: the estimator's own spread, not a guess.
struct Transect {
    std::vector<double> mean, se, pred;
};

Transect renderTransect(ir::SceneIR& s, const ir::Sensor& cam, int renders, uint64_t seedBase,
                        const std::function<double(int)>& predict) {
    s.sensors = {cam};
    const Scene scene(s, ".");
    const EstimatorSet est(scene);
    const int n = cam.width * cam.height;
    std::vector<double> sum(n, 0.0), sum2(n, 0.0);
    for (int k = 0; k < renders; ++k) {
        s.render.seed = 7919 * static_cast<uint64_t>(k) + seedBase;  // the Scene reads the seed at render time
        const SensorImage img = renderSensor(scene, est, s.sensors[0], quiet());
        for (int p = 0; p < n; ++p) {
            const double v = img.film.at(cam.width > 1 ? p : 0, cam.width > 1 ? 0 : p, 0);
            sum[p] += v;
            sum2[p] += v * v;
        }
    }
    Transect t;
    for (int p = 0; p < n; ++p) {
        const double m = sum[p] / renders;
        const double var = std::max(0.0, (sum2[p] - renders * m * m) / (renders - 1));
        t.mean.push_back(m);
        t.se.push_back(std::sqrt(var / renders));
        t.pred.push_back(predict(p));
    }
    return t;
}

// Every pixel within 5 standard errors plus the reference's own accuracy: sunDiscAverage's
// small-angle quadrature is good to ~radius^2 = 2e-5 relative for the 0.53 deg sun, and the film
// stores floats (6e-8): 1e-4 relative covers both. With ~40 pixels per transect and 16 transects
// per estimator, 5 standard errors (two-sided p = 6e-7 per pixel, standard errors from 256 renders)
// make a false alarm unlikely (< 1e-3 per run). 256 rather than fewer renders: in the lobes' tails
// the disc samples' values are skewed (f changes by a factor of ~4 across the 0.53 deg disc there),
// and with 96 renders the spread underestimated the error now and then (|z| up to 4.5 in one of 656
// pixels); with 256, over four seed sets, the largest |z| of the 656 pixels was 2.9 to 3.5, as
// expected of normal errors. A real error in f, the pdf or the MIS weights shows up as tens of
// standard errors (the glint peak's standard error is ~0.1 %).
void expectTransect(const Transect& t, const std::string& what, double* worstZ) {
    double peak = 0;
    for (double p : t.pred) peak = std::max(peak, p);
    double z2 = 0, zmax = 0, relAtMax = 0;
    for (size_t p = 0; p < t.mean.size(); ++p) {
        const double tol = 5.0 * t.se[p] + 1e-4 * t.pred[p] + 1e-9 * peak;
        EXPECT_NEAR(t.mean[p], t.pred[p], tol) << what << " pixel " << p << " se " << t.se[p];
        const double z = t.se[p] > 0 ? (t.mean[p] - t.pred[p]) / t.se[p] : 0.0;
        z2 += z * z;
        if (std::abs(z) > zmax) zmax = std::abs(z), relAtMax = t.pred[p] > 0 ? t.mean[p] / t.pred[p] - 1 : 0;
    }
    *worstZ = std::max(*worstZ, zmax);
    std::printf("[ %s ] peak %.6g, max |z| %.2f (relative difference there %+.1e), mean z^2 %.2f\n", what.c_str(), peak,
                zmax, relAtMax, z2 / t.mean.size());
}

// Glint seen from above and the transmitted sun seen from below, upwind and crosswind, for
// W = 2, 3, 5, 8 m/s, by both estimators. Sun at the zenith, the wind toward +x (upwind axis x).
//  * Reflected: nadir camera at H = 10 m; the pixel-centre ray meets the sea at (x, y) and the
//    closed form is E * <Eq. 5.4>_disc with toViewer = (-x, -y, H)/R (glint.h reflected()).
//  * Transmitted: upward camera at depth d = 5 m in the water; the pixel-centre ray meets the
//    surface at (x, y) and the closed form is E * <digest 1.6 BTDF>_disc with toViewer =
//    (-x, -y, -d)/R (glint.h transmitted(); the n^2 law is in it).
// <>_disc: average over the solar disc (glint.h sunDiscAverage), as the renderer samples it.
// Each transect spans +-3.5 standard deviations of the facet slope along its axis.
class GlintTransects : public ::testing::TestWithParam<ir::Estimator> {};

TEST_P(GlintTransects, MatchClosedForms) {
    const double H = 10.0, d = 5.0;
    const int N = 41, renders = 256;
    const double radius = 0.5 * deg2rad(kSunDeg);
    double worstZ = 0;
    for (double W : {2.0, 3.0, 5.0, 8.0}) {
        const glint::SlopeVariances v = glint::dissertationSlopes(W);
        for (glint::Axis axis : {glint::Axis::Upwind, glint::Axis::Crosswind}) {
            const bool up = axis == glint::Axis::Upwind;
            const double sigma = std::sqrt(up ? v.upwind : v.crosswind);
            const double beta = std::atan(3.5 * sigma);
            // Reflected: a facet tilted by beta sends the zenith sun 2 beta from the zenith.
            {
                const double xMax = H * std::tan(2 * beta);
                const double f = 0.01, pitch = f * (2 * xMax / H) / N;
                // Strip along x (upwind) or y (crosswind); pixel-centre ground points (camera.cpp:
                // right = +x, image up = +y for a nadir view with up = north).
                const ir::Sensor cam = up ? pinhole("above", {0, 0, H}, {0, 0, -1}, {0, 1, 0}, N, 1, f, pitch)
                                          : pinhole("above", {0, 0, H}, {0, 0, -1}, {0, 1, 0}, 1, N, f, pitch);
                ir::SceneIR s = roughSea(W, GetParam());
                const Transect t = renderTransect(s, cam, renders, static_cast<uint64_t>(100 * W + up), [&](int p) {
                    const double o = (p + 0.5 - N / 2.0) * pitch / f * H;
                    const double x = up ? o : 0.0, y = up ? 0.0 : -o;
                    const double R = std::sqrt(x * x + y * y + H * H);
                    const glint::Dir toViewer{-x / R, -y / R, H / R};
                    return kRoughE * glint::sunDiscAverage([&](const glint::Dir& ws) { return glint::reflected(v, ws, toViewer); },
                                                      {0, 0, 1}, radius);
                });
                expectTransect(t, fmt::format("{} reflected W {} {}", nameOf(GetParam()), W, up ? "upwind" : "crosswind"),
                               &worstZ);
            }
            // Transmitted: the zenith sun refracted by a facet tilted by beta leaves at
            // beta - asin(sin(beta)/n) from the vertical in the water.
            {
                const double delta = beta - std::asin(std::sin(beta) / kRoughN);
                const double xMax = d * std::tan(delta);
                const double f = 0.01, pitch = f * (2 * xMax / d) / N;
                // Looking up with up = north: right = -x, image up = +y.
                const ir::Sensor cam = up ? pinhole("below", {0, 0, -d}, {0, 0, 1}, {0, 1, 0}, N, 1, f, pitch, "water")
                                          : pinhole("below", {0, 0, -d}, {0, 0, 1}, {0, 1, 0}, 1, N, f, pitch, "water");
                ir::SceneIR s = roughSea(W, GetParam());
                const Transect t = renderTransect(s, cam, renders, static_cast<uint64_t>(100 * W + up + 50), [&](int p) {
                    const double o = (p + 0.5 - N / 2.0) * pitch / f * d;
                    const double x = up ? -o : 0.0, y = up ? 0.0 : -o;
                    const double R = std::sqrt(x * x + y * y + d * d);
                    const glint::Dir toViewer{-x / R, -y / R, -d / R};
                    return kRoughE * glint::sunDiscAverage(
                                    [&](const glint::Dir& ws) { return glint::transmitted(v, ws, toViewer); }, {0, 0, 1},
                                    radius);
                });
                expectTransect(t, fmt::format("{} transmitted W {} {}", nameOf(GetParam()), W, up ? "upwind" : "crosswind"),
                               &worstZ);
            }
        }
    }
    std::printf("[ glint transects %s ] worst |z| %.2f\n", std::string(nameOf(GetParam())).c_str(), worstZ);
}

INSTANTIATE_TEST_SUITE_P(Estimators, GlintTransects, ::testing::Values(ir::Estimator::Path, ir::Estimator::Dirsig),
                         [](const auto& info) { return std::string(nameOf(info.param)); });

// Mean and standard error of Li along one ray under one strategy for the sun at glossy hits.
struct Estimate {
    double mean = 0, se = 0;
};
Estimate estimateLi(const Scene& scene, const RenderConfig& cfg, const Ray& ray, int medium, int n, uint64_t pass) {
    const auto est = Estimator::create(scene, cfg, BandGroup{0, 1});
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n; ++i) {
        RandomStream rng(scene.ir().render.seed, pass, static_cast<uint64_t>(i));
        const double v = est->Li(ray, medium, rng)[0];
        sum += v;
        sum2 += v * v;
    }
    Estimate e;
    e.mean = sum / n;
    e.se = std::sqrt(std::max(0.0, sum2 / n - e.mean * e.mean) / (n - 1));
    return e;
}

// The three ways a glossy hit can get the sun estimate the same radiance: next-event estimation
// alone, BSDF sampling alone (the sampled direction lands in the disc) and their combination by
// the power heuristic. If the MIS weights did not sum to one, or a strategy missed or double-counted
// the disc, they would differ by the missing or extra part. A 2 deg sun (to give BSDF sampling
// hits to count) over a calm sea: transmitted at W = 0.5 m/s, where the BSDF's density in air
// (~1000 sr^-1) is comparable to the disc's (1/Omega = 1045 sr^-1), so both MIS weights matter;
// reflected at W = 0.05 m/s, where BSDF sampling finds the disc ~0.3 % of the time.
// Tolerances: 4 combined standard errors between strategies (from the samples' own variance);
// against the closed form, 4 standard errors plus sunDiscAverage's small-angle error (~radius^2 =
// 3e-4 relative for the 2 deg disc; 1e-3 allowed).
TEST(RoughInterfaceSun, NextEventBsdfAndMisAgree) {
    using GS = RenderConfig::GlossySun;
    struct Case {
        const char* what;
        double W;
        Point3 eye;
        Point3 target;
        bool below;
        int n;
    };
    const Case cases[] = {{"transmitted", 0.5, {0, 0, -5}, {0.05, 0.03, 0}, true, 60000},
                          {"reflected", 0.05, {0, 0, 10}, {0.1, 0.05, 0}, false, 400000}};
    const double sunDeg = 2.0;
    for (const Case& c : cases) {
        ir::SceneIR s = roughSea(c.W, ir::Estimator::Path, sunDeg);
        const Scene scene(s, ".");
        RenderConfig cfg = makeRenderConfig(s);
        Ray ray;
        ray.o = c.eye;
        ray.d = normalize(c.target - c.eye);
        const int medium = c.below ? 1 : 0;
        Estimate e[3];
        const GS modes[3] = {GS::NeeOnly, GS::BsdfOnly, GS::Mis};
        for (int k = 0; k < 3; ++k) {
            cfg.glossySun = modes[k];
            e[k] = estimateLi(scene, cfg, ray, medium, c.n, 100 + k);
        }
        // Closed form: E <f cos>_disc toward the eye.
        const glint::SlopeVariances v = glint::dissertationSlopes(c.W);
        const Vec3 tv = -ray.d;
        const glint::Dir toViewer{tv.x, tv.y, tv.z};
        const double ref = kRoughE * glint::sunDiscAverage(
                                    [&](const glint::Dir& ws) {
                                        return c.below ? glint::transmitted(v, ws, toViewer) : glint::reflected(v, ws, toViewer);
                                    },
                                    {0, 0, 1}, 0.5 * deg2rad(sunDeg));
        const char* names[3] = {"NEE only", "BSDF only", "MIS"};
        for (int a = 0; a < 3; ++a) {
            EXPECT_NEAR(e[a].mean, ref, 4 * e[a].se + 1e-3 * ref) << c.what << " " << names[a];
            for (int b = a + 1; b < 3; ++b)
                EXPECT_NEAR(e[a].mean, e[b].mean, 4 * std::hypot(e[a].se, e[b].se))
                    << c.what << " " << names[a] << " vs " << names[b];
        }
        std::printf("[ sun at glossy hits, %s ] closed form %.6g; NEE %.6g +- %.2g, BSDF %.6g +- %.2g, MIS %.6g +- %.2g\n",
                    c.what, ref, e[0].mean, e[0].se, e[1].mean, e[1].se, e[2].mean, e[2].se);
        // MIS is never worse than the better strategy by more than the balance of the two.
        EXPECT_LT(e[2].se, 1.5 * std::min(e[0].se, e[1].se)) << c.what;
    }
}

// Slope quadrature of the transmittance of a rough surface for the sun at the zenith: the light
// falling on facets of slope (zx, zy) per unit horizontal area is p_s dzx dzy (cos alpha / cos beta
// times the facet area sec beta cos beta...: for a vertical beam the projected facet area is the
// horizontal area), the facet's incidence angle is its tilt beta, and it transmits 1 - r_f(beta),
// all downward. T = Int p_s (1 - r_f(beta)) dzx dzy (G = 1), midpoint rule over +-8 sigma.
double zenithTransmittance(double W) {
    const glint::SlopeVariances v = glint::dissertationSlopes(W);
    const double su = std::sqrt(v.upwind), sc = std::sqrt(v.crosswind);
    const int n = 800;
    double T = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const double zx = (-8 + 16 * (i + 0.5) / n) * su, zy = (-8 + 16 * (j + 0.5) / n) * sc;
            const double cb = 1.0 / std::sqrt(1 + zx * zx + zy * zy);
            T += glint::slopePdf(v, zx, zy) * (1 - glint::fresnelSinTan(cb, 1.0, kRoughN)) * (16 * su / n) * (16 * sc / n);
        }
    return T;
}

// A probe just below a horizontally periodic rough sea (pure water, black floor, sun at the
// zenith, black sky) measures Ed = E T: every transmitted photon goes down and none comes back.
// The direct sun reaches the probe only through the rough interface's transmission lobe (the
// in-water sun estimate), and the probe's sampled rays must not count it again (SunChain): both
// estimators, W = 2 and 8 m/s. Tolerance: 4 standard errors from the probe's batches, plus the
// quadrature's 1e-5.
TEST(RoughInterfaceSun, ProbeBelowRoughSeaMeasuresTheTransmittance) {
    for (ir::Estimator e : {ir::Estimator::Path, ir::Estimator::Dirsig})
        for (double W : {2.0, 8.0}) {
            ir::SceneIR s;
            s.name = "rough-probe";
            s.render.bands = {Band{0.4, 0.6}};
            s.render.estimator = e;
            s.sun.enabled = true;
            s.sun.zenith = 0;
            s.sun.irradiance = Spectrum::constant(kRoughE);
            s.sky.radiance = Spectrum::constant(0.0);
            const double L = 20, depth = 10;
            s.domain = {-L, L, -L, L, true};
            s.media.push_back(water(0, 0, kRoughN));
            s.materials.push_back(roughMaterial(W, CoxMunkSea::Dissertation, 0.4));
            s.materials.push_back(material("black", M::Type::Black, M::Solver::Classic));
            ir::Material wall;
            wall.name = "periodic-wall";
            wall.type = M::Type::Periodic;
            s.materials.push_back(wall);
            s.meshes.push_back(meshOf("water", periodicSlab(L, depth), {"sea", "black", "periodic-wall"}, "water", "", true));
            ir::Probe p;
            p.name = "below";
            p.position = {1.3, -2.1, -1.0};
            p.quantities = {"Ed", "Eu"};
            p.medium = "water";
            p.samples = 1024;
            s.probes.push_back(p);
            const Scene scene(s, ".");
            const auto v = evaluateProbe(scene, s.probes[0], 0, quiet());
            const double ref = kRoughE * zenithTransmittance(W);
            EXPECT_NEAR(v[0].mean[0], ref, 4 * v[0].stderr_[0] + 1e-5 * ref) << nameOf(e) << " W " << W;
            EXPECT_NEAR(v[1].mean[0], 0.0, 1e-12) << "nothing comes back up from a black floor";
            std::printf("[ probe below rough sea, %s, W %g ] Ed %.6f +- %.2g (E T = %.6f)\n",
                        std::string(nameOf(e)).c_str(), W, v[0].mean[0], v[0].stderr_[0], ref);
        }
}

}  // namespace
}  // namespace littoral::render
