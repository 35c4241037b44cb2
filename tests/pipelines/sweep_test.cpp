// Long runs that are killed and resumed. A progressive photon-map run killed (SIGKILL) after pass 2
// of 4 and resumed equals the uninterrupted run. `littoral sweep` (docs/sweeps.md): the 2 x 2
// example of the docs equals the four single runs
// made from hand-edited scene files, byte for byte, and is indexed; a sweep killed (SIGKILL) after
// two runs resumes with the others and keeps the finished ones; a Slurm job array, run task by
// task, gives the same folders; bad --vary options and foreign output folders are refused with a
// clear error and nothing written.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <thread>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>


#include "core/image_io.h"
#include "core/atomic_file.h"
#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using namespace littoral::testing_support;

namespace {

std::string quotedPath(const fs::path& p) { return "'" + p.string() + "'"; }

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

const fs::path kDoc = fs::path(LITTORAL_SOURCE_DIR) / "docs" / "sweeps.md";

// The docs' example: its scene (with sand.csv beside it) in `dir`, and its command's --vary options.
std::string docExample(const fs::path& dir) {
    const auto yaml = markdownBlocks(kDoc, "yaml"), sh = markdownBlocks(kDoc, "sh");
    EXPECT_FALSE(yaml.empty() || sh.empty());
    writeTextFile(dir, "study.yaml", yaml.at(0));
    writeTextFile(dir, "sand.csv", "# wavelength_um, reflectance\n0.3, 0.25\n0.6, 0.35\n0.9, 0.4\n");
    std::string cmd = sh.at(0);
    const std::string head = "littoral sweep study.yaml ", tail = " --out study\n";
    EXPECT_EQ(cmd.rfind(head, 0), 0u) << cmd;
    EXPECT_EQ(cmd.substr(cmd.size() - tail.size()), tail) << cmd;
    return cmd.substr(head.size(), cmd.size() - head.size() - tail.size());
}

// Every regular file under `dir`, relative to it, but for the sweep's own files.
std::set<std::string> outputFiles(const fs::path& dir) {
    std::set<std::string> s;
    for (auto it = fs::recursive_directory_iterator(dir); it != fs::recursive_directory_iterator(); ++it) {
        const std::string name = it->path().filename().string();
        if (it->is_regular_file() && name != "scene.yaml" && name != "sweep_run.json" && name != ".littoral.lock")
            s.insert(fs::relative(it->path(), dir).string());
    }
    return s;
}

std::vector<float> exrPixels(const fs::path& p) {
    littoral::imageio::Reader in(p);
    EXPECT_TRUE(in.ok()) << p << ": " << in.error();
    if (!in.ok()) return {};
    const auto& spec = in.header();
    std::vector<float> px(static_cast<size_t>(spec.width) * spec.height * spec.channels);
    EXPECT_TRUE(in.read(spec.channels, littoral::imageio::PixelType::Float, px.data())) << p;
    return px;
}

// validity.json without the build's wall-clock timings.
nlohmann::json withoutTimings(const fs::path& p) {
    auto j = nlohmann::json::parse(slurp(p));
    j.erase("seconds");
    return j;
}

// The outputs of two run folders are the same: the same files, each with the same bytes, but for
// the wall-clock records: an EXR's header holds the time it was written (its pixels are compared),
// validity.json the build's timings (the rest of it is compared).
void expectSameOutputs(const fs::path& a, const fs::path& b) {
    const auto fa = outputFiles(a), fb = outputFiles(b);
    EXPECT_EQ(fa, fb) << a << " vs " << b;
    EXPECT_GT(fa.size(), 5u);
    for (const auto& f : fa) {
        if (!fb.count(f)) continue;
        if (fs::path(f).extension() == ".exr") {
            // Bit for bit (the truth image's sky pixels are NaN, which == would call different).
            const auto pa = exrPixels(a / f), pb = exrPixels(b / f);
            EXPECT_TRUE(pa.size() == pb.size() && std::memcmp(pa.data(), pb.data(), pa.size() * sizeof(float)) == 0) << f;
        } else if (fs::path(f).filename() == "validity.json") {
            EXPECT_EQ(withoutTimings(a / f), withoutTimings(b / f)) << f;
        } else {
            EXPECT_TRUE(slurp(a / f) == slurp(b / f)) << f << " differs between " << a << " and " << b;
        }
    }
}

std::vector<std::vector<std::string>> csvRows(const fs::path& p) {
    std::istringstream in(slurp(p));
    std::vector<std::vector<std::string>> rows;
    std::string line;
    while (std::getline(in, line)) {
        std::vector<std::string> cells;
        std::stringstream ls(line);
        std::string c;
        while (std::getline(ls, c, ',')) cells.push_back(c);
        rows.push_back(cells);
    }
    return rows;
}

}  // namespace

