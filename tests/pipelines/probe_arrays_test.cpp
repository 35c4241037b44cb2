// Probe arrays end to end (issue 18): a vertical profile and a horizontal grid in one scene entry
// each, read back from probes.csv by its documented columns; and probes that a wave trough or
// crest puts in the other medium, refused at their entry by check-scene, build and run.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using littoral::testing_support::runLittoral;

namespace {

std::vector<std::string> splitCsv(const std::string& line) {
    std::vector<std::string> out;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) out.push_back(cell);
    return out;
}

// The flat-water scene of cli_test (black sky and seabed, coastal water c = 0.388 m^-1), with a
// profile of 5 probes from 0.5 to 2.5 m and a 3 x 2 grid at 1 m.
const char* kArrayScene = R"(scene:
  name: arrays
  domain: {x: [-10, 10], y: [-10, 10]}
sun: {zenith_deg: 30, azimuth_deg: 135, irradiance: 1000}
sky: {radiance: 0}
water:
  surface: {model: flat, size: [20, 20]}
  optics: {preset: coastal, solver: attenuation}   # the direct beam alone (scattering as loss)
bathymetry: {type: planar_slope, z0_m: -3, slope_x: 0.1, slope_y: 0, spacing_m: 1.0, material: floor}
materials:
  - {name: floor, type: black}
probes:
  - {name: prof, line: {from: [0, 0, -0.5], to: [0, 0, -2.5], count: 5}, quantities: [Ed]}
  - {name: g, grid: {from: [-2, -1, -1], to: [2, 1, -1], count: [3, 2]}, quantities: [Ed]}
render:
  probe_samples: 256
)";

// A sinusoid of amplitude 0.4 m and wavelength 5 m; `probes` is the probe entry.
std::string sinusoidScene(const std::string& probes) {
    return std::string(R"(scene:
  name: trough
  domain: {x: [-10, 10], y: [-10, 10]}
sun: {zenith_deg: 30, azimuth_deg: 135, irradiance: 1000}
sky: {radiance: 0}
water:
  surface: {model: sinusoid, amplitude: 0.4, wavelength: 5.0, size: [20, 20], centre: [0, 0], spacing: 0.1}
  optics: {preset: coastal, solver: attenuation}   # the direct beam alone (scattering as loss)
bathymetry: {type: planar_slope, z0_m: -3, spacing_m: 1.0, material: floor}
materials:
  - {name: floor, type: black}
probes:
)") + probes + "render: {probe_samples: 64}\n";
}

}  // namespace

