#pragma once
// Subcommands of `littoral` register themselves: each cmd_*.cpp in pipelines/ defines a static
// CommandRegistrar, and main() asks the registry to add every subcommand to the CLI11 app.
// The cmd_*.cpp files are compiled straight into the executable (not an archive), so the
// registrars are never dropped by the linker.
//
//   static littoral::CommandRegistrar registerWaves{"waves", [](CLI::App& app) {
//       auto* cmd = app.add_subcommand("waves", "Generate a wind-roughened sea surface");
//       auto opts = std::make_shared<WavesOptions>();
//       cmd->add_option("--wind", opts->wind, "...");
//       cmd->callback([opts] { littoral::setExitCode(runWaves(*opts)); });
//   }};
//
// Callbacks report user errors by throwing littoral::InputError (exit 1; main prints it) and
// return normally on success (exit 0) unless they call setExitCode().
#include <functional>
#include <string>
#include <vector>

// CLI11 costs about 10 s of compilation in each file that includes it: only the command files
// and main.cpp, which add options, include it.
namespace CLI {
class App;
}

namespace littoral {

using CommandSetup = std::function<void(CLI::App&)>;

struct CommandRegistrar {
    CommandRegistrar(std::string name, CommandSetup setup);
};

// Every registered subcommand, sorted by name (so --help is stable).
std::vector<std::pair<std::string, CommandSetup>>& commandRegistry();

// A command may set a non-zero exit status without throwing (e.g. check-mesh: 1 = invalid mesh).
void setExitCode(int code);
int exitCode();

// Global options every command sees (set by main before the callback runs).
struct GlobalOptions {
    bool stats = false;   // --stats: print named counters at exit
    bool quiet = false;   // --quiet: no progress output
};
GlobalOptions& globalOptions();

}  // namespace littoral
