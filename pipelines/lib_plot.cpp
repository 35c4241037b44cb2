#include "pipelines/lib_plot.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <fcntl.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "pipelines/plot_script.h"

extern char** environ;

namespace littoral::pipelines {

namespace fs = std::filesystem;

namespace {

nlohmann::json numbers(const std::vector<double>& v) {
    nlohmann::json a = nlohmann::json::array();
    for (double x : v) a.push_back(std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr));
    return a;
}

nlohmann::json chartJson(const Chart& c) {
    nlohmann::json j = {{"file", c.file},          {"title", c.spec.title}, {"xlabel", c.spec.xLabel},
                        {"ylabel", c.spec.yLabel}, {"logx", c.spec.logX},   {"logy", c.spec.logY},
                        {"invert_y", c.spec.invertY}};
    j["series"] = nlohmann::json::array();
    for (const auto& s : c.spec.series)
        j["series"].push_back({{"label", s.label},
                               {"x", numbers(s.x)},
                               {"y", numbers(s.y)},
                               {"yerr", numbers(s.yErr)},
                               {"markers", s.markers},
                               {"dashed", s.dashed},
                               {"line", s.line},
                               {"colour", s.colour}});
    return j;
}

std::string interpreter() {
    if (const char* e = std::getenv("LITTORAL_PYTHON"); e && *e) return e;
    if (access("/usr/bin/python3", X_OK) == 0) return "/usr/bin/python3";
    return "python3";
}

// A private scratch folder, removed when this goes out of scope.
struct ScratchFolder {
    fs::path path;
    ScratchFolder() {
        std::string t = (fs::temp_directory_path() / "littoral-plots-XXXXXX").string();
        if (!mkdtemp(t.data())) throw InputError(fmt::format("cannot make a scratch folder for the plots: {}", std::strerror(errno)));
        path = t;
    }
    ~ScratchFolder() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

// Runs `python script data` with stdout and stderr into `log`; the exit status, or -1 if the
// interpreter could not be started.
int runScript(const std::string& python, const fs::path& script, const fs::path& data, const fs::path& log) {
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
    posix_spawn_file_actions_addclose(&fa, 0);
    std::string a0 = python, a1 = script.string(), a2 = data.string();
    char* argv[] = {a0.data(), a1.data(), a2.data(), nullptr};
    pid_t pid = 0;
    const int rc = posix_spawnp(&pid, python.c_str(), &fa, nullptr, argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) return -1;
    int status = 0;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

// A scratch file's bytes. Not readTextFile: that notes the file as one of the command's inputs, and
// a later output given the deleted scratch file's inode would then be refused as overwriting it.
std::string scratchBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string lastLine(const std::string& text) {
    std::string t = text;
    while (!t.empty() && (t.back() == '\n' || t.back() == '\r')) t.pop_back();
    const auto nl = t.rfind('\n');
    return nl == std::string::npos ? t : t.substr(nl + 1);
}

}  // namespace

std::string drawCharts(const fs::path& folder, const std::vector<Chart>& charts) {
    nlohmann::json all = nlohmann::json::array();
    for (const auto& c : charts) all.push_back(chartJson(c));
    const std::string data = all.dump(1) + "\n";
    writeTextFileAtomic(folder / "charts.json", data);
    writeTextFileAtomic(folder / "littoral_plots.py", kPlotScript);
    if (charts.empty()) return "";

    const ScratchFolder scratch;
    {
        const OutputSetPause pause;  // scratch files, outside every output folder
        writeTextFileAtomic(scratch.path / "littoral_plots.py", kPlotScript);
        writeTextFileAtomic(scratch.path / "charts.json", data);
    }
    const std::string python = interpreter();
    const int rc = runScript(python, scratch.path / "littoral_plots.py", scratch.path / "charts.json", scratch.path / "log.txt");
    std::error_code ec;
    const std::string log = scratchBytes(scratch.path / "log.txt");
    if (rc == -1) return fmt::format("plots not drawn: cannot start {} (install python3-matplotlib)", python);
    if (rc != 0) {
        if (log.find("No module named 'matplotlib'") != std::string::npos)
            return fmt::format("plots not drawn: {} has no matplotlib (apt-get install python3-matplotlib)", python);
        return fmt::format("plots not drawn: {} exited with {}: {}", python, rc, lastLine(log));
    }
    for (const auto& c : charts) {
        const fs::path png = scratch.path / c.file;
        if (!fs::is_regular_file(png, ec)) return fmt::format("plots not drawn: {} did not write {}", python, c.file);
        writeFileAtomic(folder / c.file, scratchBytes(png));
    }
    return "";
}

}  // namespace littoral::pipelines
