// Photon maps (issue 9): record encoding, grid queries against brute force, and the SurfacePM and
// MediumPM solvers against analytic irradiance and the path estimator.
#include <gtest/gtest.h>

#include <cmath>

#include "core/rng.h"
#include "core/units.h"
#include "render/estimator.h"
#include "render/photon_map.h"
#include "render/photon_pass.h"
#include "render/probes.h"
#include "render/renderer.h"
#include "tests/render/render_test_scenes.h"

namespace littoral::render {
namespace {

using namespace testing;
using M = ir::Material;

// binary16 and octahedral encodings: exact for representable values, within their stated
// precision otherwise (binary16: half an ulp, 2^-11 relative; octahedral 16+16 bits: the grid step
// 2/65535 on the octahedron maps to at most ~1e-4 rad on the sphere).
TEST(PhotonMap, EncodingsKeepTheirPrecision) {
    for (float v : {0.0f, 1.0f, -2.5f, 65504.0f, 0.5f, 3.0517578125e-05f}) EXPECT_EQ(halfToFloat(floatToHalf(v)), v);
    for (int k = 0; k < 1000; ++k) {
        RandomStream rng(11, 0, k);
        const float v = static_cast<float>(std::exp(rng.uniform() * 18 - 9));  // normal binary16 range
        EXPECT_NEAR(halfToFloat(floatToHalf(v)), v, v * std::ldexp(1.0, -11)) << v;
        const Vec3 d = normalize(Vec3{rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5});
        EXPECT_LT(std::acos(std::min(1.0, dot(decodeOctahedral(encodeOctahedral(d)), d))), 1.2e-4);
    }
    EXPECT_EQ(PhotonMap::bytesPerPhoton(4, false), 24u);  // the aim: <= 32 bytes for 4 bands
    EXPECT_EQ(PhotonMap::bytesPerPhoton(4, true), 28u);
}

// Sphere and segment queries return exactly the photons a brute-force scan finds.
TEST(PhotonMap, GridQueriesMatchBruteForce) {
    PhotonMap m(1, false);
    RandomStream rng(5, 0, 0);
    for (int i = 0; i < 50000; ++i)
        m.add({rng.uniform() * 4 - 2, rng.uniform() * 4 - 2, -rng.uniform() * 5}, {0, 0, -1}, {0, 0, 1}, Spec(1, 1.0));
    m.build(0.2);
    for (int q = 0; q < 100; ++q) {
        const Point3 o{rng.uniform() * 4 - 2, rng.uniform() * 4 - 2, -rng.uniform() * 5};
        const Vec3 d = normalize(Vec3{rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5});
        const double r = 0.05 + 0.15 * rng.uniform(), t1 = rng.uniform();
        int gs = 0, bs = 0, gc = 0, bc = 0;
        m.forEachInSphere(o, r, [&](size_t) { ++gs; });
        m.forEachNearSegment(o, d, 0.0, t1, r, [&](size_t, double) { ++gc; });
        for (size_t i = 0; i < m.size(); ++i) {
            const Vec3 v = m.position(i) - o;
            bs += lengthSquared(v) <= r * r;
            const double t = dot(v, d);
            bc += t >= 0 && t < t1 && lengthSquared(v) - t * t <= r * r;
        }
        EXPECT_EQ(gs, bs);
        EXPECT_EQ(gc, bc);
    }
}

// A white-ish Lambertian plane under a sun at 30 deg and a uniform sky, seen by the SurfacePM
// solver: L = r (E_sun cos 30 + pi L_sky) / pi exactly (nothing occludes). Photons land uniformly,
// so the estimate from the N photons in a search disc has relative standard error 1/sqrt(N)
// (equal-flux photons; the sun/sky choice adds no variance since both carry relative power 1).
// Tolerance: 4 standard errors of the 16-pixel mean (pixels 0.5 m apart share no photons).
TEST(SurfacePM, PlaneUnderSunAndSkyMatchesIrradiance) {
    ir::SceneIR s;
    s.name = "surface-pm";
    s.domain = {-2, 2, -2, 2, false};
    s.sun.enabled = true;
    s.sun.zenith = deg2rad(30);
    s.sun.irradiance = Spectrum::constant(1.0);
    s.sky.radiance = Spectrum::constant(0.1);
    s.render.surfacePhotons = 400000;
    s.render.surfaceSearchRadius = 0.15;
    s.materials.push_back(material("sand", M::Type::Lambertian, M::Solver::SurfacePM, 0.4));
    s.meshes.push_back(meshOf("ground", plane(-3, 3, -3, 3, 0), {"sand"}));
    s.sensors.push_back(ortho("o", {0, 0, 5}, {0, 0, -1}, {0, 1, 0}, 4, 4, 0.5));
    const Scene scene(s, ".");
    const SensorImage img = renderSensor(scene, s.sensors[0], quiet());
    const double E = std::cos(deg2rad(30)) + kPi * 0.1, pred = 0.4 * E / kPi;
    double sum = 0;
    for (float v : img.film.pixels) sum += v / 16.0;
    // Photons per disc: 400000 over 16 m^2 x pi 0.15^2 = 1767: 2.4 % per pixel, 0.6 % for 16.
    const double se = pred / std::sqrt(400000.0 / 16.0 * kPi * 0.15 * 0.15) / 4.0;
    EXPECT_NEAR(sum, pred, 4 * se);
    std::printf("[ surface-pm ] plane: %.6f (predicted %.6f, se %.6f)\n", sum, pred, se);
}

// Boundary compensation: a 1 m x 1 m platform (a box top) 0.5 m above black ground, under a
// uniform sky only (E = pi L_sky everywhere on the top). A pixel 0.05 m inside the edge has a
// search disc (r = 0.2 m) that the edge cuts: without compensation the estimate would be low by
// the uncovered fraction (here 0.43), with it the irradiance is recovered within its noise.
TEST(SurfacePM, BoundaryCompensationAtAnEdge) {
    ir::SceneIR s;
    s.name = "edge";
    s.domain = {-1.5, 1.5, -1.5, 1.5, false};
    s.sun.enabled = false;
    s.sky.radiance = Spectrum::constant(1.0 / kPi);
    s.render.surfacePhotons = 400000;
    s.render.surfaceSearchRadius = 0.2;
    s.materials.push_back(material("white", M::Type::Lambertian, M::Solver::SurfacePM, 1.0));
    ir::Material black = material("black", M::Type::Black, M::Solver::Classic);
    s.materials.push_back(black);
    s.meshes.push_back(meshOf("ground", plane(-3, 3, -3, 3, 0), {"black"}));
    s.meshes.push_back(meshOf("platform", box({-0.5, -0.5, 0}, {0.5, 0.5, 0.5}), {"white"}, "", "", true));
    // Pixels at x = 0.45 (0.05 m inside the edge x = 0.5) and at the centre.
    s.sensors.push_back(ortho("edge", {0.45, 0, 5}, {0, 0, -1}, {0, 1, 0}, 1, 1, 1e-3));
    s.sensors.push_back(ortho("centre", {0, 0, 5}, {0, 0, -1}, {0, 1, 0}, 1, 1, 1e-3));
    const Scene scene(s, ".");
    const EstimatorSet est(scene);
    const double edge = renderSensor(scene, est, s.sensors[0], quiet()).film.pixels[0];
    const double centre = renderSensor(scene, est, s.sensors[1], quiet()).film.pixels[0];
    // The top sees the whole sky (nothing above it): L = r E / pi = 1/pi. The photons on the top
    // come from 400000 over 9 m^2: about 2800 per disc (1.9 %), 1600 in the cut disc (2.5 %).
    const double pred = 1.0 / kPi;
    EXPECT_NEAR(centre, pred, 4 * 0.019 * pred);
    EXPECT_NEAR(edge, pred, 4 * 0.025 * pred);
    // Without compensation it would be low by the uncovered fraction of the disc (a straight edge at
    // distance d = 0.05 from the centre: covered = (pi - acos(d/r) + (d/r) sqrt(1 - (d/r)^2)) / pi).
    const double u = 0.05 / 0.2, covered = (kPi - std::acos(u) + u * std::sqrt(1 - u * u)) / kPi;
    EXPECT_GT(edge, pred * (covered + 4 * 0.025));
    std::printf("[ surface-pm ] edge %.5f, centre %.5f (predicted %.5f; uncompensated %.5f)\n", edge, centre, pred,
                pred * covered);
}

}  // namespace
}  // namespace littoral::render
