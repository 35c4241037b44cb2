// Hostile but realistic input, as a user would give it to `littoral` (issue 11). One test per
// class of bad input; each asserts the exit status, the location and cause in the message, and
// that the output folder holds nothing new (or the complete set). docs/reliability.md lists
// every class with the test that covers it.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "bathymetry/geo_frame.h"
#include "core/atomic_file.h"
#include "core/scene_ir.h"
#include "scenegen/mesh_io.h"
#include "scenegen/primitives.h"
#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using littoral::testing_support::CommandResult;
using littoral::testing_support::runLittoral;
using littoral::testing_support::spawnLittoral;
using littoral::testing_support::scratchDir;
using littoral::testing_support::writeTextFile;

namespace {

std::string quotedArg(const fs::path& p) { return "'" + p.string() + "'"; }

// Every file and folder under `dir`, relative to it ("" if `dir` does not exist).
std::set<std::string> listing(const fs::path& dir) {
    std::set<std::string> s;
    std::error_code ec;
    if (!fs::exists(dir, ec)) return s;
    for (auto it = fs::recursive_directory_iterator(dir, ec); it != fs::recursive_directory_iterator(); ++it)
        s.insert(fs::relative(it->path(), dir).string());
    return s;
}

std::string join(const std::set<std::string>& s) {
    std::string r;
    for (const auto& x : s) r += x + " ";
    return r;
}

// The output folder must not exist or be empty: nothing partial, nothing at all.
void expectNothingWritten(const fs::path& out, const std::string& what) {
    EXPECT_TRUE(listing(out).empty()) << what << ": left behind: " << join(listing(out));
}

bool contains(const std::string& haystack, const std::string& needle) { return haystack.find(needle) != std::string::npos; }

// The small valid scene of tests/support/test_support.h (line 8 is the sensor, 10 the probe).
const char* const kScene = littoral::testing_support::kSmallScene;

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
}

int waitStatus(pid_t pid) {
    int st = 0;
    waitpid(pid, &st, 0);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

class Hostile : public testing::Test {
protected:
    void SetUp() override {
        ASSERT_TRUE(fs::exists(littoral::testing_support::littoralBinary())) << "build the littoral target first";
        dir_ = scratchDir("hostile", testing::UnitTest::GetInstance()->current_test_info()->name());
        out_ = dir_ / "out";
    }
    // Writes `text` as dir/scene.yaml and runs `littoral COMMAND scene.yaml [--out out]`.
    CommandResult runScene(const std::string& command, const std::string& text, bool withOut = true) {
        writeTextFile(dir_, "scene.yaml", text);
        return runLittoral("-q " + command + " " + quotedArg(dir_ / "scene.yaml") + (withOut ? " --out " + quotedArg(out_) : ""));
    }
    // Builds kScene into dir/ir and replaces `from` by `to` in its scene.json (a hand edit).
    void editBuiltIr(const std::string& from, const std::string& to) {
        ASSERT_EQ(runLittoral("-q build " + quotedArg(writeTextFile(dir_, "scene.yaml", kScene)) + " --out " + quotedArg(dir_ / "ir")).status,
                  0);
        std::string json;
        {
            std::ifstream f(dir_ / "ir" / "scene.json");
            json.assign(std::istreambuf_iterator<char>(f), {});
        }
        std::ofstream(dir_ / "ir" / "scene.json") << replaced(json, from, to);
    }
    fs::path dir_, out_;
};

}  // namespace

// ---- 1. Names that become file names ---------------------------------------------------------

TEST_F(Hostile, TraversalAbsoluteNulAndCollidingNamesAreLocatedErrors) {
    const struct {
        std::string name, where, cause;
    } cases[] = {
        {"\"../../x\"", "scene.yaml:8:12: error: sensors[0].name:", "contains a path separator"},
        {"\"/tmp/abs\"", "scene.yaml:8:12: error: sensors[0].name:", "contains a path separator"},
        {"\"a\\0b\"", "scene.yaml:8:12: error: sensors[0].name:", "contains a NUL byte"},
        {"\"a\\tb\"", "scene.yaml:8:12: error: sensors[0].name:", "control character \\x09"},
        {"..", "scene.yaml:8:12: error: sensors[0].name:", "relative folder reference"},
        {"-rf", "scene.yaml:8:12: error: sensors[0].name:", "must not start with '-'"},
    };
    for (const auto& c : cases) {
        const CommandResult r = runScene("run", replaced(kScene, "name: nadir", "name: " + c.name));
        EXPECT_EQ(r.status, 1) << c.name << "\n" << r.output;
        EXPECT_TRUE(contains(r.output, c.where)) << r.output;
        EXPECT_TRUE(contains(r.output, c.cause)) << r.output;
        expectNothingWritten(out_, c.name);
        EXPECT_FALSE(fs::exists(dir_.parent_path().parent_path() / "x.exr"));
    }
    // "cam" writes cam_truth.exr, so a second sensor named cam_truth would overwrite it.
    std::string two = replaced(kScene, "name: nadir", "name: cam");
    two = replaced(two, "probes:", "  - {name: cam_truth, type: frame, elevation_deg: 90, azimuth_deg: 0, range_m: 50, "
                                   "gsd_m: 0.5, width: 8, height: 8}\nprobes:");
    const CommandResult r = runScene("run", two);
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "scene.yaml:9:12: error: sensors[1].name: sensors 'cam' (line 8) and 'cam_truth' "
                                   "would both write cam_truth.exr"))
        << r.output;
    expectNothingWritten(out_, "cam / cam_truth");
    // check-scene says the same (it used to call all of these valid).
    EXPECT_EQ(runScene("check-scene", two, false).status, 1);
}

TEST_F(Hostile, RenderRefusesBadNamesInAnIR) {
    editBuiltIr("\"name\": \"nadir\"", "\"name\": \"../../evil\"");
    const CommandResult r = runLittoral("-q render " + quotedArg(dir_ / "ir") + " --out " + quotedArg(out_));
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "scene.json: error: sensors[0].name: sensor name '../../evil' contains a path "
                                   "separator"))
        << r.output;
    expectNothingWritten(out_, "render");
    EXPECT_FALSE(fs::exists(dir_.parent_path() / "evil.exr"));
}

// ---- 2. Special files at output targets --------------------------------------------------------

TEST_F(Hostile, SpecialFilesAtOutputTargetsAreRefusedAndKept) {
    // Devices: `--stats /dev/null` or `/dev/full` must not turn the device into a regular file when
    // run as root. Tested on copies of those devices made in the scratch folder (mknod, root only),
    // so that a regression cannot damage the machine's own /dev.
    struct stat st;
    for (const auto& [name, minor] : {std::pair<const char*, int>{"null", 3}, {"full", 7}}) {
        const fs::path dev = dir_ / name;
        if (::mknod(dev.c_str(), S_IFCHR | 0666, makedev(1, minor)) != 0) {
            std::printf("mknod not permitted (not root): device case skipped, FIFO and symlink cases below\n");
            break;
        }
        const CommandResult r = runLittoral("-q waves --wind 6 --size 20 --spacing 0.5 --stats " + quotedArg(dev));
        EXPECT_EQ(r.status, 1) << r.output;
        EXPECT_TRUE(contains(r.output, dev.string() + ": error: --stats: refusing to write output: a character device "
                                                      "is in the way"))
            << r.output;
        ASSERT_EQ(::stat(dev.c_str(), &st), 0);
        EXPECT_TRUE(S_ISCHR(st.st_mode));
    }

    // A symlink, a FIFO and a folder where render would put its files.
    fs::create_directories(out_);
    writeTextFile(dir_, "precious.txt", "keep me");
    fs::create_symlink(dir_ / "precious.txt", out_ / "nadir.png");
    ASSERT_EQ(::mkfifo((out_ / "nadir.exr").c_str(), 0644), 0);
    fs::create_directories(out_ / "nadir_truth.exr");
    const auto before = listing(out_);
    const auto t0 = std::chrono::steady_clock::now();
    const CommandResult r = runScene("run", kScene);
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(60)) << "a FIFO target must not block";
    EXPECT_TRUE(contains(r.output, "nadir.exr: error: refusing to write output: a FIFO (named pipe) is in the way"))
        << r.output;
    // The IR was published before rendering (it is a complete set of its own); nothing else is new.
    std::set<std::string> after = listing(out_);
    for (auto it = after.begin(); it != after.end();) it = it->rfind("ir", 0) == 0 ? after.erase(it) : std::next(it);
    EXPECT_EQ(after, before) << join(after);
    EXPECT_TRUE(fs::is_symlink(out_ / "nadir.png"));
    ASSERT_EQ(::stat((out_ / "nadir.exr").c_str(), &st), 0);
    EXPECT_TRUE(S_ISFIFO(st.st_mode));
    std::ifstream keep(dir_ / "precious.txt");
    std::string text;
    std::getline(keep, text);
    EXPECT_EQ(text, "keep me");
}

// ---- 3. Full disk -------------------------------------------------------------------------------

