// `littoral waves` end to end: outputs on success, exit 1 and no file on each input mistake.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "tests/support/test_support.h"
#include <nlohmann/json.hpp>

#include "core/mesh.h"

namespace fs = std::filesystem;

namespace {
const std::string kBinary = std::string(LITTORAL_BINARY_DIR) + "/bin/littoral";

using CmdResult = littoral::testing_support::CommandResult;
CmdResult run(const std::string& args) { return littoral::testing_support::runLittoral("-q " + args); }

fs::path tempDir() {
    const fs::path d = fs::temp_directory_path() / ("littoral_waves_cli_" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
}
}  // namespace

TEST(WavesCli, WritesMeshAndStats) {
    ASSERT_TRUE(fs::exists(kBinary)) << "littoral binary not built: " << kBinary;
    const fs::path d = tempDir();
    const fs::path mesh = d / "sea.ply", stats = d / "stats.json";
    const CmdResult r = run("waves --wind 6 --size 60 --spacing 0.5 --triangles 3000 --out " + mesh.string() + " --stats " +
                      stats.string());
    ASSERT_EQ(r.status, 0) << r.output;
    ASSERT_TRUE(fs::exists(mesh));
    ASSERT_TRUE(fs::exists(stats));
    const auto j = nlohmann::json::parse(std::ifstream(stats));
    EXPECT_EQ(j["model"], "beaufort");
    EXPECT_EQ(j["wind_speed"].get<double>(), 6.0);
    EXPECT_EQ(j["wind_from_deg"].get<double>(), 270.0);  // the default: from the west
    EXPECT_TRUE(j["waves_from_deg"].is_null());
    EXPECT_EQ(j["beaufort"]["number"].get<int>(), 4);
    EXPECT_EQ(j["beaufort"]["description"], "Small waves");
    // Predicted values of Tables 9.5/10.2 at 6 m/s.
    EXPECT_NEAR(j["predicted"]["rms_height"].get<double>(), 0.576, 1e-12);
    EXPECT_NEAR(j["predicted"]["rms_slope"].get<double>(), 0.03372, 1e-12);
    EXPECT_NEAR(j["predicted"]["correlation_length"].get<double>(), 24.157, 1e-3);
    for (const char* k : {"rms_height", "rms_slope", "correlation_length", "mss_upwind", "mss_crosswind"})
        EXPECT_TRUE(j["actual"][k].is_number()) << k;
    const littoral::TriMesh m = littoral::readPly(mesh);
    EXPECT_EQ(j["mesh"]["triangles"].get<size_t>(), m.numTriangles());
    EXPECT_EQ(j["mesh"]["vertices"].get<size_t>(), m.numVertices());
    EXPECT_LE(m.numTriangles(), 3000u);
    // OBJ output with normals.
    const fs::path obj = d / "sea.obj";
    ASSERT_EQ(run("waves --model sinusoid --amplitude 0.3 --wavelength 4 --size 20 --spacing 0.5 --triangles 0 --out " +
                  obj.string()).status, 0);
    std::ifstream in(obj);
    std::string line;
    int v = 0, vn = 0, f = 0;
    while (std::getline(in, line)) {
        if (line.rfind("v ", 0) == 0) ++v;
        if (line.rfind("vn ", 0) == 0) ++vn;
        if (line.rfind("f ", 0) == 0) ++f;
    }
    EXPECT_EQ(v, 41 * 41);
    EXPECT_EQ(vn, 41 * 41);
    EXPECT_EQ(f, 2 * 40 * 40);
    fs::remove_all(d);
}

// Each mistake: exit status 1, a message naming the option, and no output file.
TEST(WavesCli, BadInputExitsOneWithoutOutput) {
    ASSERT_TRUE(fs::exists(kBinary)) << "littoral binary not built: " << kBinary;
    const fs::path d = tempDir();
    const fs::path mesh = d / "bad.ply", stats = d / "bad.json";
    const std::string outs = " --out " + mesh.string() + " --stats " + stats.string();
    const struct {
        std::string args, needle;
    } cases[] = {
        {"waves --wind -3", "--wind"},
        {"waves --wind 500", "--wind"},
        {"waves --wind 6 --spacing 0", "--spacing"},
        {"waves --wind 6 --size 90000 --spacing 0.01", "GiB"},
        {"waves --wind 6 --size 100 --spacing 1 --triangles 50000", "--triangles"},
        {"waves --wind 6 --model jonswapp", "did you mean 'jonswap'"},
        {"waves --model beaufort", "--wind"},
        // The old direction option explains the change instead of being reinterpreted.
        {"waves --wind 6 --direction 30", "--wind-from"},
        {"waves --model sinusoid --direction 30", "--waves-from"},
        {"waves --wind 6 --wind-from 400", "0 to 360"},
        {"waves --model sinusoid --wind-from 10", "--waves-from"},
        {"waves --wind 6 --sea slick", "cox-munk only"},
        {"waves --model cox-munk --wind 20", "Cox-Munk range"},
        {"waves --model cox-munk --wind 6 --sea slik", "did you mean 'slick'"},
        {"waves --model elfouhaily --wind 0.01 --size 1 --spacing 0.5 --triangles 0", "below the smallest allowed"},
    };
    for (const auto& c : cases) {
        const CmdResult r = run(c.args + outs);
        EXPECT_EQ(r.status, 1) << c.args << "\n" << r.output;
        EXPECT_NE(r.output.find(c.needle), std::string::npos) << c.args << "\n" << r.output;
        EXPECT_FALSE(fs::exists(mesh)) << c.args;
        EXPECT_FALSE(fs::exists(stats)) << c.args;
    }
    const CmdResult r = run("waves --wind 6 --out " + (d / "x.stl").string());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("--out"), std::string::npos) << r.output;
    fs::remove_all(d);
}

