// `littoral check-mesh` exit codes and output, run as the user runs it.
#include <gtest/gtest.h>

#include "tests/support/test_support.h"

#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "scenegen/mesh_io.h"
#include "scenegen/primitives.h"
#include "scenegen/synthetic_site.h"

using namespace littoral;
using namespace littoral::scenegen;
namespace fs = std::filesystem;

namespace {

struct CliRun {
    int status = -1;
    std::string out, err;
};

std::string slurp(const fs::path& p) {
    std::ifstream f(p);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

CliRun run(const std::string& args, const fs::path& dir) {
    const fs::path exe = fs::path(LITTORAL_BINARY_DIR) / "bin" / "littoral";
    EXPECT_TRUE(fs::exists(exe)) << exe << " is missing: build the 'littoral' target before test_scenegen";
    const std::string cmd = exe.string() + " " + args + " > " + (dir / "out.txt").string() + " 2> " +
                            (dir / "err.txt").string();
    const int raw = std::system(cmd.c_str());
    CliRun r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    r.out = slurp(dir / "out.txt");
    r.err = slurp(dir / "err.txt");
    return r;
}


// Binary little-endian PLY with float vertices, written by hand so a NaN can be stored.
void writeFloatPly(const fs::path& p, const TriMesh& m) {
    std::ofstream f(p, std::ios::binary);
    f << "ply\nformat binary_little_endian 1.0\nelement vertex " << m.positions.size()
      << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << m.triangles.size()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
    for (const auto& v : m.positions)
        for (double c : {v.x, v.y, v.z}) {
            const float x = static_cast<float>(c);
            f.write(reinterpret_cast<const char*>(&x), 4);
        }
    for (const auto& t : m.triangles) {
        const unsigned char n = 3;
        f.write(reinterpret_cast<const char*>(&n), 1);
        for (uint32_t i : t) {
            const int32_t k = static_cast<int32_t>(i);
            f.write(reinterpret_cast<const char*>(&k), 4);
        }
    }
}

}  // namespace

TEST(CheckMeshCli, ExitCodesAndReasons) {
    const fs::path dir = testing_support::scratchDir("scenegen", "cli");
    const TriMesh box = makeBox(2, 3, 4);
    writeMeshFile(dir / "box.obj", box);

    CliRun ok = run("check-mesh " + (dir / "box.obj").string(), dir);
    EXPECT_EQ(ok.status, 0) << ok.err;
    EXPECT_NE(ok.out.find("valid closed volume"), std::string::npos) << ok.out;

    TriMesh holed = box;
    holed.triangles.erase(holed.triangles.begin());
    holed.faceMaterial.clear();
    writeMeshFile(dir / "holed.off", holed);
    CliRun h = run("check-mesh " + (dir / "holed.off").string(), dir);
    EXPECT_EQ(h.status, 1);
    EXPECT_NE(h.err.find("not closed: 3 boundary edges"), std::string::npos) << h.err;

    TriMesh nan = box;
    nan.positions[5].y = std::numeric_limits<double>::quiet_NaN();
    writeFloatPly(dir / "nan.ply", nan);
    CliRun n = run("check-mesh " + (dir / "nan.ply").string(), dir);
    EXPECT_EQ(n.status, 1);
    EXPECT_NE(n.err.find("NaN or infinite coordinates: vertex 5"), std::string::npos) << n.err;

    std::ofstream(dir / "empty.stl").close();
    CliRun e = run("check-mesh " + (dir / "empty.stl").string(), dir);
    EXPECT_EQ(e.status, 2);
    EXPECT_NE(e.err.find("file is empty"), std::string::npos) << e.err;

    CliRun missing = run("check-mesh " + (dir / "nope.obj").string(), dir);
    EXPECT_EQ(missing.status, 2);

    // A readable file with no faces is an invalid (empty) mesh, not an unreadable one.
    std::ofstream(dir / "points.obj") << "v 0 0 0\nv 1 0 0\n";
    CliRun pts = run("check-mesh " + (dir / "points.obj").string(), dir);
    EXPECT_EQ(pts.status, 1);
    EXPECT_NE(pts.err.find("mesh is empty"), std::string::npos) << pts.err;
}

TEST(CheckMeshCli, JsonReportAndRepair) {
    const fs::path dir = testing_support::scratchDir("scenegen", "cli_json");
    TriMesh inward = makeBox(2, 3, 4);
    for (auto& t : inward.triangles) std::swap(t[1], t[2]);
    writeMeshFile(dir / "inward.stl", inward);
    CliRun r = run("check-mesh --json --repair " + (dir / "fixed.ply").string() + " " + (dir / "inward.stl").string(), dir);
    EXPECT_EQ(r.status, 1) << r.err;  // the input is invalid; the repaired copy is written beside it
    const auto j = nlohmann::json::parse(r.out);
    for (const char* k : {"closed", "manifold", "self_intersections", "bounds_volume", "outward", "volume_m3",
                          "boundary_edges", "components"})
        EXPECT_TRUE(j.contains(k)) << k;
    EXPECT_EQ(j["closed"], true);
    EXPECT_EQ(j["outward"], false);
    EXPECT_NEAR(j["volume_m3"].get<double>(), -24.0, 1e-9);
    EXPECT_EQ(j["repair"]["faces_reversed_net"], 12);
    EXPECT_EQ(j["repair"]["valid_after"], true);
    CliRun fixed = run("check-mesh " + (dir / "fixed.ply").string(), dir);
    EXPECT_EQ(fixed.status, 0) << fixed.err;
}

TEST(BuildCli, BuildsTheSiteAndRefusesABrokenObject) {
    const fs::path dir = testing_support::scratchDir("scenegen", "cli_build");
    SiteOptions opt;
    opt.surfaceTriangles = 4000;
    const SiteSummary site = writeSyntheticSite(dir / "site", opt);
    CliRun ok = run("-q build " + site.sceneFile.string() + " --out " + (dir / "ir").string(), dir);
    EXPECT_EQ(ok.status, 0) << ok.err;
    EXPECT_TRUE(fs::exists(dir / "ir" / "scene.json"));
    const auto v = nlohmann::json::parse(slurp(dir / "ir" / "validity.json"));
    EXPECT_EQ(v["valid"], true);
    EXPECT_EQ(v["water"]["boundary_edges"], 0);

    // Replace the boat with an open hull: the build stops with exit 1, naming the object and why,
    // and writes no IR.
    TriMesh hull = makeBoat(5.0, 2.0, 0.8);
    hull.triangles.pop_back();
    hull.faceMaterial.pop_back();
    writeMeshFile(dir / "site" / "objects" / "boat.ply", hull);
    CliRun bad = run("-q build " + site.sceneFile.string() + " --out " + (dir / "ir_bad").string(), dir);
    EXPECT_EQ(bad.status, 1);
    EXPECT_NE(bad.err.find("object 'boat'"), std::string::npos) << bad.err;
    EXPECT_NE(bad.err.find("not closed: 3 boundary edges"), std::string::npos) << bad.err;
    EXPECT_NE(bad.err.find("scene.yaml:"), std::string::npos) << bad.err;  // the object's file:line:column
    EXPECT_FALSE(fs::exists(dir / "ir_bad" / "scene.json"));
}