// The outputs go to a 64 KiB tmpfs in a private mount namespace (unshare -m as root, unshare -rm
// otherwise); where mounting is not allowed, RLIMIT_FSIZE makes the same writes fail (EFBIG
// instead of ENOSPC, the same checked-write path).
TEST_F(Hostile, FullDiskIsAnErrorAndLeavesNothing) {
    // 200 x 150 px x 3 bands: the ENVI data alone (360 KB) exceeds the 64 KiB disk.
    std::string scene = replaced(kScene, "width: 16, height: 12", "width: 200, height: 150");
    scene = replaced(scene, "render: {", "render: {bands: [[0.4, 0.5], [0.5, 0.6], [0.6, 0.7]], ");
    ASSERT_EQ(runLittoral("-q build " + quotedArg(writeTextFile(dir_, "scene.yaml", scene)) + " --out " + quotedArg(dir_ / "ir")).status, 0);
    fs::create_directories(out_);
    const std::string render = littoral::testing_support::littoralBinary().string() + " -q render " + quotedArg(dir_ / "ir") +
                               " --out " + quotedArg(out_);
    const std::string inner = "mount -t tmpfs -o size=64k tmpfs " + quotedArg(out_) + " && { " + render +
                              "; rc=\\$?; echo LISTING; ls -A " + quotedArg(out_) + "; exit \\$rc; }";
    std::string mode;
    CommandResult r;
    for (const char* unshare : {"unshare -m", "unshare -rm"}) {
        const std::string cmd = std::string(unshare) + " sh -c \"" + inner + "\" 2>&1";
        FILE* p = popen(cmd.c_str(), "r");
        ASSERT_TRUE(p);
        r.output.clear();
        char buf[4096];
        while (size_t n = fread(buf, 1, sizeof buf, p)) r.output.append(buf, n);
        const int st = pclose(p);
        r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
        if (contains(r.output, "LISTING")) {
            mode = "tmpfs";
            break;
        }
    }
    if (mode.empty()) {
        mode = "RLIMIT_FSIZE";
        const std::string cmd = "sh -c \"trap '' XFSZ; prlimit --fsize=65536 " + render + "\" 2>&1";
        FILE* p = popen(cmd.c_str(), "r");
        ASSERT_TRUE(p);
        r.output.clear();
        char buf[4096];
        while (size_t n = fread(buf, 1, sizeof buf, p)) r.output.append(buf, n);
        const int st = pclose(p);
        r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    }
    std::printf("full disk simulated with %s\n", mode.c_str());
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "cannot write output") &&
                (contains(r.output, "No space left on device") || contains(r.output, "File too large")))
        << r.output;
    if (mode == "tmpfs") {
        const std::string after = r.output.substr(r.output.find("LISTING") + 8);
        EXPECT_EQ(after.find_first_not_of(" \n"), std::string::npos) << "left on the full disk: " << after;
    } else {
        expectNothingWritten(out_, "RLIMIT_FSIZE");
    }
}

// ---- 4. Lying headers ---------------------------------------------------------------------------

TEST_F(Hostile, LyingHeadersAreRefusedBeforeAllocating) {
    // 60 bytes that claim four billion vertices (96 GB of float data).
    writeTextFile(dir_, "lie.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
                                   "property float y\nproperty float z\nend_header\n");
    const auto t0 = std::chrono::steady_clock::now();
    CommandResult r = runLittoral("check-mesh " + quotedArg(dir_ / "lie.ply"));
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(20));
    EXPECT_EQ(r.status, 2) << r.output;  // unreadable
    EXPECT_TRUE(contains(r.output, "lie.ply: PLY header declares 4000000000 vertex elements, needing at least "
                                   "48000000000 bytes of binary data, but the file holds only 0 bytes"))
        << r.output;
    writeTextFile(dir_, "abc.ply", "ply\nformat ascii 1.0\nelement vertex abc\nend_header\n");
    r = runLittoral("check-mesh " + quotedArg(dir_ / "abc.ply"));
    EXPECT_EQ(r.status, 2);
    EXPECT_TRUE(contains(r.output, "abc.ply:3:1: PLY header: expected 'element <name> <count>'")) << r.output;
    // The same mesh as a scene object: exit 1, located at the object's entry.
    std::string scene = replaced(kScene, "probes:", "probes:");
    scene += "objects:\n  - {name: liar, mesh: lie.ply, materials: floor, position_m: [0, 0], draft_m: 0.5}\n";
    r = runScene("build", scene);
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "scene.yaml:13:5: error: object 'liar': cannot read mesh")) << r.output;
    expectNothingWritten(out_, "lying object");
    // A binary STL whose count disagrees with its size, and an ASCII grid header asking for 10^12
    // samples (8 TB) in a 100-byte file.
    std::string stl(84, '\0');
    stl[80] = 12;
    writeTextFile(dir_, "short.stl", stl);
    r = runLittoral("check-mesh " + quotedArg(dir_ / "short.stl"));
    EXPECT_EQ(r.status, 2);
    EXPECT_TRUE(contains(r.output, "binary STL header declares 12 triangles, which take 684 bytes, but the file has 84"))
        << r.output;
    writeTextFile(dir_, "huge.asc", "ncols 1000000\nnrows 1000000\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n");
    scene = replaced(kScene, "bathymetry: {type: planar_slope, z0_m: -2, material: floor}",
                     "bathymetry: {type: raster, file: huge.asc, material: floor}");
    r = runScene("check-scene", scene, false);
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "huge.asc:2: error: an elevation grid of 1000000 x 1000000 samples would need 7.28 "
                                   "TiB of memory, more than the memory budget"))
        << r.output;
}

// ---- 5. Alias amplification ----------------------------------------------------------------------

TEST_F(Hostile, AliasAmplificationIsCapped) {
    // Ten nested levels of ten aliases each: 10^10 nodes when expanded, 1 KB on disk.
    std::string bomb = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n";
    for (int i = 1; i < 10; ++i) {
        bomb += "a" + std::to_string(i) + ": &a" + std::to_string(i) + " [";
        for (int k = 0; k < 10; ++k) bomb += (k ? ", *a" : "*a") + std::to_string(i - 1);
        bomb += "]\n";
    }
    const auto t0 = std::chrono::steady_clock::now();
    const CommandResult r = runScene("run", bomb);
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(20));
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "scene.yaml:6:") && contains(r.output, "the document expands to more than 1000000 "
                                                                          "nodes"))
        << r.output;
    expectNothingWritten(out_, "bomb");
    // An alias to the node that contains it would make every walk of the tree endless.
    const CommandResult loop = runScene("check-scene", "scene: &s {name: *s}\n", false);
    EXPECT_EQ(loop.status, 1);
    EXPECT_TRUE(contains(loop.output, "scene.yaml:1:18: error: this alias refers to a node that contains it"))
        << loop.output;
}

// ---- 6. Signals while writing ---------------------------------------------------------------------

// A render whose writing takes long enough to be caught: 1000 x 1000 px, 12 bands (48 MB film).
TEST_F(Hostile, SignalWhileWritingRemovesPartialOutputs) {
    std::string big = kScene;
    big = replaced(big, "gsd_m: 0.5, width: 16, height: 12", "gsd_m: 0.01, width: 1000, height: 1000");
    big = replaced(big, "render: {probe_samples: 64, hemisphere_samples: 4}",
                   "render: {probe_samples: 64, hemisphere_samples: 1, bands: {range_um: [0.4, 0.7], count: 12}}");
    big = replaced(big, "water: {optics: {preset: coastal}}\n", "");
    big = replaced(big, "probes:\n  - {name: p, position: [0, 0, -1], quantities: [Ed]}\n", "");
    big = replaced(big, "z0_m: -2", "z0_m: 0");
    ASSERT_EQ(runLittoral("-q build " + quotedArg(writeTextFile(dir_, "scene.yaml", big)) + " --out " + quotedArg(dir_ / "ir")).status, 0);
    for (const int sig : {SIGTERM, SIGINT}) {
        fs::remove_all(out_);
        const pid_t pid = spawnLittoral({"-q", "render", (dir_ / "ir").string(), "--out", out_.string()});
        ASSERT_GT(pid, 0);
        // Wait until the first finished temporary appears, then signal.
        bool seen = false;
        for (int i = 0; i < 6000 && !seen; ++i) {
            for (const auto& f : listing(out_)) seen = seen || contains(f, ".tmp-");
            if (!seen) std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        EXPECT_TRUE(seen) << "no temporary output appeared within 60 s";
        ::kill(pid, sig);
        const int status = waitStatus(pid);
        EXPECT_EQ(status, 128 + sig) << "signal " << sig;
        expectNothingWritten(out_, sig == SIGTERM ? "SIGTERM" : "SIGINT");
    }
}

// ---- 7. Non-UTF-8 text ----------------------------------------------------------------------------

TEST_F(Hostile, NonUtf8TextIsALocatedInputError) {
    const CommandResult r = runScene("run", replaced(kScene, "name: hostile", "name: \"hos\xfftile\""));
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "scene.yaml:1:19: error: the file is not UTF-8 text: byte 0xff")) << r.output;
    expectNothingWritten(out_, "non-UTF-8");
    // Valid UTF-8, but not a portable file name: refused where it is written.
    const CommandResult u = runScene("run", replaced(kScene, "name: nadir", "name: caméra"));
    EXPECT_EQ(u.status, 1) << u.output;
    EXPECT_TRUE(contains(u.output, "scene.yaml:8:12: error: sensors[0].name: sensor name 'cam\\xc3\\xa9ra' contains "
                                   "the non-ASCII byte \\xc3"))
        << u.output;
}

