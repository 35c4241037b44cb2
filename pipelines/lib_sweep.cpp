#include "pipelines/lib_sweep.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <variant>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include "core/atomic_file.h"
#include "pipelines/lib_scene.h"
#include "scenegen/scene_file.h"
#include "scenegen/yaml_reader.h"

namespace littoral::pipelines {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr size_t kMaxRuns = 100000;
constexpr const char* kMarker = "sweep_run.json";  // written last: the run is complete

std::string trim(std::string s) {
    const auto b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
    return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

[[noreturn]] void refuseAxis(const std::string& option, const std::string& why) {
    throw InputError(SourceLoc{"--vary " + option}, why);
}

// "water.surface.wind_speed" -> {water, surface, wind_speed}; "sensors[0].gsd_m" -> {sensors, 0, gsd_m}.
using KeyStep = std::variant<std::string, size_t>;
std::vector<KeyStep> keySteps(const std::string& option, const std::string& key) {
    std::vector<KeyStep> steps;
    size_t i = 0;
    const auto bad = [&](const std::string& what) {
        refuseAxis(option, fmt::format("key '{}' {}; a key is a dotted path such as water.surface.wind_speed or "
                                       "sensors[0].gsd_m", key, what));
    };
    while (i < key.size()) {
        if (key[i] == '[') {
            const size_t close = key.find(']', i);
            const std::string digits = close == std::string::npos ? "" : key.substr(i + 1, close - i - 1);
            if (digits.empty() || digits.size() > 6 || !std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c) != 0; }))
                bad("has a malformed index");
            steps.emplace_back(static_cast<size_t>(std::stoul(digits)));
            i = close + 1;
            if (i < key.size() && key[i] == '.') ++i;
            continue;
        }
        size_t end = key.find_first_of(".[", i);
        if (end == std::string::npos) end = key.size();
        if (end == i) bad("has an empty part");
        steps.emplace_back(key.substr(i, end - i));
        i = end;
        if (i < key.size() && key[i] == '.') {
            if (++i == key.size()) bad("ends with '.'");
        }
    }
    if (steps.empty()) bad("is empty");
    return steps;
}

std::string stepName(const KeyStep& s) {
    return s.index() == 0 ? std::get<0>(s) : fmt::format("[{}]", std::get<1>(s));
}

// Sets `value` at `key` in the scene document. Every part of the path but the last must exist; the
// last may be absent from its map (a key left at its default), but not a map or a list itself.
void setAtKey(YAML::Node root, const std::string& option, const std::string& key, const std::string& value) {
    const auto steps = keySteps(option, key);
    YAML::Node node = root;
    std::string where;
    for (size_t i = 0; i < steps.size(); ++i) {
        const bool last = i + 1 == steps.size();
        const std::string here = where.empty() ? stepName(steps[i]) : where + (steps[i].index() == 0 ? "." : "") +
                                                                          stepName(steps[i]);
        if (steps[i].index() == 0) {
            if (!node.IsMap())
                refuseAxis(option, fmt::format("'{}' is not a map of keys in the scene file, so it has no key '{}'",
                                               where, std::get<0>(steps[i])));
            const YAML::Node& cnode = node;  // a const lookup does not create the key
            const YAML::Node child = cnode[std::get<0>(steps[i])];
            if (!child.IsDefined() && !last)
                refuseAxis(option, fmt::format("the scene file has no '{}' (vary a key whose section is written "
                                               "in the scene file)", here));
            if (last && !child.IsDefined()) {
                node[std::get<0>(steps[i])] = value;  // a new key: its section's parser checks it
                return;
            }
            node.reset(child);
        } else {
            const size_t idx = std::get<1>(steps[i]);
            if (!node.IsSequence() || idx >= node.size())
                refuseAxis(option, fmt::format("'{}' is not in the scene file ({} is {})", here, where.empty() ? "the scene" : where,
                                               node.IsSequence() ? fmt::format("a list of {}", node.size()) : "not a list"));
            node.reset(node[idx]);
        }
        where = here;
    }
    if (node.IsMap() || node.IsSequence())
        refuseAxis(option, fmt::format("'{}' holds a {} in the scene file; a sweep varies single values", key,
                                       node.IsMap() ? "map of keys" : "list"));
    node = value;  // keeps the entry's line and column for error messages
}

