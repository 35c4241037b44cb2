// Scene-format tests: every kind of mistake is reported with file:line:column and the key.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>

#include "core/error.h"
#include "core/units.h"
#include "scenegen/scene_file.h"

using namespace littoral;
using namespace littoral::scenegen;
namespace fs = std::filesystem;

namespace {

const char* kValid = R"(scene:
  name: unit
sun:
  zenith_deg: 30
  azimuth_deg: 315
  irradiance: 1500
sky:
  radiance: 30
water:
  optics:
    preset: low
    phase: {type: henyey-greenstein, g: 0.88}
materials:
  - name: sand
    reflectance: 0.3
sensors:
  - name: cam
    type: frame
    elevation_deg: 60
    azimuth_deg: 315
    range_m: 500
    gsd_m: 0.2
    width: 64
    height: 48
render:
  bands: {range_um: [0.4, 0.6], count: 2}
  estimator: path
)";

fs::path writeScene(const std::string& name, const std::string& text) {
    const fs::path d = fs::temp_directory_path() / "littoral_scene_file_test";
    fs::create_directories(d);
    const fs::path p = d / name;
    std::ofstream(p) << text;
    return p;
}

std::string replaceOnce(std::string s, const std::string& from, const std::string& to) {
    const auto pos = s.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    return s.replace(pos, from.size(), to);
}

// Loads the scene and returns the error text; fails the test if the scene loads.
std::string errorOf(const std::string& name, const std::string& text) {
    const fs::path p = writeScene(name, text);
    try {
        loadSceneFile(p);
    } catch (const InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << name << " was accepted";
    return "";
}

// "file:line:column:" at the start of the message, with the expected line and column.
void expectLocation(const std::string& msg, const std::string& file, int line, int column) {
    const std::regex re("^(.*):(\\d+):(\\d+): ");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(msg, m, re)) << msg;
    EXPECT_NE(m[1].str().find(file), std::string::npos) << msg;
    EXPECT_EQ(std::stoi(m[2].str()), line) << msg;
    EXPECT_EQ(std::stoi(m[3].str()), column) << msg;
}

}  // namespace

TEST(SceneFile, ValidSceneParses) {
    const auto spec = loadSceneFile(writeScene("valid.yaml", kValid));
    EXPECT_EQ(spec.scene.name, "unit");
    ASSERT_EQ(spec.sensors.size(), 1u);
    EXPECT_NEAR(spec.sun.zenith, deg2rad(30), 1e-15);
    EXPECT_EQ(spec.render.settings.bands.size(), 2u);
    EXPECT_EQ(spec.waterOptics.iops.preset, "low");
    // Table 10.3 "Low" at 0.5 um: a = 0.001469 + 0.003963 + 0.001472 = 0.006904 m^-1. The preset is
    // 0.01 x the Table 9.6 spectra, of which the printed entries are 6-decimal truncations (up to
    // 1e-6 each), so the sum of three may differ by up to 3e-6. The scene file adds pure sea water,
    // 0.0204 m^-1 at 500 nm (Pope & Fry 1997), which the table at 2.5 nm holds exactly.
    EXPECT_NEAR(spec.waterOptics.iops.absorption.at(0.5), 0.006904 + 0.0204, 3e-6);
}

TEST(SceneFile, UnknownKey) {
    const auto msg = errorOf("unknown.yaml", replaceOnce(kValid, "  name: unit\n", "  name: unit\n  colour: blue\n"));
    expectLocation(msg, "unknown.yaml", 3, 3);
    EXPECT_NE(msg.find("scene.colour"), std::string::npos) << msg;
    EXPECT_NE(msg.find("unknown key"), std::string::npos) << msg;
    EXPECT_NE(msg.find("allowed: name, origin, domain"), std::string::npos) << msg;
}

TEST(SceneFile, MisspeltKeySuggestsTheRightOne) {
    const auto msg = errorOf("misspelt.yaml", replaceOnce(kValid, "    range_m: 500", "    rnage_m: 500"));
    expectLocation(msg, "misspelt.yaml", 21, 5);
    EXPECT_NE(msg.find("sensors[0].rnage_m"), std::string::npos) << msg;
    EXPECT_NE(msg.find("did you mean 'range_m'?"), std::string::npos) << msg;
}