// ---- 8. Unwritable outputs -------------------------------------------------------------------------

TEST_F(Hostile, UnwritableOutputsExitOneBeforeAnyWork) {
    writeTextFile(dir_, "afile", "x");
    for (const fs::path& bad : {dir_ / "afile", dir_ / "afile" / "sub"}) {
        out_ = bad;
        const CommandResult r = runScene("run", kScene);
        EXPECT_EQ(r.status, 1) << r.output;
        EXPECT_TRUE(contains(r.output, "cannot create output folder") && contains(r.output, "exists and is not a folder"))
            << r.output;
    }
    ASSERT_EQ(runLittoral("-q build " + quotedArg(writeTextFile(dir_, "scene.yaml", kScene)) + " --out " + quotedArg(dir_ / "ir")).status, 0);
    const CommandResult r = runLittoral("-q render " + quotedArg(dir_ / "ir") + " --out " + quotedArg(dir_ / "afile"));
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "afile: error: --out: cannot create output folder")) << r.output;
    // A read-only folder: a read-only tmpfs in a private mount namespace (root ignores permission
    // bits), or a folder without write permission where that is not possible (not root).
    fs::create_directories(dir_ / "ro");
    const std::string render = littoral::testing_support::littoralBinary().string() + " -q render " + quotedArg(dir_ / "ir") +
                               " --out " + quotedArg(dir_ / "ro" / "out");
    std::string ro;
    for (const char* unshare : {"unshare -m", "unshare -rm"}) {
        const std::string cmd = std::string(unshare) + " sh -c \"mount -t tmpfs -o ro tmpfs " + quotedArg(dir_ / "ro") +
                                " && " + render + "\" 2>&1; echo \"rc=$?\"";
        FILE* p = popen(cmd.c_str(), "r");
        ASSERT_TRUE(p);
        ro.clear();
        char buf[4096];
        while (size_t n = fread(buf, 1, sizeof buf, p)) ro.append(buf, n);
        pclose(p);
        if (contains(ro, "Read-only file system")) break;
    }
    if (!contains(ro, "Read-only file system") && ::geteuid() != 0) {
        fs::permissions(dir_ / "ro", fs::perms::owner_read | fs::perms::owner_exec);
        const CommandResult p = runLittoral("-q render " + quotedArg(dir_ / "ir") + " --out " + quotedArg(dir_ / "ro" / "out"));
        ro = p.output + "rc=" + std::to_string(p.status);
        fs::permissions(dir_ / "ro", fs::perms::owner_all);
    }
    EXPECT_TRUE(contains(ro, "rc=1")) << ro;
    EXPECT_TRUE(contains(ro, "--out: output folder") &&
                (contains(ro, "Read-only file system") || contains(ro, "Permission denied")))
        << ro;
    EXPECT_TRUE(listing(dir_ / "ro").empty());
    const CommandResult w = runLittoral("-q waves --wind 6 --size 20 --spacing 0.5 --out /nonexistent-dir/sea.ply");
    EXPECT_EQ(w.status, 1);
    EXPECT_TRUE(contains(w.output, "--out: the folder '/nonexistent-dir' does not exist")) << w.output;
    // The mesh would be overwritten by the statistics.
    const CommandResult same = runLittoral("-q waves --wind 6 --size 20 --spacing 0.5 --out " + quotedArg(dir_ / "s.ply") +
                                           " --stats " + quotedArg(dir_ / "s.ply"));
    EXPECT_EQ(same.status, 1);
    EXPECT_TRUE(contains(same.output, "is the same file as --out")) << same.output;
    EXPECT_FALSE(fs::exists(dir_ / "s.ply"));
}

// ---- 9. Duplicate keys and documents ---------------------------------------------------------------

TEST_F(Hostile, DuplicateKeysAndDocumentsAreErrors) {
    CommandResult r = runScene("run", std::string(kScene) + "scene: {name: again}\n");
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "scene.yaml:12:1: error: duplicate key 'scene' (first given at line 1, column 1)"))
        << r.output;
    expectNothingWritten(out_, "duplicate section");
    r = runScene("check-scene", replaced(kScene, "width: 16,", "width: 16, width: 17,"), false);
    EXPECT_EQ(r.status, 1);
    EXPECT_TRUE(contains(r.output, "scene.yaml:8:103: error: duplicate key 'width' (first given at line 8, column 92)")) << r.output;
    r = runScene("run", std::string(kScene) + "---\nscene: {name: second}\n");
    EXPECT_EQ(r.status, 1);
    EXPECT_TRUE(contains(r.output, "scene.yaml:12:1: error: a second YAML document starts here")) << r.output;
    expectNothingWritten(out_, "second document");
    r = runLittoral("-q demo --seed -1 --out " + quotedArg(out_));
    EXPECT_EQ(r.status, 1);
    EXPECT_TRUE(contains(r.output, "--seed: Value -1 not in range")) << r.output;
    expectNothingWritten(out_, "--seed -1");
}

// ---- Resource limits ---------------------------------------------------------------------------------

TEST_F(Hostile, MemoryBudgetRefusalsNameTheSettingAndTheMemory) {
    CommandResult r = runLittoral("-q --max-memory 64M check-scene " +
                                  quotedArg(writeTextFile(dir_, "scene.yaml", replaced(kScene, "width: 16, height: 12",
                                                                               "width: 20000, height: 20000"))));
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "scene.yaml:8:5: error: sensors[0]: sensor 'nadir' (20000 x 20000 px x 1 bands) "
                                   "would need 14.9 GiB of memory, more than the memory budget of 64 MiB "
                                   "(--max-memory)"))
        << r.output;
    r = runScene("run", replaced(replaced(kScene, "reflectance: 0.2}", "reflectance: 0.2, solver: surface-pm}"), "render: {",
                                 "render: {photons: {surface: 10000000000}, "));
    EXPECT_EQ(r.status, 1) << r.output;
    // One band: a surface record is 12 + 4 + 4 + 2 = 22 B, 23.4 B with the pass's 1/16 reserve, plus
    // 8 B of grid and 20 B of build buffers = 51.4 B; 10^10 of them are 5.14e11 B = 478.7 GiB, and
    // the default 10^6 volume photons of the scattering (coastal) water add 47 MB: 479 GiB.
    EXPECT_TRUE(contains(r.output, "scene.yaml:11:29: error: render.photons.surface: 10000000000 surface and 1000000 "
                                   "volume photons need 479 GiB (51 and 47 bytes each with the search grid and its build "
                                   "buffers), more than the memory budget of"))
        << r.output;
    expectNothingWritten(out_, "photons");
    // A hand-edited IR asking for a 100000^2 sensor.
    ASSERT_EQ(runLittoral("-q build " + quotedArg(writeTextFile(dir_, "scene.yaml", kScene)) + " --out " + quotedArg(dir_ / "ir")).status, 0);
    std::string json;
    {
        std::ifstream f(dir_ / "ir" / "scene.json");
        json.assign(std::istreambuf_iterator<char>(f), {});
    }
    json = replaced(json, "\"width\": 16", "\"width\": 100000");
    std::ofstream(dir_ / "ir" / "scene.json") << replaced(json, "\"height\": 12", "\"height\": 100000");
    r = runLittoral("-q --max-memory 8G render " + quotedArg(dir_ / "ir") + " --out " + quotedArg(out_));
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "scene.json: error: rendering sensor 'nadir' (100000 x 100000 px x 1 bands) would "
                                   "need 373 GiB of memory, more than the memory budget of 8 GiB (--max-memory)"))
        << r.output;
    expectNothingWritten(out_, "IR sensor");
    r = runLittoral("--max-memory lots check-scene " + quotedArg(dir_ / "scene.yaml"));
    EXPECT_EQ(r.status, 1);
    EXPECT_TRUE(contains(r.output, "--max-memory: 'lots' is not a memory size")) << r.output;
}

TEST_F(Hostile, NonRegularInputsAreRefused) {
    const auto t0 = std::chrono::steady_clock::now();
    CommandResult r = runLittoral("check-scene /dev/zero");
    EXPECT_EQ(r.status, 1);
    EXPECT_TRUE(contains(r.output, "/dev/zero: error: is a character device, not a regular file")) << r.output;
    ASSERT_EQ(::mkfifo((dir_ / "fifo.yaml").c_str(), 0644), 0);
    r = runLittoral("check-scene " + quotedArg(dir_ / "fifo.yaml"));
    EXPECT_EQ(r.status, 1);
    EXPECT_TRUE(contains(r.output, "fifo.yaml: error: is a FIFO (named pipe), not a regular file")) << r.output;
    r = runLittoral("check-scene " + quotedArg(dir_));
    EXPECT_EQ(r.status, 1);
    EXPECT_TRUE(contains(r.output, "error: is a folder, not a scene file")) << r.output;
    ASSERT_EQ(::mkfifo((dir_ / "fifo.ply").c_str(), 0644), 0);
    r = runLittoral("check-mesh " + quotedArg(dir_ / "fifo.ply"));
    EXPECT_EQ(r.status, 2);
    EXPECT_TRUE(contains(r.output, "fifo.ply: is a FIFO (named pipe), not a regular file")) << r.output;
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(30)) << "nothing may block on a FIFO";
}

