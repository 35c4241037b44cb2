// The bathymetry / objects / texture_classes section parsers: values, and errors at file:line:col.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/units.h"
#include "scenegen/assembly_sections.h"
#include "scenegen/surface_section.h"
#include "surfaces/wave_surface.h"

using namespace littoral;
using namespace littoral::scenegen;
namespace fs = std::filesystem;

namespace {

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(AssemblySections, BathymetryKinds) {
    const auto root = YamlNode::loadString("bathymetry:\n  type: planar_slope\n  z0_m: 1.5\n  slope_x: -0.04\n"
                                           "  material: sand\n  spacing_m: 0.75\n",
                                           "s.yaml");
    const BathymetrySpec b = parseBathymetry(root["bathymetry"]);
    EXPECT_EQ(b.kind, BathymetrySpec::Kind::PlanarSlope);
    EXPECT_EQ(b.planar.z0, 1.5);
    EXPECT_EQ(b.planar.slopeX, -0.04);
    EXPECT_EQ(b.spacing, 0.75);
    EXPECT_EQ(b.material, "sand");

    const auto bar = YamlNode::loadString("b:\n  type: bar_trough\n  A: 0.12\n  shoreline_x_m: -20\n  bar_crest_m: 50\n"
                                          "  trough_m: 30\n",
                                          "s.yaml");
    const BathymetrySpec bt = parseBathymetry(bar["b"]);
    EXPECT_EQ(bt.kind, BathymetrySpec::Kind::BarTrough);
    EXPECT_EQ(bt.barTrough.dean.A, 0.12);
    EXPECT_EQ(bt.barTrough.dean.shorelineX, -20);
    EXPECT_EQ(bt.barTrough.barCrestDistance, 50);
}

TEST(AssemblySections, BathymetryErrorsNameTheKey) {
    // A key of another bathymetry type is unknown here, with its location.
    const auto root = YamlNode::loadString("bathymetry:\n  type: planar_slope\n  bar_crest_m: 3\n", "s.yaml");
    const std::string e = errorOf([&] { parseBathymetry(root["bathymetry"]); });
    EXPECT_NE(e.find("s.yaml:3:"), std::string::npos) << e;
    EXPECT_NE(e.find("bar_crest_m"), std::string::npos) << e;
    const auto bad = YamlNode::loadString("bathymetry:\n  type: sloped\n", "s.yaml");
    const std::string e2 = errorOf([&] { parseBathymetry(bad["bathymetry"]); });
    EXPECT_NE(e2.find("s.yaml:2:"), std::string::npos) << e2;
    EXPECT_NE(e2.find("planar_slope"), std::string::npos) << e2;
    const auto bar = YamlNode::loadString("b:\n  type: bar_trough\n  bar_crest_m: 20\n  trough_m: 30\n", "s.yaml");
    EXPECT_NE(errorOf([&] { parseBathymetry(bar["b"]); }).find("landward of the bar crest"), std::string::npos);
}

TEST(AssemblySections, ObjectsPoseAndErrors) {
    const fs::path dir = fs::path(LITTORAL_BINARY_DIR) / "test_tmp" / "scenegen" / "sections";
    fs::create_directories(dir);
    std::ofstream(dir / "hull.obj") << "v 0 0 0\n";
    const std::string yaml = "objects:\n  - name: boat\n    mesh: hull.obj\n    materials: [fiberglass, aluminum]\n"
                             "    position_m: [10, -4]\n    heading_deg: 90\n    draft_m: 0.3\n";
    std::ofstream(dir / "scene.yaml") << yaml;
    const auto root = YamlNode::loadFile(dir / "scene.yaml");
    const auto objs = parseObjects(root["objects"]);
    ASSERT_EQ(objs.size(), 1u);
    EXPECT_EQ(objs[0].materials.size(), 2u);
    EXPECT_NEAR(objs[0].heading, kPi / 2, 1e-15);
    EXPECT_EQ(*objs[0].draft, 0.3);
    EXPECT_EQ(objs[0].mesh, dir / "hull.obj");

    std::ofstream(dir / "both.yaml") << "objects:\n  - name: boat\n    mesh: hull.obj\n    materials: m\n"
                                        "    position_m: [0, 0]\n    draft_m: 0.3\n    z_m: 1\n";
    const auto both = YamlNode::loadFile(dir / "both.yaml");
    const std::string e = errorOf([&] { parseObjects(both["objects"]); });
    EXPECT_NE(e.find("both.yaml:2:"), std::string::npos) << e;
    EXPECT_NE(e.find("exactly one of 'draft_m'"), std::string::npos) << e;

    std::ofstream(dir / "typo.yaml") << "objects:\n  - name: boat\n    mesh: hull.obj\n    materials: m\n"
                                        "    position_m: [0, 0]\n    draft: 0.3\n";
    const auto typo = YamlNode::loadFile(dir / "typo.yaml");
    const std::string e3 = errorOf([&] { parseObjects(typo["objects"]); });
    EXPECT_NE(e3.find("typo.yaml:6:"), std::string::npos) << e3;
    EXPECT_NE(e3.find("draft_m"), std::string::npos) << e3;  // did you mean

    std::ofstream(dir / "missing.yaml") << "objects:\n  - name: boat\n    mesh: nothere.obj\n    materials: m\n"
                                           "    position_m: [0, 0]\n    draft_m: 0.3\n";
    const auto missing = YamlNode::loadFile(dir / "missing.yaml");
    EXPECT_NE(errorOf([&] { parseObjects(missing["objects"]); }).find("missing.yaml:3:"), std::string::npos);
}

TEST(AssemblySections, TextureClassesChecks) {
    const fs::path dir = fs::path(LITTORAL_BINARY_DIR) / "test_tmp" / "scenegen" / "sections_tc";
    fs::create_directories(dir);
    std::ofstream(dir / "map.png") << "x";
    std::ofstream(dir / "tc.yaml") << "texture_classes:\n  map: map.png\n  extent: {x: [0, 90], y: [0, 60]}\n"
                                      "  classes:\n    - {index: 0, name: sand, reflectance: 0.3}\n"
                                      "    - {index: 0, name: wet, reflectance: 0.2}\n";
    const auto root = YamlNode::loadFile(dir / "tc.yaml");
    const std::string e = errorOf([&] { parseTextureClasses(root["texture_classes"]); });
    EXPECT_NE(e.find("tc.yaml:6:"), std::string::npos) << e;
    EXPECT_NE(e.find("defined twice"), std::string::npos) << e;
    std::ofstream(dir / "ok.yaml") << "texture_classes:\n  map: map.png\n  classes:\n"
                                      "    - {index: 2, name: sand, reflectance: {wavelengths_um: [0.4, 0.7], values: [0.2, 0.4]}}\n";
    const auto ok = YamlNode::loadFile(dir / "ok.yaml");
    const TextureClassesSpec t = parseTextureClasses(ok["texture_classes"]);
    EXPECT_NEAR(t.classes[0].reflectance.at(0.55), 0.3, 1e-12);
    EXPECT_FALSE(t.extent.has_value());
}

// A flat water.surface needs no resolution: without spacing and triangles it takes the coarse grid
// of an omitted surface (a quarter of the shorter side, kept whole); given, both are honoured.
TEST(AssemblySections, FlatSurfaceTakesACoarseGridUnlessItsResolutionIsGiven) {
    const auto bare = YamlNode::loadString("surface: {model: flat, size: [80, 40]}\n", "s.yaml");
    const surfaces::WaveParams p = parseWaterSurface(bare["surface"]);
    EXPECT_DOUBLE_EQ(p.spacing, 10.0);
    EXPECT_EQ(p.triangles, 0u);
    const auto given = YamlNode::loadString("surface: {model: flat, size: 40, spacing: 0.5, triangles: 100}\n", "s.yaml");
    const surfaces::WaveParams q = parseWaterSurface(given["surface"]);
    EXPECT_DOUBLE_EQ(q.spacing, 0.5);
    EXPECT_EQ(q.triangles, 100u);
    // Other models keep the documented defaults (0.25 m; 30 000 triangles).
    const auto waves = YamlNode::loadString("surface: {model: beaufort, wind_speed: 5, size: 40}\n", "s.yaml");
    const surfaces::WaveParams w = parseWaterSurface(waves["surface"]);
    EXPECT_DOUBLE_EQ(w.spacing, 0.25);
    EXPECT_EQ(w.triangles, surfaces::kDefaultTriangles);
}