// The docs' 2 x 2 example against four `littoral run`s of the scene edited by hand (the base
// scene's own text with the two values replaced), in another folder than the sweep's.
TEST(Sweep, TwoByTwoGridEqualsTheFourSingleRunsAndIsIndexed) {
    const fs::path dir = scratchDir("sweep", "two_by_two");
    const std::string vary = docExample(dir);
    EXPECT_EQ(vary, "--vary water.surface.roughness.wind_speed=3,6 --vary sun.zenith_deg=20,40");
    auto r = runLittoral(fmt::format("-q sweep {} {} --out {}", quotedPath(dir / "study.yaml"), vary, quotedPath(dir / "study")));
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("sweep of 4 run(s)"), std::string::npos) << r.output;
    const std::string base = slurp(dir / "study.yaml");
    const std::vector<std::pair<std::string, std::string>> points = {{"3", "20"}, {"3", "40"}, {"6", "20"}, {"6", "40"}};
    for (size_t i = 0; i < points.size(); ++i) {
        std::string text = replacedOnce(base, "roughness: {wind_speed: 5}", "roughness: {wind_speed: " + points[i].first + "}");
        text = replacedOnce(text, "zenith_deg: 30", "zenith_deg: " + points[i].second);
        // In a folder of its own, named scene.yaml as the run's is (the IR records the file's name),
        // with the material file beside it.
        const fs::path hand = dir / fmt::format("hand{}", i), single = hand / "out";
        const fs::path scene = writeTextFile(hand, "scene.yaml", text);
        fs::copy_file(dir / "sand.csv", hand / "sand.csv");
        const auto s = runLittoral(fmt::format("-q run {} --out {}", quotedPath(scene), quotedPath(single)));
        ASSERT_EQ(s.status, 0) << s.output;
        expectSameOutputs(dir / "study" / "runs" / fmt::format("{:04d}", i), single);
    }
    // The runs differ from one another (the values reached the renderer): the probe on the floor
    // sees the sun at 20 and at 40 degrees.
    EXPECT_NE(slurp(dir / "study/runs/0000/probes.csv"), slurp(dir / "study/runs/0001/probes.csv"));
    // index.csv: one row per run, the last --vary fastest, every run done.
    const auto rows = csvRows(dir / "study" / "index.csv");
    ASSERT_EQ(rows.size(), 5u);
    EXPECT_EQ(rows[0], (std::vector<std::string>{"run", "water.surface.roughness.wind_speed", "sun.zenith_deg", "status",
                                                 "folder", "seconds"}));
    for (size_t i = 0; i < points.size(); ++i) {
        ASSERT_EQ(rows[i + 1].size(), 6u);
        EXPECT_EQ(rows[i + 1][0], fmt::format("{:04d}", i));
        EXPECT_EQ(rows[i + 1][1], points[i].first);
        EXPECT_EQ(rows[i + 1][2], points[i].second);
        EXPECT_EQ(rows[i + 1][3], "done");
        EXPECT_EQ(rows[i + 1][4], fmt::format("runs/{:04d}", i));
    }
    // index.json: typed parameters and every output file of each run, each of which exists.
    const auto j = nlohmann::json::parse(slurp(dir / "study" / "index.json"));
    ASSERT_EQ(j["index"].size(), 4u);
    EXPECT_EQ(j["index"][3]["parameters"]["sun.zenith_deg"].get<double>(), 40);
    EXPECT_EQ(j["index"][3]["outputs"].size(), outputFiles(dir / "study/runs/0003").size());
    for (const auto& f : j["index"][3]["outputs"]) EXPECT_TRUE(fs::is_regular_file(dir / "study" / f.get<std::string>())) << f;
    // The run's scene file stands alone: its material file's path is absolute.
    EXPECT_NE(slurp(dir / "study/runs/0002/scene.yaml").find((dir / "sand.csv").string()), std::string::npos);
    // The same command again runs nothing and keeps every finished run as it was.
    const std::string marker = slurp(dir / "study/runs/0001/sweep_run.json");
    r = runLittoral(fmt::format("-q sweep {} {} --out {}", quotedPath(dir / "study.yaml"), vary, quotedPath(dir / "study")));
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("4 already done"), std::string::npos) << r.output;
    EXPECT_EQ(slurp(dir / "study/runs/0001/sweep_run.json"), marker);
}