// ---- Scene errors that need the geometry: located, and found by check-scene --------------------------

TEST_F(Hostile, GeometricSceneErrorsAreLocated) {
    littoral::scenegen::writeMeshFile(dir_ / "box.obj", littoral::scenegen::makeBox(1, 1, 1, -0.5));
    const std::string obj = "objects:\n  - {name: a, mesh: box.obj, materials: floor, position_m: [0, 0], z_m: -1}\n";
    const struct {
        std::string scene, where, cause;
    } cases[] = {
        {std::string(kScene) + replaced(obj, "[0, 0]", "[40, 0]"), "scene.yaml:13:5: error:",
         "object 'a' spans [39.5, 40.5] x [-0.5, 0.5] m in plan, which lies outside the scene domain"},
        {std::string(kScene) + replaced(obj, "[0, 0]", "[4.8, 0]"), "scene.yaml:13:5: error:", "crosses the edge of"},
        {std::string(kScene) + obj + "  - {name: b, mesh: box.obj, materials: floor, position_m: [0.5, 0], z_m: -1}\n",
         "scene.yaml:14:5: error:", "object 'b' intersects or contains object 'a' (line 13)"},
        {replaced(std::string(kScene) + obj, "probes:",
                  "  - {name: inside, type: pinhole, position: [0, 0, -1], direction: [1, 0, 0], focal_length_mm: 5, "
                  "pixel_pitch_um: 10, width: 4, height: 4}\nprobes:"),
         "scene.yaml:9:5: error:", "sensor 'inside' sits at (0, 0, -1), inside object 'a'"},
        {replaced(kScene, "probes:", "  - {name: sky, type: pinhole, position: [0, 0, 20], direction: [0, 0, 1], "
                                     "focal_length_mm: 5, pixel_pitch_um: 10, width: 4, height: 4}\nprobes:"),
         "scene.yaml:9:5: error:", "sensor 'sky' at (0, 0, 20) looking along (0, 0, 1) sees nothing of the scene"},
        {replaced(kScene, "position: [0, 0, -1]", "position: [0, 0, -3]"), "scene.yaml:10:5: error:",
         "probe 'p' at (0, 0, -3) is 1 m under the seabed"},
        {replaced(kScene, "water: {optics: {preset: coastal}}", "water: {surface: {model: flat, size: [6, 20]}}"),
         "scene.yaml:4:18: error:", "water.surface covers [-3, 3] x [-10, 10] m, which does not cover the scene domain"},
    };
    for (const auto& c : cases) {
        const CommandResult r = runScene("check-scene", c.scene, false);
        EXPECT_EQ(r.status, 1) << c.cause << "\n" << r.output;
        EXPECT_TRUE(contains(r.output, c.where) && contains(r.output, c.cause)) << r.output;
        const CommandResult b = runScene("build", c.scene);
        EXPECT_EQ(b.status, 1);
        expectNothingWritten(out_, c.cause);
    }
}

// Inputs whose old messages named the wrong cause.
TEST_F(Hostile, UnreadableInputsNameTheRealCause) {
    // A spectrum "file" that cannot be read (here a folder) is not "a spectrum without wavelengths".
    fs::create_directories(dir_ / "refl.csv");
    CommandResult r = runScene("check-scene", replaced(kScene, "reflectance: 0.2", "reflectance: {file: refl.csv}"), false);
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "scene.yaml:6:47: error: materials[0].reflectance.file: file") &&
                contains(r.output, "refl.csv' does not exist or is not a regular file"))
        << r.output;
    // A spectrum file with only a header is empty, and says so with its name.
    writeTextFile(dir_, "empty.csv", "wavelength_um,value\n");
    r = runScene("check-scene", replaced(kScene, "reflectance: 0.2", "reflectance: {file: empty.csv}"), false);
    EXPECT_EQ(r.status, 1);
    EXPECT_TRUE(contains(r.output, "empty.csv: the file holds no 'wavelength_um, value' rows")) << r.output;
    // A YAML syntax error names its place and yaml-cpp's reason, not "bad file".
    r = runScene("check-scene", "scene: {name: x\nsky: [1, 2\n", false);
    EXPECT_EQ(r.status, 1);
    EXPECT_TRUE(contains(r.output, "scene.yaml:") && contains(r.output, "error: YAML syntax error: ")) << r.output;
    EXPECT_FALSE(contains(r.output, "bad file")) << r.output;
    // Class maps: an RGB image has no class index per pixel (it used to read as class 128), and a
    // value without a class is located at texture_classes with the pixel that holds it.
    ASSERT_EQ(std::system(("oiiotool --pattern constant:color=0.5,0.5,0.5 4x4 3 -d uint8 -o " + quotedArg(dir_ / "rgb.png") +
                           " > /dev/null 2>&1").c_str()),
              0);
    ASSERT_EQ(std::system(("oiiotool --pattern constant:color=0.02745098 4x4 1 -d uint8 -o " + quotedArg(dir_ / "seven.png") +
                           " > /dev/null 2>&1").c_str()),
              0);
    const std::string classes = replaced(kScene, "bathymetry: {type: planar_slope, z0_m: -2, material: floor}",
                                         "bathymetry: {type: planar_slope, z0_m: -2}") +
                                "texture_classes:\n  map: MAP\n  classes:\n    - {index: 0, name: sand, reflectance: 0.3}\n";
    r = runScene("check-scene", replaced(classes, "MAP", "rgb.png"), false);
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "rgb.png: error: classification map has 3 channels; it must be a single-channel "
                                   "image of class indices"))
        << r.output;
    r = runScene("check-scene", replaced(classes, "MAP", "seven.png"), false);
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "scene.yaml:13:3: error: texture_classes.classes: the classification map") &&
                contains(r.output, "holds class value 7 (16 pixels, the first at column 0, row 0), but no class has "
                                   "index 7; defined: 0"))
        << r.output;
}

// What docs/scene-format.md calls optional is optional, and the ENVI header prints band widths as
// the numbers they are.
// Correct by default: the scene file's scattering water renders its in-scatter (medium-pm, written
// into the IR); an IR whose scattering medium names no solver (hand-written, or edited) renders it
// as loss and says so at run time, naming the medium and the two solvers.
TEST_F(Hostile, ScatteringWaterWithoutASolverIsWarnedAbout) {
    editBuiltIr("      ],\n      \"solver\": \"medium-pm\"\n", "      ]\n");
    std::string json;
    {
        std::ifstream f(dir_ / "ir" / "scene.json");
        json.assign(std::istreambuf_iterator<char>(f), {});
    }
    ASSERT_FALSE(contains(json, "\"solver\": \"medium-pm\"")) << json.substr(0, 4000);
    const CommandResult r = runLittoral("render " + quotedArg(dir_ / "ir") + " --out " + quotedArg(out_));
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "warning: medium 'water' scatters but names no solver: the dirsig estimator counts "
                                   "its scattering as loss"))
        << r.output;
}

TEST_F(Hostile, DocumentedDefaultsAreDefaults) {
    // No sky, and water without a surface (a flat surface over the domain).
    std::string scene = replaced(kScene, "sky: {radiance: 0}\n", "");
    scene = replaced(scene, "render: {", "render: {bands: [[0.4, 0.5], [0.5, 0.6]], ");
    const CommandResult r = runScene("run", scene);
    ASSERT_EQ(r.status, 0) << r.output;
    for (const char* f : {"nadir.exr", "nadir.img", "nadir.hdr", "nadir.png", "nadir_truth.exr", "nadir_material.png",
                          "probes.csv", "probes.json", "ir/scene.json", "ir/validity.json", "ir/meshes/water.ply"})
        EXPECT_TRUE(fs::exists(out_ / f)) << f;
    std::ifstream hdr(out_ / "nadir.hdr");
    std::string text((std::istreambuf_iterator<char>(hdr)), {});
    EXPECT_TRUE(contains(text, "fwhm = {0.1, 0.1}")) << text;
    EXPECT_TRUE(contains(text, "wavelength = {0.45, 0.55}")) << text;
}

// ---- Mesh readers: the right cause in every format --------------------------------------------------

