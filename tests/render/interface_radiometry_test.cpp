// Chapter 4 interface tests (seed-ch01-04.md §4): Fresnel reflectance under a uniform sky
// (test A), the Snell window seen by a submerged camera (test C) and the droplet over a
// Lambertian ground (test D).
#include <gtest/gtest.h>

#include <cmath>

#include "core/progress.h"
#include "core/units.h"
#include "render/renderer.h"
#include "tests/render/render_test_scenes.h"

namespace littoral::render {
namespace {

using namespace testing;
using M = ir::Material;

// ---------------------------------------------------------------------------------------------
// Test A (§4.1): a 10 m water hemisphere on a black ground under a uniform sky (E_h = 1,
// L_sky = 1/pi), nadir pinhole camera on the axis at H = 30 m. Per pixel (centre ray at angle
// alpha from the axis) the law of sines gives the incidence angle theta_i = asin((H/R) sin alpha)
// (§4.1 derived form); the reflected ray leaves at 2 theta_i - alpha from the zenith, so the
// pixel sees the sky, L = r_f(theta_i)/pi (Eq. 4.4), when 2 theta_i - alpha < 90 deg and the black
// ground (0) otherwise: the exact, pixel-dependent cut-off theta_i = 45 deg + alpha/2. The
// transmitted part ends on the black ground and contributes nothing.
TEST(InterfaceRadiometry, HemisphereFresnelReflectanceUnderUniformSky) {
    const double R = 10.0, H = 30.0, n = 1.34;
    const int W = 96;
    const double f = 0.005, pitch = 40e-6;
    const int nTheta = 256, nPhi = 512;
    ir::SceneIR s = uniformSkyScene();
    s.media.push_back(water(0, 0, n));
    s.materials.push_back(material("water", M::Type::Dielectric, M::Solver::Fresnel));
    s.materials.push_back(material("black", M::Type::Black, M::Solver::Classic));
    s.meshes.push_back(meshOf("droplet", dome({0, 0, 0}, R, nTheta, nPhi), {"water"}, "water", ""));
    s.meshes.push_back(meshOf("ground", plane(-1000, 1000, -1000, 1000, 0), {"black"}));
    s.sensors.push_back(pinhole("nadir", {0, 0, H}, {0, 0, -1}, {0, 1, 0}, W, W, f, pitch));
    const Scene scene(s, ".");
    const SensorImage img = renderSensor(scene, s.sensors[0], quiet());

    // Faceting bound: a lat-long cell spans dTheta = (pi/2)/256 by dPhi = 2 pi/512; a triangle
    // inscribed in the sphere has its facet normal along its circumcentre, and every point of the
    // triangle lies within the circumradius, at most half the cell diagonal, of it:
    // delta <= sqrt(dTheta^2 + dPhi^2)/2 = 6.9e-3 rad. The normal error shifts theta_i by at most
    // delta and the reflected direction by 2 delta.
    const double dTh = 0.5 * kPi / nTheta, dPh = 2 * kPi / nPhi;
    const double delta = 0.5 * std::sqrt(dTh * dTh + dPh * dPh);
    int tested = 0, lit = 0, dark = 0;
    for (int j = 0; j < W; ++j)
        for (int i = 0; i < W; ++i) {
            const double u = (i + 0.5 - W / 2.0) * pitch, v = (j + 0.5 - W / 2.0) * pitch;
            const double alpha = std::atan(std::hypot(u, v) / f);
            const double L = img.film.at(i, j, 0);
            const double s1 = H / R * std::sin(alpha);
            if (s1 >= 1.0) {
                // Misses the sphere: black ground. Skip the limb ring where the faceted silhouette
                // differs from the sphere's.
                if (s1 > 1.0 / std::cos(delta) + 1e-3) {
                    EXPECT_EQ(L, 0.0) << i << "," << j;
                    ++tested;
                }
                continue;
            }
            const double thetaI = std::asin(s1);                // law of sines, Fig. 4.4
            if (thetaI > deg2rad(80)) continue;                 // grazing limb: faceting dominates
            const double elevFromZenith = 2 * thetaI - alpha;   // reflected ray
            if (std::abs(elevFromZenith - 0.5 * kPi) < 2 * delta + 1e-3) continue;  // straddles the cut-off ring
            if (elevFromZenith < 0.5 * kPi) {
                const double pred = fresnelEq42(thetaI, 1.0, n) / kPi;  // Eq. 4.4, E_h = 1
                // Tolerance: the largest change of r_f/pi over theta_i +- delta, plus float storage.
                const double tol = std::max(std::abs(fresnelEq42(thetaI + delta, 1.0, n) / kPi - pred),
                                            std::abs(fresnelEq42(std::max(0.0, thetaI - delta), 1.0, n) / kPi - pred)) +
                                   1e-6 * pred;
                EXPECT_NEAR(L, pred, tol) << "pixel " << i << "," << j << " theta_i " << rad2deg(thetaI);
                ++lit;
            } else {
                EXPECT_EQ(L, 0.0) << "pixel " << i << "," << j << " beyond the 45 + alpha/2 cut-off";
                ++dark;
            }
            ++tested;
        }
    // The droplet covers pi (R/H)^2 of the field... in pixels: most of the disc must be tested.
    EXPECT_GT(lit, 3000);
    EXPECT_GT(dark, 300);
    EXPECT_GT(tested, W * W * 8 / 10);
    // Centre value (§4.1): r_f(0)/pi = 0.0067201.
    EXPECT_NEAR(img.film.at(W / 2, W / 2, 0), 0.0067201, 2e-6);
    std::printf("[ hemisphere ] %d pixels tested (%d lit, %d beyond cut-off), centre %.7f\n", tested, lit, dark,
                img.film.at(W / 2, W / 2, 0));
}

// ---------------------------------------------------------------------------------------------
// Test C (§4.3): submerged upward camera, 200 x 200 px, f = 5000 um, pitch 100 um, at depth
// z = 5 m in a 10 m deep water volume (n = 1.34, a = 0.05, b = 0.09 m^-1, c = 0.14) under a
// uniform sky. Inside the Snell window L = (E_h/pi) T_f(theta_w) n^2 exp(-c z / cos theta_w)
// (Eq. 4.7); beyond the critical angle asin(1/1.34) = 48.27 deg the ray is totally reflected to
// the black floor: L = 0.
TEST(InterfaceRadiometry, SubmergedCameraSnellWindow) {
    const double n = 1.34, a = 0.05, b = 0.09, c = a + b, z = 5.0;
    const int W = 200;
    const double f = 5000e-6, pitch = 100e-6;
    ir::SceneIR s = uniformSkyScene();
    s.media.push_back(water(a, b, n));
    s.materials.push_back(material("surface", M::Type::Dielectric, M::Solver::Fresnel));
    s.materials.push_back(material("black", M::Type::Black, M::Solver::Classic));
    // Closed water volume: top face = air-water interface (slot 0), floor and walls black (slot 1).
    s.meshes.push_back(meshOf("water", box({-300, -300, -10}, {300, 300, 0}, 0, 1), {"surface", "black"}, "water",
                              "", true));
    s.sensors.push_back(pinhole("up", {0, 0, -z}, {0, 0, 1}, {0, 1, 0}, W, W, f, pitch, "water"));
    const Scene scene(s, ".");
    const SensorImage img = renderSensor(scene, s.sensors[0], quiet());

    const double thetaC = std::asin(1.0 / n);
    double maxRel = 0;
    int inside = 0;
    for (int j = 0; j < W; ++j)
        for (int i = 0; i < W; ++i) {
            const double u = (i + 0.5 - W / 2.0) * pitch, v = (j + 0.5 - W / 2.0) * pitch;
            const double thetaW = std::atan(std::hypot(u, v) / f);
            const double L = img.film.at(i, j, 0);
            if (thetaW >= thetaC) {
                EXPECT_EQ(L, 0.0) << i << "," << j;
                continue;
            }
            const double Tf = 1.0 - fresnelEq42(thetaW, n, 1.0);
            const double pred = (1.0 / kPi) * Tf * n * n * std::exp(-c * z / std::cos(thetaW));  // Eq. 4.7
            // The interface is exactly flat and every pixel uses its centre ray: the only error is
            // float storage of the film (6e-8 relative) and double rounding; 1e-6 relative bounds both.
            EXPECT_NEAR(L, pred, 1e-6 * pred) << i << "," << j;
            maxRel = std::max(maxRel, std::abs(L - pred) / pred);
            ++inside;
        }
    // TIR boundary on the central row (pixel centres at tan theta = 0.02 (i + 0.5 - 100)): the
    // predicted first and last lit pixels are those with |i + 0.5 - 100| * 0.02 < tan(theta_c)
    // (in the row j = 100 the centre also sits 0.5 px off the axis, included exactly here).
    const int j = W / 2;
    int first = -1, last = -1;
    for (int i = 0; i < W; ++i)
        if (img.film.at(i, j, 0) > 0) {
            if (first < 0) first = i;
            last = i;
        }
    int pf = -1, pl = -1;
    for (int i = 0; i < W; ++i) {
        const double t = std::hypot(i + 0.5 - W / 2.0, j + 0.5 - W / 2.0) * pitch / f;
        if (std::atan(t) < thetaC) {
            if (pf < 0) pf = i;
            pl = i;
        }
    }
    EXPECT_EQ(first, pf);
    EXPECT_EQ(last, pl);
    EXPECT_EQ(pf, 44);   // §4.3: "pixel locations 44 and 156" (156 = one past the last lit, 155)
    EXPECT_EQ(pl, 155);
    // On-axis value (§4.3 table, z = 5: 0.55949 exp(-0.7) = 0.27784).
    EXPECT_NEAR(img.film.at(W / 2, W / 2, 0), 0.55949 * std::exp(-c * z), 2e-4);
    std::printf("[ snell window ] %d pixels inside, max rel. error %.2e, TIR edge at columns %d..%d\n", inside,
                maxRel, first, last);
}

// ---------------------------------------------------------------------------------------------
// Test D (§4.4): nadir camera over a 10 m water hemisphere on a Lambertian ground (r_g = 0.2,
// Generic solver, max bounce 1) under a uniform sky. At the droplet centre the camera ray enters
// at normal incidence and every hemisphere sample of the ground leaves along a radius, so
//   L = r_f(0)/pi + T_f(0)^2 (r_g/pi) exp(-2 c R)
// (Eq. 4.8 with the corrected attenuation exp(-2 sigma R); the n^2 factors cancel).
// c = 0.02: 0.0476112; c = 0: 0.0677224.
TEST(InterfaceRadiometry, DropletOverLambertianGroundTestD) {
    const double R = 10.0, n = 1.34, rg = 0.2;
    for (double sigma : {0.02, 0.0}) {
        ir::SceneIR s = uniformSkyScene();
        s.render.settings.set("max_bounces", 1);
        s.render.settings.set("hemisphere_samples", 64);
        s.media.push_back(water(sigma / 2, sigma / 2, n));
        s.materials.push_back(material("water", M::Type::Dielectric, M::Solver::Fresnel));
        s.materials.push_back(material("ground", M::Type::Lambertian, M::Solver::Generic, rg));
        s.meshes.push_back(meshOf("droplet", dome({0, 0, 0}, R, 128, 256), {"water"}, "water", ""));
        s.meshes.push_back(meshOf("ground", plane(-1000, 1000, -1000, 1000, 0), {"ground"}));
        const int W = 41;
        s.sensors.push_back(pinhole("nadir", {0, 0, 30}, {0, 0, -1}, {0, 1, 0}, W, W, 0.005, 130e-6));
        const Scene scene(s, ".");
        const SensorImage img = renderSensor(scene, s.sensors[0], quiet());
        const double rf0 = sqr((n - 1) / (n + 1));
        const double pred = rf0 / kPi + sqr(1 - rf0) * rg / kPi * std::exp(-2 * sigma * R);
        const double centre = img.film.at(W / 2, W / 2, 0);
        // Error budget at the centre: the tessellation (128 rings) tilts facets by at most
        // delta = 0.009 rad, changing T_f near normal incidence by O(delta^2) ~ 1e-5 and the radial
        // path by R (1 - cos delta) = 4e-4 m (exp change 2 c x 4e-4 = 2e-5); the camera ray's
        // refraction moves the ground point by < 1 cm, where the mean radial path changes only
        // to second order. Each ground sample ray is split deterministically at the dome and its
        // reflected half ends on the ground at the bounce limit, so there is no sampling noise:
        // 2e-4 relative covers all of it.
        EXPECT_NEAR(centre, pred, 2e-4 * pred) << "sigma " << sigma;
        // Far from the droplet the ground sees the whole sky: r_g/pi = 0.0636620 (E_h = 1). The
        // image corners are ~20 m from the centre, where the droplet hides part of the sky
        // (some of it transmitted with losses): slightly lower, as DIRSIG's edge pixels (§4.4).
        const double bare = rg / kPi;
        const double corner = img.film.at(0, 0, 0);
        EXPECT_LT(corner, bare);
        EXPECT_GT(corner, 0.9 * bare);
        std::printf("[ droplet D ] sigma %.2f: centre %.7f (predicted %.7f), corner %.7f (bare %.7f)\n", sigma,
                    centre, pred, corner, bare);
    }
}

// Test D under the path estimator (maxBounces 1 as above, no per-material solver): each path
// takes one cosine-sampled ray at the ground, so the centre is estimated with noise. A 3 x 3
// image of 2e-4 rad pixels: every ray enters within 3e-4 rad of normal incidence and lands within
// 5 mm of the axis, where (by symmetry, to second order) T_f and the mean radial path change by
// < 1e-6 relative, so the 9 pixels are independent estimates of the same value: their mean must
// match the prediction within 4 standard errors of the mean (from their spread) plus the 2e-4
// faceting budget of the test above, and that standard error must be below 1 %. (From the
// centre every sampled ray leaves along a radius and meets the dome at normal incidence, so
// every path carries the same value: the spread is nearly zero.)
TEST(InterfaceRadiometry, DropletOverLambertianGroundTestDPathEstimator) {
    const double R = 10.0, n = 1.34, rg = 0.2, sigma = 0.02;
    ir::SceneIR s = uniformSkyScene();
    s.render.estimator = ir::Estimator::Path;
    s.render.settings.set("max_bounces", 1);
    s.media.push_back(water(sigma / 2, 0.0, n));
    s.media.back().layers[0].absorption = Spectrum::constant(sigma);  // all of sigma as absorption
    s.materials.push_back(material("water", M::Type::Dielectric, M::Solver::Fresnel));
    s.materials.push_back(material("ground", M::Type::Lambertian, M::Solver::Generic, rg));
    for (auto& m : s.materials) m.solver.reset();
    s.meshes.push_back(meshOf("droplet", dome({0, 0, 0}, R, 128, 256), {"water"}, "water", ""));
    s.meshes.push_back(meshOf("ground", plane(-1000, 1000, -1000, 1000, 0), {"ground"}));
    ir::Sensor cam = pinhole("nadir", {0, 0, 30}, {0, 0, -1}, {0, 1, 0}, 3, 3, 0.005, 1e-6);
    cam.samplesPerPixel = 4096;
    s.sensors.push_back(cam);
    const Scene scene(s, ".");
    const SensorImage img = renderSensor(scene, s.sensors[0], quiet());
    const double rf0 = sqr((n - 1) / (n + 1));
    const double pred = rf0 / kPi + sqr(1 - rf0) * rg / kPi * std::exp(-2 * sigma * R);
    double sum = 0, sum2 = 0;
    for (float v : img.film.pixels) sum += v, sum2 += double(v) * v;
    const double mean = sum / 9, se = std::sqrt((sum2 / 9 - mean * mean) / 8);
    EXPECT_NEAR(mean, pred, 4 * se + 2e-4 * pred);
    EXPECT_LT(se / pred, 0.01);
    std::printf("[ droplet D path ] centre %.6f +- %.6f (predicted %.7f)\n", mean, se, pred);
}

}  // namespace
}  // namespace littoral::render

