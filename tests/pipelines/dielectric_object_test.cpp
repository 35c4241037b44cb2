// Transparent (dielectric) objects from a scene file (issue 10): a glass cube floating on flat
// water. Its shadow on the floor is not black: the direct sun crosses it along beams refracted at
// each face (issue 18; Fresnel transmittance at each face, Beer–Lambert inside), checked against
// the product of Fresnel transmittances; the light it refracts lands where Snell's law at its faces
// puts it, checked in the surface photon map and in the beams of the direct sun against an
// independent 2-D ray tracer; and a dielectric without a refractive index is a located error.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/units.h"
#include "core/rng.h"
#include "render/estimator.h"
#include "render/film.h"
#include "render/image_output.h"
#include "render/photon_pass.h"
#include "render/renderer.h"
#include "render/scene.h"
#include "render/sun_connection.h"
#include "scenegen/assemble.h"
#include "tests/support/connection_check.h"
#include "tests/support/glint.h"
#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using namespace littoral;
using namespace littoral::testing_support;
namespace glint = littoral::testing_support::glint;

namespace {

// The cube floats with half of it under water (draft 0.5 m) over a flat floor 2 m deep, in pure
// water (n = 1.34), in a periodic 6 m x 5 m domain; glass n = 1.5 absorbing 0.2 m^-1.
std::string cubeScene(double sunZenith, const std::string& floor, const std::string& render, const std::string& extra = "",
                      double discDeg = 0.53) {
    return "scene:\n  name: cube\n  domain: {x: [-3, 3], y: [-2.5, 2.5]}\n"
           "sun: {zenith_deg: " + std::to_string(sunZenith) + ", azimuth_deg: 90, irradiance: 1000, angular_diameter_deg: " +
           std::to_string(discDeg) + "}\n"
           "sky: {radiance: 0}\n"
           "water:\n  horizontal: periodic\n  surface: {model: flat, size: [6, 5], spacing: 1}\n"
           "  optics: {absorption_per_m: 0}\n"
           "bathymetry: {type: planar_slope, z0_m: -2, spacing_m: 1, material: floor}\n"
           "objects:\n  - {name: cube, mesh: cube.obj, materials: [glass], position_m: [0, 0], draft_m: 0.5}\n"
           "materials:\n  - " + floor + "\n"
           "  - {name: glass, type: dielectric, refractive_index: 1.5, absorption_per_m: 0.2}\n" + extra +
           "render:\n" + render;
}

fs::path writeScene(const std::string& name, const std::string& text) {
    const fs::path dir = scratchDir("dielectric_object", name);
    writeTextFile(dir, "cube.obj", kUnitCubeObj);
    return writeTextFile(dir, "scene.yaml", text);
}

double fresnelNormal(double n1, double n2) { return glint::fresnelSinTan(1.0, n1, n2); }

}  // namespace

