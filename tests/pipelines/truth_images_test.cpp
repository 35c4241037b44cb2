// The truth images look through the water: a nadir view of a sand floor under flat water has the
// interface as its first hit and the sand as the surface each pixel sees, and the legend names
// both with the share of pixels of each. A view wider than the domain is warned about with the
// fraction of its pixels that see past the edge.
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "render/image_output.h"
#include "core/atomic_file.h"
#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using namespace littoral;
using littoral::testing_support::runLittoral;
using littoral::testing_support::scratchDir;
using littoral::testing_support::writeTextFile;

namespace {

// The legend row of a material: "id,name,type,r,g,b,first,surface".
std::vector<std::string> legendRow(const std::string& csv, const std::string& name) {
    std::istringstream in(csv);
    std::string line;
    while (std::getline(in, line)) {
        std::vector<std::string> f;
        std::stringstream ls(line);
        std::string cell;
        while (std::getline(ls, cell, ',')) f.push_back(cell);
        if (f.size() == 8 && f[1] == name) return f;
    }
    return {};
}

}  // namespace

TEST(TruthImages, SeeThroughTheWaterToTheSeabedAndNameEveryValue) {
    const fs::path dir = scratchDir("truth_images", "through_water");
    const fs::path scene = writeTextFile(dir, "scene.yaml", R"(scene: {name: truth, domain: {x: [-5, 5], y: [-5, 5]}}
sun: {zenith_deg: 30, irradiance: 1000}
sky: {radiance: 0}
water: {optics: {absorption_per_m: 0.1}}
bathymetry: {type: planar_slope, z0_m: -2, material: sand}
materials: [{name: sand, reflectance: 0.3}]
sensors:
  - {name: nadir, type: frame, elevation_deg: 90, azimuth_deg: 0, range_m: 50, gsd_m: 0.5, width: 12, height: 12}
render: {hemisphere_samples: 4}
)");
    const auto r = runLittoral("-q run " + scene.string() + " --out " + (dir / "out").string());
    ASSERT_EQ(r.status, 0) << r.output;
    const render::TruthImages t = render::readTruthExr(dir / "out" / "nadir_truth.exr");
    const std::string legend = littoral::readTextFile(dir / "out" / "nadir_legend.csv");
    const auto sand = legendRow(legend, "sand"), iface = legendRow(legend, "air-water-interface");
    ASSERT_FALSE(sand.empty()) << legend;
    ASSERT_FALSE(iface.empty()) << legend;
    const int sandId = std::stoi(sand[0]), ifaceId = std::stoi(iface[0]);
    for (size_t p = 0; p < t.materialId.size(); ++p) {
        EXPECT_EQ(t.materialId[p], ifaceId) << p;
        EXPECT_EQ(t.surfaceId[p], sandId) << p;
        EXPECT_NEAR(t.hitDepth[p], 2.0, 1e-4) << p;
    }
    // Every pixel: the interface first, the sand seen through it.
    EXPECT_EQ(iface[6], "1.000000");
    EXPECT_EQ(iface[7], "0.000000");
    EXPECT_EQ(sand[6], "0.000000");
    EXPECT_EQ(sand[7], "1.000000");
    EXPECT_EQ(sand[2], "lambertian");
    // The PNG's colour of the sand is the legend's.
    uint8_t rgb[3];
    render::materialIdColour(sandId, rgb);
    EXPECT_EQ(sand[3] + "," + sand[4] + "," + sand[5],
              std::to_string(rgb[0]) + "," + std::to_string(rgb[1]) + "," + std::to_string(rgb[2]));
}

// 40 x 40 pixels of 0.5 m over a 10 m domain: the centres of 20 columns and 20 rows fall inside,
// so 1 - 400 / 1600 = 75 % of the pixels look down past the domain's edge at nothing.
TEST(TruthImages, AViewPastTheDomainIsWarnedAboutWithItsFraction) {
    const fs::path dir = scratchDir("truth_images", "past_domain");
    const fs::path scene = writeTextFile(dir, "scene.yaml", R"(scene: {name: wide, domain: {x: [-5, 5], y: [-5, 5]}}
sun: {zenith_deg: 30, irradiance: 1000}
sky: {radiance: 0}
bathymetry: {type: planar_slope, z0_m: 0, material: sand}
materials: [{name: sand, reflectance: 0.3}]
sensors:
  - {name: wide, type: frame, elevation_deg: 90, azimuth_deg: 0, range_m: 50, gsd_m: 0.5, width: 40, height: 40}
  - {name: narrow, type: frame, elevation_deg: 90, azimuth_deg: 0, range_m: 50, gsd_m: 0.5, width: 16, height: 16}
render: {hemisphere_samples: 4}
)");
    const auto r = runLittoral("run " + scene.string() + " --out " + (dir / "out").string());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("sensor 'wide': 75 % of the pixels see past the scene's domain"), std::string::npos)
        << r.output;
    EXPECT_EQ(r.output.find("sensor 'narrow':"), std::string::npos) << r.output;
}