namespace littoral::render {
namespace {

using namespace testing;
using M = ir::Material;

// Test B (§4.2) with the physically exact glint rule: flat water (black floor), nadir sun,
// skyfraction 0.5 of E_h = 1 (L_sky = 0.5/pi, E_sun = 0.5), nadir camera with an IFOV of
// 0.053 deg. A pixel whose mirrored ray (angle alpha off the zenith) lies inside the 0.265 deg
// solar disc returns r_f(alpha) (E_sun / Omega_sun + L_sky), Omega_sun = 2 pi (1 - cos 0.265 deg);
// elsewhere r_f(alpha) L_sky. The planar glint is 10 pixels wide (sun diameter / IFOV).
TEST(InterfaceRadiometry, PlanarSunGlintExact) {
    ir::SceneIR s = uniformSkyScene();
    const auto split = skyFractionSplit(1.0, 0.5, 0.0);
    s.sky.radiance = Spectrum::constant(split.skyRadiance);
    s.sun.enabled = true;
    s.sun.zenith = 0;
    s.sun.irradiance = Spectrum::constant(split.sunBeamIrradiance);
    s.media.push_back(water(0, 0, 1.34));
    s.materials.push_back(material("surface", M::Type::Dielectric, M::Solver::Fresnel));
    s.materials.push_back(material("black", M::Type::Black, M::Solver::Classic));
    s.meshes.push_back(meshOf("water", box({-500, -500, -99}, {500, 500, 0}, 0, 1), {"surface", "black"}, "water", "",
                              true));
    const int W = 40;
    const double f = 0.1, pitch = 0.1 * std::tan(deg2rad(0.053));
    s.sensors.push_back(pinhole("nadir", {0, 0, 1}, {0, 0, -1}, {0, 1, 0}, W, W, f, pitch));
    const Scene scene(s, ".");
    const SensorImage img = renderSensor(scene, s.sensors[0], quiet());
    const double half = s.sun.halfAngle, omega = 2 * kPi * (1 - std::cos(half));
    int glintRow = 0;
    for (int j = 0; j < W; ++j)
        for (int i = 0; i < W; ++i) {
            const double alpha = std::atan(std::hypot(i + 0.5 - W / 2.0, j + 0.5 - W / 2.0) * pitch / f);
            const double rf = fresnelEq42(alpha, 1.0, 1.34);
            if (std::abs(alpha - half) < 1e-6) continue;  // no pixel centre sits on the rim here
            const double pred = rf * (split.skyRadiance + (alpha < half ? 0.5 / omega : 0.0));
            EXPECT_NEAR(img.film.at(i, j, 0), pred, 1e-6 * pred) << i << "," << j;
            if (j == W / 2 && alpha < half) ++glintRow;
        }
    EXPECT_EQ(glintRow, 10);  // §4.2: 10 x 10 pixel glint for a 0.053 deg IFOV
    std::printf("[ glint ] %d px across, glint radiance %.1f (DIRSIG Eq. 4.6 would give E_s r_f/Omega_d = %.1f)\n",
                glintRow, img.film.at(W / 2, W / 2, 0), 0.5 * fresnelEq42(0, 1, 1.34) / sqr(pitch / f));
}

}  // namespace
}  // namespace littoral::render

