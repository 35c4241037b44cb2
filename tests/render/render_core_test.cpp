// Render core: Fresnel optics, sampling triples, the Embree adapter (instancing, double-precision
// hits, self-intersection), camera geometry, thread-count determinism, probes and bad-input errors.
#include <gtest/gtest.h>

#include <limits>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <vector>

#include "core/error.h"
#include "core/frame.h"
#include "core/rng.h"
#include "core/stats.h"
#include "core/units.h"
#include "render/camera.h"
#include "render/embree_scene.h"
#include "render/bxdf.h"
#include "render/probes.h"
#include "render/render_job.h"
#include "render/renderer.h"
#include "render/sampling.h"
#include "tests/render/render_test_scenes.h"

namespace littoral::render {
namespace {

using namespace testing;
using M = ir::Material;

// ---- optics ---------------------------------------------------------------------------------

TEST(Fresnel, MatchesEq42AndPublishedValues) {
    const double n = 1.34;
    for (double deg = 0; deg < 89.9; deg += 0.5) {
        const double th = deg2rad(deg);
        EXPECT_NEAR(fresnelDielectric(std::cos(th), 1.0, n), fresnelEq42(th, 1.0, n), 1e-12) << deg;
        EXPECT_NEAR(fresnelDielectric(std::cos(th), n, 1.0), fresnelEq42(th, n, 1.0), 1e-12) << deg;
    }
    // seed-ch01-04.md §6 tables (n = 1.34), printed to 6 decimals.
    EXPECT_NEAR(fresnelDielectric(1.0, 1.0, n), 0.0211118, 1e-7);  // Eq. 4.3
    EXPECT_NEAR(fresnelDielectric(std::cos(deg2rad(45)), 1.0, n), 0.028782, 1e-6);
    EXPECT_NEAR(fresnelDielectric(std::cos(deg2rad(70)), 1.0, n), 0.135361, 1e-6);
    EXPECT_NEAR(fresnelDielectric(std::cos(deg2rad(40)), n, 1.0), 0.058813, 1e-6);
    EXPECT_NEAR(fresnelDielectric(std::cos(deg2rad(48)), n, 1.0), 0.570533, 1e-6);
    // Critical angle asin(1/1.34) = 48.268 deg: TIR just beyond.
    EXPECT_EQ(fresnelDielectric(std::cos(deg2rad(48.3)), n, 1.0), 1.0);
    EXPECT_LT(fresnelDielectric(std::cos(deg2rad(48.25)), n, 1.0), 1.0);
}

TEST(DielectricBxDF, EnergyAndN2Law) {
    // Importance transport conserves flux: R + T = 1 for every incidence, both sides.
    // Radiance transport scales the transmitted lobe by (n_o/n_t)^2.
    const DielectricBxDF w{1.0, 1.34};
    for (double deg = 1; deg < 89; deg += 4) {
        for (double side : {1.0, -1.0}) {
            const Vec3 wo{std::sin(deg2rad(deg)), 0, side * std::cos(deg2rad(deg))};
            BSDFSample r, t, ri, ti;
            const bool tr = w.specularPair(wo, TransportMode::Radiance, &r, &t);
            const bool tri = w.specularPair(wo, TransportMode::Importance, &ri, &ti);
            ASSERT_EQ(tr, tri);
            const double R = r.f * std::abs(r.wi.z);
            if (!tr) {
                EXPECT_DOUBLE_EQ(R, 1.0);
                continue;
            }
            EXPECT_NEAR(R + ti.f * std::abs(ti.wi.z), 1.0, 1e-12);
            const double nO = side > 0 ? 1.0 : 1.34, nT = side > 0 ? 1.34 : 1.0;
            EXPECT_NEAR(t.f / ti.f, sqr(nO / nT), 1e-12);
            // Snell, Eq. 4.1: n_o sin(theta_o) = n_t sin(theta_t), and the ray crosses the surface.
            EXPECT_NEAR(nO * std::sin(deg2rad(deg)), nT * std::sqrt(1 - t.wi.z * t.wi.z), 1e-12);
            EXPECT_LT(t.wi.z * wo.z, 0);
        }
    }
}

// Chi-square goodness of fit of cosine-hemisphere sampling against its pdf, and the inversion.
TEST(Sampling, CosineHemisphereMatchesPdf) {
    const int bins = 16, n = 200000;
    std::vector<double> counts(bins, 0);
    for (int k = 0; k < n; ++k) {
        RandomStream rng(3, 0, k);
        const double u1 = rng.uniform(), u2 = rng.uniform();
        const Vec3 w = sampleCosineHemisphere(u1, u2);
        ASSERT_NEAR(length(w), 1.0, 1e-12);
        const Vec2 back = invertCosineHemisphere(w);
        ASSERT_NEAR(back.x, u1, 1e-9);
        ASSERT_NEAR(back.y, u2, 1e-9);
        const int b = std::min(bins - 1, static_cast<int>(w.z * bins));
        counts[b] += 1;
    }
    // Expected fraction in cos(theta) in [a, b]: Int 2 pi (mu/pi) dmu = b^2 - a^2.
    double chi2 = 0;
    for (int b = 0; b < bins; ++b) {
        const double e = n * (sqr((b + 1.0) / bins) - sqr(double(b) / bins));
        chi2 += sqr(counts[b] - e) / e;
    }
    // 15 degrees of freedom: P(chi2 > 37.7) = 1e-3.
    EXPECT_LT(chi2, 37.7);
}

// White furnace: a Lambertian surface of reflectance 1 under a uniform sky L returns L whatever
// the solver (no occluders): r E/pi with E = pi L.
TEST(Lambertian, WhiteFurnace) {
    for (M::Solver solver : {M::Solver::Classic, M::Solver::Generic}) {
        ir::SceneIR s = uniformSkyScene();
        s.render.settings.set("hemisphere_samples", 16);
        s.materials.push_back(material("white", M::Type::Lambertian, solver, 1.0));
        s.meshes.push_back(meshOf("ground", plane(-10, 10, -10, 10, 0), {"white"}));
        s.sensors.push_back(ortho("o", {0, 0, 5}, {0, 0, -1}, {0, 1, 0}, 8, 8, 0.5));
        const Scene scene(s, ".");
        const SensorImage img = renderSensor(scene, s.sensors[0], quiet());
        for (float v : img.film.pixels) EXPECT_NEAR(v, 1.0 / kPi, 1e-7);
    }
}

// ---- Embree adapter --------------------------------------------------------------------------

// A unit dome at the origin and an instance of it rotated 90 deg about x (row-major), its pole
// along -y, moved to (instanceX, 0, 0).
ir::SceneIR domeAndRotatedInstance(double instanceX) {
    ir::SceneIR s = uniformSkyScene();
    s.materials.push_back(material("m", M::Type::Lambertian, M::Solver::Classic, 0.5));
    s.meshes.push_back(meshOf("sphere", dome({0, 0, 0}, 1.0, 32, 64), {"m"}));
    ir::Instance in;
    in.mesh = "sphere";
    const double R[9] = {1, 0, 0, 0, 0, -1, 0, 1, 0};
    std::copy(R, R + 9, in.rotation);
    in.translation = {instanceX, 0, 0};
    s.instances.push_back(in);
    return s;
}

TEST(EmbreeScene, InstancesDoubleHitsAndNoSelfIntersection) {
    const ir::SceneIR s = domeAndRotatedInstance(100);
    const EmbreeScene es(s);
    EXPECT_EQ(es.triangleCount(), 2 * s.meshes[0].data.triangles.size());

    // The instance's dome pole now points along -y: a ray along +y from (100, -5, 0) hits it at
    // y = -1 with the outward normal -y.
    Ray r;
    r.o = {100, -5, 0};
    r.d = {0, 1, 0};
    SurfaceHit h;
    ASSERT_TRUE(es.intersect(r, &h));
    EXPECT_EQ(h.instance, 0);
    EXPECT_EQ(h.mesh, 0);
    EXPECT_TRUE(h.front);
    EXPECT_NEAR(h.t, 4.0, 1e-12);  // pole vertex: the plane reconstruction is exact in double
    EXPECT_NEAR(h.ng.y, -1.0, 0.01);

    // Spawned rays never re-hit their own triangle: from 20000 hits on the dome (near the
    // origin and 100 m away, where float spacing is 100x coarser), rays leaving into random
    // directions on either side must not hit the same face at a tiny distance.
    int selfHits = 0, tested = 0;
    for (int k = 0; k < 20000; ++k) {
        RandomStream rng(11, 0, k);
        const double offsetX = (k % 2) ? 100.0 : 0.0;
        Ray q;
        const Vec3 target{offsetX + 0.9 * (rng.uniform() - 0.5), 0.9 * (rng.uniform() - 0.5), 0};
        q.o = target + Vec3{0, 0, 3};
        q.d = {0, 0, -1};
        if (k % 2) {  // the instance's dome faces -y
            q.o = Vec3{offsetX + 0.9 * (rng.uniform() - 0.5), -3, 0.9 * (rng.uniform() - 0.5)};
            q.d = {0, 1, 0};
        }
        SurfaceHit a;
        if (!es.intersect(q, &a)) continue;
        Vec3 w = sampleUniformHemisphere(rng.uniform(), rng.uniform());
        const Frame fr = Frame::fromNormal((k % 3 == 0) ? -a.ng : a.ng);  // leave outward or inward
        w = fr.toWorld(w);
        SurfaceHit b;
        ++tested;
        if (es.intersect(spawnRay(a.p, a.ng, w), &b) && b.face == a.face && b.instance == a.instance &&
            b.t < 1e-3)
            ++selfHits;
    }
    EXPECT_GT(tested, 15000);
    EXPECT_EQ(selfHits, 0);
}

// Finite rays through empty space are answered by the clearance grid without Embree: that must be
// invisible. Short segments around a direct mesh and a rotated instance (near the origin and 100 m
// away) hit or miss, and are occluded or not, exactly as bare Embree says, and the grid answered
// a good share of them.
TEST(EmbreeScene, ClearanceGridAnswersAsEmbreeDoes) {
    for (const double instanceX : {1.5, 100.0}) {
        const ir::SceneIR s = domeAndRotatedInstance(instanceX);
        const EmbreeScene es(s);
        StatCounter& answered = statCounter("rays answered by the clearance grid (no Embree traversal)");
        flushRayStats();
        const int64_t before = answered.value.load();
        int disagree = 0, hits = 0;
        const int n = 40000;
        for (int k = 0; k < n; ++k) {
            RandomStream rng(21, 0, k);
            const BBox3 b = es.bounds();
            Ray r;
            if (k % 2) {  // anywhere in the bounds
                r.o = {b.lo.x + (b.hi.x - b.lo.x) * rng.uniform(), b.lo.y + (b.hi.y - b.lo.y) * rng.uniform(),
                       b.lo.z + (b.hi.z - b.lo.z) * rng.uniform()};
            } else {  // within 1.3 m of a dome's centre
                const double cx = (k % 4 == 0) ? 0.0 : instanceX;
                r.o = {cx + 2.6 * (rng.uniform() - 0.5), 2.6 * (rng.uniform() - 0.5), 2.6 * (rng.uniform() - 0.5)};
            }
            r.d = sampleUniformHemisphere(rng.uniform(), rng.uniform());
            if (rng.uniform() < 0.5) r.d.z = -r.d.z;
            r.tMax = 0.05 + 0.3 * rng.uniform();
            SurfaceHit h;
            const bool hit = es.intersect(r, &h);
            hits += hit;
            disagree += hit != (es.rawIntersectCount(&r, 1) == 1);
            disagree += es.occluded(r) != (es.rawOccludedCount(&r, 1) == 1);
        }
        flushRayStats();
        EXPECT_EQ(disagree, 0) << "instance at x = " << instanceX;
        EXPECT_GT(hits, n / 100);  // the segments do meet the geometry (2535 and 765 when written)
        std::printf("instance at x = %g: %d of %d segments hit; the grid answered %lld of %d queries\n", instanceX, hits,
                    n, static_cast<long long>(answered.value.load() - before), 2 * n);
        // Of the 2n queries (intersect and occluded), a quarter or more in empty space: half the
        // origins are within 1.3 m of a dome, half anywhere in the bounds (51 % and 82 % when written).
        EXPECT_GT(answered.value.load() - before, n / 2) << "instance at x = " << instanceX;
    }
}

// The packet path (8 rays per Embree call) must give exactly the hits of the single-ray path:
// rays from one point into random directions (the Classic hemisphere case), over a direct mesh and
// a rotated instance, with misses, and a count that leaves a partial last packet.
TEST(EmbreeScene, CoherentPacketsMatchSingleRays) {
    const ir::SceneIR s = domeAndRotatedInstance(1.5);
    const EmbreeScene es(s);  // (keeps pointers to the IR's meshes)
    int hitsSeen = 0, missesSeen = 0, instanceHits = 0;
    for (int origin = 0; origin < 40; ++origin) {
        RandomStream rng(5, 1, origin);
        const Point3 o{0.8 * (rng.uniform() - 0.5), -2.0 + rng.uniform(), 0.3 * rng.uniform()};
        const int n = 13 + origin % 20;  // 13..32 rays: full and partial packets
        std::vector<Ray> rays(static_cast<size_t>(n));
        for (Ray& r : rays) {
            r.o = o;
            r.d = sampleUniformHemisphere(rng.uniform(), rng.uniform());
            if (rng.uniform() < 0.5) r.d.z = -r.d.z;  // the whole sphere of directions
        }
        std::vector<SurfaceHit> hits(rays.size());
        std::unique_ptr<bool[]> found(new bool[rays.size()]);
        es.intersectCoherent(rays.data(), n, hits.data(), found.get());
        for (int i = 0; i < n; ++i) {
            SurfaceHit h;
            const bool single = es.intersect(rays[static_cast<size_t>(i)], &h);
            ASSERT_EQ(found[i], single) << "origin " << origin << " ray " << i;
            if (!single) {
                ++missesSeen;
                continue;
            }
            ++hitsSeen;
            instanceHits += h.instance == 0;
            const SurfaceHit& p = hits[static_cast<size_t>(i)];
            EXPECT_EQ(p.face, h.face);
            EXPECT_EQ(p.instance, h.instance);
            EXPECT_EQ(p.mesh, h.mesh);
            EXPECT_EQ(p.front, h.front);
            EXPECT_EQ(p.t, h.t);  // the same double reconstruction from the same primitive
        }
    }
    // Coverage (not tolerances): every case was exercised many times (seen: 150 hits, 34 of them on
    // the instance, the rest of ~900 rays misses).
    EXPECT_GT(hitsSeen, 100);
    EXPECT_GT(missesSeen, 100);
    EXPECT_GT(instanceHits, 20);
}

TEST(Camera, PixelCentreConvention) {
    const ir::Sensor s = pinhole("c", {1, 2, 3}, {0, 0, -1}, {0, 1, 0}, 200, 100, 0.005, 1e-4);
    const Camera cam(s);
    // Pixel (0, 0) is top-left: -x (left) and +y (up in the image = upOrtho = +y).
    const Ray r = cam.generateRay(0.5, 0.5);
    const Vec3 expect = normalize(Vec3{-99.5 * 1e-4, 49.5 * 1e-4, -0.005});
    EXPECT_NEAR(r.d.x, expect.x, 1e-15);
    EXPECT_NEAR(r.d.y, expect.y, 1e-15);
    EXPECT_NEAR(r.d.z, expect.z, 1e-15);
    ir::Sensor bad = s;
    bad.width = 0;
    EXPECT_THROW(Camera{bad}, InputError);
}

// An up vector is a direction: (0, 1e200, 0), whose length overflows a double, gives the camera
// of (0, 1, 0) (it was refused as "parallel to forward"); zero and non-finite ones are refused.
TEST(Camera, UpVectorIsADirectionWhateverItsLength) {
    const ir::Sensor s = pinhole("c", {1, 2, 3}, {0, 0, -1}, {0, 1, 0}, 20, 10, 0.005, 1e-4);
    ir::Sensor huge = s;
    huge.up = {0, 1e200, 0};
    const Ray a = Camera(s).generateRay(0.5, 0.5), b = Camera(huge).generateRay(0.5, 0.5);
    EXPECT_EQ(a.d.x, b.d.x);
    EXPECT_EQ(a.d.y, b.d.y);
    EXPECT_EQ(a.d.z, b.d.z);
    for (const Vec3 bad : {Vec3{0, 0, 0}, Vec3{0, std::numeric_limits<double>::infinity(), 0}, Vec3{0, 0, 1}}) {
        ir::Sensor t = s;
        t.up = bad;
        EXPECT_THROW(Camera{t}, InputError);
    }
}

// ---- determinism -----------------------------------------------------------------------------

ir::SceneIR noisyScene() {
    ir::SceneIR s = uniformSkyScene();
    s.render.bands = {Band{0.4, 0.5}, Band{0.5, 0.6}};
    s.render.settings.set("hemisphere_samples", 8);
    s.render.settings.set("max_bounces", 3);
    s.sun.enabled = true;
    s.sun.zenith = deg2rad(30);
    s.sun.azimuth = deg2rad(20);
    s.sun.irradiance = Spectrum::constant(1.5);
    s.media.push_back(water(0.05, 0.05));
    s.materials.push_back(material("water", M::Type::Dielectric, M::Solver::Fresnel));
    s.materials.push_back(material("ground", M::Type::Lambertian, M::Solver::Generic, 0.3));
    s.materials.push_back(material("box", M::Type::Lambertian, M::Solver::Classic, 0.6));
    s.meshes.push_back(meshOf("droplet", dome({0, 0, 0}, 3, 24, 48), {"water"}, "water", ""));
    s.meshes.push_back(meshOf("ground", plane(-50, 50, -50, 50, 0), {"ground"}));
    s.meshes.push_back(meshOf("box", box({4, -1, 0}, {6, 1, 2}), {"box"}, "", "", true));
    ir::Sensor cam = pinhole("cam", {-8, -8, 8}, normalize(Vec3{1, 1, -0.8}), {0, 0, 1}, 40, 30, 0.005, 2e-4);
    cam.samplesPerPixel = 3;
    s.sensors.push_back(cam);
    return s;
}

TEST(Determinism, OneAndTwoThreadsBitwiseEqual) {
    const ir::SceneIR s = noisyScene();
    const Scene scene(s, ".");
    const SensorImage a = renderSensor(scene, s.sensors[0], quiet(1));
    const SensorImage b = renderSensor(scene, s.sensors[0], quiet(2));
    ASSERT_EQ(a.film.pixels.size(), b.film.pixels.size());
    EXPECT_EQ(0, std::memcmp(a.film.pixels.data(), b.film.pixels.data(), a.film.pixels.size() * sizeof(float)));
    EXPECT_EQ(a.truth.materialId, b.truth.materialId);
    // The image is not trivially constant (the test would be vacuous otherwise).
    double mn = 1e30, mx = 0;
    for (float v : a.film.pixels) {
        mn = std::min<double>(mn, v);
        mx = std::max<double>(mx, v);
    }
    EXPECT_GT(mx, 2 * mn + 1e-3);
    // A different seed changes the noise.
    ir::SceneIR s2 = s;
    s2.render.seed = 99;
    const Scene scene2(s2, ".");
    const SensorImage c = renderSensor(scene2, s2.sensors[0], quiet(2));
    EXPECT_NE(0, std::memcmp(a.film.pixels.data(), c.film.pixels.data(), a.film.pixels.size() * sizeof(float)));
}

// Progressive pass p draws its own pixel and probe samples: its estimates are independent of pass
// 1's (the passes' spread is the run's standard error), and pass 1 is what a single-pass render
// gives. (EstimatorSet(scene, pass) is what render_job builds for each pass.)
TEST(Determinism, ProgressivePassesDrawTheirOwnSamples) {
    ir::SceneIR s = noisyScene();
    ir::Probe p;
    p.name = "p";
    p.position = {-2, -2, 1};
    p.quantities = {"Eu"};  // the ground, box and droplet below: direction sampling is noisy
    s.render.settings.set("probe_samples", 64);
    s.probes.push_back(p);
    const Scene scene(s, ".");
    const EstimatorSet pass1(scene, 1), pass2(scene, 2);
    const SensorImage single = renderSensor(scene, s.sensors[0], quiet(2));
    const SensorImage a = renderSensor(scene, pass1, s.sensors[0], quiet(2));
    const SensorImage b = renderSensor(scene, pass2, s.sensors[0], quiet(2));
    const size_t bytes = a.film.pixels.size() * sizeof(float);
    EXPECT_EQ(0, std::memcmp(single.film.pixels.data(), a.film.pixels.data(), bytes));
    EXPECT_NE(0, std::memcmp(a.film.pixels.data(), b.film.pixels.data(), bytes));
    // Same expectation: the frame means agree within their noise (4 standard errors of a
    // difference of two independent means over the pixels).
    double ma = 0, mb = 0, va = 0;
    const size_t n = a.film.pixels.size();
    for (size_t k = 0; k < n; ++k) ma += a.film.pixels[k], mb += b.film.pixels[k];
    ma /= n, mb /= n;
    for (size_t k = 0; k < n; ++k) va += (a.film.pixels[k] - b.film.pixels[k]) * (a.film.pixels[k] - b.film.pixels[k]);
    const double seDiff = std::sqrt(va / n / n);  // the pixel differences' spread (an upper bound)
    EXPECT_NEAR(ma, mb, 4 * seDiff);
    const auto v1 = evaluateProbe(scene, pass1, s.probes[0], 0, quiet(2));
    const auto v2 = evaluateProbe(scene, pass2, s.probes[0], 0, quiet(2));
    ASSERT_EQ(v1.size(), 1u);
    EXPECT_NE(v1[0].mean[0], v2[0].mean[0]);
    EXPECT_NEAR(v1[0].mean[0], v2[0].mean[0], 4 * std::hypot(v1[0].stderr_[0], v2[0].stderr_[0]));
}

// ---- probes ----------------------------------------------------------------------------------

// In air above a black ground under a uniform sky L = 1/pi with a sun of beam irradiance 2 at
// 60 deg zenith: Ed = pi L + E_sun cos 60 = 1 + 1 = 2, Eod = 2 pi L + E_sun = 2 + 2 = 4,
// Eu = Eou = Lu = 0. Uniform radiance makes every sample equal: the estimate is exact.
TEST(Probes, IrradiancesAboveBlackGround) {
    ir::SceneIR s = uniformSkyScene();
    s.sun.enabled = true;
    s.sun.zenith = deg2rad(60);
    s.sun.irradiance = Spectrum::constant(2.0);
    s.render.settings.set("probe_samples", 256);
    s.materials.push_back(material("black", M::Type::Black, M::Solver::Classic));
    s.meshes.push_back(meshOf("ground", plane(-100, 100, -100, 100, 0), {"black"}));
    ir::Probe p;
    p.name = "p";
    p.position = {0, 0, 1};
    p.quantities = {"Ed", "Eod", "Eu", "Eou", "Lu"};
    s.probes.push_back(p);
    const Scene scene(s, ".");
    const auto v = evaluateProbe(scene, s.probes[0], 0, quiet());
    ASSERT_EQ(v.size(), 5u);
    // The sun's shadow ray samples the 0.53 deg disc: cos varies by < sin(60) * 0.0046 = 0.4 %.
    EXPECT_NEAR(v[0].mean[0], 2.0, 0.01);
    EXPECT_NEAR(v[1].mean[0], 4.0, 1e-9);
    EXPECT_EQ(v[2].mean[0], 0.0);
    EXPECT_EQ(v[3].mean[0], 0.0);
    EXPECT_EQ(v[4].mean[0], 0.0);
    ir::Probe bad = p;
    bad.quantities = {"Edd"};
    EXPECT_THROW(evaluateProbe(scene, bad, 0, quiet()), InputError);
}

// ---- bad input -------------------------------------------------------------------------------

std::filesystem::path freshDir(const std::string& name) {
    const auto d = std::filesystem::path(LITTORAL_BINARY_DIR) / "test_output" / name;
    std::filesystem::remove_all(d);
    return d;
}

void expectInputError(const ir::SceneIR& s, const std::string& fragment, const std::string& name) {
    const auto out = freshDir(name);
    RenderJobOptions o;
    o.progress = false;
    try {
        runRenderJob(s, ".", out, o);
        ADD_FAILURE() << name << ": no InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << name << ": " << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(out)) << name << ": output written despite the error";
}

TEST(BadInput, ClearErrorsAndNoOutput) {
    ir::SceneIR good = uniformSkyScene();
    good.materials.push_back(material("grey", M::Type::Lambertian, M::Solver::Classic, 0.5));
    good.meshes.push_back(meshOf("ground", plane(-10, 10, -10, 10, 0), {"grey"}));
    good.meshes.push_back(meshOf("rock", box({2, 2, 0}, {4, 4, 2}), {"grey"}, "", "", true));
    good.sensors.push_back(pinhole("cam", {0, 0, 10}, {0, 0, -1}, {0, 1, 0}, 16, 16, 0.005, 1e-4));
    {
        const auto out = freshDir("good");
        RenderJobOptions o;
        o.progress = false;
        const auto res = runRenderJob(good, ".", out, o);
        for (const auto& p : res.written) EXPECT_TRUE(std::filesystem::exists(p)) << p;
    }
    ir::SceneIR inside = good;
    inside.sensors[0].position = {3, 3, 1};
    expectInputError(inside, "inside the closed opaque mesh 'rock'", "inside");

    ir::SceneIR empty = good;
    empty.sensors[0].forward = {0, 0, 1};  // looking at the empty sky
    expectInputError(empty, "empty view", "empty");

    ir::SceneIR zero = good;
    zero.sensors[0].width = 0;
    expectInputError(zero, "width and height must be positive", "zero");

    ir::SceneIR band = good;
    band.materials[0].reflectance = Spectrum::tabulated({0.45, 0.55, 0.7}, {0.1, 0.2, 0.3}, "grey");
    expectInputError(band, "material 'grey' reflectance: band [0.4, 0.6] um lies outside the tabulated range",
                     "band");

    RenderJobOptions o;
    o.progress = false;
    o.sensor = "cma";
    try {
        runRenderJob(good, ".", freshDir("sensor"), o);
        ADD_FAILURE() << "unknown sensor accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("did you mean 'cam'"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace littoral::render

namespace littoral::render {
namespace {

using namespace testing;
using M = ir::Material;

// Textured reflectance: a 4 x 2 greyscale PGM draped over [0, 4] x [0, 2] m (row 0 = north edge),
// under a uniform sky with nothing in the way: L = r t / pi per texel t (E_h = 1, F = 1).
TEST(Textured, PlanViewLookupAndOrientation) {
    const auto dir = std::filesystem::path(LITTORAL_BINARY_DIR) / "test_output" / "texture";
    std::filesystem::create_directories(dir);
    const unsigned char texels[8] = {0, 51, 102, 153, 204, 255, 25, 76};
    {
        FILE* fp = std::fopen((dir / "classes.pgm").c_str(), "wb");
        ASSERT_TRUE(fp);
        std::fprintf(fp, "P5\n4 2\n255\n");
        std::fwrite(texels, 1, 8, fp);
        std::fclose(fp);
    }
    ir::SceneIR s = uniformSkyScene();
    s.render.settings.set("hemisphere_samples", 4);
    M m = material("sand", M::Type::Textured, M::Solver::Classic, 0.8);
    m.texture = "classes.pgm";
    m.textureX0 = 0;
    m.textureX1 = 4;
    m.textureY0 = 0;
    m.textureY1 = 2;
    s.materials.push_back(m);
    s.meshes.push_back(meshOf("ground", plane(-10, 10, -10, 10, 0), {"sand"}));
    s.sensors.push_back(ortho("o", {2, 1, 5}, {0, 0, -1}, {0, 1, 0}, 4, 2, 1.0));
    const Scene scene(s, dir);
    const SensorImage img = renderSensor(scene, s.sensors[0], quiet());
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 4; ++i)
            EXPECT_NEAR(img.film.at(i, j, 0), 0.8 * texels[j * 4 + i] / 255.0 / kPi, 1e-7) << i << "," << j;
    M bad = m;
    bad.texture = "missing.png";
    s.materials[0] = bad;
    EXPECT_THROW(Scene(s, dir), InputError);
}

}  // namespace
}  // namespace littoral::render

namespace littoral::render {
namespace {

// The Lambertian BxDF's sample() agrees with its f() and pdf() (the pbrt-v4 triple), its weight
// f |cos| / pdf equals the reflectance (white furnace of the sampler), and it stays on wo's side.
// Uniform-cone sampling matches its pdf: the fraction of samples within half the cone's
// solid angle (cos <= (1 + cos a)/2) is 1/2, binomial standard error 1/(2 sqrt(n)).
TEST(Sampling, LambertianTripleAndCone) {
    const LambertianBxDF bxdf{0.37};
    for (int k = 0; k < 10000; ++k) {
        RandomStream rng(5, 0, k);
        const Vec3 wo = normalize(Vec3{rng.uniform() - 0.5, rng.uniform() - 0.5, (k % 2 ? -1.0 : 1.0) * rng.uniform()});
        const double u1 = rng.uniform(), u2 = rng.uniform();
        const auto s = bxdf.sample(wo, 0.5, Vec2{u1, u2});
        ASSERT_TRUE(s.has_value());
        EXPECT_GT(s->wi.z * wo.z, 0);
        EXPECT_NEAR(s->f, bxdf.f(wo, s->wi), 1e-15);
        EXPECT_NEAR(s->pdf, bxdf.pdf(wo, s->wi), 1e-15);
        EXPECT_NEAR(s->f * std::abs(s->wi.z) / s->pdf, 0.37, 1e-12);
    }
    const double cosA = std::cos(deg2rad(0.265));
    const int n = 100000;
    int inner = 0;
    for (int k = 0; k < n; ++k) {
        RandomStream rng(6, 0, k);
        const Vec3 w = sampleUniformCone(rng.uniform(), rng.uniform(), cosA);
        ASSERT_GE(w.z, cosA - 1e-15);
        EXPECT_GT(pdfUniformCone(w, cosA), 0);
        inner += w.z >= 0.5 * (1 + cosA);
    }
    EXPECT_NEAR(double(inner) / n, 0.5, 4 * 0.5 / std::sqrt(double(n)));
}

}  // namespace
}  // namespace littoral::render

namespace littoral::render {
namespace {

// Table 10.1 placement: a camera 30 deg off nadir, from the east-north-east, 200 m from the
// target with a 0.1 m GSD: the central pixel's ray passes through the target, and one pixel of
// angle pitch/f at range 200 m spans 0.1 m normal to the axis.
TEST(Camera, FrameCameraPlacement) {
    const Point3 target{10, -5, 0};
    const ir::Sensor s = frameCamera("f", target, deg2rad(30), deg2rad(20), 200.0, 0.1, 101, 81, 1e-5);
    const Camera cam(s);
    EXPECT_NEAR(distance(cam.position(), target), 200.0, 1e-9);
    EXPECT_NEAR(cam.position().z, 200.0 * std::cos(deg2rad(30)), 1e-9);
    const Ray c = cam.generateRay(50.5, 40.5);  // odd sizes: the exact image centre
    const Vec3 toTarget = normalize(target - c.o);
    EXPECT_NEAR(dot(c.d, toTarget), 1.0, 1e-12);
    const Ray r = cam.generateRay(51.5, 40.5);  // one pixel to the right
    EXPECT_NEAR(200.0 * std::tan(std::acos(dot(r.d, c.d))), 0.1, 1e-6);
    EXPECT_GT(cam.upOrtho().z, 0);  // image up points skyward
    EXPECT_THROW(frameCamera("f", target, deg2rad(95), 0, 200, 0.1, 10, 10, 1e-5), InputError);
}

}  // namespace
}  // namespace littoral::render
