// Scene file section water.surface: values read, every key range-checked, errors at line:column.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "core/units.h"
#include "scenegen/surface_section.h"

using namespace littoral;
using namespace littoral::surfaces;
using littoral::scenegen::YamlNode;

namespace {
WaveParams parse(const std::string& text) {
    const YamlNode root = YamlNode::loadString(text, "scene.yaml");
    return scenegen::parseWaterSurface(root["water"]["surface"]);
}
std::string errorOf(const std::string& text) {
    try {
        parse(text);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}
}  // namespace

TEST(SurfaceSection, ReadsValues) {
    const WaveParams p = parse(
        "water:\n"
        "  surface:\n"
        "    model: jonswap\n"
        "    wind_speed: 8.5\n"
        "    wind_direction_deg: 90\n"
        "    fetch: 20000\n"
        "    gamma: 2.5\n"
        "    size: [120, 80]\n"
        "    centre: [10, -5]\n"
        "    spacing: 0.5\n"
        "    seed: 42\n"
        "    triangles: 5000\n"
        "    time: 2.5\n"
        "    depth: 12\n");
    EXPECT_EQ(p.model, WaveModel::Jonswap);
    EXPECT_EQ(p.windSpeed, 8.5);
    EXPECT_NEAR(p.windDirection, kPi / 2, 1e-15);
    EXPECT_EQ(p.fetch, 20000);
    EXPECT_EQ(p.gamma, 2.5);
    EXPECT_EQ(p.sizeX, 120);
    EXPECT_EQ(p.sizeY, 80);
    EXPECT_EQ(p.centreX, 10);
    EXPECT_EQ(p.centreY, -5);
    EXPECT_EQ(p.spacing, 0.5);
    EXPECT_EQ(p.seed, 42u);
    EXPECT_EQ(p.triangles, 5000u);
    EXPECT_EQ(p.time, 2.5);
    EXPECT_EQ(p.depth, 12);
    // Defaults are the dissertation's.
    const WaveParams d = parse("water:\n  surface:\n    wind_speed: 6\n");
    EXPECT_EQ(d.model, WaveModel::Beaufort);
    EXPECT_EQ(d.sizeX, 300);
    EXPECT_EQ(d.spacing, 0.25);
    EXPECT_EQ(d.seed, 500u);
    EXPECT_EQ(d.triangles, 30000u);
}

TEST(SurfaceSection, ErrorsNameKeyAndPosition) {
    // Out-of-range wind: line 4, the value's column.
    std::string e = errorOf("water:\n  surface:\n    model: beaufort\n    wind_speed: 95\n");
    EXPECT_NE(e.find("scene.yaml:4:17"), std::string::npos) << e;
    EXPECT_NE(e.find("wind_speed"), std::string::npos) << e;
    e = errorOf("water:\n  surface:\n    wind_speed: -2\n");
    EXPECT_NE(e.find("scene.yaml:3:17"), std::string::npos) << e;
    // Zero spacing.
    e = errorOf("water:\n  surface:\n    wind_speed: 6\n    spacing: 0\n");
    EXPECT_NE(e.find("scene.yaml:4:14"), std::string::npos) << e;
    EXPECT_NE(e.find("spacing"), std::string::npos) << e;
    // Missing wind for a wind-driven model.
    e = errorOf("water:\n  surface:\n    model: elfouhaily\n");
    EXPECT_NE(e.find("wind_speed"), std::string::npos) << e;
    // A key of another model.
    e = errorOf("water:\n  surface:\n    wind_speed: 6\n    gamma: 3\n");
    EXPECT_NE(e.find("scene.yaml:4:12"), std::string::npos) << e;
    EXPECT_NE(e.find("jonswap"), std::string::npos) << e;
    // Unknown key, with a suggestion.
    e = errorOf("water:\n  surface:\n    wind_sped: 6\n");
    EXPECT_NE(e.find("wind_speed"), std::string::npos) << e;
    // Combination check reported at the key it names: more triangles than the grid has.
    e = errorOf("water:\n  surface:\n    wind_speed: 6\n    size: 100\n    spacing: 1\n    triangles: 50000\n");
    EXPECT_NE(e.find("scene.yaml:6:16"), std::string::npos) << e;
    EXPECT_NE(e.find("triangles"), std::string::npos) << e;
    // Unknown model.
    e = errorOf("water:\n  surface:\n    model: pierson\n    wind_speed: 6\n");
    EXPECT_NE(e.find("pierson-moskowitz"), std::string::npos) << e;
}
