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
        "    wind_from_deg: 180\n"
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
    EXPECT_NEAR(p.windDirection, kPi / 2, 1e-15);  // from the south: blowing toward +y (north)
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

// The wind is a compass direction it comes FROM (clockwise from north), like every azimuth in a
// scene file; inside, WaveParams::windDirection is where it blows toward, ccw from east. A wind from
// the west blows toward east (0), from the north toward south (-pi/2), and so on; the default is
// from the west, the same physical wind as the old default (wind_direction_deg: 0).
TEST(SurfaceSection, WindComesFromACompassDirection) {
    const struct { double from, toward; } cases[] = {{270, 0}, {0, -kPi / 2}, {90, kPi}, {180, kPi / 2}, {360, -kPi / 2},
                                                     {225, kPi / 4}};
    for (const auto& c : cases) {
        const WaveParams p = parse("water:\n  surface:\n    wind_speed: 6\n    wind_from_deg: " + std::to_string(c.from) + "\n");
        EXPECT_NEAR(std::remainder(p.windDirection - c.toward, 2 * kPi), 0.0, 1e-12) << c.from;
        EXPECT_NEAR(compassFromDirection(p.windDirection), std::fmod(c.from, 360.0), 1e-9) << c.from;
    }
    EXPECT_NEAR(parse("water:\n  surface:\n    wind_speed: 6\n").windDirection, 0.0, 1e-15);
    // The sinusoid's waves come from a compass direction too.
    const WaveParams s = parse("water:\n  surface:\n    model: sinusoid\n    waves_from_deg: 0\n");
    EXPECT_NEAR(s.windDirection, -kPi / 2, 1e-12);
}

// The old key is refused with an explanation and its conversion, never reinterpreted; the new keys
// belong to their models; the range is a compass range.
TEST(SurfaceSection, OldWindKeyIsExplained) {
    std::string e = errorOf("water:\n  surface:\n    wind_speed: 6\n    wind_direction_deg: 90\n");
    EXPECT_NE(e.find("scene.yaml:4:25"), std::string::npos) << e;
    EXPECT_NE(e.find("removed"), std::string::npos) << e;
    EXPECT_NE(e.find("wind_from_deg"), std::string::npos) << e;
    EXPECT_NE(e.find("TOWARD"), std::string::npos) << e;
    EXPECT_NE(e.find("wind_from_deg: 180"), std::string::npos) << e;  // toward north = from south
    e = errorOf("water:\n  surface:\n    model: sinusoid\n    wind_direction_deg: 0\n");
    EXPECT_NE(e.find("waves_from_deg: 270"), std::string::npos) << e;
    e = errorOf("water:\n  surface:\n    model: sinusoid\n    wind_from_deg: 10\n");
    EXPECT_NE(e.find("does not apply to model sinusoid"), std::string::npos) << e;
    e = errorOf("water:\n  surface:\n    wind_speed: 6\n    waves_from_deg: 10\n");
    EXPECT_NE(e.find("does not apply to model beaufort"), std::string::npos) << e;
    e = errorOf("water:\n  surface:\n    wind_speed: 6\n    wind_from_deg: -10\n");
    EXPECT_NE(e.find("wind_from_deg"), std::string::npos) << e;
    EXPECT_NE(e.find("360"), std::string::npos) << e;
}

// Model cox-munk: its keys, the Cox-Munk wind range, and the full grid by default.
TEST(SurfaceSection, CoxMunkModel) {
    const WaveParams p = parse("water:\n  surface:\n    model: cox-munk\n    wind_speed: 7\n    sea: slick\n"
                               "    size: 40\n    spacing: 0.2\n");
    EXPECT_EQ(p.model, WaveModel::CoxMunk);
    EXPECT_EQ(p.sea, CoxMunkSea::Slick);
    EXPECT_EQ(p.triangles, 0u);
    EXPECT_EQ(parse("water:\n  surface:\n    model: cox-munk\n    wind_speed: 7\n    size: 40\n").sea, CoxMunkSea::Clean);
    for (const char* U : {"15", "50", "0", "-1"}) {
        const std::string e = errorOf(std::string("water:\n  surface:\n    model: cox-munk\n    wind_speed: ") + U + "\n");
        EXPECT_NE(e.find("scene.yaml:4:17"), std::string::npos) << e;
        EXPECT_NE(e.find("Cox-Munk range"), std::string::npos) << e;
        EXPECT_NE(e.find("0.01 to 14"), std::string::npos) << e;
    }
    std::string e;
    e = errorOf("water:\n  surface:\n    wind_speed: 6\n    sea: slick\n");
    EXPECT_NE(e.find("does not apply to model beaufort"), std::string::npos) << e;
    e = errorOf("water:\n  surface:\n    model: cox-munk\n    wind_speed: 6\n    sea: slik\n");
    EXPECT_NE(e.find("did you mean 'slick'"), std::string::npos) << e;
    // The grid must resolve the correlation length (0.39 m across the wind at 2 m/s).
    e = errorOf("water:\n  surface:\n    model: cox-munk\n    wind_speed: 2\n    size: 20\n    spacing: 0.5\n");
    EXPECT_NE(e.find("spacing"), std::string::npos) << e;
    EXPECT_NE(e.find("correlation length"), std::string::npos) << e;
}