namespace {

// The small scene of test_support.h with fewer volume photons, so that each run takes about a second.
std::string quickScene() { return replacedOnce(kSmallScene, "probe_samples: 64", "probe_samples: 64, photons: {volume: 50000}"); }

}  // namespace

// SIGKILL as soon as the second run is marked done; the sweep again resumes: the finished runs stay
// as they were (their markers unchanged), the others are made, and the run that was killed halfway
// equals a `littoral run` of its own scene file.
TEST(Sweep, KilledAfterTwoRunsResumesWithTheOthers) {
    const fs::path dir = scratchDir("sweep", "killed");
    const fs::path scene = writeTextFile(dir, "scene.yaml", quickScene()), out = dir / "study";
    const std::vector<std::string> args = {"-q", "sweep", scene.string(), "--vary", "sun.zenith_deg=10,20,30,40", "--out",
                                           out.string(), "--threads", "1"};
    const pid_t pid = spawnLittoral(args);
    ASSERT_GT(pid, 0);
    const auto t0 = std::chrono::steady_clock::now();
    while (!fs::exists(out / "runs/0001/sweep_run.json") && std::chrono::steady_clock::now() - t0 < std::chrono::minutes(3))
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    ::kill(pid, SIGKILL);
    int st = 0;
    waitpid(pid, &st, 0);
    ASSERT_TRUE(WIFSIGNALED(st));
    std::map<int, std::string> markers;
    for (int i = 0; i < 4; ++i)
        if (fs::exists(out / fmt::format("runs/{:04d}/sweep_run.json", i))) markers[i] = slurp(out / fmt::format("runs/{:04d}/sweep_run.json", i));
    ASSERT_TRUE(markers.count(0) && markers.count(1));
    ASSERT_LT(markers.size(), 4u) << "the runs were too quick for the kill to land before the last";
    const int killed = static_cast<int>(markers.size());  // the run that was rendering
    std::string cmd = "-q";
    for (size_t i = 1; i < args.size(); ++i) cmd += " " + quotedPath(args[i]);
    const auto r = runLittoral(cmd);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find(fmt::format("{} already done", markers.size())), std::string::npos) << r.output;
    for (const auto& [i, m] : markers) EXPECT_EQ(slurp(out / fmt::format("runs/{:04d}/sweep_run.json", i)), m) << i;
    for (int i = 0; i < 4; ++i) EXPECT_TRUE(fs::exists(out / fmt::format("runs/{:04d}/sweep_run.json", i))) << i;
    const fs::path runDir = out / fmt::format("runs/{:04d}", killed);
    const auto s = runLittoral(fmt::format("-q run {} --out {} --threads 2", quotedPath(runDir / "scene.yaml"), quotedPath(dir / "single")));
    ASSERT_EQ(s.status, 0) << s.output;
    expectSameOutputs(runDir, dir / "single");
    // Nothing the killed process was writing is left (its temporaries go with its lock).
    for (auto it = fs::recursive_directory_iterator(out); it != fs::recursive_directory_iterator(); ++it)
        EXPECT_EQ(it->path().filename().string().find(".tmp-"), std::string::npos) << it->path();
    EXPECT_EQ(csvRows(out / "index.csv").size(), 5u);
    for (const auto& row : csvRows(out / "index.csv")) EXPECT_TRUE(row.at(2) == "done" || row.at(2) == "status");
}

