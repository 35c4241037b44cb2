// `littoral column SCENE.yaml --out DIR`: depth profiles and radiance tables of a plane-parallel
// scene from the deterministic 1-D solver (column/, docs/column.md).
#include <cstdio>
#include <memory>

#include <CLI/CLI.hpp>

#include "pipelines/command_registry.h"
#include "pipelines/lib_column.h"

namespace {

littoral::CommandRegistrar registerColumn{"column", [](CLI::App& app) {
    auto* cmd = app.add_subcommand("column", "Solve a horizontally homogeneous scene as a 1-D column (depth profiles)");
    auto o = std::make_shared<littoral::pipelines::ColumnOptions>();
    cmd->add_option("SCENE", o->scene, "Scene file (YAML)")->required();
    cmd->add_option("--out", o->out, "Output directory")->required();
    cmd->add_option("--depths", o->depths, "Depths, m below the surface (replaces the default grid)")
        ->delimiter(',')
        ->check(CLI::Range(0.0, 1e5));
    cmd->add_option("--step", o->step, "Default grid spacing, m")->check(CLI::Range(1e-3, 1e4))->capture_default_str();
    cmd->add_option("--max-depth", o->maxDepth, "Default grid extent, m (the bottom, if shallower)")
        ->check(CLI::Range(1e-3, 1e5))
        ->capture_default_str();
    cmd->add_option("--streams", o->streams, "Gauss directions on each side of the Snell-window edge, per hemisphere")
        ->check(CLI::Range(2, 32))
        ->capture_default_str();
    cmd->add_option("--azimuths", o->azimuths, "Azimuths 0..180 deg of the radiance table")
        ->check(CLI::Range(2, 361))
        ->capture_default_str();
    cmd->callback([o] { std::printf("%s", littoral::pipelines::runColumn(*o).c_str()); });
}};

}  // namespace
