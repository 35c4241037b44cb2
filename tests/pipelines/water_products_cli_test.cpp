// Water-leaving products through the command line (sensor key water_products):
//  * Rrs of optically deep water at nadir from the 3-D path estimator against the deterministic
//    1-D column solver (a separate code: column/ shares no transport with render/), on
//    data_synthetic/water_products/deep_column.yaml (Henyey-Greenstein g = 0.9, albedo 0.75);
//  * Ed(0+) against E_sun cos + pi L_sky;
//  * the ENVI files and their headers (quantity, units, wavelengths);
//  * the sensor key refused where it cannot work (no water, a sensor under water), by run and
//    check-scene alike, with the location and no output; stale product files removed when the
//    products are turned off.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/units.h"
#include "render/image_output.h"
#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using namespace littoral;
using namespace littoral::testing_support;

namespace {

const fs::path kDeepColumn = fs::path(LITTORAL_SOURCE_DIR) / "data_synthetic" / "water_products" / "deep_column.yaml";

double columnRrs(const fs::path& dir, int streams, double* edAbove) {
    const auto r = runLittoral(fmt::format("-q column {} --out {} --streams {}", kDeepColumn.string(), dir.string(), streams));
    EXPECT_EQ(r.status, 0) << r.output;
    const auto j = nlohmann::json::parse(littoral::readTextFile(dir / "profiles.json"));
    if (edAbove) *edAbove = j["bands"][0]["Ed_above"].get<double>();
    return j["bands"][0]["Rrs_per_sr"].get<double>();
}

}  // namespace

// The 3-D Rrs is the ratio of the image means of Lw and Ed(0+) (the pixels are independent: each
// its own random streams, 64 samples of 4096 pixels), its standard error that of the Lw mean
// (Ed(0+) has no noise here but the solar disc's, below 1e-5). The column's own error is taken as
// its change from 8 to 16 streams (docs/column.md). Tolerance: 3 standard errors plus that change,
// plus 0.1 % for what the two models do differently and the column ignores (the sun's 0.53 deg
// disc; the 3-D image's 0.06 deg field of view around nadir).
// Measured: 3-D 0.0026456 +- 0.45 %, column 0.0026346 (8 streams) and 0.0026341 (16): +0.42 %.
TEST(WaterProductsCli, DeepWaterRrsAtNadirMatchesTheColumnSolver) {
    const fs::path dir = scratchDir("water_products", "deep_column");
    const auto r = runLittoral("-q run " + kDeepColumn.string() + " --out " + (dir / "out").string());
    ASSERT_EQ(r.status, 0) << r.output;
    const render::Film lw = render::readEnvi(dir / "out" / "nadir_water_leaving.img");
    const render::Film ed = render::readEnvi(dir / "out" / "nadir_ed0.img");
    const render::Film rrs = render::readEnvi(dir / "out" / "nadir_rrs.img");
    const size_t n = lw.pixels.size();
    double sum = 0, sum2 = 0, edSum = 0;
    for (size_t i = 0; i < n; ++i) {
        sum += lw.pixels[i], sum2 += static_cast<double>(lw.pixels[i]) * lw.pixels[i], edSum += ed.pixels[i];
        ASSERT_NEAR(rrs.pixels[i], lw.pixels[i] / ed.pixels[i], 1e-6 * rrs.pixels[i]);
    }
    const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / (n - 1)), edMean = edSum / n;
    double ed8 = 0;
    const double c8 = columnRrs(dir / "column8", 8, &ed8), c16 = columnRrs(dir / "column16", 16, nullptr);
    const double rrs3d = mean / edMean, rrsSe = se / edMean;
    std::printf("[ Rrs deep water ] 3-D %.7f +- %.2f %%, column %.7f (8 streams) %.7f (16); difference %+.2f %%\n", rrs3d,
                100 * rrsSe / rrs3d, c8, c16, 100 * (rrs3d / c8 - 1));
    EXPECT_NEAR(rrs3d, c8, 3 * rrsSe + std::abs(c16 - c8) + 1e-3 * c8);
    // Ed(0+): the column's E cos(30 deg) + pi L (a point sun) against the image's disc-sampled mean.
    EXPECT_NEAR(edMean, 1000 * std::cos(30 * kPi / 180) + kPi * 30, 1e-4 * edMean);
    EXPECT_NEAR(ed8, edMean, 1e-4 * edMean);
    // A 3-D standard error small enough for the comparison to mean something.
    EXPECT_LT(rrsSe / rrs3d, 0.01);
    // The probe 1 m above the sea: its Rrs (the batch ratios' mean, standard error from their
    // spread) against the column, with the same allowance; its Lw is in the probe table too.
    const auto j = nlohmann::json::parse(littoral::readTextFile(dir / "out" / "probes.json"));
    double probeRrs = 0, probeSe = 0, probeLw = 0;
    for (const auto& p : j["probes"]) {
        if (p["quantity"] == "Rrs") probeRrs = p["value"][0].get<double>(), probeSe = p["stderr"][0].get<double>();
        if (p["quantity"] == "Lw") probeLw = p["value"][0].get<double>();
        if (p["quantity"] == "Rrs") {
            EXPECT_EQ(p["units"], "sr^-1");
        }
    }
    std::printf("[ Rrs probe ] %.7f +- %.2f %% (Lw %.5f), column %.7f: %+.2f %%\n", probeRrs, 100 * probeSe / probeRrs, probeLw,
                c8, 100 * (probeRrs / c8 - 1));
    EXPECT_GT(probeSe, 0.0);
    EXPECT_NEAR(probeRrs, c8, 3 * probeSe + std::abs(c16 - c8) + 1e-3 * c8);
    EXPECT_NEAR(probeLw / edMean, probeRrs, 4 * probeSe);
}