// --slurm writes the job array instead of running; each array task (the script run with
// SLURM_ARRAY_TASK_ID set, as Slurm does) renders its run; the sweep again then indexes them.
TEST(Sweep, SlurmJobArrayRunsTaskByTask) {
    const fs::path dir = scratchDir("sweep", "slurm");
    const fs::path scene = writeTextFile(dir, "scene.yaml", quickScene()), out = dir / "study";
    const std::string cmd = fmt::format("-q sweep {} --vary sun.zenith_deg=20,40 --out {}", quotedPath(scene), quotedPath(out));
    auto r = runLittoral(cmd + " --slurm");
    ASSERT_EQ(r.status, 0) << r.output;
    const std::string script = slurp(out / "sweep.sbatch");
    EXPECT_NE(script.find("#SBATCH --array=0-1\n"), std::string::npos) << script;
    EXPECT_FALSE(fs::exists(out / "runs/0000/sweep_run.json"));
    EXPECT_EQ(csvRows(out / "index.csv").at(1).at(2), "pending");
    for (int task = 0; task < 2; ++task) {
        const std::string sh = fmt::format("SLURM_ARRAY_TASK_ID={} SLURM_CPUS_PER_TASK=2 bash {} 2>&1", task, quotedPath(out / "sweep.sbatch"));
        ASSERT_EQ(std::system(sh.c_str()), 0) << sh;
        EXPECT_TRUE(fs::exists(out / fmt::format("runs/{:04d}/sweep_run.json", task)));
    }
    r = runLittoral(cmd);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("2 already done"), std::string::npos) << r.output;
    EXPECT_EQ(csvRows(out / "index.csv").at(2).at(2), "done");
    const auto s = runLittoral(fmt::format("-q run {} --out {}", quotedPath(out / "runs/0001/scene.yaml"), quotedPath(dir / "single")));
    ASSERT_EQ(s.status, 0) << s.output;
    expectSameOutputs(out / "runs/0001", dir / "single");
    // --slurm with --task would ignore one of them: refused.
    r = runLittoral(cmd + " --slurm --task 0");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("--task: error: --task runs one task of the array that --slurm writes"), std::string::npos)
        << r.output;
    // A task number outside the array is refused.
    r = runLittoral(cmd + " --task 2");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("--task: error: 2 is out of range; the sweep has runs 0 to 1"), std::string::npos) << r.output;
}

// Each bad --vary: exit 1, one clear error, and no sweep folder.
TEST(Sweep, BadVaryOptionsAreRefusedBeforeAnythingIsWritten) {
    const fs::path dir = scratchDir("sweep", "bad");
    const fs::path scene = writeTextFile(dir, "scene.yaml", kSmallScene), out = dir / "study";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"sun.zenit_deg=10,20", "did you mean 'zenith_deg'"},
        {"sun.zenith_deg=10,95", "95 is out of range"},
        {"sun.zenith_deg=10,95", "(in sweep run 0001: sun.zenith_deg=95)"},
        {"nosuch.key=1,2", "--vary nosuch.key=1,2: error: the scene file has no 'nosuch'"},
        {"sensors[3].gsd_m=1,2", "'sensors[3]' is not in the scene file (sensors is a list of 1)"},
        {"sun=1,2", "'sun' holds a map of keys in the scene file; a sweep varies single values"},
        {"sun.zenith_deg", "expected KEY=V1,V2,..."},
        {"sun.zenith_deg=10,,20", "a value is empty"},
        {"sun.zenith_deg=10,10", "value '10' is listed twice"},
        {"sun.zenith_deg=[1 2]", "is not a single value"},
        {"sun..zenith_deg=1", "has an empty part"},
        {"sensors[x].gsd_m=1", "has a malformed index"},
    };
    for (const auto& [vary, message] : cases) {
        const auto r = runLittoral(fmt::format("-q sweep {} --vary {} --out {}", quotedPath(scene), quotedPath(vary), quotedPath(out)));
        EXPECT_EQ(r.status, 1) << vary << ": " << r.output;
        EXPECT_NE(r.output.find(message), std::string::npos) << vary << ": " << r.output;
        EXPECT_FALSE(fs::exists(out)) << vary;
    }
    // The same key twice.
    auto r = runLittoral(fmt::format("-q sweep {} --vary sun.zenith_deg=1 --vary sun.zenith_deg=2 --out {}", quotedPath(scene), quotedPath(out)));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("the key is varied twice"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
}