TEST(SceneFile, WrongType) {
    const auto msg = errorOf("type.yaml", replaceOnce(kValid, "    width: 64", "    width: wide"));
    expectLocation(msg, "type.yaml", 23, 12);
    EXPECT_NE(msg.find("sensors[0].width"), std::string::npos) << msg;
    EXPECT_NE(msg.find("expected an integer"), std::string::npos) << msg;
}

TEST(SceneFile, OutOfRangeNumberNamesTheAllowedRange) {
    const auto msg = errorOf("range.yaml", replaceOnce(kValid, "  zenith_deg: 30", "  zenith_deg: 95"));
    expectLocation(msg, "range.yaml", 4, 15);
    EXPECT_NE(msg.find("sun.zenith_deg"), std::string::npos) << msg;
    EXPECT_NE(msg.find("allowed [0, 90] degrees"), std::string::npos) << msg;
}

TEST(SceneFile, MissingReferencedFile) {
    const auto msg = errorOf("missing.yaml", replaceOnce(kValid, "    reflectance: 0.3", "    reflectance: {file: no_such_sand.csv}"));
    expectLocation(msg, "missing.yaml", 15, 25);
    EXPECT_NE(msg.find("materials[0].reflectance.file"), std::string::npos) << msg;
    EXPECT_NE(msg.find("no_such_sand.csv"), std::string::npos) << msg;
}

TEST(SceneFile, MissingRequiredKey) {
    const auto msg = errorOf("required.yaml", replaceOnce(kValid, "    gsd_m: 0.2\n", ""));
    EXPECT_NE(msg.find("missing required key 'gsd_m'"), std::string::npos) << msg;
    expectLocation(msg, "required.yaml", 17, 5);  // the sensor's map starts at its first key
}

TEST(SceneFile, UnknownEnumValueSuggests) {
    const auto msg = errorOf("enum.yaml", replaceOnce(kValid, "preset: low", "preset: lwo"));
    expectLocation(msg, "enum.yaml", 11, 13);
    EXPECT_NE(msg.find("did you mean 'low'?"), std::string::npos) << msg;
}

TEST(SceneFile, BandOutsideTabulatedReflectance) {
    const auto msg = errorOf("band.yaml", replaceOnce(kValid, "    reflectance: 0.3",
                                                      "    reflectance: {wavelengths_um: [0.45, 0.7], values: [0.2, 0.3]}"));
    EXPECT_NE(msg.find("does not cover the band [0.4, 0.5] um"), std::string::npos) << msg;
    expectLocation(msg, "band.yaml", 14, 5);
}

TEST(SceneFile, YamlSyntaxErrorHasLocation) {
    const auto msg = errorOf("syntax.yaml", replaceOnce(kValid, "  bands: {range_um: [0.4, 0.6], count: 2}", "  bands: {range_um: [0.4, 0.6"));
    EXPECT_NE(msg.find("YAML syntax error"), std::string::npos) << msg;
    EXPECT_NE(msg.find("syntax.yaml:"), std::string::npos) << msg;
}

TEST(SceneFile, DuplicateNamesRejected) {
    const auto msg = errorOf("dup.yaml", replaceOnce(kValid, "    reflectance: 0.3\n", "    reflectance: 0.3\n  - name: sand\n    reflectance: 0.5\n"));
    EXPECT_NE(msg.find("material name 'sand' is used twice"), std::string::npos) << msg;
}

// Table 10.1 frame geometry: sensor at elevation 60 deg, compass azimuth 315 deg (north-west),
// range 500 m. Its position is 500 (cos60 sin315, cos60 cos315, sin60) = (-176.78, 176.78, 433.01)
// and its IFOV = GSD / range = 0.2 / 500 = 0.4 mrad (spec/seed-ch05-10.md §3.2).
TEST(SceneFile, FrameSensorPlacement) {
    const auto spec = loadSceneFile(writeScene("frame.yaml", kValid));
    const auto c = placeSensor(spec.sensors[0], 0.0, true);
    EXPECT_NEAR(c.position.x, -176.7767, 1e-4);
    EXPECT_NEAR(c.position.y, 176.7767, 1e-4);
    EXPECT_NEAR(c.position.z, 433.0127, 1e-4);
    EXPECT_NEAR(length(c.forward + c.position / 500.0), 0.0, 1e-12);
    EXPECT_NEAR(c.pixelPitch / c.focalLength, 0.4e-3, 1e-15);
    EXPECT_EQ(c.medium, "");
}

