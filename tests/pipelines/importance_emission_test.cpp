// Importance emission of the photon pass (render/photon_pass.h, render.photons.importance): a
// concrete block (Classic, stores nothing) fills a third of the domain beside open water over a
// surface-photon-mapped sand floor. Photons aimed at the block are mostly wasted, so with
// importance emission the surface map fills after fewer emitted photons, while its estimate is
// unchanged (each photon's weight undoes the emission density).
//
// The nadir view of the water beside the block (its shadow included) is rendered with and without
// importance, three seeds each. Tolerance on the difference of the two groups' mean radiance: 4
// standard errors from the spread of the six runs about their group means (4 degrees of freedom;
// photon-map and camera noise together), and the check must resolve 1 % of the radiance.
#include <cmath>
#include <cstdio>
#include <regex>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "render/image_output.h"
#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using namespace littoral::testing_support;

namespace {

std::string scene(bool importance, int seed) {
    return fmt::format(R"(scene: {{name: importance, domain: {{x: [-10, 10], y: [-5, 5]}}}}
sun: {{zenith_deg: 30, azimuth_deg: 90, irradiance: 1000}}
sky: {{radiance: 20}}
water:
  surface: {{model: flat, size: [20, 10]}}
  optics: {{absorption_per_m: 0.05}}
bathymetry: {{type: planar_slope, z0_m: -3, spacing_m: 1, material: sand}}
objects:
  - {{name: block, mesh: cube.obj, materials: [concrete], position_m: [6, 0], draft_m: 2, scale: 8}}
materials:
  - {{name: sand, reflectance: 0.3, solver: surface-pm}}
  - {{name: concrete, reflectance: 0.3}}
sensors:
  - {{name: nadir, type: orthographic, position: [-5, 0, 10], direction: [0, 0, -1], up: [0, 1, 0], pixel_size_m: 0.5,
     width: 16, height: 16, samples_per_pixel: 4}}
render: {{photons: {{surface: 1000000, importance: {}}}, search_radius_m: {{surface: 0.3}}, seed: {}}}
)",
                       importance ? "true" : "false", seed);
}

struct PassRun {
    double mean = 0;
    double emitted = 0, storedPercent = 0;
};

PassRun run(const fs::path& dir, bool importance, int seed) {
    const std::string name = fmt::format("{}_{}", importance ? "importance" : "uniform", seed);
    const fs::path yaml = writeTextFile(dir, name + ".yaml", scene(importance, seed));
    const auto r = runLittoral(fmt::format("run '{}' --out '{}'", yaml.string(), (dir / name).string()));
    EXPECT_EQ(r.status, 0) << r.output;
    PassRun out;
    const littoral::render::Film f = littoral::render::readEnvi(dir / name / "nadir.img");
    for (float v : f.pixels) out.mean += v / static_cast<double>(f.pixels.size());
    std::smatch m;
    const std::regex line(R"(photon pass: (\d+) photons emitted( \(importance emission\))?, \d+ stored .*: ([0-9.]+) % of the emitted)");
    EXPECT_TRUE(std::regex_search(r.output, m, line)) << r.output;
    if (!m.empty()) {
        out.emitted = std::stod(m[1].str());
        out.storedPercent = std::stod(m[3].str());
        EXPECT_EQ(m[2].matched, importance) << r.output;
    }
    return out;
}

}  // namespace

TEST(ImportanceEmission, FewerPhotonsEmittedForTheSameEstimate) {
    const fs::path dir = scratchDir("importance_emission", "block");
    writeTextFile(dir, "cube.obj", kUnitCubeObj);
    std::vector<PassRun> with, without;
    for (int seed : {1, 2, 3}) with.push_back(run(dir, true, seed)), without.push_back(run(dir, false, seed));
    auto groupMean = [](const std::vector<PassRun>& v) {
        double s = 0;
        for (const PassRun& r : v) s += r.mean / static_cast<double>(v.size());
        return s;
    };
    const double a = groupMean(with), b = groupMean(without);
    double ss = 0;
    for (const PassRun& r : with) ss += (r.mean - a) * (r.mean - a);
    for (const PassRun& r : without) ss += (r.mean - b) * (r.mean - b);
    const double pooled = ss / 4;  // 6 runs, 2 group means
    const double se = std::sqrt(pooled / 3 + pooled / 3);
    std::printf("[ importance emission ] mean radiance %.4f with, %.4f without (difference +- %.4f); emitted %.0f "
                "against %.0f, stored %.1f %% against %.1f %%\n",
                a, b, se, with[0].emitted, without[0].emitted, with[0].storedPercent, without[0].storedPercent);
    EXPECT_NEAR(a, b, 4 * se);
    EXPECT_LT(4 * se, 0.01 * b);  // the check resolves 1 %
    // The block covers 32 % of the domain: the uniform pass stores from about half its photons
    // (the rest end on the block or leave the scene); importance emission must save a third or more.
    for (size_t k = 0; k < with.size(); ++k) EXPECT_LT(with[k].emitted, 0.67 * without[k].emitted);
}