// A folder that is not this sweep's: files without a plan, another sweep, or a base scene edited
// since the sweep began. Each is refused and left as it was.
TEST(Sweep, AFolderHoldingSomethingElseIsRefused) {
    const fs::path dir = scratchDir("sweep", "foreign");
    const fs::path scene = writeTextFile(dir, "scene.yaml", kSmallScene), out = dir / "study";
    // The scene's own folder: it holds the scene, and no plan.
    auto r = runLittoral(fmt::format("-q sweep {} --vary sun.zenith_deg=10 --out {}", quotedPath(scene), quotedPath(dir)));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("the folder holds files but no sweep.json"), std::string::npos) << r.output;
    std::set<std::string> left;
    for (const auto& e : fs::directory_iterator(dir)) left.insert(e.path().filename().string());
    EXPECT_EQ(left, (std::set<std::string>{"scene.yaml"}));
    ASSERT_EQ(runLittoral(fmt::format("-q sweep {} --vary sun.zenith_deg=10 --out {} --slurm", quotedPath(scene), quotedPath(out))).status, 0);
    const auto before = outputFiles(out);
    r = runLittoral(fmt::format("-q sweep {} --vary sun.zenith_deg=20 --out {}", quotedPath(scene), quotedPath(out)));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("--out holds another sweep"), std::string::npos) << r.output;
    writeTextFile(dir, "scene.yaml", replacedOnce(kSmallScene, "irradiance: 1000", "irradiance: 900"));
    r = runLittoral(fmt::format("-q sweep {} --vary sun.zenith_deg=10 --out {}", quotedPath(scene), quotedPath(out)));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("runs/0000/scene.yaml: error: this run's scene differs"), std::string::npos) << r.output;
    EXPECT_EQ(outputFiles(out), before);
}