// The scene's paths rewritten as absolute ones, so that DIR/runs/NNNN/scene.yaml runs on its own.
std::string selfContained(const scenegen::YamlNode& root, const fs::path& baseDir) {
    for (YAML::Node n : root.pathNodes()) {
        const fs::path p(n.Scalar());
        if (!p.is_absolute()) n = fs::absolute(baseDir / p).lexically_normal().string();
    }
    YAML::Emitter e;
    e << root.yaml();
    return std::string(e.c_str()) + "\n";
}

std::string pointLabel(const std::vector<SweepAxis>& axes, const std::vector<std::string>& values) {
    std::string s;
    for (size_t a = 0; a < axes.size(); ++a) s += fmt::format("{}{}={}", a ? ", " : "", axes[a].key, values[a]);
    return s;
}

std::string runName(size_t i, size_t n) {
    const int width = std::max<int>(4, static_cast<int>(fmt::format("{}", n ? n - 1 : 0).size()));
    return fmt::format("{:0{}}", i, width);
}

// A value as the index shows it: a number where the YAML scalar is one, else its text.
json typedValue(const std::string& v) {
    char* end = nullptr;
    const double d = std::strtod(v.c_str(), &end);
    if (!v.empty() && end == v.c_str() + v.size() && std::isfinite(d)) return d;
    if (v == "true" || v == "false") return v == "true";
    return v;
}

json planJson(const SweepOptions& o, const std::vector<SweepAxis>& axes, size_t nRuns) {
    json j;
    j["scene"] = fs::absolute(o.scene).lexically_normal().string();
    j["axes"] = json::array();
    for (const auto& a : axes) j["axes"].push_back({{"key", a.key}, {"values", a.values}});
    j["runs"] = nRuns;
    return j;
}

}  // namespace

