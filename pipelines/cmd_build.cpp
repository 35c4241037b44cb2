// `littoral build SCENE.yaml --out DIR`: parse, generate geometry, close the water volume, check
// every mesh and write the Scene IR (scene.json, meshes/*.ply, textures/*.tif) plus validity.json.
#include <iostream>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/log.h"
#include "pipelines/command_registry.h"
#include "pipelines/lib_scene.h"
#include "scenegen/assemble.h"

namespace {

struct BuildOptions {
    std::string scene;
    std::string out;
    size_t surfaceTriangles = 0;
};

void runBuild(const BuildOptions& o) {
    using namespace littoral::scenegen;
    // The renderer's checks run before anything is written (check-scene refuses the same).
    AssembleOptions ao = littoral::pipelines::checkedAssembly(o.scene);
    if (o.surfaceTriangles > 0) ao.surfaceTriangles = o.surfaceTriangles;
    // Render settings are part of the IR: refuse ones the chosen estimator would not read before
    // anything is written.
    littoral::pipelines::checkRenderSettings(loadSceneFile(o.scene));
    const AssembledScene s = buildScene(o.scene, o.out, ao);
    if (littoral::globalOptions().quiet) return;
    std::cerr << fmt::format("built {} -> {}\n", o.scene, o.out);
    for (const auto& m : s.ir.meshes)
        std::cerr << fmt::format("  mesh {:<20} {:>8} faces  {}\n", m.name, m.data.numTriangles(),
                                 m.closed ? fmt::format("closed, volume {:.6g} m^3", m.data.signedVolume()) : "open");
    const auto& t = s.seconds;
    std::cerr << fmt::format("  seconds: parse {:.2f}, surface {:.2f}, terrain {:.2f}, textures {:.2f}, objects {:.2f}, "
                             "booleans {:.2f}, checks {:.2f}, write {:.2f}, total {:.2f}\n",
                             t.parse, t.surface, t.terrain, t.textures, t.objects,
                             t.waterPrism + t.waterTerrain + t.waterBoolean + t.waterSolids, t.validity, t.write,
                             t.total());
}

littoral::CommandRegistrar registerBuild{"build", [](CLI::App& app) {
    auto* cmd = app.add_subcommand("build", "Assemble a scene file into a checked Scene IR directory (plus validity.json)");
    auto o = std::make_shared<BuildOptions>();
    cmd->add_option("scene", o->scene, "Scene file (YAML)")->required()->check(CLI::ExistingFile);
    cmd->add_option("--out", o->out, "Output directory for the IR")->required();
    cmd->add_option("--surface-triangles", o->surfaceTriangles,
                    "Override the water surface's triangle target (0 = as in the scene file)");
    cmd->callback([o] {
        const littoral::OutputFolderLock lock(o->out);  // one command per output folder
        runBuild(*o);
    });
}};

}  // namespace