// DIRSIG simple atmosphere (spec/seed-ch01-04.md §4.0): L_sky = F E_h / pi, and the sun carries
// (1 - F) E_h on a horizontal plane, i.e. (1 - F) E_h / cos(zenith) normal to the beam.
TEST(SceneFile, SimpleAtmosphereSplit) {
    std::string t = replaceOnce(kValid, "  irradiance: 1500\n", "");
    t = replaceOnce(t, "  radiance: 30\n", "  model: simple\n  hemisphere_irradiance: 1.0\n  sky_fraction: 0.5\n");
    const auto spec = loadSceneFile(writeScene("simple.yaml", t));
    ir::SceneIR s;
    applyCommonSections(spec, &s);
    EXPECT_NEAR(s.sky.radiance.at(0.5), 0.5 / kPi, 1e-15);
    // The sun carries (1 - F) E_h = 0.5 on the ground: the beam times the disc's mean cosine, which for
    // a disc of half-angle a wholly above the horizon is cos(zenith) (1 + cos a) / 2.
    EXPECT_NEAR(s.sun.irradiance.at(0.5) * std::cos(s.sun.zenith) * (1 + std::cos(s.sun.halfAngle)) / 2, 0.5, 1e-12);
    // Compass 315 deg (north-west) -> IR azimuth counter-clockwise from east = 135 deg.
    EXPECT_NEAR(rad2deg(s.sun.azimuth), 135.0, 1e-12);
    EXPECT_NEAR(s.sun.direction().x, -s.sun.direction().y, 1e-12);
    EXPECT_LT(s.sun.direction().x, 0.0);
}

// A sun given by date and time goes through NREL SPA at scene.origin. Reda & Andreas (2004)
// example: 2003-10-17 12:30:30 MST (19:30:30 UTC), 39.742476 N, 105.1786 W, 1830.14 m: topocentric
// zenith 50.11162 deg, azimuth 194.34024 deg. The paper uses 820 mbar and 11 C for refraction;
// the scene file uses the standard atmosphere (1013.25 mbar, 15 C), which raises the 0.0163 deg
// refraction at this zenith by about a fifth: |difference| < 0.005 deg, so allow 0.01 deg.
TEST(SceneFile, SunFromDateTimeUsesSolarPosition) {
    std::string t = replaceOnce(kValid, "  zenith_deg: 30\n  azimuth_deg: 315\n", "  date_time_utc: 2003-10-17T19:30:30Z\n");
    t = replaceOnce(t, "  name: unit\n", "  name: unit\n  origin: {latitude: 39.742476, longitude: -105.1786, altitude: 1830.14}\n");
    const auto spec = loadSceneFile(writeScene("spa.yaml", t));
    ir::SceneIR s;
    applyCommonSections(spec, &s);
    EXPECT_NEAR(rad2deg(s.sun.zenith), 50.11162, 0.01);
    // Compass 194.34024 deg -> counter-clockwise from east: 90 - 194.34024 = -104.34024 deg.
    EXPECT_NEAR(std::remainder(rad2deg(s.sun.azimuth) + 104.34024, 360.0), 0.0, 0.01);

    const auto msg = errorOf("spa_no_origin.yaml",
                             replaceOnce(kValid, "  zenith_deg: 30\n  azimuth_deg: 315\n", "  date_time_utc: 2003-10-17T19:30:30Z\n"));
    EXPECT_NE(msg.find("needs scene.origin"), std::string::npos) << msg;
    const auto bad = errorOf("spa_bad.yaml",
                             replaceOnce(kValid, "  zenith_deg: 30\n  azimuth_deg: 315\n", "  date_time_utc: 17/10/2003 19:30\n"));
    EXPECT_NE(bad.find("expected an ISO 8601 UTC time"), std::string::npos) << bad;
}

