// The `littoral` command. Exit codes: 0 success; 1 anything the user can fix (invalid input, an
// output that cannot be written, a refused memory request; the message names the file, line and
// column, or the option); 2 an internal error; 130 / 143 interrupted by SIGINT / SIGTERM (with
// this run's partial outputs removed, see core/atomic_file.h).
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <memory>
#include <new>
#include <string>

#include <CLI/CLI.hpp>
#include <cpl_error.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/log.h"
#include "core/progress.h"
#include "core/ranks.h"
#include "core/resource_limits.h"
#include "core/stats.h"
#include "core/version.h"
#include "pipelines/command_registry.h"
#include "pipelines/lib_mpi.h"
#include "render/estimator_settings.h"

namespace {

std::string inputErrorText(const littoral::InputError& e) {
    const std::string loc = e.where().str();
    return loc.empty() ? "error: " + e.message() : loc + ": error: " + e.message();
}

// Under mpirun: the commands that share their work across ranks. Any other command would run once
// per rank into the same outputs.
void checkCommandTakesRanks(int argc, char** argv, const littoral::pipelines::MpiSession& mpi) {
    if (mpi.size() < 2) return;
    for (int i = 1; i < argc; ++i)
        for (const auto& [name, setup] : littoral::commandRegistry())
            if (name == argv[i]) {
                if (name == "run" || name == "render") return;
                throw littoral::InputError("`littoral " + name + "` does not use MPI ranks (only run and render do): "
                                           "run it without mpirun");
            }
}

// Parses the command line and runs the command. Returns the exit code; on failure `message` holds
// the error as printed (on stderr, by rank 0 of an MPI run or by the only process).
int runCommand(CLI::App& app, int argc, char** argv, const littoral::pipelines::MpiSession& mpi, std::string* message) {
    using namespace littoral;
    int rc = 0;
    try {
        checkCommandTakesRanks(argc, argv, mpi);
        // Every file a command writes belongs to this set: all of it is published when the
        // command succeeds, none of it when it fails.
        OutputSet outputs;
        app.parse(argc, argv);
        outputs.commit();
        return exitCode();
    } catch (const CLI::ParseError& e) {
        const int code = isRootRank() ? app.exit(e) : (e.get_exit_code() == 0 ? 0 : 1);
        *message = e.what();
        return code == 0 ? 0 : 1;
    } catch (const InputError& e) {
        *message = inputErrorText(e), rc = 1;
    } catch (const std::filesystem::filesystem_error& e) {
        // The file system refused something (permissions, a file where a folder should be, a full
        // disk): the user can fix it, so it is not an internal error.
        const std::string p = e.path1().string();
        *message = p + (p.empty() ? "" : ": ") + "error: " + e.code().message(), rc = 1;
    } catch (const std::bad_alloc&) {
        *message = "error: out of memory; lower the sizes in the input, or the memory budget (--max-memory) so that "
                   "such inputs are refused up front",
        rc = 1;
    } catch (const std::exception& e) {  // InternalError and everything unexpected
        *message = std::string("internal error: ") + e.what(), rc = 2;
    }
    if (isRootRank()) std::fprintf(stderr, "%s\n", message->c_str());
    return rc;
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
    // GDAL's messages are not printed: its registration takes over libtiff's error handler, so
    // every later TIFF that OpenImageIO encodes (the IR's class textures) would print libtiff's
    // notes about tags as "ERROR 1: ...". Littoral's GDAL calls check what GDAL returns and
    // report failures themselves (the raster reader collects GDAL's reason with its own handler).
    CPLSetErrorHandler(CPLQuietErrorHandler);
    // The estimators' descriptors, which the scene-file parser reads (render/estimator_settings.h).
    render::registerEstimatorKinds();
    // Under mpirun, MPI and the ranks (pipelines/lib_mpi.h); ranks other than 0 stay silent.
    std::unique_ptr<pipelines::MpiSession> mpi;
    try {
        mpi = std::make_unique<pipelines::MpiSession>(&argc, &argv);
    } catch (const InputError& e) {
        std::fprintf(stderr, "%s\n", inputErrorText(e).c_str());
        return 1;
    }
    auto& g = globalOptions();
    if (!isRootRank()) {
        g.quiet = true;
        Progress::setEnabled(false);
        log::setLevel(log::Level::Quiet);
    }

    CLI::App app{"Littoral: coastal ocean scene generation and physically based rendering"};
    app.set_version_flag("--version", std::string("littoral ") + LITTORAL_VERSION);
    app.require_subcommand(1);
    // Global options may also follow the subcommand (`littoral waves --max-memory 2G`).
    app.fallthrough();
    app.add_flag("--stats", g.stats, "Print named statistics counters when the command ends");
    // Flag callbacks of the main app run before any subcommand's callback, so --quiet takes
    // effect for the whole command.
    app.add_flag_callback("-q,--quiet", [&g] {
        g.quiet = true;
        Progress::setEnabled(false);
    }, "No progress output");
    app.add_flag_callback("-v,--verbose", [] {
        if (log::level() > log::Level::Debug && log::level() != log::Level::Quiet) log::setLevel(log::Level::Debug);
    }, "Also print diagnostic detail (for example why each probe value took the method it did)");
    app.add_option_function<std::string>(
           "--max-memory", [](const std::string& v) { setMemoryBudget(parseByteSize(v)); },
           "Memory budget: inputs that would need more (image size x bands, photons, grids, file headers) are "
           "refused before allocating. A size such as 512M or 8G (a bare number is GiB); default 3/4 of this "
           "machine's memory (" + formatBytes(static_cast<double>(defaultMemoryBudget())) + ")")
        ->type_name("SIZE");
    for (auto& [name, setup] : commandRegistry()) setup(app);
    refuseNonFiniteNumbers(app);
    std::string message;
    const int rc = runCommand(app, argc, argv, *mpi, &message);
    if (rc == 0 && g.stats && isRootRank()) statsPrint(std::cerr);
    return mpi->finish(rc, message);
}