TEST_F(Hostile, MeshReadersReportTheRightCause) {
    const std::string verts = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
    const std::string faces = "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";
    const struct {
        std::string file, text;
        int status;
        std::string cause;
    } cases[] = {
        {"nan.obj", replaced(verts, "v 0 0 0", "v nan 0 0") + faces, 1, "NaN or infinite coordinates: vertex 0"},
        {"huge.obj", replaced(verts, "v 0 0 1", "v 0 0 1e400") + faces, 1, "NaN or infinite coordinates: vertex 3"},
        {"nan.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                    "element face 4\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 inf\n0 0 1\n"
                    "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n",
         1, "NaN or infinite coordinates: vertex 2"},
        {"nan.stl", "solid t\nfacet normal 0 0 0\nouter loop\nvertex 0 0 nan\nvertex 1 0 0\nvertex 0 1 0\nendloop\n"
                    "endfacet\nendsolid t\n",
         1, "NaN or infinite coordinates: vertex 0"},
        {"index.obj", verts + replaced(faces, "f 2 3 4", "f 2 3 9"), 2,
         "index.obj:7:7: face refers to vertex 9, but the file defines only 4 vertices"},
        {"index.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 7\n", 2,
         "index.off:7:7: face 0 refers to vertex 7, but there are 4 vertices"},
        {"garbage.obj", "\x7f" "ELF\x02\x01\x01 binary junk\n", 2, "is not an OBJ statement"},
        {"garbage.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n", 2,
         "the file ends where 'vertex x y z' (a facet has exactly 3 vertices) was expected (truncated)"},
        {"truncated.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n", 2,
         "truncated.off:2:1: the header declares 4 vertices and 4 faces, which need at least 56 bytes of lines, but only "
         "12 bytes follow"},
    };
    for (const auto& c : cases) {
        writeTextFile(dir_, c.file, c.text);
        const CommandResult r = runLittoral("check-mesh " + quotedArg(dir_ / c.file));
        EXPECT_EQ(r.status, c.status) << c.file << "\n" << r.output;
        EXPECT_TRUE(contains(r.output, c.cause)) << c.file << "\n" << r.output;
        EXPECT_FALSE(contains(r.output, "mesh is empty")) << c.file;
    }
}

// A closed cube with a fin triangle on one edge: the edge is non-manifold, but faces that share
// only an edge or a vertex do not intersect. An open mesh has no volume to report.
TEST_F(Hostile, CheckMeshHasNoFalseIntersectionsOrVolumes) {
    littoral::TriMesh cube = littoral::scenegen::makeBox(1, 1, 1);
    cube.faceMaterial.clear();
    // The fin leaves the edge away from the cube's centre, so it touches the cube only along the edge.
    const auto t0 = cube.triangles[0];
    const littoral::Point3 mid = (cube.positions[t0[0]] + cube.positions[t0[1]]) * 0.5;
    const littoral::Point3 centre{0, 0, 0.5};
    cube.positions.push_back(mid + (mid - centre) * 3.0);
    cube.triangles.push_back({t0[0], t0[1], static_cast<uint32_t>(cube.positions.size() - 1)});
    littoral::scenegen::writeMeshFile(dir_ / "fin.off", cube);
    CommandResult r = runLittoral("check-mesh " + quotedArg(dir_ / "fin.off"));
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "not manifold: 1 edges are shared by three or more faces")) << r.output;
    EXPECT_TRUE(contains(r.output, "self-intersections 0")) << r.output;
    EXPECT_FALSE(contains(r.output, "self-intersecting")) << r.output;
    EXPECT_TRUE(contains(r.output, "volume n/a (the mesh does not bound a volume)")) << r.output;
    littoral::TriMesh open = littoral::scenegen::makeBox(1, 1, 1);
    open.faceMaterial.clear();
    open.triangles.pop_back();
    littoral::scenegen::writeMeshFile(dir_ / "open.obj", open);
    r = runLittoral("check-mesh --json " + quotedArg(dir_ / "open.obj"));
    EXPECT_EQ(r.status, 1);
    EXPECT_TRUE(contains(r.output, "\"volume_m3\": null")) << r.output;
}

// ---- Round 3, data loss (issue 20): no command writes over one of its own inputs -------------

namespace {
std::string fileText(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
}
}  // namespace

TEST_F(Hostile, BuildRefusesToOverwriteItsInputs) {
    // A scene written in JSON syntax (valid YAML) named scene.json, built into its own folder:
    // the IR's scene.json would replace it.
    std::string json = R"({"scene": {"name": "j", "domain": {"x": [-5, 5], "y": [-5, 5]}},
 "sun": {"zenith_deg": 30, "irradiance": 1000}, "sky": {"radiance": 0},
 "water": {"optics": {"preset": "coastal"}},
 "bathymetry": {"type": "planar_slope", "z0_m": -2, "material": "floor"},
 "materials": [{"name": "floor", "reflectance": 0.2}]}
)";
    const fs::path in = writeTextFile(dir_, "scene.json", json);
    const CommandResult r = runLittoral("-q build " + quotedArg(in) + " --out " + quotedArg(dir_));
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "refusing to write output: it would replace '" + in.string() + "'")) << r.output;
    EXPECT_EQ(fileText(in), json) << "the input scene file was changed";
    EXPECT_FALSE(fs::exists(dir_ / "meshes")) << "a partial IR was left";
    EXPECT_FALSE(fs::exists(dir_ / "validity.json"));
    EXPECT_FALSE(fs::exists(dir_ / littoral::OutputFolderLock::kFileName));
}

TEST_F(Hostile, RunRefusesAnOutputNamedLikeAnInputUnderAnotherPath) {
    // The scene file is out/nadir.png's twin: a hard link to the very file `run` would write as
    // the sensor's preview. The same file under another name is still an input.
    fs::create_directories(out_);
    const fs::path scene = writeTextFile(dir_, "scene.yaml", kScene);
    fs::create_hard_link(scene, out_ / "nadir.png");
    const CommandResult r = runLittoral("-q run " + quotedArg(scene) + " --out " + quotedArg(out_));
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "it would replace '" + scene.string() + "', which this command reads")) << r.output;
    EXPECT_EQ(fileText(scene), kScene);
}

// ---- Round 3: one command per output folder --------------------------------------------------

TEST_F(Hostile, ASecondCommandIntoTheSameFolderIsRefused) {
    // A live owner: this test process itself holds the lock.
    fs::create_directories(out_);
    writeTextFile(out_, littoral::OutputFolderLock::kFileName, std::to_string(::getpid()) + "\n");
    CommandResult r = runScene("run", kScene);
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "another littoral command (process " + std::to_string(::getpid()) +
                                       ") is writing into this folder"))
        << r.output;
    EXPECT_EQ(listing(out_), std::set<std::string>{littoral::OutputFolderLock::kFileName}) << join(listing(out_));

    // A stale lock (its process has ended) is taken over with a warning, and released at the end.
    const pid_t child = fork();
    if (child == 0) _exit(0);
    ASSERT_GT(child, 0);
    waitpid(child, nullptr, 0);
    writeTextFile(out_, littoral::OutputFolderLock::kFileName, std::to_string(child) + "\n");
    r = runLittoral("build " + quotedArg(dir_ / "scene.yaml") + " --out " + quotedArg(out_));
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "taking over the lock of process " + std::to_string(child) + ", which no longer runs"))
        << r.output;
    EXPECT_FALSE(fs::exists(out_ / littoral::OutputFolderLock::kFileName));
    EXPECT_TRUE(fs::exists(out_ / "scene.json"));

    // A killed owner that nobody has reaped yet (a zombie: in a container, PID 1 may never reap a
    // command whose mpirun was stopped) no longer writes: its lock is taken over too.
    const pid_t zombie = fork();
    if (zombie == 0) _exit(0);
    ASSERT_GT(zombie, 0);
    const fs::path stat = "/proc/" + std::to_string(zombie) + "/stat";
    for (int i = 0; i < 2000 && fileText(stat).find(") Z") == std::string::npos; ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    ASSERT_NE(fileText(stat).find(") Z"), std::string::npos) << "the child did not become a zombie";
    writeTextFile(out_, littoral::OutputFolderLock::kFileName, std::to_string(zombie) + "\n");
    fs::create_directories(out_ / "again");
    writeTextFile(out_ / "again", littoral::OutputFolderLock::kFileName, std::to_string(zombie) + "\n");
    r = runLittoral("build " + quotedArg(dir_ / "scene.yaml") + " --out " + quotedArg(out_ / "again"));
    waitpid(zombie, nullptr, 0);
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "taking over the lock of process " + std::to_string(zombie) + ", which no longer runs"))
        << r.output;
    EXPECT_FALSE(fs::exists(out_ / "again" / littoral::OutputFolderLock::kFileName));
}

TEST_F(Hostile, TwoConcurrentRunsNeverMixTheirOutputs) {
    // Two `run`s started together into one folder: exactly one renders, the other is refused.
    writeTextFile(dir_, "scene.yaml", kScene);
    const std::string cmd = littoral::testing_support::littoralBinary().string() + " -q run " + quotedArg(dir_ / "scene.yaml") +
                            " --out " + quotedArg(out_) + " > /dev/null 2>&1";
    std::thread a([&] { EXPECT_GE(std::system(cmd.c_str()), 0); });
    std::thread b([&] { EXPECT_GE(std::system(cmd.c_str()), 0); });
    a.join();
    b.join();
    EXPECT_FALSE(fs::exists(out_ / littoral::OutputFolderLock::kFileName));
    EXPECT_TRUE(fs::exists(out_ / "nadir.exr"));
    EXPECT_TRUE(fs::exists(out_ / "ir" / "scene.json"));
}