// Issue 19 section 3: each scatterer of a layer given by coefficients has its own phase function;
// each constituent can have its own; pure water's phase function takes its depolarisation ratio.
TEST(SceneFile, EachScattererKeepsItsOwnPhaseFunction) {
    const std::string head = "scene: {name: s}\nwater:\n  optics:\n";
    const auto spec = loadSceneFile(writeScene(
        "scatterers.yaml",
        head + "    absorption_per_m: 0.05\n    scatterers:\n"
               "      - {name: water, scattering_per_m: 0.0029, phase: {type: pure-water, depolarization_ratio: 0.2}}\n"
               "      - {name: particles, scattering_per_m: 0.25, phase: {type: petzold}}\n"
               "render: {estimator: path}\n"));
    const auto& sc = spec.waterOptics.iops.scatterers;
    ASSERT_EQ(sc.size(), 2u);
    EXPECT_EQ(sc[0].name, "water");
    EXPECT_EQ(sc[0].phase.type, "pure-water");
    EXPECT_EQ(sc[0].phase.params.number("depolarization_ratio"), 0.2);
    EXPECT_EQ(sc[1].phase.type, "petzold");
    EXPECT_EQ(sc[1].scattering.at(0.5), 0.25);
    // Constituents: pure water defaults to pure-water (0.09); phytoplankton and sediment each their own.
    const auto c = loadSceneFile(writeScene(
        "constituents.yaml",
        head + "    constituents: {chlorophyll_mg_m3: 1, sediment_g_m3: 2, particle_phase: {type: petzold},\n"
               "                   sediment_phase: {type: fournier-forand, backscatter_fraction: 0.02}}\n"));
    const auto& k = c.waterOptics.iops.scatterers;
    ASSERT_EQ(k.size(), 3u);
    EXPECT_EQ(k[0].phase.type, "pure-water");
    EXPECT_EQ(k[0].phase.params.number("depolarization_ratio"), 0.09);
    EXPECT_EQ(k[1].phase.type, "petzold");
    EXPECT_EQ(k[2].phase.type, "fournier-forand");
}

// The Table 10.3 presets list the constituents alone (spec/seed-ch05-10.md 3.4: "Pure water is not
// listed"); a scene file adds pure sea water. At 0.5 um "low" sums to a = 0.006904 m^-1, Pope &
// Fry (1997) give pure water 0.0204 m^-1 (their 500 nm entry) and Morel (1974) sea water b =
// 0.0029 m^-1 (docs/scene-format.md); `pure_water: none` keeps the table as printed. The band is
// 2 nm wide around 500 nm, over which both curves are linear to well within the tolerances.
TEST(SceneFile, TableTenThreePresetsAddPureWaterUnlessToldNot) {
    auto parse = [](const std::string& name, const std::string& optics, const std::string& render = "") {
        return loadSceneFile(writeScene(name, "scene: {name: s}\nrender: {bands: [[0.495, 0.505]]" + render +
                                                  "}\nwater:\n  optics:\n    preset: low\n" + optics));
    };
    const SceneSpec with = parse("low.yaml", ""), without = parse("low_none.yaml", "    pure_water: none\n");
    const double aWith = with.waterOptics.iops.absorption.at(0.5);
    const double aWithout = without.waterOptics.iops.absorption.at(0.5);
    EXPECT_NEAR(aWithout, 0.006904, 3e-6);  // 6-decimal truncations, as in ValidSceneParses
    // The added water is tabulated on the band's 5 nm grid (0.495, 0.5, 0.505 um), so at 0.5 um it
    // is Pope & Fry's entry, printed to 3 significant digits (+-5e-5).
    EXPECT_NEAR(aWith - aWithout, 0.0204, 5e-5);
    double bWater = 0;
    for (const auto& sc : with.waterOptics.iops.scatterers)
        if (sc.name == "pure water") bWater = sc.scattering.at(0.5);
    EXPECT_NEAR(bWater, 0.0029, 1e-4);
    EXPECT_EQ(with.waterOptics.iops.scatterers.size(), without.waterOptics.iops.scatterers.size() + 1);
    // The dirsig estimator renders this water's in-scatter unless told not to; the path estimator
    // follows scattering itself and takes no solver.
    EXPECT_EQ(with.waterOptics.solver, "medium-pm");
    EXPECT_TRUE(with.waterOptics.solverDefaulted);
    EXPECT_EQ(parse("low_att.yaml", "    solver: attenuation\n").waterOptics.solver, "attenuation");
    EXPECT_EQ(parse("low_path.yaml", "", ", estimator: path").waterOptics.solver, "");
}