namespace littoral::render {
namespace {

using namespace testing;
using M = ir::Material;

// Direct sun on a Lambertian bottom under flat water, seen from above (black sky, sun at 30 deg):
//   bottom:  L_b = (r/pi) T_f(30 deg) E_sun cos(30 deg) exp(-c D / cos theta_sw)   (Snell: sin theta_sw = sin 30/n)
//   sensor:  L = T_f(alpha) (1/n^2) exp(-c D / cos alpha_w) L_b                     (n^2 law on exit)
// The in-water sun estimate traces the refracted beam to the surface (Fresnel, Beer–Lambert,
// solid-angle compression); with the sampled point of the 0.53 deg disc varying T_f and the
// cosines by < 1e-3 relative.
TEST(InterfaceRadiometry, RefractedSunOnSubmergedBottom) {
    const double n = 1.34, c = 0.1, D = 5.0, r = 0.5, Es = 2.0, thS = deg2rad(30);
    ir::SceneIR s = uniformSkyScene();
    s.sky.radiance = Spectrum::constant(0.0);
    s.sun.enabled = true;
    s.sun.zenith = thS;
    s.sun.azimuth = deg2rad(40);
    s.sun.irradiance = Spectrum::constant(Es);
    s.render.settings.set("hemisphere_samples", 4);
    s.media.push_back(water(0.04, 0.06, n));
    s.materials.push_back(material("surface", M::Type::Dielectric, M::Solver::Fresnel));
    s.materials.push_back(material("sand", M::Type::Lambertian, M::Solver::Classic, r));
    s.meshes.push_back(meshOf("water", box({-100, -100, -D}, {100, 100, 0}, 0, 1), {"surface", "sand"}, "water", "",
                              true));
    const int W = 21;
    const double f = 0.01, pitch = 1e-4;
    s.sensors.push_back(pinhole("nadir", {0, 0, 10}, {0, 0, -1}, {0, 1, 0}, W, W, f, pitch));
    const Scene scene(s, ".");
    const SensorImage img = renderSensor(scene, s.sensors[0], quiet());
    const double thSw = std::asin(std::sin(thS) / n);
    const double Lb = r / kPi * (1 - fresnelEq42(thS, 1, n)) * Es * std::cos(thS) * std::exp(-c * D / std::cos(thSw));
    // Each pixel uses one uniformly sampled point of the disc (half-angle a = 0.265 deg): cos theta_s
    // then varies by up to tan(30 deg) a = 0.27 % (T_f and the slant path by far less), so a pixel
    // lies within 0.35 % of the disc-centre prediction. Over the 441 pixels the relative spread
    // (uniform over the disc: sd <= 0.27 %/2) averages down to a standard error of 0.007 %; the
    // mean ratio must be 1 within 4 standard errors plus the 1e-4 second-order disc-average term.
    const double a = s.sun.halfAngle;
    double sumRatio = 0;
    for (int j = 0; j < W; ++j)
        for (int i = 0; i < W; ++i) {
            const double alpha = std::atan(std::hypot(i + 0.5 - W / 2.0, j + 0.5 - W / 2.0) * pitch / f);
            const double alphaW = std::asin(std::sin(alpha) / n);
            const double pred = (1 - fresnelEq42(alpha, 1, n)) / (n * n) * std::exp(-c * D / std::cos(alphaW)) * Lb;
            EXPECT_NEAR(img.film.at(i, j, 0), pred, (std::tan(thS) * a + 8e-4) * pred) << i << "," << j;
            sumRatio += img.film.at(i, j, 0) / pred;
        }
    const double meanRatio = sumRatio / (W * W);
    EXPECT_NEAR(meanRatio, 1.0, 4 * 0.5 * std::tan(thS) * a / W + 1e-4);
    std::printf("[ refracted sun ] bottom radiance %.6f, nadir pixel %.6f, mean pixel/prediction %.6f\n", Lb,
                img.film.at(W / 2, W / 2, 0), meanRatio);
}

}  // namespace
}  // namespace littoral::render

