// check-scene refuses everything `run` refuses before rendering (issue 20): each case below is a
// scene that only the renderer's own checks catch (the scene on its bands, the estimator's
// settings, each sensor's view, each probe's plan). For every case, `check-scene`, `build` and
// `run` all exit 1 with one error located in the scene file, and `build` and `run` leave no output
// folder behind (the renderer's checks run before the IR is written). The table of cases in
// docs/reliability.md is generated from this list: the test fails when it is out of date and
// prints the table to paste (or rewrites it with LITTORAL_WRITE_DOCS=1).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using littoral::testing_support::expectSceneRefused;
using littoral::testing_support::replacedOnce;

namespace {

// The small valid scene (flat water over a flat seabed at -2 m, one nadir frame sensor on line 8,
// one probe on line 10, the material on line 6).
const char* const kBase = littoral::testing_support::kSmallScene;

struct Case {
    std::string name;
    std::string what;     // the table's description
    std::string from, to;  // the edit of kBase
    std::string where;    // ":line:column" of the error
    std::string message;  // a fragment of the error
};

// A 4 x 4 class map of value 0, written once with oiiotool; the path is relative to each case's
// scene file (coverage/<case>/), so the error columns do not depend on where the build is.
std::string classMap() {
    static const bool written = [] {
        const fs::path p = littoral::testing_support::scratchDir("coverage", "map") / "map.png";
        const std::string cmd = "oiiotool --pattern constant:color=0 4x4 1 -d uint8 -o '" + p.string() + "' >/dev/null";
        return std::system(cmd.c_str()) == 0;
    }();
    EXPECT_TRUE(written);
    return "../map/map.png";
}

const std::vector<Case>& cases() {
    static const std::vector<Case> c{
        {"probe_on_seabed", "a probe exactly on the seabed (its lower hemisphere would read 0)",
         "position: [0, 0, -1]", "position: [0, 0, -2]", ":10:5", "closer than 0.0001 m"},
        {"probe_wrong_medium", "a probe in air declared `medium: water`", "position: [0, 0, -1]",
         "position: [0, 0, 1], medium: water", ":10:5", "declared in medium 'water'"},
        {"probe_batches", "`probes[].samples` fewer than `render.probe_batches`", "quantities: [Ed]}",
         "quantities: [Ed], samples: 2}", ":10:5", "2 samples cannot form 16 batches"},
        {"pinhole_sees_nothing", "a pinhole camera whose view misses the scene",
         "{name: nadir, type: frame, elevation_deg: 90, azimuth_deg: 0, range_m: 50, gsd_m: 0.5, width: 16, height: 12}",
         "{name: nadir, type: pinhole, position: [0, 0, 5], direction: [0, 0, 1], focal_length_mm: 5, "
         "pixel_pitch_um: 10, width: 8, height: 8}",
         ":8:5", "sensor 'nadir'"},
        {"camera_wrong_medium", "a pinhole camera under water declared `medium: air`",
         "{name: nadir, type: frame, elevation_deg: 90, azimuth_deg: 0, range_m: 50, gsd_m: 0.5, width: 16, height: 12}",
         "{name: nadir, type: pinhole, position: [0, 0, -1], direction: [0, 0, -1], focal_length_mm: 5, "
         "pixel_pitch_um: 100, width: 8, height: 8, medium: air}",
         ":8:5", "declared in medium 'air', but the interfaces around its position (0, 0, -1) put it in 'water'"},
        {"frame_up_parallel", "a nadir frame sensor with `up: [0, 0, 1]` (parallel to the view)",
         "width: 16, height: 12}", "width: 16, height: 12, up: [0, 0, 1]}", ":8:119",
         "sensors[0].up: 'up' (0, 0, 1) must not be parallel to the view direction (0, 0, -1)"},
        {"rough_equal_indices", "a rough water surface over water of refractive index 1 (no interface to be rough)",
         "water: {optics: {preset: coastal}}",
         "water: {surface: {model: flat, size: 12, spacing: 1, roughness: {wind_speed: 5}}, optics: {preset: coastal, "
         "refractive_index: 1.0}}",
         ":4:65", "water.surface.roughness: a rough surface needs water of another refractive index than the air's"},
        {"class_mean_reflectance", "a texture class whose `mean` times its reflectance exceeds 1",
         "bathymetry: {type: planar_slope, z0_m: -2, material: floor}",
         "bathymetry: {type: planar_slope, z0_m: -2}\ntexture_classes: {map: " + classMap() +
             ", extent: {x: [-5, 5], y: [-5, 5]}, classes: [{index: 0, name: c0, reflectance: 0.9, mean: 10}]}",
         ":6:84", "material 'c0': reflectance 9 outside [0, 1]"},
    };
    return c;
}

std::string table() {
    std::ostringstream t;
    t << "| case | what the renderer refuses | check-scene | build | run |\n|---|---|---|---|---|\n";
    for (const Case& c : cases())
        t << "| `" << c.name << "` | " << c.what << " | refused, exit 1 | refused, nothing written | refused, nothing written |\n";
    return t.str();
}

const char* kBegin = "<!-- generated by tests/pipelines/check_scene_coverage_test.cpp: begin -->\n";
const char* kEnd = "<!-- generated: end -->\n";

}  // namespace

TEST(CheckSceneCoverage, EveryRenderTimeRefusalIsRefusedByCheckSceneBuildAndRun) {
    ASSERT_TRUE(fs::exists(littoral::testing_support::littoralBinary())) << "build the littoral target first";
    // The base scene itself is valid (else every case would pass for the wrong reason).
    {
        const fs::path dir = littoral::testing_support::scratchDir("coverage", "base");
        const fs::path scene = littoral::testing_support::writeTextFile(dir, "base.yaml", kBase);
        const auto r = littoral::testing_support::runLittoral("--quiet check-scene " + scene.string());
        ASSERT_EQ(r.status, 0) << r.output;
    }
    for (const Case& c : cases()) {
        SCOPED_TRACE(c.name);
        expectSceneRefused("coverage", c.name, replacedOnce(kBase, c.from, c.to), c.where, c.message);
    }
}

TEST(CheckSceneCoverage, TheReliabilityTableIsGeneratedFromTheCases) {
    const fs::path doc = fs::path(LITTORAL_SOURCE_DIR) / "docs" / "reliability.md";
    std::ifstream in(doc);
    std::stringstream ss;
    ss << in.rdbuf();
    std::string text = ss.str();
    const size_t b = text.find(kBegin), e = text.find(kEnd);
    ASSERT_NE(b, std::string::npos) << "docs/reliability.md lacks the generated block";
    ASSERT_NE(e, std::string::npos);
    const std::string now = text.substr(b + std::string(kBegin).size(), e - b - std::string(kBegin).size());
    const std::string want = table();
    if (now != want && std::getenv("LITTORAL_WRITE_DOCS")) {
        text.replace(b + std::string(kBegin).size(), now.size(), want);
        std::ofstream(doc) << text;
        return;
    }
    EXPECT_EQ(now, want) << "docs/reliability.md is out of date; paste:\n" << want;
}