// ---- Round 3: checkpoints are checked against the run that resumes them ----------------------

TEST_F(Hostile, ResumeRefusesCheckpointsOfAnotherShape) {
    // A progressive photon-map scene (3 passes); checkpoints are written here by hand, in the
    // format render_job.cpp saves, with the IR's own hash, so that only the field under test is
    // wrong in each.
    std::string text = replaced(kScene, "materials: [{name: floor, reflectance: 0.2}]",
                                "materials: [{name: floor, reflectance: 0.2, solver: surface-pm}]");
    text = replaced(text, "render: {probe_samples: 64, hemisphere_samples: 4}",
                    "render: {probe_samples: 64, hemisphere_samples: 4, photons: {surface: 2000}, progressive: {passes: 3}}");
    const CommandResult b = runScene("build", text);
    ASSERT_EQ(b.status, 0) << b.output;
    const littoral::ir::SceneIR ir = littoral::ir::readIR(out_);
    const std::string hash = std::to_string(std::hash<std::string>{}(littoral::ir::toJsonText(ir)));
    const fs::path render = dir_ / "render", ckpt = render / "progressive.checkpoint";
    const size_t pixels = 16 * 12;  // the nadir sensor, one band
    auto checkpoint = [&](const std::string& sensor, long long passesDone, size_t imageValues) {
        fs::remove_all(render);
        fs::create_directories(ckpt);
        writeTextFile(ckpt, "state.json",
                      "{\"format\": \"littoral-progressive-checkpoint\", \"ir_hash\": \"" + hash + "\", \"sensor\": \"" +
                          sensor + "\", \"passes\": 3, \"passes_done\": " + std::to_string(passesDone) +
                          ", \"probe_sums\": [[1.0]], \"probe_squares\": [[1.0]], \"image_sizes\": [" +
                          std::to_string(imageValues) + "]}\n");
        writeTextFile(ckpt, fmt::format("image0-{}.f64", passesDone), std::string(imageValues * sizeof(double), '\0'));
    };
    auto resume = [&] { return runLittoral("-q render " + quotedArg(out_) + " --out " + quotedArg(render) + " --resume"); };

    checkpoint("nadir", 1, pixels);  // made with --sensor nadir; resumed for everything (it crashed)
    CommandResult r = resume();
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "--resume: the checkpoint was made with --sensor nadir, this run renders every "
                                   "sensor; resume with the same --sensor selection"))
        << r.output;

    checkpoint("", -2000000000, pixels);  // an edited pass count (an internal error before)
    r = resume();
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "state.json: error: --resume: unreadable checkpoint: passes_done is -2000000000; a "
                                   "checkpoint of this 3-pass run holds 1 to 2 passes"))
        << r.output;

    checkpoint("", 1, pixels / 2);  // sums of another image size
    r = resume();
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "unreadable checkpoint: image 0 holds 96 values, the sensor renders 192")) << r.output;

    checkpoint("", 1, pixels);  // the right shape: the run resumes and finishes
    r = resume();
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(fs::exists(render / "nadir.exr"));
    EXPECT_FALSE(fs::exists(ckpt)) << "a finished run keeps no checkpoint";
}

// ---- Issue 17: settings that were read but ignored are refused -------------------------------

TEST_F(Hostile, WaterOpticsInterfaceIsRefused) {
    // water.optics.interface could only say `fresnel`, which the air-water interface always is:
    // check-scene and run refuse it at its location instead of reading it silently.
    const std::string text = replaced(kScene, "water: {optics: {preset: coastal}}",
                                      "water: {optics: {preset: coastal, interface: fresnel}}");
    for (const char* cmd : {"check-scene", "run"}) {
        const CommandResult r = runScene(cmd, text, std::string(cmd) != "check-scene");
        EXPECT_EQ(r.status, 1) << cmd << ": " << r.output;
        EXPECT_TRUE(contains(r.output, "scene.yaml:4:") && contains(r.output, "water.optics.interface") &&
                    contains(r.output, "the air-water interface always uses the Fresnel solver"))
            << cmd << ": " << r.output;
    }
    expectNothingWritten(out_, "run");
}

// ---- Issue 20: rasters (NaN/Inf pixels, extents that miss the domain) and OBJ usemtl ----------

namespace {

// A little-endian grey PFM (rows stored bottom first, so file row 0 is image row h - 1).
void writePfm(const fs::path& p, int w, int h, const std::vector<float>& fileOrder) {
    std::string bytes = "Pf\n" + std::to_string(w) + " " + std::to_string(h) + "\n-1.0\n";
    bytes.append(reinterpret_cast<const char*>(fileOrder.data()), fileOrder.size() * sizeof(float));
    std::ofstream(p, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

// kScene with the seabed from texture_classes: one class (index 0) with texture tex.pfm.
std::string texturedScene() {
    return replaced(kScene, "bathymetry: {type: planar_slope, z0_m: -2, material: floor}",
                    "bathymetry: {type: planar_slope, z0_m: -2}") +
           "texture_classes:\n  map: map.png\n  classes:\n    - {index: 0, name: sand, reflectance: 0.3, texture: "
           "tex.pfm, stddev: 0.1}\n";
}

// An ESRI ASCII grid of n x n samples at -2 m, lower-left corner (x0, y0), 1 m cells.
std::string asciiGrid(int n, double x0, double y0, const std::string& sample = "-2") {
    std::string g = fmt::format("ncols {}\nnrows {}\nxllcorner {:.3f}\nyllcorner {:.3f}\ncellsize 1\n", n, n, x0, y0);
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) g += (i ? " " : "") + (i == 3 && j == 1 ? sample : std::string("-2"));
        g += "\n";
    }
    return g;
}

// Writes `text` as dir/scene.yaml (beside the inputs it names) and checks that check-scene, build
// and run all refuse it: exit 1, the error at scene.yaml`where`, `message` in it, no output folder.
void expectRefusedByAll(const fs::path& dir, const std::string& text, const std::string& where,
                        const std::string& message) {
    const fs::path scene = writeTextFile(dir, "scene.yaml", text);
    for (const std::string cmd : {"check-scene", "build", "run"}) {
        const fs::path out = dir / ("out-" + cmd);
        const CommandResult r = runLittoral("-q " + cmd + " " + quotedArg(scene) + (cmd == "check-scene" ? "" : " --out " + quotedArg(out)));
        EXPECT_EQ(r.status, 1) << cmd << ": " << r.output;
        EXPECT_TRUE(contains(r.output, "scene.yaml" + where + ": error: ")) << cmd << ": " << r.output;
        EXPECT_TRUE(contains(r.output, message)) << cmd << ": " << r.output;
        EXPECT_FALSE(fs::exists(out)) << cmd << ": output left behind";
    }
}

}  // namespace

TEST_F(Hostile, NonFiniteTexturePixelsAreRefusedAtTheirPixel) {
    // A NaN (or an infinity) in a class texture spread through the class's mean into every pixel
    // of the remapped texture: exit 0 with nan in probes.csv. Now refused at the texture key.
    ASSERT_EQ(std::system(("oiiotool --pattern constant:color=0 4x4 1 -d uint8 -o " + quotedArg(dir_ / "map.png") +
                           " > /dev/null 2>&1").c_str()),
              0);
    for (const float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
        std::vector<float> v(16);
        for (int i = 0; i < 16; ++i) v[size_t(i)] = 0.5f + 0.1f * float(i);
        v[2] = bad;  // file row 0 (the bottom), column 2: image row 3
        writePfm(dir_ / "tex.pfm", 4, 4, v);
        expectRefusedByAll(dir_, texturedScene(), ":15:57",
            std::string("texture image ") + (dir_ / "tex.pfm").string() +
                ": pixel (column 2, row 3; counted from 0, row 0 at the top), channel 0 is " +
                (std::isnan(bad) ? "nan" : "inf") + "; texture values must be finite numbers");
    }
}

