// `littoral waves`: generate a wind-roughened (or sinusoidal, or flat) sea surface, write the
// facetized mesh (PLY or OBJ) and its predicted and measured statistics (stats.json).
// See docs/waves.md.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/cox_munk_fit.h"
#include "core/error.h"
#include "core/mesh.h"
#include "core/names.h"
#include "core/progress.h"
#include "core/suggest.h"
#include "core/units.h"
#include "pipelines/command_registry.h"
#include "pipelines/lib_waves.h"
#include "surfaces/facetize.h"
#include "surfaces/wave_report.h"
#include "surfaces/wave_surface.h"

namespace {

using littoral::InputError;
namespace surf = littoral::surfaces;
using littoral::pipelines::WavesOptions;
using littoral::pipelines::toParams;

// The folder of an output file must exist (it is not created: a typo in a folder name should not
// silently make a new tree) and hold nothing but a regular file at the name.
void checkOutputFile(const std::string& option, const std::filesystem::path& p) {
    const auto dir = p.parent_path().empty() ? std::filesystem::path(".") : p.parent_path();
    if (!std::filesystem::is_directory(dir))
        throw InputError(fmt::format("{}: the folder '{}' does not exist", option, dir.string()));
    try {
        littoral::checkOutputTarget(p);
    } catch (const InputError& e) {
        throw InputError(e.where(), option + ": " + e.message());
    }
}

// Two options naming one file would have one output overwrite the other.
bool sameFile(const std::filesystem::path& a, const std::filesystem::path& b) {
    std::error_code ea, eb;
    const auto ca = std::filesystem::weakly_canonical(a, ea), cb = std::filesystem::weakly_canonical(b, eb);
    return !ea && !eb ? ca == cb : a.lexically_normal() == b.lexically_normal();
}

std::string lowerExtension(const std::filesystem::path& p) {
    std::string e = p.extension().string();
    for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return e;
}

void runWaves(const WavesOptions& o) {
    if (littoral::globalOptions().quiet) littoral::Progress::setEnabled(false);
    const surf::WaveParams params = toParams(o);
    // Check the outputs before the (possibly long) generation, so a mistake costs nothing.
    if (!o.out.empty()) {
        const std::string ext = lowerExtension(o.out);
        if (ext != ".ply" && ext != ".obj")
            throw InputError(fmt::format("--out: '{}' has an unsupported extension; allowed: .ply, .obj", o.out));
        checkOutputFile("--out", o.out);
    }
    if (!o.stats.empty()) checkOutputFile("--stats", o.stats);
    if (!o.out.empty() && !o.stats.empty() && sameFile(o.out, o.stats))
        throw InputError(fmt::format("--stats: '{}' is the same file as --out; the statistics would overwrite the mesh",
                                     o.stats));
    surf::validateWaveParams(params);

    const surf::WaveSurface s = surf::generateWaveSurface(params);
    if (!o.out.empty()) {
        if (lowerExtension(o.out) == ".obj")
            surf::writeObj(o.out, s.mesh, s.vertexNormals);
        else
            littoral::writePly(o.out, s.mesh);
    }
    if (!o.stats.empty()) littoral::writeTextFileAtomic(o.stats, surf::waveStatsJson(s).dump(2) + "\n");
    std::fputs(surf::waveSummary(s).c_str(), stdout);
}

littoral::CommandRegistrar registerWaves{"waves", [](CLI::App& app) {
    auto* cmd = app.add_subcommand("waves", "Generate a wind-roughened sea surface mesh and its statistics");
    auto o = std::make_shared<WavesOptions>();
    cmd->add_option("--wind", o->wind, "Wind speed, m/s, at the model's reference height (beaufort and cox-munk "
                                       "12.5 m, pierson-moskowitz 19.5 m, jonswap/elfouhaily 10 m)");
    cmd->add_option("--wind-from", o->windFromDeg,
                    "Compass direction the wind comes from, degrees clockwise from north (default 270: from the west)");
    cmd->add_option("--waves-from", o->wavesFromDeg,
                    "Sinusoid: compass direction the waves come from, degrees clockwise from north (default 270)");
    // The old option, hidden, so that using it explains the change instead of "unknown option".
    cmd->add_option("--direction", o->removedDirection, "Removed: use --wind-from / --waves-from")->group("");
    cmd->add_option("--model", o->model,
                    "beaufort | pierson-moskowitz | jonswap | elfouhaily | cox-munk | sinusoid | flat")
        ->capture_default_str();
    cmd->add_option("--sea", o->sea, "cox-munk: which Cox-Munk fit the slopes follow: clean (default) | slick | "
                                     "dissertation");
    cmd->add_option("--size", o->size, "Side of the square surface, m (centred on the origin)")->capture_default_str();
    cmd->add_option("--size-y", o->sizeY, "Extent along y, m, if different from --size");
    cmd->add_option("--spacing", o->spacing, "Grid spacing, m")->capture_default_str();
    cmd->add_option("--seed", o->seed, "Random seed, 0 to 2^62")
        ->check(CLI::Range(uint64_t{0}, uint64_t{1} << 62))
        ->capture_default_str();
    cmd->add_option("--triangles", o->triangles,
                    "Target triangle count after decimation (0 = full grid); default 30000, or the full grid for "
                    "cox-munk and for a grid of fewer triangles");
    cmd->add_option("--out", o->out, "Mesh output (.ply or .obj)");
    cmd->add_option("--stats", o->stats, "Statistics output (JSON)");
    cmd->add_option("--fetch", o->fetch, "Fetch, m, for jonswap and elfouhaily (0 = fully developed)")->capture_default_str();
    cmd->add_option("--gamma", o->gamma, "JONSWAP peak enhancement factor (1 to 10)")->capture_default_str();
    cmd->add_option("--amplitude", o->amplitude, "Sinusoid amplitude, m")->capture_default_str();
    cmd->add_option("--wavelength", o->wavelength, "Sinusoid wavelength, m")->capture_default_str();
    cmd->add_option("--phase", o->phase, "Sinusoid: position of the first trough along the direction, m")
        ->capture_default_str();
    cmd->add_option("--time", o->time, "Time, s: advances each wave component by its dispersion relation")
        ->capture_default_str();
    cmd->add_option("--depth", o->depth, "Water depth for the dispersion relation, m (0 = deep water)")
        ->capture_default_str();
    cmd->callback([o] { runWaves(*o); });
}};

}  // namespace
