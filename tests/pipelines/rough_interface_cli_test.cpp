// The rough interface from a scene file (water.surface.roughness): a valid scene renders, and each
// mistake (a wind outside Cox and Munk's range, Gram-Charlier terms on a fit that has none, an
// unknown shadowing term, a surface with no wind to lend) gets one located error
// (file:line:column, the key, what is allowed), exit status 1 and no output, from check-scene,
// build and run alike.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using namespace littoral::testing_support;

namespace {

const std::string kRoughBase = R"(scene:
  name: rough
  domain: {x: [-10, 10], y: [-10, 10]}
sun: {zenith_deg: 20, azimuth_deg: 135, irradiance: 1000}
sky: {radiance: 10}
water:
  horizontal: periodic
  surface:
    model: flat
    size: [20, 20]
    roughness: {model: cox-munk, wind_speed: 6, wind_from_deg: 200, sea: clean, gram_charlier: true, shadowing: smith-light}
  optics: {absorption_per_m: 0.1}
bathymetry: {type: planar_slope, z0_m: -5, spacing_m: 5, material: floor}
materials:
  - {name: floor, reflectance: 0.2}
sensors:
  - {name: cam, type: frame, elevation_deg: 70, azimuth_deg: 315, range_m: 40, gsd_m: 0.5, width: 16, height: 12}
probes:
  - {name: p, position: [0, 0, -1], quantities: [Ed]}
render:
  estimator: path
  probe_samples: 64
  probe_batches: 4
)";

std::string replaceText(const std::string& text, const std::string& from, const std::string& to) {
    return replacedOnce(text, from, to);
}

void expectRefused(const char* name, const std::string& text, const char* where, const char* message) {
    expectSceneRefused("rough_interface_cli", name, text, where, message);
}

}  // namespace

TEST(RoughInterfaceCli, ValidSceneRendersAndCarriesTheRoughness) {
    const fs::path dir = scratchDir("rough_interface_cli", "valid");
    const fs::path scene = writeTextFile(dir, "valid.yaml", kRoughBase);
    const CommandResult r = runLittoral("--quiet run " + scene.string() + " --out " + (dir / "out").string());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(fs::exists(dir / "out" / "probes.csv"));
    EXPECT_TRUE(fs::exists(dir / "out" / "cam.exr"));
    // The IR names the rough interface with every setting (wind from 200 deg: toward 20 deg east of
    // north, i.e. 70 deg counter-clockwise from east = 1.2217 rad).
    std::string json;
    {
        std::ifstream in(dir / "out" / "ir" / "scene.json");
        json.assign(std::istreambuf_iterator<char>(in), {});
    }
    EXPECT_NE(json.find("\"rough-dielectric\""), std::string::npos);
    EXPECT_NE(json.find("\"wind_speed_mps\": 6.0"), std::string::npos) << json.substr(0, 2000);
    EXPECT_NE(json.find("\"wind_azimuth_rad\": 1.221730476"), std::string::npos);
    EXPECT_NE(json.find("\"sea\": \"clean\""), std::string::npos);
    EXPECT_NE(json.find("\"gram_charlier\": true"), std::string::npos);
    EXPECT_NE(json.find("\"shadowing\": \"smith-light\""), std::string::npos);
}

TEST(RoughInterfaceCli, WindOutsideTheCoxMunkRange) {
    expectRefused("wind-high", replaceText(kRoughBase, "wind_speed: 6,", "wind_speed: 20,"), ":11:46",
                  "water.surface.roughness.wind_speed: 20 m/s is outside the Cox-Munk range; allowed 0.01 to 14 m/s");
    expectRefused("wind-zero", replaceText(kRoughBase, "wind_speed: 6,", "wind_speed: 0,"), ":11:46",
                  "water.surface.roughness.wind_speed: 0 m/s is outside the Cox-Munk range");
    // Taken from a wind-driven surface: reported at the surface's wind, naming the roughness.
    expectRefused("wind-from-surface",
                  replaceText(replaceText(kRoughBase, "model: flat\n    size: [20, 20]",
                                          "model: beaufort\n    wind_speed: 30\n    size: [20, 20]\n    spacing: 1\n    triangles: 0"),
                              "wind_speed: 6, ", ""),
                  ":10:17", "taken by water.surface.roughness");
}

TEST(RoughInterfaceCli, OtherRoughnessMistakes) {
    expectRefused("gc-slick", replaceText(kRoughBase, "sea: clean", "sea: slick"), ":11:96",
                  "Gram-Charlier coefficients for the clean sea only");
    expectRefused("shadowing", replaceText(kRoughBase, "shadowing: smith-light", "shadowing: smith-lite"), ":11:113",
                  "did you mean 'smith-light'");
    expectRefused("no-wind", replaceText(kRoughBase, "wind_speed: 6, ", ""), ":11:16", "missing required key 'wind_speed'");
    expectRefused("unknown-key", replaceText(kRoughBase, "sea: clean", "sea: clean, windspeed: 3"), ":11:81", "windspeed");
}
