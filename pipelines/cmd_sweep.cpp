// `littoral sweep SCENE.yaml --vary KEY=V1,V2,... [--vary ...] --out DIR`: a grid of runs, one folder
// each, with an index of their parameters and outputs; resumable, or written as a Slurm job array
// (pipelines/lib_sweep.h, docs/sweeps.md).
#include <cstdio>
#include <memory>

#include <CLI/CLI.hpp>

#include "pipelines/command_registry.h"
#include "pipelines/lib_scene.h"
#include "pipelines/lib_sweep.h"

namespace {

littoral::CommandRegistrar registerSweep{"sweep", [](CLI::App& app) {
    auto* cmd = app.add_subcommand("sweep", "Run a scene over a grid of values (a study), one run folder each, with an index");
    auto o = std::make_shared<littoral::pipelines::SweepOptions>();
    cmd->add_option("SCENE", o->scene, "Scene file (YAML)")->required();
    cmd->add_option("--vary", o->vary,
                    "KEY=V1,V2,...: a scene-file key (dotted, e.g. water.surface.wind_speed or sensors[0].gsd_m) and "
                    "its values; repeat for a grid (the last --vary varies fastest)")
        ->required()
        ->take_all()
        ->allow_extra_args(false);
    cmd->add_option("--out", o->out, "Sweep folder: runs/NNNN/ per run, index.csv, index.json, sweep.json")->required();
    cmd->add_option("--threads", o->threads, "Worker threads per run (0 = all cores; at most 1024)")->check(CLI::Range(0, 1024));
    cmd->add_flag("--slurm", o->slurm, "Write OUT/sweep.sbatch (a Slurm job array, one task per run) instead of running");
    cmd->add_option("--task", o->task, "Run only run number TASK (0-based), as a task of the Slurm array does")
        ->check(CLI::Range(0LL, 99999LL));
    littoral::pipelines::addPreviewOptions(cmd, &o->preview);
    cmd->callback([o] {
        o->progress = !littoral::globalOptions().quiet;
        std::printf("%s", littoral::pipelines::runSweep(*o).c_str());
    });
}};

}  // namespace