// Sun at the zenith: light crosses the cube's top (air -> glass) and bottom (glass -> water) at
// normal incidence. The disc is narrowed to 0.01 deg: the rim of a 0.53 deg disc grazes the cube's
// vertical faces, and the light it sends in through them (refracted exactly, issue 18) lands on the
// open floor and near the probe, 1e-4 to 6e-4 of E (its order alpha^2: 4e-8 at 0.01 deg); the 25 deg
// test below covers the real disc against a tracer. A floor camera 0.1 m above the floor
// (in the water, black sky, Classic solver) sees r/pi E T under the cube, with
//   T = (1 - R(1, 1.5)) exp(-0.2 m^-1 x 1 m) (1 - R(1.34, 1.5)) = 0.96 x 0.81873 x 0.99683
// and r/pi E (1 - R(1, 1.34)) in the open; a probe under the cube (over a black floor) measures
// Ed = E T.
// Tolerance: 1e-4 relative (the 0.53 deg disc changes the path length in the glass and the
// Fresnel factors by less than 1e-5; the film stores floats), and the probe's 4 standard errors.
TEST(DielectricObject, FloorShadowIsTheFresnelProductNotBlack) {
    const fs::path file =
        writeScene("shadow", cubeScene(0, "{name: floor, reflectance: 0.5}", "  hemisphere_samples: 1\n",
                                       "sensors:\n  - {name: floor, type: orthographic, position: [0, 0, -1.9], "
                                       "direction: [0, 0, -1], up: [0, 1, 0], pixel_size_m: 0.05, width: 120, height: 100}\n",
                                       0.01));
    const fs::path out = file.parent_path() / "out";
    const CommandResult r = runLittoral("--quiet run " + file.string() + " --out " + out.string());
    ASSERT_EQ(r.status, 0) << r.output;
    const render::Film film = render::readExr(out / "floor.exr");
    const double E = 1000.0, rho = 0.5;
    const double Tcube = (1 - fresnelNormal(1.0, 1.5)) * std::exp(-0.2) * (1 - fresnelNormal(1.34, 1.5));
    const double Topen = 1 - fresnelNormal(1.0, 1.34);
    int inside = 0, outside = 0;
    double minInside = 1e30;
    for (int j = 0; j < film.height; ++j)
        for (int i = 0; i < film.width; ++i) {
            // Pixel centre on the floor (orthographic, looking down with up = north: right = -x).
            const double x = -(i + 0.5 - film.width / 2.0) * 0.05, y = -(j + 0.5 - film.height / 2.0) * 0.05;
            const double L = film.at(i, j, 0);
            if (std::abs(x) < 0.45 && std::abs(y) < 0.45) {
                const double pred = rho / glint::kPi * E * Tcube;
                EXPECT_NEAR(L, pred, 1e-4 * pred) << "under the cube at " << x << ", " << y;
                minInside = std::min(minInside, L);
                ++inside;
            } else if (std::abs(x) > 0.55 || std::abs(y) > 0.55) {
                const double pred = rho / glint::kPi * E * Topen;
                EXPECT_NEAR(L, pred, 1e-4 * pred) << "open water at " << x << ", " << y;
                ++outside;
            }
        }
    EXPECT_EQ(inside, 18 * 18);
    EXPECT_GT(outside, 10000);
    EXPECT_GT(minInside, 0.7 * rho / glint::kPi * E * Topen);  // not black: 80 % of the open floor
    // The probe, over a black floor (else the floor's light, reflected down by the water surface,
    // adds to Ed).
    const fs::path probeFile =
        writeScene("shadow-probe", cubeScene(0, "{name: floor, type: black}", "  hemisphere_samples: 1\n",
                                             "probes:\n  - {name: under, position: [0.1, -0.2, -1.0], quantities: [Ed], "
                                             "samples: 256}\n",
                                             0.01));
    const CommandResult rp = runLittoral("--quiet run " + probeFile.string() + " --out " + (probeFile.parent_path() / "out").string());
    ASSERT_EQ(rp.status, 0) << rp.output;
    const std::string csv = readTextFile(probeFile.parent_path() / "out" / "probes.csv");
    double ed = 0, se = 0;
    ASSERT_EQ(std::sscanf(csv.substr(csv.find("under,Ed")).c_str(), "under,Ed,%*[^,],%*[^,],%lf,%lf", &ed, &se), 2) << csv;
    EXPECT_NEAR(ed, E * Tcube, 4 * se + 1e-4 * E * Tcube);
    std::printf("[ cube shadow ] floor under the cube %.6g (r E T / pi = %.6g, T = %.6f), open %.6g; probe Ed %.6f +- %.2g\n",
                minInside, rho / glint::kPi * E * Tcube, Tcube, rho / glint::kPi * E * Topen, ed, se);
}

