// The `littoral` command. Exit codes: 0 success; 1 anything the user can fix (invalid input, an
// output that cannot be written, a refused memory request; the message names the file, line and
// column, or the option); 2 an internal error; 130 / 143 interrupted by SIGINT / SIGTERM (with
// this run's partial outputs removed, see core/atomic_file.h).
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <new>

#include <CLI/CLI.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/log.h"
#include "core/progress.h"
#include "core/resource_limits.h"
#include "core/stats.h"
#include "core/version.h"
#include "pipelines/command_registry.h"
#include "render/estimator_settings.h"

namespace {

void printInputError(const littoral::InputError& e) {
    const std::string loc = e.where().str();
    if (loc.empty()) std::fprintf(stderr, "error: %s\n", e.message().c_str());
    else std::fprintf(stderr, "%s: error: %s\n", loc.c_str(), e.message().c_str());
}

// Every floating-point option of every command refuses nan and inf before the command runs
// (CLI11's ranges compare, and a NaN passes every comparison).
void refuseNonFiniteNumbers(CLI::App& app) {
    static const CLI::Validator finite(
        [](std::string& s) -> std::string {
            std::size_t used = 0;
            double v = 0;
            try {
                v = std::stod(s, &used);
            } catch (const std::exception&) {
                return "";  // not a number at all: the option's own conversion reports it
            }
            return std::isfinite(v) ? "" : "must be a finite number, not " + s;
        },
        "", "finite");
    for (CLI::Option* o : app.get_options())
        if (o->get_type_name() == "FLOAT" || o->get_type_name() == "FLOAT ...") o->check(finite);
    for (CLI::App* sub : app.get_subcommands({})) refuseNonFiniteNumbers(*sub);
}

}  // namespace

int main(int argc, char** argv) {
    using namespace littoral;
    // Before any thread exists: SIGINT / SIGTERM are handled by one thread that removes this
    // run's partial outputs and exits 130 / 143.
    installInterruptCleanup();
    // The estimators' descriptors, which the scene-file parser reads (render/estimator_settings.h).
    render::registerEstimatorKinds();

    CLI::App app{"Littoral: coastal ocean scene generation and physically based rendering"};
    app.set_version_flag("--version", std::string("littoral ") + LITTORAL_VERSION);
    app.require_subcommand(1);
    // Global options may also follow the subcommand (`littoral waves --max-memory 2G`).
    app.fallthrough();
    auto& g = globalOptions();
    app.add_flag("--stats", g.stats, "Print named statistics counters when the command ends");
    // Flag callbacks of the main app run before any subcommand's callback, so --quiet takes
    // effect for the whole command.
    app.add_flag_callback("-q,--quiet", [&g] {
        g.quiet = true;
        Progress::setEnabled(false);
    }, "No progress output");
    app.add_option_function<std::string>(
           "--max-memory", [](const std::string& v) { setMemoryBudget(parseByteSize(v)); },
           "Memory budget: inputs that would need more (image size x bands, photons, grids, file headers) are "
           "refused before allocating. A size such as 512M or 8G (a bare number is GiB); default 3/4 of this "
           "machine's memory (" + formatBytes(static_cast<double>(defaultMemoryBudget())) + ")")
        ->type_name("SIZE");
    for (auto& [name, setup] : commandRegistry()) setup(app);
    refuseNonFiniteNumbers(app);
    int rc = 0;
    try {
        // Every file a command writes belongs to this set: all of it is published when the
        // command succeeds, none of it when it fails.
        OutputSet outputs;
        app.parse(argc, argv);
        outputs.commit();
        rc = exitCode();
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? 0 : 1;
    } catch (const InputError& e) {
        printInputError(e);
        return 1;
    } catch (const std::filesystem::filesystem_error& e) {
        // The file system refused something (permissions, a file where a folder should be, a full
        // disk): the user can fix it, so it is not an internal error.
        const std::string p = e.path1().string();
        std::fprintf(stderr, "%s%serror: %s\n", p.c_str(), p.empty() ? "" : ": ", e.code().message().c_str());
        return 1;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "error: out of memory; lower the sizes in the input, or the memory budget "
                             "(--max-memory) so that such inputs are refused up front\n");
        return 1;
    } catch (const InternalError& e) {
        std::fprintf(stderr, "internal error: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "internal error: %s\n", e.what());
        return 2;
    }
    if (g.stats) statsPrint(std::cerr);
    return rc;
}