// What cannot be honoured is refused at its key (line:column of the offending node).
TEST(SceneFile, PhaseFunctionsThatCannotBeHonouredAreRefusedWhereTheyAreWritten) {
    const std::string head = "scene: {name: s}\nwater:\n  optics:\n";
    struct Case {
        std::string text, message;
        int line, column;
    };
    const Case cases[] = {
        {head + "    constituents: {pure_water: none, pure_water_phase: {type: rayleigh}}\n", "pure_water is none", 4, 56},
        {head + "    constituents: {phytoplankton_phase: {type: petzold}}\n", "chlorophyll_mg_m3 is 0", 4, 41},
        {head + "    constituents: {chlorophyll_mg_m3: 1, particle_phase: {type: petzold}}\n    phase: {type: isotropic}\n",
         "'phase' beside 'constituents' replaces", 4, 58},
        {head + "    constituents: {pure_water_phase: {type: pure-water, depolarization_ratio: 1.5}}\n",
         "1.5 is out of range; allowed [0, 1]", 4, 79},
        {head + "    scattering_per_m: 0.1\n    scatterers: [{name: a, scattering_per_m: 0.1}]\n", "not beside it", 4, 23},
        {head + "    scatterers: [{name: a, scattering_per_m: 0.1}, {name: a, scattering_per_m: 0.2}]\n", "listed twice", 4, 59},
        {head + "    scatterers: [{name: a, scattering_per_m: 0.1}, {name: b, scattering_per_m: 0.1}, {name: c, "
                "scattering_per_m: 0.1}, {name: d, scattering_per_m: 0.1}, {name: e, scattering_per_m: 0.1}]\n",
         "at most 4 per layer", 4, 17},
        {head + "    solver: attenuation\n    scatterers: [{name: a, scattering_per_m: 0.1, phase: {type: petzold}}]\n",
         "scatterers[].phase: not used: water.optics.solver attenuation treats scattering as loss", 4, 5},
        {head + "    preset: coastal\n    pure_water: sea\n", "not used: preset 'coastal' gives measured totals", 5, 17},
        {head + "    preset: pure\n    pure_water: fresh\n", "not used: preset 'pure' is a purely refracting", 5, 17},
        {head + "    absorption_per_m: 0.1\n    pure_water: sea\n", "pure_water goes beside 'preset'", 5, 17},
        {head + "    preset: low\n    pure_water: salty\n", "salty", 5, 17},
    };
    for (const Case& c : cases) {
        const std::string msg = errorOf("refused.yaml", c.text);
        EXPECT_NE(msg.find(c.message), std::string::npos) << c.text << "\n" << msg;
        expectLocation(msg, "refused.yaml", c.line, c.column);
    }
}