namespace {

// An independent 2-D tracer of the cube's cross-section y = 0 (x along the sun's azimuth): air above
// z = 0, water below down to the floor at z = -2, glass in the cube [-0.5, 0.5] x [-0.5, 0.5].
// Sunlight falls on the line z = 1 with direction (-sin t, -cos t) and irradiance E cos t on the
// horizontal; every interface splits a ray into its Fresnel-weighted reflected and refracted parts
// (Eq. 4.2, Snell), the glass absorbs 0.2 m^-1 (Beer-Lambert), branches below 1e-7 of the start are
// dropped, the domain repeats in x with period 6 m, and the floor absorbs and records. Returns the floor irradiance per x bin (W m^-2).
struct Seg {
    double x0, z0, x1, z1;
    double nLeft, nRight;  // index on the left / right of the direction (x1 - x0, z1 - z0)
    bool floor;
};

// With reflections = false every reflected branch is dropped: what is left is the light of pure
// transmission chains, the beams of the direct sun (issue 18).
std::vector<double> referenceProfile(double sunZenithDeg, double binWidth, double x0, int bins, bool reflections = true) {
    const double nw = 1.34, ng = 1.5;
    std::vector<Seg> segs = {
        {-3.0, 0.0, -0.5, 0.0, 1.0, nw, false},   // water surface west of the cube (left = above)
        {0.5, 0.0, 3.0, 0.0, 1.0, nw, false},     // east of it
        {-0.5, 0.5, 0.5, 0.5, 1.0, ng, false},    // cube top
        {-0.5, -0.5, 0.5, -0.5, ng, nw, false},   // cube bottom (left = above = glass)
        {-0.5, 0.0, -0.5, 0.5, ng, 1.0, false},   // west side above water (left of upward = west... see below)
        {-0.5, -0.5, -0.5, 0.0, ng, nw, false},   // west side under water
        {0.5, 0.0, 0.5, 0.5, 1.0, ng, false},     // east side above water
        {0.5, -0.5, 0.5, 0.0, nw, ng, false},     // east side under water
        {-3.0, -2.0, 3.0, -2.0, nw, nw, true},    // floor
    };
    // "Left" of a directed segment is the side its normal (-dz, dx) points to. For the west side
    // (upward at x = -0.5) the left normal is -x: outside the cube... correct the indices so each
    // segment's left is the +normal side: recompute from a probe point.
    auto indexAt = [&](double x, double z) {
        if (std::abs(x) < 0.5 && z > -0.5 && z < 0.5) return ng;
        return z > 0 ? 1.0 : nw;
    };
    for (Seg& s : segs) {
        if (s.floor) continue;
        const double mx = 0.5 * (s.x0 + s.x1), mz = 0.5 * (s.z0 + s.z1);
        const double dx = s.x1 - s.x0, dz = s.z1 - s.z0, l = std::hypot(dx, dz);
        const double nx = -dz / l, nz = dx / l;
        s.nLeft = indexAt(mx + 1e-6 * nx, mz + 1e-6 * nz);
        s.nRight = indexAt(mx - 1e-6 * nx, mz - 1e-6 * nz);
    }
    std::vector<double> E(bins, 0.0);
    const double period = 6.0;
    std::function<void(double, double, double, double, double, int)> trace = [&](double px, double pz, double dx, double dz,
                                                                               double w, int depth) {
        if (w < 1e-7 || depth > 60) return;
        // Nearest segment along the ray (segments are short relative to 6 m; wrap in x at +-3).
        double best = 1e30;
        int hit = -1;
        for (size_t k = 0; k < segs.size(); ++k) {
            const Seg& s = segs[k];
            const double ex = s.x1 - s.x0, ez = s.z1 - s.z0;
            const double den = dx * ez - dz * ex;
            if (std::abs(den) < 1e-15) continue;
            const double t = ((s.x0 - px) * ez - (s.z0 - pz) * ex) / den;
            const double u = ((s.x0 - px) * dz - (s.z0 - pz) * dx) / den;
            if (t > 1e-9 && u >= 0 && u <= 1 && t < best) best = t, hit = static_cast<int>(k);
        }
        // The periodic walls at x = +-3.
        const double tWall = dx > 0 ? (3.0 - px) / dx : dx < 0 ? (-3.0 - px) / dx : 1e30;
        if (tWall < best) {
            trace(px + tWall * dx - (dx > 0 ? period : -period), pz + tWall * dz, dx, dz, w, depth + 1);
            return;
        }
        if (hit < 0) return;  // up into the sky
        const Seg& s = segs[hit];
        const double hx = px + best * dx, hz = pz + best * dz;
        // Beer-Lambert in the glass (0.2 m^-1; the water is pure). Direction vectors are unit.
        if (indexAt(0.5 * (px + hx), 0.5 * (pz + hz)) == ng) w *= std::exp(-0.2 * best);
        if (s.floor) {
            const int b = static_cast<int>(std::floor((hx - x0) / binWidth));
            if (b >= 0 && b < bins) E[b] += w;
            return;
        }
        const double ex = s.x1 - s.x0, ez = s.z1 - s.z0, l = std::hypot(ex, ez);
        double nx = -ez / l, nz = ex / l;  // left normal
        double n1 = s.nLeft, n2 = s.nRight;
        double c = -(dx * nx + dz * nz);  // cos of incidence, ray arriving on the left side
        if (c < 0) nx = -nx, nz = -nz, c = -c, std::swap(n1, n2);
        const double R = glint::fresnelSinTan(c, n1, n2);
        // Reflection.
        if (reflections) trace(hx, hz, dx + 2 * c * nx, dz + 2 * c * nz, w * R, depth + 1);
        if (R < 1) {
            const double eta = n1 / n2, k = 1 - eta * eta * (1 - c * c);
            const double ct = std::sqrt(std::max(0.0, k));
            const double tx = eta * dx + (eta * c - ct) * nx, tz = eta * dz + (eta * c - ct) * nz;
            trace(hx, hz, tx, tz, w * (1 - R), depth + 1);
        }
    };
    // The sun disc (0.53 deg) projected on the x-z plane: angular offsets with the semicircle
    // density of a uniform disc seen edge-on (Gauss-Chebyshev nodes of the second kind).
    const int K = 7, rays = 200000;
    const double alpha = 0.5 * deg2rad(0.53);
    double wsum = 0;
    std::vector<double> node(K), weight(K);
    for (int k = 0; k < K; ++k) {
        const double th = glint::kPi * (k + 1) / (K + 1);
        node[k] = std::cos(th) * alpha;
        weight[k] = std::sin(th) * std::sin(th);
        wsum += weight[k];
    }
    for (int k = 0; k < K; ++k) {
        const double t = deg2rad(sunZenithDeg) + node[k];
        const double dx = -std::sin(t), dz = -std::cos(t);
        // Rays spaced evenly along z = 1 over one period: each carries E cos(t) dx of flux per unit
        // length in y; binned flux / bin width is the irradiance.
        for (int i = 0; i < rays; ++i) {
            const double px = -3.0 + period * (i + 0.5) / rays;
            trace(px, 1.0, dx, dz, 1000.0 * std::cos(t) * (period / rays) / binWidth * weight[k] / wsum, 0);
        }
    }
    return E;
}

}  // namespace

