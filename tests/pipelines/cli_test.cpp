// End-to-end tests of the `littoral` command: exit codes and messages as a user sees them.
#include <gtest/gtest.h>

#include "tests/support/test_support.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;

namespace {

const fs::path kBinary = fs::path(LITTORAL_BINARY_DIR) / "bin" / "littoral";

using Result = littoral::testing_support::CommandResult;
Result run(const std::string& args) { return littoral::testing_support::runLittoral(args); }

fs::path tempDir() {
    const fs::path d = fs::temp_directory_path() / "littoral_cli_test";
    fs::create_directories(d);
    return d;
}

}  // namespace

class Cli : public testing::Test {
protected:
    void SetUp() override {
        ASSERT_TRUE(fs::exists(kBinary)) << "littoral binary not built: " << kBinary;
    }
};

TEST_F(Cli, VersionAndHelp) {
    const auto v = run("--version");
    EXPECT_EQ(v.status, 0);
    EXPECT_NE(v.output.find("littoral "), std::string::npos);
    const auto h = run("check-scene --help");
    EXPECT_EQ(h.status, 0);
    EXPECT_NE(h.output.find("SCENE"), std::string::npos);
}

TEST_F(Cli, CheckSceneExitCodes) {
    const fs::path good = tempDir() / "good.yaml";
    std::ofstream(good) << "scene: {name: cli, domain: {x: [-5, 5], y: [-5, 5]}}\nsky: {radiance: 1}\n"
                           "bathymetry: {type: planar_slope, z0_m: -2, material: floor}\n"
                           "materials: [{name: floor, reflectance: 0.2}]\n";
    const auto ok = run("check-scene " + good.string());
    EXPECT_EQ(ok.status, 0) << ok.output;
    EXPECT_NE(ok.output.find("valid"), std::string::npos);

    const fs::path bad = tempDir() / "bad.yaml";
    std::ofstream(bad) << "scene: {name: cli}\nsky: {radiance: 1, modle: uniform}\n";
    const auto r = run("check-scene " + bad.string());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("bad.yaml:2:20: error: sky.modle: unknown key 'modle'"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("did you mean 'model'?"), std::string::npos) << r.output;

    const auto missing = run("check-scene " + (tempDir() / "nope.yaml").string());
    EXPECT_EQ(missing.status, 1);
    EXPECT_NE(missing.output.find("nope.yaml: error: scene file does not exist"), std::string::npos) << missing.output;
}

TEST_F(Cli, UnknownSubcommandIsAUsageError) {
    const auto r = run("frobnicate");
    EXPECT_EQ(r.status, 1);
}

namespace {
const char* kRunScene = R"(scene:
  name: run-test
  domain: {x: [-10, 10], y: [-10, 10]}
sun: {zenith_deg: 30, azimuth_deg: 135, irradiance: 1000}
sky: {radiance: 0}
water:
  surface: {model: flat, size: [20, 20]}
  optics: {preset: coastal, solver: attenuation}   # the direct beam alone (scattering as loss)
bathymetry: {type: planar_slope, z0_m: -3, slope_x: 0.1, slope_y: 0, spacing_m: 1.0, material: floor}
materials:
  - {name: floor, type: black}
sensors:
  - {name: nadir, type: frame, elevation_deg: 90, azimuth_deg: 0, range_m: 100, gsd_m: 0.5, width: 32, height: 24}
probes:
  - {name: p, position: [0, 0, -1], quantities: [Ed]}
render:
  probe_samples: 256
)";
}  // namespace

// `littoral run` end to end: scene file -> IR -> images and probe table. Under a flat surface,
// black bottom and black sky, the downwelling irradiance at depth z is the refracted sun alone:
// Ed = E_sun cos(theta_s) T_f(theta_s) exp(-c z / cos(theta_w)) (Snell Eq. 4.1, Fresnel Eq. 4.2,
// Beer–Lambert with c = a + b = 0.388 m^-1 for the Table 9.3 "coastal" water) = 557.388 W m^-2 um^-1
// for theta_s = 30 deg, z = 1 m, n = 1.34. Tolerance: 4 standard errors of the probe's estimate
// (its sampling of the 0.53 deg solar disc), read from probes.csv.
TEST_F(Cli, RunBuildsRendersAndMatchesRefractedSunIrradiance) {
    const fs::path dir = littoral::testing_support::scratchDir("pipelines", "run");
    std::ofstream(dir / "scene.yaml") << kRunScene;
    const auto r = run("-q run " + (dir / "scene.yaml").string() + " --out " + (dir / "out").string());
    ASSERT_EQ(r.status, 0) << r.output;
    for (const char* f : {"nadir.exr", "nadir.img", "nadir.hdr", "nadir.png", "nadir_truth.exr", "probes.csv",
                          "ir/scene.json", "ir/validity.json"})
        EXPECT_TRUE(fs::exists(dir / "out" / f)) << f;
    std::ifstream csv(dir / "out" / "probes.csv");
    std::string header, row;
    std::getline(csv, header);
    std::getline(csv, row);
    std::replace(row.begin(), row.end(), ',', ' ');
    std::istringstream rs(row);
    std::string name, quantity;
    double lo, hi, value, se;
    ASSERT_TRUE(rs >> name >> quantity >> lo >> hi >> value >> se) << row;
    EXPECT_EQ(quantity, "Ed");
    const double predicted = littoral::testing_support::refractedSunEd(1000, 30, 1.34, 0.388, 1.0);
    EXPECT_NEAR(predicted, 557.388, 1e-3);
    EXPECT_NEAR(value, predicted, 4 * se + 1e-9) << "se " << se;
}

// A scene mistake (a band outside a tabulated water IOP table) exits 1 and leaves no image.
TEST_F(Cli, RunWithBadInputLeavesNoOutput) {
    const fs::path dir = littoral::testing_support::scratchDir("pipelines", "run_bad");
    std::string text = kRunScene;
    text.replace(text.find("  probe_samples: 256"), 20, "  probe_samples: 256\n  bands: [[0.4, 0.5], [0.5, 0.7]]");
    std::ofstream(dir / "scene.yaml") << text;  // "coastal" is flat, so this is valid: render it
    ASSERT_EQ(run("-q run " + (dir / "scene.yaml").string() + " --out " + (dir / "ok").string()).status, 0);
    text.replace(text.find("preset: coastal"), 15, "preset: low");  // Table 10.3 stops at 0.6 um
    std::ofstream(dir / "scene.yaml") << text;
    const auto r = run("-q run " + (dir / "scene.yaml").string() + " --out " + (dir / "out").string());
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("does not cover the band [0.5, 0.7] um"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "out" / "nadir.exr"));
    EXPECT_FALSE(fs::exists(dir / "out" / "probes.csv"));
}

// Preview options are range-checked before anything runs: exit 1 naming the option.
TEST_F(Cli, PreviewOptionsAreChecked) {
    const auto r = run("render /nonexistent --out /tmp/x --gamma 0");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("--gamma"), std::string::npos) << r.output;
    const auto b = run("run /nonexistent.yaml --out /tmp/x --blur -1");
    EXPECT_EQ(b.status, 1);
    EXPECT_NE(b.output.find("--blur"), std::string::npos) << b.output;
}
