// Water-leaving products (sensor water_products, render/water_products.cpp): the radiance split at
// the sea surface into water-leaving, sky-reflected, glint and other parts, and Ed(0+).
//  * The parts add up to the radiance, and turning the products on leaves the radiance as it was,
//    for both estimators on a smooth and a rough sea with land and sky in view.
//  * Sky-reflected of a flat sea under a uniform sky is r(theta) L_sky, with the Fresnel
//    reflectance of the thesis' Eq. 4.2 written out in the test.
//  * Glint of a rough sea under a zenith sun is the Cox–Munk closed form of tests/support/glint.h.
//  * Ed(0+) is E_sun cos + pi L_sky in the open, and under an opaque square plate the sky's share
//    is cut by the plate's view factor (the closed form for a point under a parallel rectangle).
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/units.h"
#include "render/camera.h"
#include "render/estimator.h"
#include "render/renderer.h"
#include "tests/render/render_test_scenes.h"
#include "tests/support/glint.h"

namespace littoral::render {
namespace {

using namespace testing;
namespace glint = littoral::testing_support::glint;
using M = ir::Material;

constexpr double kProductsN = 1.34;
constexpr double kProductsE = 1000.0;  // sun irradiance normal to the beam, W m^-2 um^-1

// A 40 m x 40 m x 5 m water box (its top the sea surface: smooth or rough `top`, sides black, a
// sandy floor), a pier (an opaque box) standing out of it, sun at 35 deg toward the camera's side,
// and a uniform sky.
ir::SceneIR coastalScene(ir::Estimator estimator, bool rough, double a, double b) {
    ir::SceneIR s;
    s.name = "wp";
    s.render.bands = {Band{0.45, 0.5}, Band{0.55, 0.6}};
    s.render.estimator = estimator;
    s.sun.enabled = true;
    s.sun.zenith = deg2rad(35);
    s.sun.azimuth = deg2rad(90);
    s.sun.irradiance = Spectrum::constant(kProductsE);
    s.sky.radiance = Spectrum::constant(40.0);
    s.media.push_back(water(a, b, kProductsN, {"henyey-greenstein", {{"g", 0.8}}}));
    if (estimator == ir::Estimator::Dirsig && b > 0) s.media.back().solver = ir::Medium::Solver::MediumPM;
    if (rough) {
        ir::Material m;
        m.name = "sea";
        m.type = M::Type::RoughDielectric;
        m.windSpeed = 5;
        m.sea = CoxMunkSea::Dissertation;
        s.materials.push_back(m);
    } else {
        s.materials.push_back(typedMaterial("sea", M::Type::Dielectric));
    }
    // (The path estimator takes no per-material solvers: the dirsig defaults, classic, are meant.)
    auto lambert = [](const char* name, double r) {
        ir::Material m = typedMaterial(name, M::Type::Lambertian);
        m.reflectance = Spectrum::constant(r);
        return m;
    };
    s.materials.push_back(typedMaterial("black", M::Type::Black));
    s.materials.push_back(lambert("sand", 0.3));
    s.materials.push_back(lambert("concrete", 0.5));
    // Water box: top = slot 0 (sea), sides black (slot 1); the floor is a separate sand plane.
    s.meshes.push_back(meshOf("water", box({-20, -20, -5}, {20, 20, 0}, 0, 1), {"sea", "black"}, "water", "", true));
    s.meshes.push_back(meshOf("floor", plane(-20, 20, -20, 20, -4.99), {"sand"}, "water", "water"));
    s.meshes.push_back(meshOf("pier", box({-4, 0, -4.99}, {4, 8, 4}), {"concrete"}, "", "", true));
    if (estimator == ir::Estimator::Dirsig) {
        s.render.settings.set("volume_photons", 100000);
        s.render.settings.set("hemisphere_samples", 8);
    }
    return s;
}

// An oblique camera from the south, the pier and the sky (the top rows) in view.
ir::Sensor obliqueCamera(int spp) {
    ir::Sensor c = pinhole("cam", {0, -25, 12}, normalize(Vec3{0, 1, -0.3}), {0, 0, 1}, 24, 18, 0.01, 0.01 * 1.2 / 24);
    c.samplesPerPixel = spp;
    return c;
}

SensorImage render(const ir::SceneIR& s, const ir::Sensor& cam, bool products) {
    ir::SceneIR t = s;
    t.sensors = {cam};
    t.sensors[0].waterProducts = products;
    const Scene scene(t, ".");
    const EstimatorSet est(scene, 1, 0, false);
    return renderSensor(scene, est, t.sensors[0], quiet());
}

// The parts sum to the radiance to float rounding (each stored as a float mean: 4 values of
// relative rounding 6e-8 each, 1e-6 relative covers them); the products leave the radiance image
// as it was, bit for bit (the same random numbers in the same order, the same throughput for
// Russian roulette; the parts' sum differs from Li's only in the order of double additions, below a
// float's resolution here). Each part is present where it belongs: the pier's pixels are all
// `other`, the sea's carry water-leaving and sky-reflected light.
TEST(WaterProducts, PartsAddUpToTheRadianceAndLeaveItUnchanged) {
    for (ir::Estimator e : {ir::Estimator::Dirsig, ir::Estimator::Path})
        for (bool rough : {false, true}) {
            const std::string what = fmt::format("{} {}", nameOf(e), rough ? "rough" : "smooth");
            const ir::SceneIR s = coastalScene(e, rough, 0.1, 0.2);
            const ir::Sensor cam = obliqueCamera(1);  // pixel-centre rays: the truth image says what each sees
            const SensorImage with = render(s, cam, true), without = render(s, cam, false);
            ASSERT_TRUE(with.products.has_value());
            ASSERT_FALSE(without.products.has_value());
            const WaterProductFilms& p = *with.products;
            const Camera camera(cam);
            int sea = 0, pier = 0, sky = 0;
            double lw = 0, reflected = 0, ed = 0;
            for (int y = 0; y < cam.height; ++y)
                for (int x = 0; x < cam.width; ++x) {
                    const size_t i = with.truth.index(x, y);
                    for (int b = 0; b < 2; ++b) {
                        const double L = with.film.at(x, y, b);
                        const double sum = p.waterLeaving.at(x, y, b) + p.skyReflected.at(x, y, b) + p.glint.at(x, y, b) +
                                           p.other.at(x, y, b);
                        ASSERT_NEAR(sum, L, 1e-6 * std::abs(L) + 1e-9) << what << " pixel " << x << "," << y;
                        ASSERT_EQ(L, without.film.at(x, y, b)) << what << " pixel " << x << "," << y;
                    }
                    const int m = with.truth.materialId[i];
                    if (m == 3) {  // the pier, seen directly
                        ++pier;
                        EXPECT_EQ(p.waterLeaving.at(x, y, 0), 0.0f);
                        EXPECT_EQ(p.skyReflected.at(x, y, 0), 0.0f);
                        EXPECT_TRUE(std::isnan(p.ed0.at(x, y, 0)));
                    } else if (m == 0) {
                        ++sea;
                        // dirsig splits a smooth sea into both lobes and follows each with its
                        // solvers: every pixel has both parts. A rough sea samples one lobe per
                        // sample, and a path may end with nothing: only their sums are checked then.
                        if (!rough && e == ir::Estimator::Dirsig) {
                            EXPECT_GT(p.waterLeaving.at(x, y, 0), 0.0f) << what;
                            EXPECT_GT(p.skyReflected.at(x, y, 0), 0.0f) << what;
                        }
                        lw += p.waterLeaving.at(x, y, 0), reflected += p.skyReflected.at(x, y, 0) + p.glint.at(x, y, 0);
                        EXPECT_EQ(p.other.at(x, y, 0), 0.0f) << what;
                        // (0 where the pier shadows the sun and the one sky ray met it.)
                        EXPECT_GE(p.ed0.at(x, y, 0), 0.0f) << what;
                        ed += p.ed0.at(x, y, 0);
                    } else if (m < 0 && camera.generateRay(x + 0.5, y + 0.5).d.z > 0.01 && cam.samplesPerPixel == 1) {
                        ++sky;  // the sky seen directly
                        EXPECT_NEAR(p.other.at(x, y, 0), 40.0, 1e-4) << what;
                    }
                }
            EXPECT_GT(sea, 100) << what;
            EXPECT_GT(pier, 10) << what;
            // The sea's mean Ed(0+) lies between the sky's pi L = 126 and the open value
            // E cos 35 deg + pi L = 945 (part of the sea is in the pier's shadow).
            EXPECT_GT(ed / sea, 0.5 * 945.0) << what;
            EXPECT_LT(ed / sea, 945.0 + 1.0) << what;
            EXPECT_GT(lw, 0.0) << what;
            EXPECT_GT(reflected, 0.0) << what;
            if (cam.samplesPerPixel == 1) {
                EXPECT_GT(sky, 10) << what;
            }
        }
}

// A flat sea over a black floor in non-attenuating water, a uniform sky of radiance L, no sun:
// every sea pixel's sky-reflected part is r(theta) L, theta the pixel ray's incidence angle, and
// nothing else reaches the camera (water-leaving and glint 0). One sample per pixel, through its
// centre, so theta is known exactly; float storage bounds the difference (1e-6 relative).
TEST(WaterProducts, SkyReflectedOfAFlatSeaIsFresnelTimesTheSky) {
    ir::SceneIR s = uniformSkyScene();
    const double L = 1.0 / kPi;
    s.media.push_back(water(0, 0, kProductsN));
    s.materials.push_back(typedMaterial("sea", M::Type::Dielectric));
    s.materials.push_back(material("black", M::Type::Black, M::Solver::Classic));
    s.meshes.push_back(meshOf("water", box({-500, -500, -10}, {500, 500, 0}, 0, 1), {"sea", "black"}, "water", "", true));
    for (ir::Estimator e : {ir::Estimator::Dirsig, ir::Estimator::Path}) {
        s.render.estimator = e;
        // Looking down at 65 deg from the zenith: incidence 40-85 deg across the frame.
        const ir::Sensor cam =
            pinhole("cam", {0, 0, 20}, normalize(Vec3{0, std::sin(deg2rad(65)), -std::cos(deg2rad(65))}), {0, 0, 1}, 16,
                    12, 0.01, 0.01 * 1.4 / 16);
        const SensorImage img = render(s, cam, true);
        const Camera camera(cam);
        double lo = 90, hi = 0;
        int n = 0;
        for (int y = 0; y < cam.height; ++y)
            for (int x = 0; x < cam.width; ++x) {
                if (img.truth.materialId[img.truth.index(x, y)] != 0) continue;
                const Ray r = camera.generateRay(x + 0.5, y + 0.5);
                const double theta = std::acos(-r.d.z);
                lo = std::min(lo, rad2deg(theta)), hi = std::max(hi, rad2deg(theta));
                const double expected = fresnelEq42(theta, 1.0, kProductsN) * L;
                EXPECT_NEAR(img.products->skyReflected.at(x, y, 0), expected, 1e-6 * expected)
                    << nameOf(e) << " theta " << rad2deg(theta);
                EXPECT_EQ(img.products->waterLeaving.at(x, y, 0), 0.0f);
                EXPECT_EQ(img.products->glint.at(x, y, 0), 0.0f);
                // Ed(0+) under the uniform sky alone: pi L = 1 from every direction drawn.
                EXPECT_NEAR(img.products->ed0.at(x, y, 0), 1.0, 1e-6);
                ++n;
            }
        EXPECT_GT(n, 150);
        EXPECT_LT(lo, 45.0);
        EXPECT_GT(hi, 75.0);
    }
}

// A rough sea (W = 5 m/s, the dissertation's slopes) under a zenith sun and a black sky, black
// below: a nadir strip sees only glint, which must be E <Eq. 5.4>_disc (tests/support/glint.h,
// independent of render/). Per-pixel means and standard errors over 64 renders of one sample per
// pixel; 5 standard errors plus the reference's quadrature accuracy (1e-4 relative), as the glint
// transect test argues for its 256 renders (the tolerance here is wider in absolute terms with
// fewer renders, and the same 41 pixels).
TEST(WaterProducts, GlintOfARoughSeaIsTheCoxMunkClosedForm) {
    const double W = 5.0, H = 10.0, radius = 0.5 * deg2rad(0.53);
    const glint::SlopeVariances v = glint::dissertationSlopes(W);
    const double beta = std::atan(3.5 * std::sqrt(v.upwind));
    const int N = 41, renders = 64;
    const double f = 0.01, pitch = f * (2 * H * std::tan(2 * beta) / H) / N;
    for (ir::Estimator e : {ir::Estimator::Dirsig, ir::Estimator::Path}) {
        ir::SceneIR s;
        s.name = "glint";
        s.render.bands = {Band{0.4, 0.6}};
        s.render.estimator = e;
        s.sun.zenith = 0;
        s.sun.irradiance = Spectrum::constant(kProductsE);
        s.sky.radiance = Spectrum::constant(0.0);
        s.media.push_back(water(0, 0, kProductsN));
        ir::Material sea;
        sea.name = "sea";
        sea.type = M::Type::RoughDielectric;
        sea.windSpeed = W;
        sea.sea = CoxMunkSea::Dissertation;
        s.materials.push_back(sea);
        s.materials.push_back(material("black", M::Type::Black, M::Solver::Classic));
        s.meshes.push_back(meshOf("water", box({-50, -50, -10}, {50, 50, 0}, 0, 1), {"sea", "black"}, "water", "", true));
        ir::Sensor cam = pinhole("cam", {0, 0, H}, {0, 0, -1}, {0, 1, 0}, N, 1, f, pitch);
        cam.waterProducts = true;
        s.sensors = {cam};
        const Scene scene(s, ".");
        const EstimatorSet est(scene, 1, 0, false);
        std::vector<double> sum(N, 0.0), sum2(N, 0.0);
        for (int k = 0; k < renders; ++k) {
            s.render.seed = 104729 * static_cast<uint64_t>(k) + 11;
            const SensorImage img = renderSensor(scene, est, s.sensors[0], quiet());
            for (int p = 0; p < N; ++p) {
                const double g = img.products->glint.at(p, 0, 0);
                EXPECT_EQ(img.products->waterLeaving.at(p, 0, 0), 0.0f);  // black below
                EXPECT_EQ(img.products->skyReflected.at(p, 0, 0), 0.0f);  // black sky, one reflection
                sum[p] += g;
                sum2[p] += g * g;
            }
        }
        double peak = 0, zmax = 0;
        for (int p = 0; p < N; ++p) {
            const double o = (p + 0.5 - N / 2.0) * pitch / f * H;
            const double R = std::sqrt(o * o + H * H);
            const glint::Dir toViewer{-o / R, 0, H / R};
            const double pred = kProductsE * glint::sunDiscAverage(
                                         [&](const glint::Dir& ws) { return glint::reflected(v, ws, toViewer); }, {0, 0, 1}, radius);
            peak = std::max(peak, pred);
            const double m = sum[p] / renders;
            const double se = std::sqrt(std::max(0.0, (sum2[p] - renders * m * m) / (renders - 1)) / renders);
            EXPECT_NEAR(m, pred, 5 * se + 1e-4 * pred + 1e-9 * kProductsE) << nameOf(e) << " pixel " << p;
            if (se > 0) zmax = std::max(zmax, std::abs(m - pred) / se);
        }
        std::printf("[ glint part %s ] peak %.5g, max |z| %.2f\n", std::string(nameOf(e)).c_str(), peak, zmax);
    }
}

// View factor from a point to a parallel rectangle A h x B h whose corner is straight above it at
// height h (Howell's catalogue, configuration B-3): the cosine-weighted share of the hemisphere it
// covers.
double cornerViewFactor(double A, double B) {
    const double a = std::sqrt(1 + A * A), b = std::sqrt(1 + B * B);
    return (A / a * std::atan(B / a) + B / b * std::atan(A / b)) / (2 * kPi);
}

// Ed(0+) at a sea point under an opaque square plate (side 2 m, 1.5 m above the sea, centred over
// the point) in a 1 x 1 pixel nadir view from below the plate: the zenith sun is shadowed and the
// sky is cut by the plate's view factor F = 4 F_corner(1/1.5, 1/1.5), so Ed(0+) = pi L (1 - F).
// One cosine-distributed sky ray per sample, 65536 samples: a binomial count, standard error
// pi L sqrt(F (1 - F) / N); tolerance 4 of them. In the open (a second pixel far from the plate),
// Ed(0+) = E_sun <cos>_disc + pi L, exact to rounding (the disc's mean cosine at the zenith differs
// from 1 by (1 - cos alpha) / 2 = 5e-6, alpha the disc's radius; the disc points' cosines spread
// by alpha^2 / (2 sqrt 12) about it, so 4 of their standard errors over 64 samples are the
// tolerance).
TEST(WaterProducts, Ed0IsTheSunAndSkyCutByWhatShadowsTheSea) {
    ir::SceneIR s = uniformSkyScene();  // L = 1 / pi: pi L = 1
    s.sun.enabled = true;
    s.sun.zenith = 0;
    s.sun.irradiance = Spectrum::constant(kProductsE);
    s.media.push_back(water(0.2, 0, kProductsN));
    s.materials.push_back(typedMaterial("sea", M::Type::Dielectric));
    s.materials.push_back(material("black", M::Type::Black, M::Solver::Classic));
    s.meshes.push_back(meshOf("water", box({-100, -100, -10}, {100, 100, 0}, 0, 1), {"sea", "black"}, "water", "", true));
    s.meshes.push_back(meshOf("plate", box({-1, -1, 1.5}, {1, 1, 1.52}), {"black"}, "", "", true));
    const int spp = 65536;
    ir::Sensor under = ortho("under", {0, 0, 0.75}, {0, 0, -1}, {0, 1, 0}, 1, 1, 1e-4);
    under.samplesPerPixel = spp;
    ir::Sensor open = ortho("open", {50, 50, 5}, {0, 0, -1}, {0, 1, 0}, 1, 1, 1e-4);
    open.samplesPerPixel = 64;
    const double F = 4 * cornerViewFactor(1 / 1.5, 1 / 1.5);
    const double expected = 1.0 - F, se = std::sqrt(F * (1 - F) / spp);
    const SensorImage a = render(s, under, true), b = render(s, open, true);
    std::printf("[ Ed(0+) ] under the plate %.5f (expected %.5f +- %.5f, F = %.4f); open %.4f\n",
                a.products->ed0.at(0, 0, 0), expected, se, F, b.products->ed0.at(0, 0, 0));
    EXPECT_NEAR(a.products->ed0.at(0, 0, 0), expected, 4 * se);
    const double alpha = s.sun.halfAngle;
    EXPECT_NEAR(b.products->ed0.at(0, 0, 0), kProductsE * (1 + std::cos(alpha)) / 2 + 1.0,
                4 * kProductsE * alpha * alpha / (2 * std::sqrt(12.0)) / std::sqrt(64.0) + 1e-4);
}

}  // namespace
}  // namespace littoral::render