SweepAxis parseSweepAxis(const std::string& option) {
    const auto eq = option.find('=');
    if (eq == std::string::npos) refuseAxis(option, "expected KEY=V1,V2,... (for example water.surface.wind_speed=3,6,9)");
    SweepAxis a{option, trim(option.substr(0, eq)), {}};
    if (a.key.empty()) refuseAxis(option, "the key before '=' is empty");
    keySteps(option, a.key);  // checks its form
    const std::string list = option.substr(eq + 1);
    size_t start = 0;
    while (true) {
        const size_t comma = list.find(',', start);
        const std::string v = trim(list.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
        if (v.empty()) refuseAxis(option, "a value is empty (values are separated by commas)");
        YAML::Node parsed;
        try {
            parsed = YAML::Load(v);
        } catch (const YAML::Exception& e) {
            refuseAxis(option, fmt::format("value '{}' is not a YAML value: {}", v, e.msg));
        }
        if (!parsed.IsScalar())
            refuseAxis(option, fmt::format("value '{}' is not a single value (null, a list or a map); a sweep varies "
                                           "single values", v));
        if (std::find(a.values.begin(), a.values.end(), v) != a.values.end())
            refuseAxis(option, fmt::format("value '{}' is listed twice", v));
        a.values.push_back(v);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return a;
}

std::vector<SweepRun> expandSweep(const std::string& sceneFile, const std::vector<SweepAxis>& axes) {
    size_t n = 1;
    for (size_t a = 0; a < axes.size(); ++a) {
        for (size_t b = 0; b < a; ++b)
            if (axes[b].key == axes[a].key) refuseAxis(axes[a].option, "the key is varied twice; list all its values in one --vary");
        n *= axes[a].values.size();
        if (n > kMaxRuns)
            throw InputError(SourceLoc{"--vary"}, fmt::format("the grid has more than {} runs; split the study into "
                                                              "several sweeps", kMaxRuns));
    }
    const fs::path baseDir = fs::absolute(sceneFile).parent_path();
    std::vector<SweepRun> runs;
    for (size_t i = 0; i < n; ++i) {
        SweepRun r;
        size_t rest = i;
        r.values.resize(axes.size());
        for (size_t a = axes.size(); a-- > 0;) {  // the last axis varies fastest
            r.values[a] = axes[a].values[rest % axes[a].values.size()];
            rest /= axes[a].values.size();
        }
        const scenegen::YamlNode root = scenegen::YamlNode::loadFile(sceneFile);
        for (size_t a = 0; a < axes.size(); ++a)
            setAtKey(root.yaml(), axes[a].option, axes[a].key, r.values[a]);
        try {
            checkRenderSettings(scenegen::parseScene(root, sceneFile));
        } catch (const InputError& e) {
            throw InputError(e.where(), fmt::format("{} (in sweep run {}: {})", e.message(), runName(i, n),
                                                    pointLabel(axes, r.values)));
        }
        r.sceneYaml = selfContained(root, baseDir);
        runs.push_back(std::move(r));
    }
    return runs;
}

namespace {

struct SweepState {
    const SweepOptions& o;
    std::vector<SweepAxis> axes;
    std::vector<SweepRun> runs;
    fs::path out;
    fs::path runDir(size_t i) const { return out / "runs" / runName(i, runs.size()); }
    bool done(size_t i) const { return fs::is_regular_file(runDir(i) / kMarker); }
};

// Refuses an --out that holds something other than this sweep: files without a sweep.json, another
// sweep's plan, or a run folder whose scene differs from this sweep's (the base scene was edited).
void checkOutFolder(const SweepState& s, const json& plan) {
    std::error_code ec;
    const fs::path planFile = s.out / "sweep.json";
    if (!fs::exists(planFile, ec)) {
        for (const auto& e : fs::directory_iterator(s.out, ec))
            if (e.path().filename() != OutputFolderLock::kFileName)
                throw InputError(SourceLoc{s.out.string()}, "--out: the folder holds files but no sweep.json, so it is "
                                                            "not a sweep's folder; choose a new or empty folder");
        return;
    }
    json old;
    try {
        old = json::parse(readTextFile(planFile));
    } catch (const json::exception& e) {
        throw InputError(SourceLoc{planFile.string()}, std::string("unreadable sweep plan: ") + e.what());
    }
    if (old != plan)
        throw InputError(SourceLoc{planFile.string()},
                         "--out holds another sweep (another scene file or other --vary values); choose another "
                         "folder, or repeat that sweep's command to resume it");
    for (size_t i = 0; i < s.runs.size(); ++i) {
        const fs::path f = s.runDir(i) / "scene.yaml";
        if (fs::exists(f, ec) && readTextFile(f) != s.runs[i].sceneYaml)
            throw InputError(SourceLoc{f.string()},
                             "this run's scene differs from what the sweep now makes (the scene file or a file it "
                             "names changed since the sweep began); choose another --out to sweep the new scene");
    }
}

// Removes what an unfinished run left (a killed or failed run), keeping its scene.yaml.
void clearUnfinished(const fs::path& dir) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) return;
    for (const auto& e : fs::directory_iterator(dir)) {
        const auto name = e.path().filename();
        if (name == "scene.yaml" || name == OutputFolderLock::kFileName) continue;
        fs::remove_all(e.path());
    }
}

std::vector<std::string> runOutputs(const SweepState& s, size_t i) {
    std::vector<std::string> files;
    const fs::path dir = s.runDir(i);
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(dir, ec); it != fs::recursive_directory_iterator(); ++it) {
        const auto name = it->path().filename();
        if (!it->is_regular_file() || name == OutputFolderLock::kFileName || name == kMarker ||
            it->path() == dir / "scene.yaml")
            continue;
        files.push_back(it->path().lexically_relative(s.out).generic_string());
    }
    std::sort(files.begin(), files.end());
    return files;
}

std::string csvField(const std::string& v) {
    if (v.find_first_of(",\"\n") == std::string::npos) return v;
    std::string q = "\"";
    for (char c : v) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}