namespace {

std::string smallScene(const std::string& sensorExtra, const std::string& waterSection = "water: {level_m: 0}\n") {
    return "scene: {name: wpcli, domain: {x: [-5, 5], y: [-5, 5]}}\n"
           "sun: {zenith_deg: 30, irradiance: 1000}\n"
           "sky: {radiance: 20}\n" +
           waterSection +
           "bathymetry: {type: planar_slope, z0_m: -2, material: sand}\n"
           "materials: [{name: sand, reflectance: 0.3}]\n"
           "sensors:\n"
           "  - {name: cam, type: frame, elevation_deg: 90, azimuth_deg: 0, range_m: 20, gsd_m: 0.5, width: 4, height: "
           "4" + sensorExtra + "}\n"
           "render: {bands: [[0.5, 0.55], [0.6, 0.65]], hemisphere_samples: 4}\n";
}

}  // namespace

// The six ENVI pairs are written with their quantities and units, and removed again (with a note)
// when the products are turned off for the next run into the same folder.
TEST(WaterProductsCli, WritesSixEnviPairsAndRemovesThemWhenTurnedOff) {
    const fs::path dir = scratchDir("water_products", "files");
    const fs::path on = writeTextFile(dir, "on.yaml", smallScene(", water_products: true"));
    auto r = runLittoral("-q run " + on.string() + " --out " + (dir / "out").string());
    ASSERT_EQ(r.status, 0) << r.output;
    const std::pair<const char*, const char*> products[] = {
        {"water_leaving", "W m^-2 sr^-1 um^-1"}, {"sky_reflected", "W m^-2 sr^-1 um^-1"}, {"glint", "W m^-2 sr^-1 um^-1"},
        {"other", "W m^-2 sr^-1 um^-1"},         {"ed0", "W m^-2 um^-1"},                {"rrs", "sr^-1"}};
    for (const auto& [name, units] : products) {
        const fs::path img = dir / "out" / fmt::format("cam_{}.img", name);
        ASSERT_TRUE(fs::exists(img)) << img;
        const std::string hdr = littoral::readTextFile(dir / "out" / fmt::format("cam_{}.hdr", name));
        EXPECT_NE(hdr.find(fmt::format("data units = {}\n", units)), std::string::npos) << name << "\n" << hdr;
        EXPECT_NE(hdr.find("wavelength = {0.525, 0.625}"), std::string::npos) << name << "\n" << hdr;
        const render::Film f = render::readEnvi(img);
        EXPECT_EQ(f.width, 4);
        EXPECT_EQ(f.bandCount(), 2);
    }
    // The parts add up to the radiance image; Ed(0+) of an open flat sea is E cos 30 + pi L.
    const render::Film L = render::readEnvi(dir / "out" / "cam.img");
    const render::Film w = render::readEnvi(dir / "out" / "cam_water_leaving.img"),
                       s = render::readEnvi(dir / "out" / "cam_sky_reflected.img"),
                       g = render::readEnvi(dir / "out" / "cam_glint.img"), o = render::readEnvi(dir / "out" / "cam_other.img"),
                       e = render::readEnvi(dir / "out" / "cam_ed0.img");
    for (size_t i = 0; i < L.pixels.size(); ++i) {
        EXPECT_NEAR(w.pixels[i] + s.pixels[i] + g.pixels[i] + o.pixels[i], L.pixels[i], 1e-6 * L.pixels[i]);
        // A nadir view of a flat sea reflects the uniform sky with r(0) = ((1.34 - 1) / 2.34)^2
        // (the scene file's default index, 1.34): 0.02111 x 20.
        EXPECT_NEAR(s.pixels[i], 0.021112 * 20, 1e-3 * 0.4222);
        // One disc point per pixel: its cosine lies within sin(30 deg) alpha + alpha^2 / 2 of
        // cos(30 deg), alpha = 0.265 deg the disc's radius.
        const double alpha = 0.265 * kPi / 180;
        EXPECT_NEAR(e.pixels[i], 1000 * std::cos(30 * kPi / 180) + kPi * 20, 1000 * (0.5 * alpha + alpha * alpha / 2) + 1e-3);
    }
    const fs::path off = writeTextFile(dir, "off.yaml", smallScene(""));
    r = runLittoral("run " + off.string() + " --out " + (dir / "out").string());
    ASSERT_EQ(r.status, 0) << r.output;
    for (const auto& [name, units] : products) {
        EXPECT_FALSE(fs::exists(dir / "out" / fmt::format("cam_{}.img", name))) << name;
        EXPECT_FALSE(fs::exists(dir / "out" / fmt::format("cam_{}.hdr", name))) << name;
    }
}