// Sun at 25 deg from the zenith in the east: the cube's top passes the light on parallel, its
// sunward side above water bends it down steeply, and its shadow, its transmitted patch and a
// bright band beside it land on the floor where refraction at its faces puts them. The surface
// photon map (floor reflectance 0: each photon is stored where it first lands) is summed per 0.1 m
// bin in x over the strip |y| < 0.4 m, inside which every ray of the sun sees the cross-section
// y = 0 (the cube's y faces are parallel to the light), and compared bin by bin with the 2-D
// tracer above. Tolerance: 4 standard errors of the bin's photon count (equal-flux photons:
// sigma = E / sqrt(N)), plus 1.5 % for the tracer's and the photons' finite sun disc at the bins
// that straddle a sharp edge. The brightest bin must be the tracer's brightest.
TEST(DielectricObject, CausticLandsWhereRefractionPutsIt) {
    const fs::path file = writeScene(
        "caustic", cubeScene(25, "{name: floor, reflectance: 0, solver: surface-pm}",
                             "  photons: {surface: 2000000}\n  search_radius_m: {surface: 0.1}\n"));
    const auto built = scenegen::buildScene(file.string(), file.parent_path() / "ir");
    const render::Scene scene(built.ir, file.parent_path() / "ir");
    render::PhotonPassSettings ps;
    ps.surfaceTarget = 2000000;
    ps.progress = false;
    ps.surfaceRadius = ps.volumeRadius = 0.1;
    for (const auto& m : built.ir.materials) ps.surfaceMaterial.push_back(m.name == "floor");
    ps.volumeMedium.assign(scene.media().size(), false);
    const auto maps = render::tracePhotons(scene, render::BandGroup{0, 1}, ps);

    const double bw = 0.1, x0 = -3.0, halfStrip = 0.4;
    const int bins = 60;
    std::vector<double> E(bins, 0.0);
    std::vector<long> count(bins, 0);
    for (size_t i = 0; i < maps.surface.size(); ++i) {
        const Point3 p = maps.surface.position(i);
        if (std::abs(p.y) >= halfStrip) continue;
        const int b = static_cast<int>(std::floor((p.x - x0) / bw));
        if (b < 0 || b >= bins) continue;
        E[b] += maps.surface.power(i, 0) * maps.surface.fluxScale[0] / (bw * 2 * halfStrip);
        ++count[b];
    }
    const std::vector<double> ref = referenceProfile(25.0, bw, x0, bins);
    int brightest = 0, refBrightest = 0;
    for (int b = 0; b < bins; ++b) {
        const double sigma = count[b] > 0 ? E[b] / std::sqrt(static_cast<double>(count[b])) : 1.0;
        EXPECT_NEAR(E[b], ref[b], 4 * sigma + 0.015 * ref[b]) << "bin " << b << " x " << x0 + (b + 0.5) * bw;
        if (E[b] > E[brightest]) brightest = b;
        if (ref[b] > ref[refBrightest]) refBrightest = b;
    }
    // The caustic's peak within one bin (0.1 m) of the tracer's: its two brightest bins differ by
    // 1.4 %, less than a bin's photon noise (about 2 %), so the map's brightest may be either.
    EXPECT_LE(std::abs(brightest - refBrightest), 1);
    const double open = 1000.0 * std::cos(deg2rad(25)) * (1 - glint::fresnelSinTan(std::cos(deg2rad(25)), 1.0, 1.34));
    std::printf("[ cube caustic ] open floor %.1f W/m^2; x, photon map, 2-D tracer:\n", open);
    for (int b = 0; b < bins; ++b)
        if (std::abs(ref[b] - open) > 0.02 * open || std::abs(E[b] - open) > 0.05 * open)
            std::printf("   %6.2f %8.1f %8.1f\n", x0 + (b + 0.5) * bw, E[b], ref[b]);
    std::printf("   brightest bin x = %.2f (tracer %.2f): %.1f vs %.1f\n", x0 + (brightest + 0.5) * bw,
                x0 + (refBrightest + 0.5) * bw, E[brightest], ref[refBrightest]);
}