// index.csv (one row per run: its parameters, status, folder and time) and index.json (the same,
// with every output file of each finished run).
void writeIndex(const SweepState& s) {
    std::string csv = "run";
    for (const auto& a : s.axes) csv += "," + csvField(a.key);
    csv += ",status,folder,seconds\n";
    json j = planJson(s.o, s.axes, s.runs.size());
    j["index"] = json::array();
    for (size_t i = 0; i < s.runs.size(); ++i) {
        const bool done = s.done(i);
        double seconds = 0;
        if (done) seconds = json::parse(readTextFile(s.runDir(i) / kMarker)).value("seconds", 0.0);
        const std::string folder = s.runDir(i).lexically_relative(s.out).generic_string();
        csv += runName(i, s.runs.size());
        json params = json::object();
        for (size_t a = 0; a < s.axes.size(); ++a) {
            csv += "," + csvField(s.runs[i].values[a]);
            params[s.axes[a].key] = typedValue(s.runs[i].values[a]);
        }
        csv += fmt::format(",{},{},{}\n", done ? "done" : "pending", csvField(folder), done ? fmt::format("{:.2f}", seconds) : "");
        json row = {{"run", runName(i, s.runs.size())}, {"folder", folder}, {"parameters", params},
                    {"status", done ? "done" : "pending"}, {"scene", folder + "/scene.yaml"}};
        if (done) row["seconds"] = seconds, row["outputs"] = runOutputs(s, i);
        j["index"].push_back(row);
    }
    writeTextFileAtomic(s.out / "index.csv", csv);
    writeTextFileAtomic(s.out / "index.json", j.dump(2) + "\n");
}

std::string shellQuoted(const std::string& v) {
    std::string q = "'";
    for (char c : v) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

// DIR/sweep.sbatch: one array task per run, each `littoral sweep ... --task $SLURM_ARRAY_TASK_ID`.
std::string slurmScript(const SweepState& s) {
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    std::string cmd = shellQuoted(ec ? std::string("littoral") : exe.string()) + " -q sweep " +
                      shellQuoted(fs::absolute(s.o.scene).lexically_normal().string());
    for (const auto& a : s.axes) {
        std::string v;
        for (const auto& x : a.values) v += (v.empty() ? "" : ",") + x;
        cmd += " --vary " + shellQuoted(a.key + "=" + v);
    }
    const fs::path outAbs = fs::absolute(s.out).lexically_normal();
    cmd += " --out " + shellQuoted(outAbs.string()) + " --task \"$SLURM_ARRAY_TASK_ID\" --threads \"${SLURM_CPUS_PER_TASK:-0}\"";
    return fmt::format(
        "#!/bin/bash\n"
        "# A Slurm job array for the sweep in this folder: one task per run (docs/sweeps.md).\n"
        "# Submit with `sbatch {0}/sweep.sbatch`; when the array has finished, repeat the sweep command\n"
        "# without --slurm: it finds every run done and writes index.csv and index.json.\n"
        "#SBATCH --job-name=littoral-sweep\n"
        "#SBATCH --array=0-{1}\n"
        "#SBATCH --ntasks=1\n"
        "#SBATCH --cpus-per-task={2}\n"
        "#SBATCH --output={0}/logs/run-%a.log\n"
        "set -euo pipefail\n"
        "exec {3}\n",
        outAbs.string(), s.runs.size() - 1, s.o.threads > 0 ? s.o.threads : 2, cmd);
}

// Runs run i into its folder (locked, cleared of an unfinished attempt) and marks it done.
double runOne(const SweepState& s, size_t i) {
    const fs::path dir = s.runDir(i);
    const OutputFolderLock lock(dir);
    if (s.done(i)) return 0;  // another process finished it meanwhile
    clearUnfinished(dir);
    const auto t0 = std::chrono::steady_clock::now();
    RunOptions ro;
    ro.scene = (dir / "scene.yaml").string();
    ro.out = dir.string();
    ro.threads = s.o.threads;
    ro.progress = s.o.progress;
    ro.preview = s.o.preview;
    try {
        runScene(ro);
    } catch (const InputError& e) {
        throw InputError(e.where(), fmt::format("{} (in sweep run {}: {})", e.message(), runName(i, s.runs.size()),
                                                pointLabel(s.axes, s.runs[i].values)));
    }
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    json m = {{"run", runName(i, s.runs.size())}, {"seconds", sec}, {"parameters", json::object()}};
    for (size_t a = 0; a < s.axes.size(); ++a) m["parameters"][s.axes[a].key] = typedValue(s.runs[i].values[a]);
    writeTextFileAtomic(dir / kMarker, m.dump(2) + "\n");
    publishStagedOutputs();  // this run is complete whatever happens to the next
    return sec;
}

// Writes the plan, the run folders' scene files and the index (publishing them), unless they are
// already there from an earlier start of the same sweep.
void writePlan(const SweepState& s, const json& plan) {
    if (!fs::exists(s.out / "sweep.json")) writeTextFileAtomic(s.out / "sweep.json", plan.dump(2) + "\n");
    for (size_t i = 0; i < s.runs.size(); ++i)
        if (!fs::exists(s.runDir(i) / "scene.yaml")) writeTextFileAtomic(s.runDir(i) / "scene.yaml", s.runs[i].sceneYaml);
    writeIndex(s);
    publishStagedOutputs();
}

std::string runLocally(SweepState& s) {
    std::vector<size_t> todo;
    for (size_t i = 0; i < s.runs.size(); ++i)
        if (!s.done(i)) todo.push_back(i);
    std::string summary = fmt::format("sweep of {} run(s) -> {}: {} already done\n", s.runs.size(), s.out.string(),
                                      s.runs.size() - todo.size());
    double spent = 0;
    for (size_t k = 0; k < todo.size(); ++k) {
        const size_t i = todo[k];
        if (s.o.progress) {
            const std::string eta = k ? fmt::format(", about {:.0f} s left", spent / k * (todo.size() - k)) : "";
            std::fprintf(stderr, "sweep: run %s (%zu of %zu to do%s): %s\n", runName(i, s.runs.size()).c_str(), k + 1,
                         todo.size(), eta.c_str(), pointLabel(s.axes, s.runs[i].values).c_str());
        }
        const double sec = runOne(s, i);
        spent += sec;
        summary += fmt::format("  {} ({:.1f} s): {}\n", s.runDir(i).string(), sec, pointLabel(s.axes, s.runs[i].values));
        writeIndex(s);
        publishStagedOutputs();
    }
    summary += fmt::format("index: {} and {}\n", (s.out / "index.csv").string(), (s.out / "index.json").string());
    return summary;
}

}  // namespace

