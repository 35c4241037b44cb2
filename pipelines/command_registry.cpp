#include "pipelines/command_registry.h"

#include <algorithm>

namespace littoral {

std::vector<std::pair<std::string, CommandSetup>>& commandRegistry() {
    static std::vector<std::pair<std::string, CommandSetup>> r;
    return r;
}

CommandRegistrar::CommandRegistrar(std::string name, CommandSetup setup) {
    auto& r = commandRegistry();
    r.emplace_back(std::move(name), std::move(setup));
    std::sort(r.begin(), r.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
}

namespace {
int gExit = 0;
}
void setExitCode(int code) { gExit = code; }
int exitCode() { return gExit; }

GlobalOptions& globalOptions() {
    static GlobalOptions g;
    return g;
}

}  // namespace littoral