// Probe arrays (issue 18): a `line` (transect or vertical profile) and a `grid` expand into
// evenly spaced probes, both ends included, named <name>_<i> and <name>_<i>_<j> with indices
// zero-padded to sort in order. Positions are checked exactly against the arithmetic.
TEST(SceneFile, ProbeLinesAndGridsExpandIntoNamedProbes) {
    const std::string probes = "probes:\n"
                               "  - {name: prof, line: {from: [1, 2, -0.5], to: [1, 2, -10.5], count: 11}, "
                               "quantities: [Ed, Eu], medium: water}\n"
                               "  - {name: g, grid: {from: [-2, -1, -3], to: [2, 1, -3], count: [5, 3]}, "
                               "quantities: [Eod], samples: 64}\n"
                               "  - {name: one, position: [0, 0, -1], quantities: [Ed]}\n"
                               "render:\n";
    const auto spec = loadSceneFile(writeScene("arrays.yaml", replaceOnce(kValid, "render:\n", probes)));
    ASSERT_EQ(spec.probes.size(), 11u + 15u + 1u);
    EXPECT_EQ(spec.probes[0].name, "prof_00");
    EXPECT_EQ(spec.probes[10].name, "prof_10");
    for (int i = 0; i <= 10; ++i) {
        EXPECT_DOUBLE_EQ(spec.probes[i].position.z, -0.5 - i) << i;
        EXPECT_EQ(spec.probes[i].position.x, 1.0);
        EXPECT_EQ(spec.probes[i].quantities.size(), 2u);
        EXPECT_EQ(spec.probes[i].medium, "water");
        EXPECT_EQ(spec.probes[i].entry, 0u);
    }
    // Grid: i along x (5 probes, 1 m apart), j along y (3 probes, 1 m apart), at z = -3.
    EXPECT_EQ(spec.probes[11].name, "g_0_0");
    EXPECT_EQ(spec.probes[11 + 3 * 4 + 2].name, "g_4_2");
    for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 3; ++j) {
            const auto& p = spec.probes[11 + 3 * i + j];
            EXPECT_DOUBLE_EQ(p.position.x, -2.0 + i);
            EXPECT_DOUBLE_EQ(p.position.y, -1.0 + j);
            EXPECT_EQ(p.position.z, -3.0);
            EXPECT_EQ(p.samples, 64);
            EXPECT_EQ(p.entry, 1u);
        }
    EXPECT_EQ(spec.probes[26].name, "one");
    EXPECT_EQ(spec.probes[26].entry, 2u);
}

// Each malformed array is refused at its key with what is allowed; a name that an array entry
// repeats is refused at the later entry.
TEST(SceneFile, MalformedProbeArraysAreRefusedAtTheirKey) {
    auto withProbe = [](const std::string& entry) {
        return replaceOnce(kValid, "render:\n", "probes:\n" + entry + "render:\n");
    };
    std::string msg = errorOf("two.yaml", withProbe("  - {name: p, position: [0, 0, -1], line: {from: [0, 0, -1], to: "
                                                    "[0, 0, -2], count: 2}, quantities: [Ed]}\n"));
    EXPECT_NE(msg.find("probes[0]: probe 'p': give exactly one of 'position' (one probe), 'line' or 'grid'"),
              std::string::npos)
        << msg;
    expectLocation(msg, "two.yaml", 26, 5);
    struct Case {
        const char *file, *entry, *message;
    };
    const Case cases[] = {
        {"none.yaml", "  - {name: p, quantities: [Ed]}\n", "found 0"},
        {"tilted.yaml", "  - {name: p, grid: {from: [0, 0, -1], to: [1, 1, -2], count: [2, 2]}, quantities: [Ed]}\n",
         "probes[0].grid.to: a grid is horizontal"},
        {"count1.yaml", "  - {name: p, line: {from: [0, 0, -1], to: [0, 0, -2], count: 1}, quantities: [Ed]}\n",
         "probes[0].line.count: 1 is out of range; allowed [2, 100000]"},
        {"huge.yaml",
         "  - {name: p, grid: {from: [0, 0, -1], to: [1, 1, -1], count: [1000, 1000]}, quantities: [Ed]}\n",
         "1000 x 1000 = 1000000 probes; at most 100000 in one array"},
        {"frac.yaml", "  - {name: p, grid: {from: [0, 0, -1], to: [1, 1, -1], count: [2.5, 2]}, quantities: [Ed]}\n",
         "expected [nx, ny]: two whole numbers"},
        {"same.yaml", "  - {name: p, line: {from: [0, 0, -1], to: [0, 0, -1], count: 3}, quantities: [Ed]}\n",
         "a line needs 'to' apart from 'from'"},
        {"dupname.yaml",
         "  - {name: p, line: {from: [0, 0, -1], to: [0, 0, -2], count: 3}, quantities: [Ed]}\n"
         "  - {name: p_1, position: [0, 0, -1], quantities: [Ed]}\n",
         "probes[1]: probe name 'p_1' is used twice"},
    };
    for (const Case& c : cases) {
        msg = errorOf(c.file, withProbe(c.entry));
        EXPECT_NE(msg.find(c.message), std::string::npos) << c.file << ": " << msg;
    }
}