std::string runSweep(const SweepOptions& o) {
    if (o.vary.empty()) throw InputError(SourceLoc{"--vary"}, "a sweep needs at least one --vary KEY=V1,V2,...");
    if (o.slurm && o.task >= 0)
        throw InputError(SourceLoc{"--task"}, "--task runs one task of the array that --slurm writes; give one or the other");
    SweepState s{o, {}, {}, fs::path(o.out)};
    for (const auto& v : o.vary) s.axes.push_back(parseSweepAxis(v));
    s.runs = expandSweep(o.scene, s.axes);
    const json plan = planJson(o, s.axes, s.runs.size());
    if (o.task >= 0) {
        // One Slurm array task: the plan must be the one the --slurm invocation wrote.
        if (o.task >= static_cast<long long>(s.runs.size()))
            throw InputError(SourceLoc{"--task"}, fmt::format("{} is out of range; the sweep has runs 0 to {}", o.task,
                                                              s.runs.size() - 1));
        if (!fs::exists(s.out / "sweep.json"))
            throw InputError(SourceLoc{s.out.string()}, "--task: the folder holds no sweep.json; write the sweep first "
                                                        "(the same command with --slurm instead of --task)");
        checkOutFolder(s, plan);
        const double sec = runOne(s, static_cast<size_t>(o.task));
        const auto task = static_cast<size_t>(o.task);
        return fmt::format("sweep run {} ({:.1f} s) -> {}\n", runName(task, s.runs.size()), sec, s.runDir(task).string());
    }
    const OutputFolderLock lock(s.out);
    checkOutFolder(s, plan);
    writePlan(s, plan);
    if (o.slurm) {
        writeTextFileAtomic(s.out / "sweep.sbatch", slurmScript(s));
        return fmt::format("sweep of {} run(s): wrote {} (submit it with sbatch) and the run folders under {}\n",
                           s.runs.size(), (s.out / "sweep.sbatch").string(), (s.out / "runs").string());
    }
    return runLocally(s);
}

}  // namespace littoral::pipelines