// The direct sun through the cube is exact (issue 18): every chain of refractions (sea, top, sides,
// bottom; up to three) is a beam, traced and weighed face by face. Under the 25 deg sun of the
// caustic test, Ed 0.1 mm above the floor, from the beams alone (SunConnection::direct, as a probe
// reads it), is averaged over 100 points per 0.1 m bin of the line y = 0 (16 disc directions each)
// and compared with the 2-D tracer without reflections (the same light: pure transmission chains).
// Tolerance per bin: 4 standard errors of the disc sampling (from each point's spread over its
// directions: where an edge's 2 cm blur crosses the bin, a few W m^-2), 0.3 % (the tracer's 3 300
// rays per bin, 3e-4), 0.8 % of the jumps to the neighbouring bins (sampling a bin at 1 mm
// misplaces an edge by at most 0.5 mm of its 100 mm, and the 0.1 mm height by up to 0.3 mm more
// under the steepest, 70 deg, beams), and 0.5 W m^-2 in the dark.
TEST(DielectricObject, DirectSunThroughTheCubeFollowsEveryRefraction) {
    const fs::path file = writeScene("beams", cubeScene(25, "{name: floor, type: black}", "  seed: 1\n"));
    const auto built = scenegen::buildScene(file.string(), file.parent_path() / "ir");
    const render::Scene scene(built.ir, file.parent_path() / "ir");
    const render::EstimatorSet est(scene);
    const render::SunConnection& sun = est.forGroup(0).sun();
    const int water = scene.mediumIndex("water", "the test");
    ASSERT_GE(water, 0);
    ASSERT_NE(sun.beamsInto(water), nullptr);
    EXPECT_EQ(sun.beamsInto(water)->maxOrder(), 3);
    const double bw = 0.1, x0 = -3.0;
    const int bins = 60, perBin = 100, discs = 16;
    const std::vector<double> ref = referenceProfile(25.0, bw, x0, bins, false);
    std::vector<double> E(bins, 0.0), var(bins, 0.0);  // var: of the bin mean, from the disc sampling
    for (int b = 0; b < bins; ++b)
        for (int i = 0; i < perBin; ++i) {
            double sum = 0, sq = 0;
            for (int k = 0; k < discs; ++k) {
                const Point3 p{x0 + (b + (i + 0.5) / perBin) * bw, 0.0, -1.9999};
                RandomStream stream(2026, 1, static_cast<uint64_t>((b * perBin + i) * discs + k));
                const double v = sun.direct(p, Normal3{0, 0, 1}, water, false, stream)[0];
                sum += v, sq += v * v;
            }
            E[b] += sum / (perBin * discs);
            var[b] += (sq - sum * sum / discs) / (discs - 1) / discs / sqr(perBin);
        }
    std::printf("[ cube beams ] %zu chains into the water; x, beams, tracer (transmissions only):\n",
                sun.beamsInto(water)->chainCount());
    for (int b = 0; b < bins; ++b) {
        const double jumps = std::abs(ref[b] - ref[std::max(b - 1, 0)]) + std::abs(ref[b] - ref[std::min(b + 1, bins - 1)]);
        EXPECT_NEAR(E[b], ref[b], 4 * std::sqrt(var[b]) + 0.003 * ref[b] + 0.008 * jumps + 0.5)
            << "bin " << b << " x " << x0 + (b + 0.5) * bw;
        if (std::abs(ref[b] - ref[0]) > 0.02 * ref[0]) std::printf("   %6.2f %8.2f +- %5.2f %8.2f\n", x0 + (b + 0.5) * bw, E[b], std::sqrt(var[b]), ref[b]);
    }
}

