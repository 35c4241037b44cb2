// The `littoral` command. Exit codes: 0 success, 1 invalid input (message on stderr),
// 2 internal error.
#include <cstdio>
#include <exception>
#include <iostream>

#include <CLI/CLI.hpp>

#include "core/error.h"
#include "core/log.h"
#include "core/progress.h"
#include "core/stats.h"
#include "core/version.h"
#include "pipelines/command_registry.h"

int main(int argc, char** argv) {
    using namespace littoral;
    CLI::App app{"Littoral: coastal ocean scene generation and physically based rendering"};
    app.set_version_flag("--version", std::string("littoral ") + LITTORAL_VERSION);
    app.require_subcommand(1);
    auto& g = globalOptions();
    app.add_flag("--stats", g.stats, "Print named statistics counters when the command ends");
    // Flag callbacks of the main app run before any subcommand's callback, so --quiet takes
    // effect for the whole command.
    app.add_flag_callback("-q,--quiet", [&g] {
        g.quiet = true;
        Progress::setEnabled(false);
    }, "No progress output");
    for (auto& [name, setup] : commandRegistry()) setup(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int rc = app.exit(e);
        return rc == 0 ? 0 : 1;
    } catch (const InputError& e) {
        const std::string loc = e.where().str();
        if (loc.empty()) std::fprintf(stderr, "error: %s\n", e.message().c_str());
        else std::fprintf(stderr, "%s: error: %s\n", loc.c_str(), e.message().c_str());
        return 1;
    } catch (const InternalError& e) {
        std::fprintf(stderr, "internal error: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "internal error: %s\n", e.what());
        return 2;
    }
    if (g.stats) statsPrint(std::cerr);
    return exitCode();
}