namespace littoral::render {
namespace {

using namespace testing;
using M = ir::Material;

// Dispersion: the water index rises linearly from 1.33 at 0.4 um to 1.35 at 0.6 um, so the bands
// [0.4, 0.5] and [0.5, 0.6] average to n = 1.335 and 1.345 and are traced as separate band
// groups with their own ray geometry. Each band's Snell window follows Eq. 4.7 with its own n
// (c = 0), and its TIR edge sits at its own critical angle. Truth images of the same render:
// every pixel-centre ray first meets the surface at range z / cos(theta); TIR pixels reach the
// black floor at depth 10 m, window pixels leave to the sky (hit depth NaN).
TEST(InterfaceRadiometry, DispersiveSnellWindowPerBandAndTruth) {
    const double z = 3.0;
    const int W = 80;
    const double f = 0.005, pitch = 1.5e-4;
    ir::SceneIR s = uniformSkyScene();
    s.render.bands = {Band{0.4, 0.5}, Band{0.5, 0.6}};
    ir::Medium w = water(0, 0);
    w.refractiveIndex = Spectrum::tabulated({0.4, 0.6}, {1.33, 1.35}, "water n");
    s.media.push_back(w);
    s.materials.push_back(material("surface", M::Type::Dielectric, M::Solver::Fresnel));
    s.materials.push_back(material("black", M::Type::Black, M::Solver::Classic));
    s.meshes.push_back(meshOf("water", box({-300, -300, -10}, {300, 300, 0}, 0, 1), {"surface", "black"}, "water",
                              "", true));
    s.sensors.push_back(pinhole("up", {0, 0, -z}, {0, 0, 1}, {0, 1, 0}, W, W, f, pitch, "water"));
    const Scene scene(s, ".");
    const SensorImage img = renderSensor(scene, s.sensors[0], quiet());
    const double nBand[2] = {1.335, 1.345};
    int differentEdge = 0;
    for (int j = 0; j < W; ++j)
        for (int i = 0; i < W; ++i) {
            const double theta = std::atan(std::hypot(i + 0.5 - W / 2.0, j + 0.5 - W / 2.0) * pitch / f);
            bool lit[2];
            for (int b = 0; b < 2; ++b) {
                const double n = nBand[b];
                lit[b] = theta < std::asin(1.0 / n);
                const double pred = lit[b] ? (1 - fresnelEq42(theta, n, 1.0)) * n * n / kPi : 0.0;
                EXPECT_NEAR(img.film.at(i, j, b), pred, 1e-6 * pred + 1e-12) << i << "," << j << " band " << b;
            }
            differentEdge += lit[0] != lit[1];
            const size_t k = img.truth.index(i, j);
            EXPECT_EQ(img.truth.materialId[k], 0);
            EXPECT_NEAR(img.truth.range[k], z / std::cos(theta), 1e-5 * z / std::cos(theta));
            // Truth follows band 0's geometry (n = 1.335).
            if (lit[0]) EXPECT_TRUE(std::isnan(img.truth.hitDepth[k]));
            else EXPECT_FLOAT_EQ(img.truth.hitDepth[k], 10.0f);
        }
    EXPECT_GT(differentEdge, 10);  // the two bands' windows differ in size by whole pixels
    std::printf("[ dispersion ] %d pixels inside the n = 1.335 window but not the n = 1.345 one\n", differentEdge);
}

}  // namespace
}  // namespace littoral::render