// A 4-pass progressive photon-map run with 4 samples per pixel (so its standard-error image is in
// the checkpoint too), killed as soon as the checkpoint says pass 2 is done, then `run --resume`:
// every output equals the uninterrupted run's (EXR pixels, validity.json but for its timings).
TEST(Resume, ProgressiveRunKilledAfterPassTwoOfFourEqualsTheUninterruptedRun) {
    const fs::path dir = scratchDir("sweep", "resume");
    std::string text = replacedOnce(kSmallScene, "materials: [{name: floor, reflectance: 0.2}]",
                                    "materials: [{name: floor, reflectance: 0.2, solver: surface-pm}]");
    text = replacedOnce(text, "width: 16, height: 12", "width: 16, height: 12, samples_per_pixel: 4");
    text = replacedOnce(text, "probe_samples: 64",
                        "probe_samples: 64, photons: {surface: 100000, volume: 100000}, progressive: {passes: 4}");
    const fs::path scene = writeTextFile(dir, "scene.yaml", text), out = dir / "killed";
    const pid_t pid = spawnLittoral({"-q", "run", scene.string(), "--out", out.string(), "--threads", "1"});
    ASSERT_GT(pid, 0);
    const fs::path state = out / "progressive.checkpoint" / "state.json";
    const auto t0 = std::chrono::steady_clock::now();
    while (std::chrono::steady_clock::now() - t0 < std::chrono::minutes(3)) {
        if (fs::exists(state) && slurp(state).find("\"passes_done\": 2") != std::string::npos) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    ::kill(pid, SIGKILL);
    int st = 0;
    waitpid(pid, &st, 0);
    ASSERT_TRUE(WIFSIGNALED(st)) << "the run ended before it could be killed";
    ASSERT_NE(slurp(state).find("\"passes_done\": 2"), std::string::npos) << slurp(state);
    ASSERT_FALSE(fs::exists(out / "nadir.img"));
    auto r = runLittoral(fmt::format("-q run {} --out {} --resume", quotedPath(scene), quotedPath(out)));
    ASSERT_EQ(r.status, 0) << r.output;
    r = runLittoral(fmt::format("-q run {} --out {}", quotedPath(scene), quotedPath(dir / "whole")));
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(fs::exists(out / "nadir_stderr.img"));
    expectSameOutputs(out, dir / "whole");
}

// A path-traced run (one pass), saving after every chunk of tiles (LITTORAL_CHECKPOINT_SECONDS=0),
// killed once its checkpoint holds some finished tiles but not all,
// then `run --resume`: it renders only the other tiles, and every output equals the uninterrupted
// run's. Two sensors, so that the kill can fall in either.
TEST(Resume, PathTracedRunKilledMidRenderEqualsTheUninterruptedRun) {
    const fs::path dir = scratchDir("sweep", "resume_path");
    std::string text = replacedOnce(kSmallScene, "width: 16, height: 12",
                                    "width: 64, height: 48, samples_per_pixel: 64}\n  - {name: oblique, type: frame, "
                                    "elevation_deg: 60, azimuth_deg: 90, range_m: 50, gsd_m: 0.5, width: 32, height: 24");
    text = replacedOnce(text, "probe_samples: 64, hemisphere_samples: 4", "estimator: path, probe_samples: 64");
    const fs::path scene = writeTextFile(dir, "scene.yaml", text), out = dir / "killed";
    ASSERT_EQ(runLittoral("-q check-scene " + quotedPath(scene)).status, 0);
    setenv("LITTORAL_CHECKPOINT_SECONDS", "0", 1);  // save after every chunk of tiles
    const pid_t pid = spawnLittoral({"-q", "run", scene.string(), "--out", out.string(), "--threads", "1"});
    unsetenv("LITTORAL_CHECKPOINT_SECONDS");
    ASSERT_GT(pid, 0);
    const fs::path state = out / "render.checkpoint" / "state.json";
    // Kill once the checkpoint has been saved at least three times. Under a loaded machine the
    // poll may miss generation 3 itself, so any later one counts; a run that ends first is
    // reported at once instead of after the timeout.
    auto generation = [&] {
        const std::string t = fs::exists(state) ? slurp(state) : std::string();
        const auto k = t.find("\"generation\": ");
        return k == std::string::npos ? -1 : std::atoi(t.c_str() + k + 14);
    };
    int st = 0;
    bool exited = false;
    const auto t0 = std::chrono::steady_clock::now();
    while (std::chrono::steady_clock::now() - t0 < std::chrono::minutes(3)) {
        if (generation() >= 3) break;
        if (waitpid(pid, &st, WNOHANG) == pid) {
            exited = true;
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    if (!exited) {
        ::kill(pid, SIGKILL);
        waitpid(pid, &st, 0);
    }
    ASSERT_TRUE(WIFSIGNALED(st)) << "the run ended before it could be killed";
    const std::string saved = slurp(state);
    ASSERT_NE(saved.find('1'), std::string::npos) << saved;
    ASSERT_FALSE(fs::exists(out / "nadir.img"));
    auto r = runLittoral(fmt::format("-q run {} --out {} --resume", quotedPath(scene), quotedPath(out)));
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_FALSE(fs::exists(out / "render.checkpoint")) << "a finished run keeps no checkpoint";
    r = runLittoral(fmt::format("-q run {} --out {}", quotedPath(scene), quotedPath(dir / "whole")));
    ASSERT_EQ(r.status, 0) << r.output;
    expectSameOutputs(out, dir / "whole");
    // A checkpoint of another scene is refused with the reason.
    fs::create_directories(out / "render.checkpoint");
    writeTextFile(out / "render.checkpoint", "state.json",
                  "{\"format\": \"littoral-tile-checkpoint\", \"ir_hash\": \"1\", \"sensor\": \"\", \"generation\": 1, "
                  "\"sensors\": []}\n");
    r = runLittoral(fmt::format("-q run {} --out {} --resume", quotedPath(scene), quotedPath(out)));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("render.checkpoint/state.json: error: --resume: the checkpoint was made by a different scene"),
              std::string::npos) << r.output;
}
