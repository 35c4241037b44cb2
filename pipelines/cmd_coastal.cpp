// `littoral coastal A..J --out DIR [--full]`: the dissertation's coastal simulations (Table 10.1)
// on the synthetic coastal site, at quick settings or the dissertation's full ones.
#include <cstdio>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "core/atomic_file.h"
#include "pipelines/command_registry.h"
#include "pipelines/lib_coastal.h"
#include "pipelines/lib_scene.h"

namespace {

littoral::CommandRegistrar registerCoastal{"coastal", [](CLI::App& app) {
    auto* cmd = app.add_subcommand("coastal", "Render one of the dissertation's coastal simulations A-J (Table 10.1) or a "
                                              "Section 10.4 demonstration (cube, shadows)");
    auto o = std::make_shared<littoral::pipelines::CoastalOptions>();
    cmd->add_option("configuration", o->configuration, "Simulation of Table 10.1 (A to J), or cube (the epoxy cube's caustic), "
                                                         "shadows (the floating-box shadow series)")->required();
    cmd->add_option("--out", o->out, "Output directory")->required();
    cmd->add_flag("--full", o->full,
                  "The dissertation's settings: 50 M surface and 70 M volume photons (minutes and gigabytes; "
                  "default: quick, 1 M + 1 M)");
    auto* seed = cmd->add_option("--seed", o->seed, "Seed of the synthetic site (A-J), 0 to 2^62")
        ->check(CLI::Range(uint64_t{0}, uint64_t{1} << 62))
        ->capture_default_str();
    cmd->add_option("--threads", o->threads, "Worker threads (0 = all cores; at most 1024)")->check(CLI::Range(0, 1024));
    littoral::pipelines::addPreviewOptions(cmd, &o->preview);
    cmd->callback([o, seed] {
        o->seedGiven = seed->count() > 0;
        littoral::pipelines::checkCoastalName(*o);  // refuse an unknown name before locking
        const littoral::OutputFolderLock lock(o->out);                 // one command per output folder
        o->progress = !littoral::globalOptions().quiet;
        std::printf("%s", littoral::pipelines::runCoastal(*o).c_str());
    });
}};

}  // namespace