// Under flat water with a black sky and seabed, Ed at depth z is the refracted sun alone:
// E_sun cos(theta_s) T_f exp(-c z / cos(theta_w)) (cli_test derives 557.388 at 1 m). Every probe of
// both arrays must match it at the depth its z_m column states, within 4 of its own standard
// errors (11 probes: a false failure about once in 1500 runs).
TEST(ProbeArrays, ProfileAndGridReadBeerLambertAtTheirPositions) {
    const fs::path dir = littoral::testing_support::scratchDir("pipelines", "probe_arrays");
    std::ofstream(dir / "scene.yaml") << kArrayScene;
    const auto r = runLittoral("-q run " + (dir / "scene.yaml").string() + " --out " + (dir / "out").string());
    ASSERT_EQ(r.status, 0) << r.output;
    std::ifstream csv(dir / "out" / "probes.csv");
    std::string line;
    std::getline(csv, line);
    ASSERT_EQ(line, "probe,quantity,band_lo_um,band_hi_um,value,stderr,units,x_m,y_m,z_m,medium,samples,batches,method");
    std::map<std::string, std::vector<double>> rows;  // name -> x, y, z
    while (std::getline(csv, line)) {
        const auto c = splitCsv(line);
        ASSERT_EQ(c.size(), 14u) << line;
        const double value = std::stod(c[4]), se = std::stod(c[5]), z = std::stod(c[9]);
        const double predicted = littoral::testing_support::refractedSunEd(1000, 30, 1.34, 0.388, -z);
        EXPECT_NEAR(value, predicted, 4 * se + 1e-9) << line;
        EXPECT_EQ(c[10], "water") << line;
        EXPECT_EQ(c[11], "256") << line;
        EXPECT_EQ(c[13], "backward") << line;  // the water does not scatter: no forward tallies
        rows[c[0]] = {std::stod(c[7]), std::stod(c[8]), z};
    }
    ASSERT_EQ(rows.size(), 11u);
    for (int i = 0; i < 5; ++i) EXPECT_DOUBLE_EQ(rows.at("prof_" + std::to_string(i))[2], -0.5 - 0.5 * i);
    EXPECT_EQ(rows.at("g_0_0"), (std::vector<double>{-2, -1, -1}));
    EXPECT_EQ(rows.at("g_1_1"), (std::vector<double>{0, 1, -1}));
    EXPECT_EQ(rows.at("g_2_0"), (std::vector<double>{2, -1, -1}));

    // The vertical profile gives K_d between its consecutive probes (kd.csv): for the direct beam
    // alone, K_d = c / cos(theta_w) = 0.388 / sqrt(1 - (0.5 / 1.34)^2) = 0.41821 m^-1 at every depth,
    // within 4 of each pair's standard errors. The grid's probes lie side by side and give none.
    std::ifstream kd(dir / "out" / "kd.csv");
    ASSERT_TRUE(std::getline(kd, line));
    ASSERT_EQ(line, "upper_probe,lower_probe,x_m,y_m,z_upper_m,z_lower_m,band_lo_um,band_hi_um,kd_per_m,kd_stderr_per_m");
    const double kdExpected = 0.388 / std::sqrt(1 - (0.5 / 1.34) * (0.5 / 1.34));
    EXPECT_NEAR(kdExpected, 0.41821, 1e-5);
    int pairs = 0;
    while (std::getline(kd, line)) {
        const auto c = splitCsv(line);
        ASSERT_EQ(c.size(), 10u) << line;
        EXPECT_EQ(c[0], "prof_" + std::to_string(pairs)) << line;
        EXPECT_EQ(c[1], "prof_" + std::to_string(pairs + 1)) << line;
        EXPECT_NEAR(std::stod(c[8]), kdExpected, 4 * std::stod(c[9]) + 1e-9) << line;
        ++pairs;
    }
    EXPECT_EQ(pairs, 4);
}

// A transect 0.3 m under the mean level crosses troughs 0.4 m deep: some of its probes are in
// air. One 0.3 m above the mean level crosses crests: some are in water. Both are refused at
// their entry (line 13, column 5) by every command, with nothing left behind; 1 m down is fine.
TEST(ProbeArrays, ProbesThatWavesPutInTheOtherMediumAreRefusedAtTheirEntry) {
    using littoral::testing_support::expectSceneRefused;
    expectSceneRefused("pipelines", "probe_in_trough",
                       sinusoidScene("  - {name: t, line: {from: [-2.5, 0, -0.3], to: [2.5, 0, -0.3], count: 11}, "
                                     "quantities: [Ed]}\n"),
                       ":13:5",
                       "lies in air above the water surface (a wave trough there), but its medium is water (taken "
                       "from the mean water level 0 m)");
    expectSceneRefused("pipelines", "probe_in_crest",
                       sinusoidScene("  - {name: c, line: {from: [-2.5, 0, 0.3], to: [2.5, 0, 0.3], count: 11}, "
                                     "quantities: [Ed]}\n"),
                       ":13:5", "lies in the water (a wave crest there), but its medium is air (taken from the mean "
                                "water level 0 m)");
    expectSceneRefused("pipelines", "probe_declared_water",
                       sinusoidScene("  - {name: w, position: [0, 0, 1], medium: water, quantities: [Ed]}\n"), ":13:5",
                       "lies in air above the water surface, but its medium is water (medium: water)");
    const fs::path dir = littoral::testing_support::scratchDir("pipelines", "probe_deep");
    std::ofstream(dir / "deep.yaml") << sinusoidScene(
        "  - {name: d, line: {from: [-2.5, 0, -1], to: [2.5, 0, -1], count: 11}, quantities: [Ed]}\n");
    const auto r = runLittoral("--quiet check-scene " + (dir / "deep.yaml").string());
    EXPECT_EQ(r.status, 0) << r.output;
}