// The path estimator stays unbiased with the cube in the water: a floor vertex's sun estimate covers
// the chains of one to three refractions its beams index, and a sampled ray counts the disc after
// any other chain (a reflection inside the cube, a re-entry). Checked the way
// FacetBeams.PathWithoutAnyInWaterSunEstimateFindsTheSameSeabed checks the waves: a nadir view of a
// sandy floor around and under the cube, rendered with the beams and with no sun estimate in water
// or glass at all (every sampled ray then counts the disc when it reaches it), with a 4 deg sun
// (half-angle) so that chance finds it. Tolerance: 4 combined standard errors of the image means,
// asserted to be under 5 % of the radiance.
TEST(DielectricObject, PathEstimatorWithTheCubeFindsTheSameFloorWithoutAnySunEstimateInWater) {
    const fs::path file = writeScene(
        "path-unbiased", cubeScene(25, "{name: floor, reflectance: 0.3}", "  estimator: path\n  seed: 3\n",
                                   "sensors:\n  - {name: nadir, type: orthographic, position: [0.3, 0, 3], direction: [0, 0, -1], "
                                   "up: [0, 1, 0], pixel_size_m: 0.15, width: 16, height: 16}\n"));
    auto built = scenegen::buildScene(file.string(), file.parent_path() / "ir");
    built.ir.sun.halfAngle = deg2rad(4.0);
    const fs::path dir = file.parent_path() / "ir";
    const auto [with, withSe] = meanOfSensorRender(built.ir, dir, true, 1024);
    const auto [without, withoutSe] = meanOfSensorRender(built.ir, dir, false, 16384);
    const double tol = 4 * std::hypot(withSe, withoutSe);
    std::printf("[ cube beams ] floor radiance, path estimator: through the beams %.4f +- %.4f, without in-water sun "
                "estimates %.4f +- %.4f (%.1f combined se apart)\n",
                with, withSe, without, withoutSe, std::abs(with - without) / std::hypot(withSe, withoutSe));
    EXPECT_NEAR(with, without, tol);
    EXPECT_LT(tol, 0.05 * with);
}

