#pragma once
// Helpers shared by the test programs: scratch directories and running the `littoral` binary.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"

extern char** environ;

namespace littoral::testing_support {

// Ed at depth `depth` m under a flat surface of index n, from a sun of irradiance E (normal to the
// beam) at zenith `zenithDeg` alone: E cos(theta_s) (1 - R_F) exp(-c depth / cos(theta_w)), with
// Snell's theta_w (Eq. 4.1) and the unpolarised Fresnel reflectance R_F (Eq. 4.2); written out
// here, apart from the renderer's Fresnel code.
inline double refractedSunEd(double E, double zenithDeg, double n, double c, double depth) {
    const double ti = zenithDeg * M_PI / 180, tr = std::asin(std::sin(ti) / n);
    const double rf = 0.5 * (std::pow(std::sin(ti - tr) / std::sin(ti + tr), 2) +
                             std::pow(std::tan(ti - tr) / std::tan(ti + tr), 2));
    return E * std::cos(ti) * (1 - rf) * std::exp(-c * depth / std::cos(tr));
}

// A fresh, empty directory for one test: <build>/test_scratch/<group>/<name>.
inline std::filesystem::path scratchDir(const std::string& group, const std::string& name) {
    const std::filesystem::path d = std::filesystem::path(LITTORAL_BINARY_DIR) / "test_scratch" / group / name;
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}

// Writes `text` to `dir / name` (binary, exactly as given) and returns the path.
inline std::filesystem::path writeTextFile(const std::filesystem::path& dir, const std::string& name,
                                           const std::string& text) {
    std::filesystem::create_directories(dir);
    const std::filesystem::path p = dir / name;
    std::ofstream(p, std::ios::binary) << text;
    return p;
}

// The message of the InputError thrown by f, or "" if none was thrown.
template <class F> std::string inputErrorOf(F&& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

inline std::filesystem::path littoralBinary() { return std::filesystem::path(LITTORAL_BINARY_DIR) / "bin" / "littoral"; }

struct CommandResult {
    int status = -1;     // exit status, -1 if the command did not exit normally
    std::string output;  // stdout and stderr together
};

// Runs a shell command line and captures its exit status and output (stderr too).
inline CommandResult runShellCommand(const std::string& commandLine) {
    CommandResult r;
    const std::string cmd = commandLine + " 2>&1";
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return r;
    char buf[4096];
    while (size_t n = fread(buf, 1, sizeof buf, p)) r.output.append(buf, n);
    const int st = pclose(p);
    r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    return r;
}

// Runs `littoral ARGS` and captures its exit status and output.
inline CommandResult runLittoral(const std::string& args) { return runShellCommand(littoralBinary().string() + " " + args); }

// Runs ARGV (argv[0] a path) as a child process (no shell, output discarded) so that the test can
// signal it; -1 if it cannot be started.
inline pid_t spawnProcess(std::vector<std::string> argv) {
    std::vector<char*> cargv;
    for (auto& a : argv) cargv.push_back(a.data());
    cargv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
    pid_t pid = -1;
    const int rc = posix_spawn(&pid, cargv[0], &fa, nullptr, cargv.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    return rc == 0 ? pid : -1;
}

// Runs `littoral ARGS` as a child process (spawnProcess).
inline pid_t spawnLittoral(const std::vector<std::string>& args) {
    std::vector<std::string> argv{littoralBinary().string()};
    argv.insert(argv.end(), args.begin(), args.end());
    return spawnProcess(std::move(argv));
}

// The fenced code blocks of language `lang` ("yaml" for ```yaml) of a Markdown file, in order.
inline std::vector<std::string> markdownBlocks(const std::filesystem::path& md, const std::string& lang) {
    std::ifstream in(md);
    std::vector<std::string> blocks;
    std::string line, cur;
    bool inside = false;
    while (std::getline(in, line)) {
        if (!inside && line.rfind("```" + lang, 0) == 0 && line.size() == 3 + lang.size()) {
            inside = true;
            cur.clear();
        } else if (inside && line.rfind("```", 0) == 0) {
            inside = false;
            blocks.push_back(cur);
        } else if (inside) {
            cur += line + "\n";
        }
    }
    return blocks;
}

// The width and height a PNG file's IHDR gives, or {0, 0} if `path` is not a PNG.
inline std::pair<uint32_t, uint32_t> pngSize(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    unsigned char h[24] = {};
    if (!in.read(reinterpret_cast<char*>(h), sizeof h)) return {0, 0};
    const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (!std::equal(sig, sig + 8, h) || std::string(reinterpret_cast<char*>(h + 12), 4) != "IHDR") return {0, 0};
    auto be = [&](int o) { return uint32_t(h[o]) << 24 | uint32_t(h[o + 1]) << 16 | uint32_t(h[o + 2]) << 8 | h[o + 3]; };
    return {be(16), be(20)};
}

// The id a truth legend (NAME_legend.csv: id,material,...) gives the material `name`; -2 if absent.
inline int legendId(const std::filesystem::path& legend, const std::string& name) {
    std::ifstream in(legend);
    std::string line;
    while (std::getline(in, line)) {
        std::stringstream ls(line);
        std::string id, n;
        std::getline(ls, id, ',');
        std::getline(ls, n, ',');
        if (n == name) return std::stoi(id);
    }
    return -2;
}

// The median (upper of the middle two) of a sample; 0 for an empty one.
inline double medianOf(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

// `text` with the first occurrence of `from` replaced by `to` (a failed expectation if absent).
// For gtest tests only (uses EXPECT_*; include <gtest/gtest.h> first).
#ifdef GTEST_API_
inline std::string replacedOnce(std::string text, const std::string& from, const std::string& to) {
    const auto pos = text.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    if (pos != std::string::npos) text.replace(pos, from.size(), to);
    return text;
}

// A unit cube as OBJ, its base centred on the origin (z from 0 to 1), outward faces.
inline constexpr const char* kUnitCubeObj = R"(v -0.5 -0.5 0
v 0.5 -0.5 0
v 0.5 0.5 0
v -0.5 0.5 0
v -0.5 -0.5 1
v 0.5 -0.5 1
v 0.5 0.5 1
v -0.5 0.5 1
f 1 4 3
f 1 3 2
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 2 3 7
f 2 7 6
f 3 4 8
f 3 8 7
f 4 1 5
f 4 5 8
)";

// A small valid scene: flat water over a planar seabed, one nadir frame sensor, one probe.
// Used by the hostile-input and check-scene coverage tests: line 6 is the material, line 8 the
// sensor, line 10 the probe.
inline constexpr const char* kSmallScene = R"(scene: {name: hostile, domain: {x: [-5, 5], y: [-5, 5]}}
sun: {zenith_deg: 30, irradiance: 1000}
sky: {radiance: 0}
water: {optics: {preset: coastal}}
bathymetry: {type: planar_slope, z0_m: -2, material: floor}
materials: [{name: floor, reflectance: 0.2}]
sensors:
  - {name: nadir, type: frame, elevation_deg: 90, azimuth_deg: 0, range_m: 50, gsd_m: 0.5, width: 16, height: 12}
probes:
  - {name: p, position: [0, 0, -1], quantities: [Ed]}
render: {probe_samples: 64, hemisphere_samples: 4}
)";

// Writes scene file `text` as <group>/<name>/<name>.yaml and checks that `check-scene`, `build` and
// `run` all refuse it: exit 1, one error located at `where` ("file:line:column" suffix, e.g.
// ":12:37") whose text contains `message`, and no output folder left behind.
inline void expectSceneRefused(const std::string& group, const std::string& name, const std::string& text,
                               const std::string& where, const std::string& message) {
    const std::filesystem::path dir = scratchDir(group, name);
    const std::filesystem::path scene = writeTextFile(dir, name + ".yaml", text);
    for (const std::string& cmd : {std::string("check-scene"), std::string("build"), std::string("run")}) {
        const std::filesystem::path out = dir / ("out-" + cmd);
        const std::string args = cmd == "check-scene" ? scene.string() : scene.string() + " --out " + out.string();
        const CommandResult r = runLittoral("--quiet " + cmd + " " + args);
        EXPECT_EQ(r.status, 1) << name << " " << cmd << ": " << r.output;
        EXPECT_NE(r.output.find(scene.filename().string() + where + ": error: "), std::string::npos)
            << name << " " << cmd << ": " << r.output;
        EXPECT_NE(r.output.find(message), std::string::npos) << name << " " << cmd << ": " << r.output;
        EXPECT_FALSE(std::filesystem::exists(out)) << name << " " << cmd << ": output left behind";
    }
}
#endif

}  // namespace littoral::testing_support
