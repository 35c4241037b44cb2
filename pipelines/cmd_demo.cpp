// `littoral demo [--out DIR]`: the built-in default scene, end to end. It writes the synthetic
// coastal site (data_synthetic's generator: beach, sandbar, six-class shore map, pier, boat,
// step targets, a Beaufort wind-roughened surface) into OUT/site, builds it into OUT/ir and
// renders its sensors into OUT.
#include <cstdio>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "core/atomic_file.h"
#include "pipelines/command_registry.h"
#include "pipelines/lib_scene.h"

namespace {

littoral::CommandRegistrar registerDemo{"demo", [](CLI::App& app) {
    auto* cmd = app.add_subcommand("demo", "Generate, build and render the built-in coastal scene");
    auto o = std::make_shared<littoral::pipelines::DemoOptions>();
    cmd->add_option("--out", o->out, "Output directory")->capture_default_str();
    cmd->add_option("--seed", o->seed, "Seed of the synthetic site and the render, 0 to 2^62")
        ->check(CLI::Range(uint64_t{0}, uint64_t{1} << 62))
        ->capture_default_str();
    cmd->add_option("--threads", o->threads, "Worker threads (0 = all cores; at most 1024)")->check(CLI::Range(0, 1024));
    littoral::pipelines::addPreviewOptions(cmd, &o->preview);
    cmd->callback([o] {
        const littoral::OutputFolderLock lock(o->out);  // one command per output folder
        o->progress = !littoral::globalOptions().quiet;
        const auto summary = littoral::pipelines::runDemo(*o);
        std::printf("%s", summary.c_str());
    });
}};

}  // namespace
