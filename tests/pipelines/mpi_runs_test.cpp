// MPI runs (pipelines/lib_mpi.h, core/ranks.h): `mpirun -np N littoral run|render` writes the same
// files, byte for byte, as one process with the same seeds and totals, for photon-map scenes (the
// photon chunks shared by the ranks), path-traced ones (tiles, the adaptive pilot and the probe
// chunks shared) and resumed runs (a checkpoint made by 2 ranks, finished by 3). These are exact
// checks: every item's result depends only on its number, so any difference is a defect.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using namespace littoral::testing_support;

namespace {

#ifdef LITTORAL_MPIEXEC
constexpr const char* kMpiexec = LITTORAL_MPIEXEC;
#else
constexpr const char* kMpiexec = "";
#endif

// The scene of the hostile-input tests, rendered by the path estimator with per-pixel convergence
// (so the adaptive pilot is shared too), standard-error images (4 samples per pixel) and probes.
std::string pathScene() {
    std::string s = replacedOnce(kSmallScene, "width: 16, height: 12}", "width: 16, height: 12, samples_per_pixel: 4}");
    s = replacedOnce(s, "quantities: [Ed]}", "quantities: [Ed, Eu]}\n  - {name: q, position: [1, 1, -0.5], quantities: [Eod]}");
    return replacedOnce(s, "render: {probe_samples: 64, hemisphere_samples: 4}",
                        "render: {estimator: path, probe_samples: 4096, target_relative_error: 0.3, "
                        "max_samples_per_pixel: 16}");
}

// The same scene with surface and volume maps of `photons` photons each, in `passes` progressive
// passes.
std::string photonScene(int passes, int photons = 40000) {
    std::string s = replacedOnce(kSmallScene, "reflectance: 0.2}", "reflectance: 0.2, solver: surface-pm}");
    return replacedOnce(s, "render: {probe_samples: 64, hemisphere_samples: 4}",
                        "render: {probe_samples: 256, hemisphere_samples: 4, photons: {surface: " + std::to_string(photons) +
                        ", volume: " + std::to_string(photons) + "}, progressive: {passes: " + std::to_string(passes) + "}}");
}

std::string readBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// Every file under `dir` (relative path -> bytes), but the folder lock; the build's validity.json
// without its "seconds" (the time of each build stage, which differ from run to run).
std::map<std::string, std::string> filesUnder(const fs::path& dir) {
    std::map<std::string, std::string> files;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file() && e.path().filename() != ".littoral.lock") {
            std::string bytes = readBytes(e.path());
            if (e.path().filename() == "validity.json") {
                nlohmann::json j = nlohmann::json::parse(bytes);
                EXPECT_EQ(j.erase("seconds"), 1u) << e.path();
                bytes = j.dump();
            }
            files[fs::relative(e.path(), dir).string()] = bytes;
        }
    return files;
}

void expectSameFiles(const fs::path& expected, const fs::path& actual) {
    const auto a = filesUnder(expected), b = filesUnder(actual);
    ASSERT_FALSE(a.empty());
    for (const auto& [name, bytes] : a) {
        const auto it = b.find(name);
        if (it == b.end()) {
            ADD_FAILURE() << actual / name << " is missing";
            continue;
        }
        EXPECT_TRUE(it->second == bytes) << actual / name << " differs from " << expected / name;
    }
    for (const auto& [name, bytes] : b) EXPECT_TRUE(a.count(name)) << actual / name << " is extra";
}

std::string mpirunPrefix(int ranks) { return fmt::format("{} -np {} --oversubscribe ", kMpiexec, ranks); }

// `mpirun -np RANKS littoral ARGS...` as a child process (output discarded), for signalling it.
pid_t spawnOnRanks(int ranks, const std::vector<std::string>& args) {
    std::vector<std::string> argv{kMpiexec, "-np", std::to_string(ranks), "--oversubscribe", littoralBinary().string()};
    argv.insert(argv.end(), args.begin(), args.end());
    return spawnProcess(std::move(argv));
}

CommandResult runOnRanks(int ranks, const std::string& args) {
    return runShellCommand(mpirunPrefix(ranks) + littoralBinary().string() + " " + args);
}

