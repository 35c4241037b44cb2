// `littoral check-scene SCENE.yaml`: validates a scene file without building or rendering it.
// Exit 0 when valid, 1 when not (the first error on stderr, with file:line:column).
#include <cstdio>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "core/log.h"
#include "pipelines/command_registry.h"
#include "pipelines/lib_scene.h"

namespace {

littoral::CommandRegistrar registerCheckScene{"check-scene", [](CLI::App& app) {
    auto* cmd = app.add_subcommand("check-scene", "Validate a scene file without running it (exit 0 valid, 1 invalid)");
    auto file = std::make_shared<std::string>();
    cmd->add_option("SCENE", *file, "Scene file (YAML)")->required();
    cmd->callback([file] {
        const auto summary = littoral::pipelines::checkScene(*file);
        std::printf("%s: valid\n%s", file->c_str(), summary.c_str());
    });
}};

}  // namespace