// water_products where it cannot work: one located error (file:line:column of the key), exit 1, by
// `run` and `check-scene` alike, and nothing written.
TEST(WaterProductsCli, IsRefusedWithoutWaterOrUnderWater) {
    const fs::path dir = scratchDir("water_products", "refused");
    struct Case {
        const char* name;
        std::string text;
        const char* message;
    };
    const Case cases[] = {
        {"dry", smallScene(", water_products: true", ""), "water_products needs water in the scene"},
        {"under", smallScene(", water_products: true, medium: water"), "water_products needs a sensor in the air"},
        {"notbool", smallScene(", water_products: 3"), "water_products"},
    };
    for (const Case& c : cases) {
        const fs::path file = writeTextFile(dir, std::string(c.name) + ".yaml", c.text);
        for (const char* cmd : {"run", "check-scene"}) {
            const fs::path out = dir / (std::string(c.name) + "_" + cmd);
            const auto r = runLittoral(fmt::format("{} {}{}", cmd, file.string(),
                                                   std::string(cmd) == "run" ? " --out " + out.string() : ""));
            EXPECT_EQ(r.status, 1) << c.name << " " << cmd << "\n" << r.output;
            EXPECT_NE(r.output.find(c.message), std::string::npos) << c.name << " " << cmd << "\n" << r.output;
            const int line = 1 + static_cast<int>(std::count(c.text.begin(), c.text.begin() + c.text.find("water_products"), '\n'));
            EXPECT_NE(r.output.find(fmt::format("{}:{}:", file.filename().string(), line)), std::string::npos)
                << c.name << "\n" << r.output;
            EXPECT_FALSE(fs::exists(out / "cam.img")) << c.name;
        }
    }
}