TEST_F(Hostile, IrTexturesMustBeFiniteAndNonNegative) {
    // A hand-edited IR texture multiplies a reflectance: NaN or a negative value is refused by
    // `render`, naming the file and the pixel, and nothing is written.
    ASSERT_EQ(std::system(("oiiotool --pattern constant:color=0 4x4 1 -d uint8 -o " + quotedArg(dir_ / "map.png") +
                           " > /dev/null 2>&1").c_str()),
              0);
    std::vector<float> v(16);
    for (int i = 0; i < 16; ++i) v[size_t(i)] = 0.5f + 0.1f * float(i);
    writePfm(dir_ / "tex.pfm", 4, 4, v);
    const fs::path ir = dir_ / "ir";
    writeTextFile(dir_, "scene.yaml", texturedScene());
    CommandResult r = runLittoral("-q build " + quotedArg(dir_ / "scene.yaml") + " --out " + quotedArg(ir));
    ASSERT_EQ(r.status, 0) << r.output;
    const fs::path tif = ir / "textures" / "sand.tif";
    for (const char* colour : {"-0.25", "nan"}) {
        fs::remove(tif);
        ASSERT_EQ(std::system(("oiiotool --pattern constant:color=" + std::string(colour) + " 4x4 1 -d float -o " +
                               quotedArg(tif) + " > /dev/null 2>&1").c_str()),
                  0);
        r = runLittoral("-q render " + quotedArg(ir) + " --out " + quotedArg(out_));
        EXPECT_EQ(r.status, 1) << r.output;
        EXPECT_TRUE(contains(r.output, tif.string() + ": error: texture pixel (column 0, row 0; counted from 0, row 0 "
                                                      "= north), channel 0 is " +
                                           (std::string(colour) == "nan" ? "nan" : "-0.25") +
                                           "; a texture multiplies a reflectance, so its values must be finite and "
                                           ">= 0"))
            << r.output;
        EXPECT_FALSE(fs::exists(out_)) << "output left behind";
    }
}

TEST_F(Hostile, BathymetryRastersMustCoverTheDomain) {
    // A UTM raster 4000 km from the local origin (origin_x_m: 0) was accepted: the seabed became
    // the raster's edge value. Refused at the key that places the raster, naming both extents.
    writeTextFile(dir_, "utm.asc", asciiGrid(12, 410000, 4000000));
    const std::string bathy = "bathymetry: {type: planar_slope, z0_m: -2, material: floor}";
    const auto scene = [&](const std::string& keys) {
        return replaced(kScene, bathy, "bathymetry: {type: raster, file: utm.asc, " + keys + "material: floor}");
    };
    const std::string both = "the raster utm.asc covers x [410000, 410012], y [4000000, 4000012] m in the local "
                             "frame (its cells), and the scene domain is x [-5, 5], y [-5, 5] m: the raster lies 4021 "
                             "km from the domain, entirely outside it; a georeferenced raster needs the projected "
                             "coordinates of the local origin: origin: scene";
    expectRefusedByAll(dir_, scene("origin_x_m: 0, "), ":5:55",
                                                  "bathymetry.origin_x_m: " + both);
    expectRefusedByAll(dir_, scene(""), ":5:34",
                                                  "bathymetry.file: " + both);
    // An extent that covers only part of the domain: the rest would repeat the edge values.
    expectRefusedByAll(dir_, scene("extent: {x: [-3, 3], y: [-5, 5]}, "), ":5:51",
        "bathymetry.extent: the raster utm.asc covers x [-3.272727273, 3.272727273], y [-5.454545455, 5.454545455] m "
        "in the local frame (its cells), and the scene domain is x [-5, 5], y [-5, 5] m, which it covers only in part");
    // The right origin: the raster's cells cover the domain (to the half cell beyond the centres).
    CommandResult r = runScene("check-scene", scene("origin_x_m: 410006, origin_y_m: 4000006, "), false);
    EXPECT_EQ(r.status, 0) << r.output;
    // An extent with an origin: the origin would be ignored.
    r = runScene("check-scene", scene("extent: {x: [-6, 6], y: [-6, 6]}, origin_x_m: 1, "), false);
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "scene.yaml:5:") &&
                contains(r.output, "'extent' places the raster in the local frame itself, so 'origin_x_m'"))
        << r.output;
}

TEST_F(Hostile, BathymetryRasterSamplesMustBeFiniteElevations) {
    // NaN in an ASCII grid: located at its line and column. An elevation beyond any on Earth (a
    // NODATA value the file does not declare, 3.4e38): named by its sample.
    const std::string bathy = "bathymetry: {type: planar_slope, z0_m: -2, material: floor}";
    const std::string scene = replaced(kScene, bathy, "bathymetry: {type: raster, file: g.asc, material: floor}");
    writeTextFile(dir_, "g.asc", asciiGrid(12, -6, -6, "nan"));
    CommandResult r = runScene("check-scene", scene, false);
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "g.asc:7:10: error: 'nan' (row 2, column 4) is not a finite number")) << r.output;
    writeTextFile(dir_, "g.asc", asciiGrid(12, -6, -6, "3.4e38"));
    for (const char* cmd : {"check-scene", "run"}) {
        r = runScene(cmd, scene, std::string(cmd) == "run");
        EXPECT_EQ(r.status, 1) << r.output;
        EXPECT_TRUE(contains(r.output, "g.asc: error: sample (column 4, row 2; counted from 1, row 1 = north) holds "
                                       "3.4e+38, which is an elevation of 3.4e+38 m after z_scale 1 and z_offset_m 0; "
                                       "allowed -12000 to 9000 m"))
            << r.output;
        expectNothingWritten(out_, cmd);
    }
}

TEST_F(Hostile, RasterOriginCanComeFromTheSceneOrigin) {
    // origin: scene takes a georeferenced raster's offset from scene.origin through the scene's
    // UTM frame, instead of a hand-written origin_x_m / origin_y_m.
    const double lat = 36.18, lon = -75.75;
    const auto utm = littoral::bathymetry::toUtm(lat, lon);
    writeTextFile(dir_, "utm.asc", asciiGrid(12, utm.easting - 6, utm.northing - 6));
    const std::string bathy = "bathymetry: {type: planar_slope, z0_m: -2, material: floor}";
    const auto scene = [&](const std::string& keys) {
        return replaced(replaced(kScene, bathy, "bathymetry: {type: raster, file: utm.asc, " + keys + "material: floor}"),
                        "scene: {name: hostile,", "scene: {name: hostile, origin: {latitude: 36.18, longitude: -75.75},");
    };
    CommandResult r = runScene("check-scene", scene("origin: scene, frame: utm, "), false);
    EXPECT_EQ(r.status, 0) << r.output;
    // The local tangent-plane frame: an ASCII grid without a .prj has no system to reproject from.
    r = runScene("check-scene", scene("origin: scene, "), false);
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "utm.asc: error: the raster declares no coordinate system") &&
                contains(r.output, "set bathymetry.frame: utm"))
        << r.output;
    // With its .prj (UTM zone 18 N, WGS 84) it is reprojected into the tangent plane.
    writeTextFile(dir_, "utm.prj",
                  "PROJCS[\"WGS_1984_UTM_Zone_18N\",GEOGCS[\"GCS_WGS_1984\",DATUM[\"D_WGS_1984\",SPHEROID["
                  "\"WGS_1984\",6378137.0,298.257223563]],PRIMEM[\"Greenwich\",0.0],UNIT[\"Degree\","
                  "0.0174532925199433]],PROJECTION[\"Transverse_Mercator\"],PARAMETER[\"False_Easting\",500000.0],"
                  "PARAMETER[\"False_Northing\",0.0],PARAMETER[\"Central_Meridian\",-75.0],PARAMETER["
                  "\"Scale_Factor\",0.9996],PARAMETER[\"Latitude_Of_Origin\",0.0],UNIT[\"Meter\",1.0]]");
    r = runScene("check-scene", scene("origin: scene, "), false);
    EXPECT_EQ(r.status, 0) << r.output;
    fs::remove(dir_ / "utm.prj");
    r = runScene("check-scene", scene("origin: scene, origin_x_m: 1, frame: utm, "), false);
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "give either 'origin: scene' or origin_x_m/origin_y_m")) << r.output;
    r = runScene("check-scene", replaced(scene("origin: scene, frame: utm, "), " origin: {latitude: 36.18, longitude: -75.75},", ""),
                 false);
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "bathymetry.origin: 'scene' takes the raster's offset from scene.origin")) << r.output;
}

TEST_F(Hostile, ObjUsemtlNamesMaterialSlots) {
    // usemtl was ignored, so a second material was silently dropped. Each distinct name now takes
    // the next face material slot; too few materials is refused naming the OBJ line.
    const std::string cube = "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n"
                             "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n"
                             "usemtl hull\nf 1 4 3 2\nf 1 2 6 5\nf 3 4 8 7\nf 2 3 7 6\nf 4 1 5 8\n"
                             "usemtl deck\nf 5 6 7 8\n";
    writeTextFile(dir_, "cube.obj", cube);
    std::string scene = kScene;
    scene += "objects:\n  - {name: box, mesh: cube.obj, materials: [floor], position_m: [0, 0], draft_m: 0.5}\n";
    expectRefusedByAll(dir_, scene, ":13:5",
        "object 'box': " + (dir_ / "cube.obj").string() + ":15: usemtl 'deck' starts face material slot 1, but "
        "'materials' lists 1 (slot 0 'hull' (line 9) -> floor, slot 1 'deck' (line 15)); list one material per "
        "distinct usemtl name, in the order the names first appear on faces");
    scene = replaced(scene, "materials: [floor]", "materials: [floor, paint]");
    scene = replaced(scene, "materials: [{name: floor, reflectance: 0.2}]",
                     "materials: [{name: floor, reflectance: 0.2}, {name: paint, reflectance: 0.6}]");
    CommandResult r = runScene("build", scene);
    ASSERT_EQ(r.status, 0) << r.output;
    const littoral::TriMesh m = littoral::scenegen::readMeshFile(out_ / "meshes" / "object_box.ply");
    const auto ir = nlohmann::json::parse(littoral::readTextFile(out_ / "scene.json"));
    std::vector<std::string> slots;
    for (const auto& mesh : ir["meshes"])
        if (mesh["name"] == "box") slots = mesh["materials"].get<std::vector<std::string>>();
    EXPECT_EQ(slots, (std::vector<std::string>{"floor", "paint"}));
    // The top (+z) faces are deck -> paint; every other face is hull -> floor.
    ASSERT_EQ(m.faceMaterial.size(), m.triangles.size());
    for (size_t f = 0; f < m.triangles.size(); ++f) {
        const littoral::Vec3 n = m.faceNormalArea(f);
        EXPECT_EQ(m.faceMaterial[f], n.z > 0.1 ? 1 : 0) << "face " << f;
    }
}