// Without --triangles a grid smaller than the default target keeps its full grid (as in a scene
// file), instead of refusing a target nobody gave.
TEST(WavesCli, SmallGridWithoutTargetKeepsTheFullGrid) {
    ASSERT_TRUE(fs::exists(kBinary)) << "littoral binary not built: " << kBinary;
    const fs::path d = tempDir();
    const fs::path stats = d / "small.json";
    const CmdResult r = run("waves --wind 5 --size 10 --spacing 1 --stats " + stats.string());
    ASSERT_EQ(r.status, 0) << r.output;
    const auto j = nlohmann::json::parse(std::ifstream(stats));
    EXPECT_EQ(j["mesh"]["triangles"].get<long long>(), 200);
    // A target given is checked against the grid as before.
    const CmdResult t = run("waves --wind 5 --size 10 --spacing 1 --triangles 1000");
    EXPECT_EQ(t.status, 1);
    EXPECT_NE(t.output.find("--triangles: 1000 is not possible"), std::string::npos) << t.output;
    fs::remove_all(d);
}

// The cox-munk model from the command line: the full grid by default, Cox-Munk's slopes predicted,
// the compass wind recorded. At 2 m/s (clean sea) L_u = 0.40 m and L_c = 0.39 m on a 40 m square,
// so the realisation's slope variances scatter by about sqrt(3 pi L_u L_c / (4 A)) = 1.5 % about
// the target (docs/waves.md): 5 standard deviations, 7.5 %, is the tolerance.
TEST(WavesCli, CoxMunkModel) {
    ASSERT_TRUE(fs::exists(kBinary)) << "littoral binary not built: " << kBinary;
    const fs::path d = tempDir();
    const fs::path stats = d / "cm.json";
    const CmdResult r = run("waves --model cox-munk --wind 2 --wind-from 45 --size 40 --spacing 0.1 --stats " +
                            stats.string());
    ASSERT_EQ(r.status, 0) << r.output;
    const auto j = nlohmann::json::parse(std::ifstream(stats));
    EXPECT_EQ(j["model"], "cox-munk");
    EXPECT_NEAR(j["wind_from_deg"].get<double>(), 45.0, 1e-9);
    EXPECT_EQ(j["predicted"]["cox_munk"]["sea"], "clean");
    EXPECT_NEAR(j["predicted"]["mss_upwind"].get<double>(), 3.16e-3 * 2, 1e-15);
    EXPECT_NEAR(j["predicted"]["mss_crosswind"].get<double>(), 0.003 + 1.92e-3 * 2, 1e-15);
    EXPECT_EQ(j["mesh"]["triangles"].get<long long>(), 2LL * 400 * 400);  // the full grid
    EXPECT_NEAR(j["actual"]["mss_upwind"].get<double>() / (3.16e-3 * 2), 1.0, 0.075);
    EXPECT_NEAR(j["actual"]["mss_crosswind"].get<double>() / (0.003 + 1.92e-3 * 2), 1.0, 0.075);
    fs::remove_all(d);
}
