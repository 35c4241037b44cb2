// The simple atmosphere's two sun conventions (issue 10): sky.sun_plane horizontal (the sun's share
// (1 - F) E_h on a horizontal plane) and normal (DIRSIG's Eq. 4.5: on a plane normal to the beam).
// At a sun zenith of 60 degrees they differ by a factor of two; a probe in the open air measures it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "core/atomic_file.h"
#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using namespace littoral;
using namespace littoral::testing_support;

namespace {

std::string scene(const std::string& sunPlane, double zenithDeg = 60) {
    return "scene:\n  name: simple-sky\n  domain: {x: [-5, 5], y: [-5, 5]}\n"
           "sun: {zenith_deg: " + std::to_string(zenithDeg) + ", azimuth_deg: 30}\n"
           "sky: {model: simple, hemisphere_irradiance: 1.0, sky_fraction: 0.25" +
           (sunPlane.empty() ? std::string() : ", sun_plane: " + sunPlane) +
           "}\n"
           "bathymetry: {type: planar_slope, z0_m: 0.5, spacing_m: 2, material: ground}\n"
           "materials:\n  - {name: ground, type: black}\n"
           "probes:\n  - {name: air, position: [0, 0, 2], quantities: [Ed], samples: 1024}\n"
           "render: {hemisphere_samples: 1}\n";
}

struct Result {
    double ed = 0, se = 0, sunIrradiance = 0;
};

Result run(const std::string& name, const std::string& sunPlane, double zenithDeg = 60) {
    const fs::path dir = scratchDir("simple_atmosphere", name);
    const fs::path file = writeTextFile(dir, "scene.yaml", scene(sunPlane, zenithDeg));
    const CommandResult r = runLittoral("--quiet run " + file.string() + " --out " + (dir / "out").string());
    EXPECT_EQ(r.status, 0) << r.output;
    Result res;
    const std::string csv = readTextFile(dir / "out" / "probes.csv");
    EXPECT_EQ(std::sscanf(csv.substr(csv.find("air,Ed")).c_str(), "air,Ed,%*[^,],%*[^,],%lf,%lf", &res.ed, &res.se), 2)
        << csv;
    // The sun irradiance normal to the beam that the IR carries (a constant spectrum: a number).
    const std::string json = readTextFile(dir / "out" / "ir" / "scene.json");
    const size_t v = json.find("\"irradiance\"", json.find("\"sun\""));
    EXPECT_EQ(std::sscanf(json.c_str() + json.find(':', v) + 1, "%lf", &res.sunIrradiance), 1);
    return res;
}

}  // namespace

// E_h = 1, F = 0.25, sun at 60 deg, a probe in the open air over a black ground: the sky gives
// Ed = F E_h = 0.25 (sky radiance F E_h / pi over the whole upper hemisphere), the sun
//   horizontal: (1 - F) E_h = 0.75 on the horizontal (beam 0.75 / <cos>), Ed = 1.0;
//   normal:     (1 - F) E_h <cos> = 0.375 (beam 0.75),                   Ed = 0.625.
// <cos> is the disc's mean cosine: over a cone of half-angle a about a direction at zenith z that
// stays above the horizon, cos z (1 + cos a) / 2 (the mean of cos over a uniform cone is
// (1 + cos a) / 2 along its axis, and the perpendicular part averages out): 0.5 (1 - 5.3e-6) for
// the default 0.53 deg disc, so the beam is 1.5 (1 + 5.3e-6). The sun's parts differ by
// 1 / <cos> = 2 to within the probe's noise. The default is horizontal. Tolerance: 4 standard
// errors of the probe plus 1e-9; the beam (a closed form) to 1e-9 relative.
TEST(SimpleAtmosphere, SunPlaneConventionsDifferByTwoAtSixtyDegrees) {
    const Result h = run("horizontal", "horizontal"), n = run("normal", "normal"), d = run("default", "");
    const double deg = 3.14159265358979323846 / 180.0, a = 0.5 * 0.53 * deg;
    const double meanCos = std::cos(60 * deg) * (1 + std::cos(a)) / 2;
    EXPECT_NEAR(h.sunIrradiance, 0.75 / meanCos, 1e-9 * 1.5);
    EXPECT_NEAR(n.sunIrradiance, 0.75, 1e-12);
    EXPECT_EQ(d.sunIrradiance, h.sunIrradiance);
    EXPECT_NEAR(h.ed, 1.0, 4 * h.se + 1e-9);
    EXPECT_NEAR(n.ed, 0.625, 4 * n.se + 1e-9);
    EXPECT_NEAR((h.ed - 0.25) / (n.ed - 0.25), 2.0, 4 * std::hypot(h.se / 0.375, 2 * n.se / 0.375) + 1e-9);
    std::printf("[ simple atmosphere ] sun 60 deg: horizontal beam %.6g, Ed %.6f +- %.2g; normal beam %.6g, Ed %.6f "
                "+- %.2g; sun parts' ratio %.6f\n",
                h.sunIrradiance, h.ed, h.se, n.sunIrradiance, n.ed, n.se, (h.ed - 0.25) / (n.ed - 0.25));
}

// sun_plane belongs to the simple model only.
TEST(SimpleAtmosphere, SunPlaneWithAUniformSkyIsRefused) {
    const fs::path dir = scratchDir("simple_atmosphere", "uniform");
    const fs::path file = writeTextFile(
        dir, "scene.yaml",
        "sun: {zenith_deg: 60, irradiance: 1}\nsky: {radiance: 0.1, sun_plane: normal}\n"
        "bathymetry: {type: planar_slope, z0_m: 0.5, spacing_m: 2, material: ground}\n"
        "materials:\n  - {name: ground, type: black}\n");
    const CommandResult r = runLittoral("--quiet check-scene " + file.string());
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("scene.yaml:2:33: error: sky.sun_plane: only used with model: simple"), std::string::npos)
        << r.output;
}

// A sun at the horizon: the disc's centre has a cosine near 0 and part of the disc is below the
// horizon, so the horizontal convention divides by the disc's mean cosine, not the centre's. Sky
// and sun must still add up to E_h = 1 on the ground (they read 1178 at 89.9 deg and 52292 at
// 89.999 deg when the centre's cosine was used). Tolerance: 4 standard errors of the probe (the
// sun estimate samples points of the disc, whose cosines differ a lot at the horizon).
TEST(SimpleAtmosphere, GrazingSunStillGivesTheHemisphereIrradiance) {
    for (const double z : {85.0, 89.9, 89.999}) {
        const Result h = run("grazing" + std::to_string(static_cast<int>(z * 1000)), "horizontal", z);
        std::printf("[ simple atmosphere ] sun %.3f deg: beam %.6g, Ed %.6f +- %.2g (E_h 1)\n", z, h.sunIrradiance, h.ed,
                    h.se);
        EXPECT_NEAR(h.ed, 1.0, 4 * h.se + 1e-9) << z;
        EXPECT_TRUE(std::isfinite(h.sunIrradiance)) << z;
    }
}