TEST_F(Hostile, PathEstimatorWarnsWhenPathsAreCutAtMaxBounces) {
    // Dense water that scatters and does not absorb: a path needs of order (b z)^2 = 4e6 events to
    // leave a 2 m column at b = 1000 m^-1, so with max_bounces 20 nearly every path is cut and its
    // radiance lost. It used to return 0 without a word; the run now says what fraction was cut.
    std::string text = replaced(kScene, "water: {optics: {preset: coastal}}",
                                "water: {optics: {absorption_per_m: 0, scattering_per_m: 1000}}");
    text = replaced(text, "render: {probe_samples: 64, hemisphere_samples: 4}",
                    "render: {estimator: path, probe_samples: 64, max_bounces: 20}");
    const CommandResult r = runScene("run", text);
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "reached render.max_bounces = 20 with weight left and were cut")) << r.output;
    // The same scene with clear water: no path is cut, no warning.
    std::string clear = replaced(kScene, "render: {probe_samples: 64, hemisphere_samples: 4}",
                                 "render: {estimator: path, probe_samples: 64}");
    fs::remove_all(out_);
    const CommandResult c = runScene("run", clear);
    EXPECT_EQ(c.status, 0) << c.output;
    EXPECT_FALSE(contains(c.output, "were cut")) << c.output;
}

TEST_F(Hostile, RenderTimeErrorsInAHandEditedIrNameSceneJsonAndTheEntry) {
    // A reflectance of 1.5 passes the IR's syntax, and the renderer refuses it; the message names
    // scene.json and the entry's JSON path, not only "material 'floor'".
    editBuiltIr("\"reflectance\": 0.2", "\"reflectance\": 1.5");
    const CommandResult r = runLittoral("-q render " + quotedArg(dir_ / "ir") + " --out " + quotedArg(out_));
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "scene.json: error: materials[") &&
                contains(r.output, "]: material 'floor': reflectance 1.5 outside [0, 1]"))
        << r.output;
    expectNothingWritten(out_, "render");
}

// ---- The image-quality study: statistics defined or blank, one output set ----------------------

TEST_F(Hostile, StudyStatisticsAreDefinedOrLeftBlankWithAReason) {
    // The hostile report's l14: 100 volume photons per m^3 in a 24-pixel image leave the step
    // under the noise; the study wrote width_10_90_m = nan and tails of -1.28 and 3.21.
    const CommandResult r = runLittoral("study image-quality --out " + quotedArg(out_) +
                                        " --pixels 24 --spp 1 --radii 0.25 0.6 --densities 100 --depths 1");
    ASSERT_EQ(r.status, 0) << r.output;
    std::ifstream f(out_ / "image_quality.csv");
    std::string header, line;
    std::getline(f, header);
    ASSERT_TRUE(contains(header, "fwhm_m,width_10_90_m,tail_fraction,seconds")) << header;
    int rows = 0, blanks = 0;
    while (std::getline(f, line)) {
        ++rows;
        EXPECT_FALSE(contains(line, "nan") || contains(line, "inf")) << line;
        std::vector<std::string> cells;
        std::stringstream ss(line);
        for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
        if (line.back() == ',') cells.emplace_back();
        ASSERT_EQ(cells.size(), 15u) << line;
        const std::string& tails = cells[13];
        if (tails.empty()) {
            ++blanks;
            continue;
        }
        const double t = std::stod(tails);
        EXPECT_GE(t, 0.0) << line;
        EXPECT_LE(t, 1.0) << line;
    }
    EXPECT_EQ(rows, 2);
    // Whatever is left blank is explained on stderr.
    if (blanks > 0 || contains(r.output, "undefined")) {
        EXPECT_TRUE(contains(r.output, "are undefined") || contains(r.output, "is undefined")) << r.output;
    }
}

TEST_F(Hostile, InterruptedStudyLeavesNothing) {
    // The hostile report's p18: SIGINT while the second of two runs was being made left the first
    // run's folder and half of the second's, and said "removed 0 partial output file(s)".
    const pid_t pid = spawnLittoral({"-q", "study", "image-quality", "--out", out_.string(), "--pixels", "24", "--spp",
                                     "1", "--radii", "0.25", "0.5", "--densities", "100", "--depths", "1"});
    ASSERT_GT(pid, 0);
    const fs::path second = out_ / "runs" / "d1_n100_r0.5";
    bool seen = false;
    for (int i = 0; i < 12000 && !seen; ++i) {
        seen = fs::exists(second / "scene.yaml");
        if (!seen) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ASSERT_TRUE(seen) << "the second run did not start within 60 s";
    ::kill(pid, SIGINT);
    EXPECT_EQ(waitStatus(pid), 130);
    expectNothingWritten(out_, "SIGINT during the study");
}

namespace {
uint32_t crc32(const std::string& bytes) {  // the PNG chunk CRC (ISO 3309)
    uint32_t c = 0xffffffffu;
    for (unsigned char b : bytes) {
        c ^= b;
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return ~c;
}
uint32_t be32(const std::string& s, size_t at) {
    return (uint32_t(uint8_t(s[at])) << 24) | (uint32_t(uint8_t(s[at + 1])) << 16) | (uint32_t(uint8_t(s[at + 2])) << 8) |
           uint32_t(uint8_t(s[at + 3]));
}
std::string put32(uint32_t v) { return {char(v >> 24), char(v >> 16), char(v >> 8), char(v)}; }
// The PNG with every IDAT chunk cut to half its data (lengths and CRCs rewritten): a well-formed
// file whose compressed image stops early, so that libpng itself reports "Not enough image data".
std::string withShortIdat(const std::string& png) {
    std::string out = png.substr(0, 8);
    for (size_t at = 8; at + 12 <= png.size();) {
        const uint32_t n = be32(png, at);
        const std::string type = png.substr(at + 4, 4);
        std::string body = png.substr(at + 8, n);
        if (type == "IDAT") body.resize(body.size() / 2);
        out += put32(uint32_t(body.size())) + type + body + put32(crc32(type + body));
        at += 12 + n;
    }
    return out;
}
}  // namespace

TEST_F(Hostile, TruncatedPngGivesOneMessageWithoutLibpngNoise) {
    // The hostile report's e18: a class map whose image data stops short printed three libpng lines
    // around the real error. A 64 x 64 PNG of varied values (so its IDAT is not tiny), with its
    // IDAT cut short inside a well-formed file, and the whole file cut to half.
    const fs::path map = dir_ / "map.png", good = dir_ / "good.png";
    ASSERT_EQ(std::system(("oiiotool --pattern noise:type=uniform:min=0:max=1 64x64 1 -d uint8 -o " + quotedArg(good) +
                           " > /dev/null 2>&1").c_str()),
              0);
    std::string png;
    {
        std::ifstream f(good, std::ios::binary);
        png.assign(std::istreambuf_iterator<char>(f), {});
    }
    const std::string text = replaced(kScene, "bathymetry: {type: planar_slope, z0_m: -2, material: floor}",
                                      "bathymetry: {type: planar_slope, z0_m: -2}\ntexture_classes: {map: map.png, "
                                      "extent: {x: [-5, 5], y: [-5, 5]}, classes: [{index: 0, name: c0, reflectance: "
                                      "0.2}]}");
    for (const std::string& bad : {withShortIdat(png), png.substr(0, png.size() / 2)}) {
        std::ofstream(map, std::ios::binary) << bad;
        for (const std::string cmd : {"check-scene", "run"}) {
            fs::remove_all(out_);
            const CommandResult r = runScene(cmd, text, cmd != "check-scene");
            EXPECT_EQ(r.status, 1) << cmd << ": " << r.output;
            EXPECT_FALSE(contains(r.output, "libpng")) << cmd << ": " << r.output;
            EXPECT_TRUE(contains(r.output, "map.png: error: cannot read classification map: ")) << cmd << ": " << r.output;
            // One message on one line (OpenImageIO's several lines are joined: core/error.h libraryMessage).
            EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << cmd << ": " << r.output;
            expectNothingWritten(out_, cmd);
        }
    }
}