// Waits (at most 60 s) until `file` exists and holds `text`, then stops mpirun (SIGTERM, which it
// forwards to the ranks) and waits for it. Whether the file was seen.
bool stopOnceWritten(pid_t pid, const fs::path& file, const std::string& text) {
    bool seen = false;
    for (int i = 0; i < 12000 && !seen; ++i) {
        seen = fs::exists(file) && readBytes(file).find(text) != std::string::npos;
        if (!seen) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ::kill(pid, SIGTERM);
    int st = 0;
    waitpid(pid, &st, 0);
    return seen;
}

size_t count(const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

class MpiRuns : public ::testing::Test {
protected:
    void SetUp() override {
        if (std::string(kMpiexec).empty()) GTEST_SKIP() << "built without MPI (LITTORAL_MPI found no MPI library)";
        // OpenMPI refuses to run as root (CI containers) unless told that it may.
        setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
        setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
        // Containers often forbid the cross-process reads (CMA) of OpenMPI's shared-memory transport:
        // copy through the shared segment instead (slower, and these exchanges are small).
        setenv("OMPI_MCA_btl_vader_single_copy_mechanism", "none", 1);
        // The EXRs' DateTime from the reproducible-builds clock, so that runs can match byte for byte.
        setenv("SOURCE_DATE_EPOCH", "1796256000", 1);
        dir_ = scratchDir("mpi_runs", ::testing::UnitTest::GetInstance()->current_test_info()->name());
    }
    // Builds `scene` into dir_/ir.
    fs::path build(const std::string& scene) {
        const fs::path file = writeTextFile(dir_, "scene.yaml", scene);
        const CommandResult r = runLittoral("-q build " + file.string() + " --out " + (dir_ / "ir").string());
        if (r.status != 0) ADD_FAILURE() << r.output;
        return dir_ / "ir";
    }
    // Renders the IR as one process; then on 2 ranks, stopped (SIGTERM to mpirun, which forwards it
    // to the ranks) once the checkpoint file `state` (in the output folder) holds `text`, and resumed
    // on 3 ranks: the resumed render must equal the uninterrupted one, every file.
    void expectResumedOnThreeRanksIsTheUninterruptedRender(const fs::path& ir, const fs::path& state,
                                                           const std::string& text) {
        CommandResult r = runLittoral("-q render " + ir.string() + " --out " + (dir_ / "one").string());
        ASSERT_EQ(r.status, 0) << r.output;
        const fs::path out = dir_ / "resumed";
        const pid_t pid = spawnOnRanks(2, {"-q", "render", ir.string(), "--out", out.string()});
        ASSERT_GT(pid, 0);
        ASSERT_TRUE(stopOnceWritten(pid, out / state, text)) << "no checkpoint holding " << text << " within 60 s";
        ASSERT_TRUE(fs::exists(out / state)) << "the render finished before it was stopped";
        // Stopped: no image was written (the interrupted ranks removed their partial outputs).
        EXPECT_FALSE(fs::exists(out / "nadir.exr"));
        // mpirun may exit before its ranks have: a user would wait for rank 0 to release the folder
        // (at most 30 s here; a lock left by a rank killed outright is taken over by the resume).
        for (int i = 0; i < 3000 && fs::exists(out / ".littoral.lock"); ++i)
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        r = runOnRanks(3, "-q render " + ir.string() + " --out " + out.string() + " --resume");
        ASSERT_EQ(r.status, 0) << r.output;
        expectSameFiles(dir_ / "one", out);
    }
    fs::path dir_;
};

TEST_F(MpiRuns, PathTracedRenderOnTwoAndThreeRanksIsTheSingleProcessRender) {
    const fs::path ir = build(pathScene());
    CommandResult r = runLittoral("-q render " + ir.string() + " --out " + (dir_ / "one").string());
    ASSERT_EQ(r.status, 0) << r.output;
    ASSERT_TRUE(fs::exists(dir_ / "one" / "nadir_stderr.img"));  // the standard-error image is compared too
    r = runOnRanks(2, "-q render " + ir.string() + " --out " + (dir_ / "two").string());
    ASSERT_EQ(r.status, 0) << r.output;
    expectSameFiles(dir_ / "one", dir_ / "two");
    // Three ranks of one thread each: another split of every item, the same bytes.
    r = runOnRanks(3, "-q render " + ir.string() + " --out " + (dir_ / "three").string() + " --threads 1");
    ASSERT_EQ(r.status, 0) << r.output;
    expectSameFiles(dir_ / "one", dir_ / "three");
}

TEST_F(MpiRuns, PhotonMapRunOnTwoAndThreeRanksIsTheSingleProcessRun) {
    const fs::path scene = writeTextFile(dir_, "scene.yaml", photonScene(2));
    CommandResult r = runLittoral("-q run " + scene.string() + " --out " + (dir_ / "one").string());
    ASSERT_EQ(r.status, 0) << r.output;
    for (int ranks : {2, 3}) {
        const fs::path out = dir_ / ("ranks" + std::to_string(ranks));
        r = runOnRanks(ranks, "run " + scene.string() + " --out " + out.string());
        ASSERT_EQ(r.status, 0) << r.output;
        // One report, from rank 0 (the others are silent).
        EXPECT_EQ(count(r.output, "rendered 1 sensor(s)"), 1u) << r.output;
        EXPECT_TRUE(r.output.find("on " + std::to_string(ranks) + " MPI ranks") != std::string::npos) << r.output;
        expectSameFiles(dir_ / "one", out);  // the IR, the images and the probe tables
    }
}

// A progressive run of 10 passes (about 0.3 s each) on 2 ranks, stopped (SIGTERM to mpirun) once its
// checkpoint holds pass 2, and resumed on 3 ranks, equals the uninterrupted single-process run.
TEST_F(MpiRuns, ACheckpointOfTwoRanksResumesOnThreeAsTheUninterruptedRun) {
    expectResumedOnThreeRanksIsTheUninterruptedRender(build(photonScene(10, 200000)),
                                                      fs::path("progressive.checkpoint") / "state.json", "\"passes_done\": 2");
}

// A one-pass path-traced render on 2 ranks saves its finished tiles (rank 0 receives them); stopped
// once it has saved some and resumed on 3 ranks, it equals the uninterrupted single-process render.
TEST_F(MpiRuns, ATileCheckpointOfTwoRanksResumesOnThreeAsTheUninterruptedRender) {
    std::string scene = replacedOnce(pathScene(), "gsd_m: 0.5, width: 16, height: 12, samples_per_pixel: 4",
                                     "gsd_m: 0.125, width: 64, height: 48, samples_per_pixel: 24");
    scene = replacedOnce(scene, "target_relative_error: 0.3, max_samples_per_pixel: 16", "max_bounces: 64");
    const fs::path ir = build(scene);
    setenv("LITTORAL_CHECKPOINT_SECONDS", "0", 1);  // save after every chunk of tiles
    expectResumedOnThreeRanksIsTheUninterruptedRender(ir, fs::path("render.checkpoint") / "state.json",
                                                      "\"generation\": 2");
    unsetenv("LITTORAL_CHECKPOINT_SECONDS");
}

TEST_F(MpiRuns, BadInputIsReportedOnceAndCommandsWithoutRanksAreRefused) {
    const fs::path ir = build(pathScene());
    CommandResult r = runOnRanks(2, "-q render " + ir.string() + " --out " + (dir_ / "bad").string() + " --sensor nadri");
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_EQ(count(r.output, "--sensor: no sensor named 'nadri'"), 1u) << r.output;  // rank 0 reports, once
    EXPECT_EQ(count(r.output, "MPI_ABORT"), 0u) << r.output;  // the ranks agreed and ended cleanly
    EXPECT_FALSE(fs::exists(dir_ / "bad"));
    // A scene that rank 0 refuses while building it for `run`: the others learn of it and end alike.
    const fs::path bad = writeTextFile(dir_, "bad.yaml", replacedOnce(pathScene(), "zenith_deg: 30", "zenith_deg: 95"));
    r = runOnRanks(3, "-q run " + bad.string() + " --out " + (dir_ / "badrun").string());
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_EQ(count(r.output, "bad.yaml:2:19: error: sun.zenith_deg: 95 is out of range"), 1u) << r.output;
    EXPECT_EQ(count(r.output, "MPI_ABORT"), 0u) << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "badrun"));
    r = runOnRanks(2, "-q build " + (dir_ / "scene.yaml").string() + " --out " + (dir_ / "built").string());
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_EQ(count(r.output, "error: `littoral build` does not use MPI ranks (only run and render do): run it without "
                              "mpirun"),
              1u)
        << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "built"));
}

}  // namespace
