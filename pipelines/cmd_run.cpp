// `littoral run SCENE.yaml --out DIR`: build the scene into DIR/ir (the checked Scene IR) and
// render it into DIR. The render reads only the IR, exactly as `littoral render DIR/ir` would.
#include <cstdio>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "core/atomic_file.h"
#include "core/progress.h"
#include "core/ranks.h"
#include "pipelines/command_registry.h"
#include "pipelines/lib_scene.h"

namespace {

littoral::CommandRegistrar registerRun{"run", [](CLI::App& app) {
    auto* cmd = app.add_subcommand("run", "Build a scene file and render it (build + render)");
    auto o = std::make_shared<littoral::pipelines::RunOptions>();
    cmd->add_option("SCENE", o->scene, "Scene file (YAML)")->required();
    cmd->add_option("--out", o->out, "Output directory (the IR goes to OUT/ir)")->required();
    cmd->add_option("--sensor", o->sensor, "Render only this sensor");
    cmd->add_option("--threads", o->threads, "Worker threads (0 = all cores; at most 1024)")->check(CLI::Range(0, 1024));
    cmd->add_flag("--resume", o->resume, "Continue an interrupted render from its checkpoint (its last saved pass, or its finished tiles)");
    littoral::pipelines::addPreviewOptions(cmd, &o->preview);
    cmd->callback([o] {
        const littoral::OutputFolderLock lock(o->out);  // one command per output folder
        o->progress = !littoral::globalOptions().quiet;
        const auto summary = littoral::pipelines::runScene(*o);
        if (littoral::isRootRank()) std::printf("%s", summary.c_str());
    });
}};

}  // namespace