// The chains are looked up and picked the same way in every thread: a path-traced view of the
// cube's floor (shadow, displaced patch, caustic band) is bitwise equal with 1 and 2 threads.
TEST(DielectricObject, BeamsThroughTheCubeAreIdenticalForOneAndTwoThreads) {
    const fs::path file = writeScene(
        "threads", cubeScene(25, "{name: floor, reflectance: 0.3}", "  estimator: path\n  seed: 5\n",
                             "sensors:\n  - {name: nadir, type: orthographic, position: [0.3, 0, 3], direction: [0, 0, -1], "
                             "up: [0, 1, 0], pixel_size_m: 0.15, width: 16, height: 16, samples_per_pixel: 16}\n"));
    const auto built = scenegen::buildScene(file.string(), file.parent_path() / "ir");
    const render::Scene scene(built.ir, file.parent_path() / "ir");
    ASSERT_GT(render::EstimatorSet(scene).forGroup(0).sun().beamsInto(scene.mediumIndex("water", "the test"))->chainCount(), 0u);
    std::vector<std::vector<float>> images;
    for (const int threads : {1, 2}) {
        render::RenderOptions o;
        o.progress = false;
        o.threads = threads;
        images.push_back(render::renderSensor(scene, built.ir.sensors[0], o).film.pixels);
    }
    ASSERT_EQ(images[0].size(), images[1].size());
    EXPECT_EQ(0, std::memcmp(images[0].data(), images[1].data(), images[0].size() * sizeof(float)));
    EXPECT_GT(*std::max_element(images[0].begin(), images[0].end()), 0.0f);
}

// The dirsig estimator's sun estimates in the air cross objects along the straight path (docs/
// rendering.md): a run where they do says so once, with the count. A probe in the air 5 cm west of
// the cube, 5 cm above the water, sees the sun (25 deg east) through the cube's west face and top.
// The path estimator's shadow ray stops at the cube instead, and its run does not warn.
TEST(DielectricObject, StraightPathSunInTheAirIsWarnedAbout) {
    for (const std::string estimator : {"dirsig", "path"}) {
        const fs::path file = writeScene(
            "straight-" + estimator,
            cubeScene(25, "{name: floor, type: black}", "  estimator: " + estimator + "\n  seed: 1\n",
                      "probes:\n  - {name: air, position: [-0.55, 0, 0.05], medium: air, quantities: [Ed], samples: 64}\n"));
        const CommandResult r = runLittoral("run " + file.string() + " --out " + (file.parent_path() / "out").string());
        ASSERT_EQ(r.status, 0) << r.output;
        const bool warned = r.output.find("along the dirsig estimator's straight-path model") != std::string::npos;
        EXPECT_EQ(warned, estimator == "dirsig") << estimator << ": " << r.output;
    }
}

// A dielectric without a refractive index, or with a reflectance, is a located error (exit 1).
TEST(DielectricObject, MissingIndexIsALocatedError) {
    struct Case {
        const char* name;
        const char* glass;
        const char* where;
        const char* message;
    };
    const Case cases[] = {
        {"no-index", "{name: glass, type: dielectric, absorption_per_m: 0.2}", ":15:5",
         "a dielectric needs 'refractive_index'"},
        {"reflectance", "{name: glass, type: dielectric, refractive_index: 1.5, reflectance: 0.3}", ":15:",
         "a dielectric material has no reflectance: a smooth Fresnel interface"},
        {"index-low", "{name: glass, type: dielectric, refractive_index: 0.9}", ":15:", "0.9 is out of range"},
    };
    for (const Case& c : cases) {
        std::string text = cubeScene(20, "{name: floor, reflectance: 0.5}", "  seed: 1\n");
        const std::string from = "{name: glass, type: dielectric, refractive_index: 1.5, absorption_per_m: 0.2}";
        text.replace(text.find(from), from.size(), c.glass);
        const fs::path file = writeScene(c.name, text);
        for (const std::string cmd : {"check-scene", "run"}) {
            const fs::path out = file.parent_path() / "out";
            const CommandResult r =
                runLittoral("--quiet " + cmd + " " + file.string() + (cmd == "run" ? " --out " + out.string() : ""));
            EXPECT_EQ(r.status, 1) << c.name << " " << cmd << ": " << r.output;
            EXPECT_NE(r.output.find("scene.yaml" + std::string(c.where)), std::string::npos) << c.name << ": " << r.output;
            EXPECT_NE(r.output.find(c.message), std::string::npos) << c.name << ": " << r.output;
            EXPECT_FALSE(fs::exists(out)) << c.name;
        }
    }
}
