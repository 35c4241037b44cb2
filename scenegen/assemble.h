#pragma once
// Scene assembly: a parsed scene file (scene_file.h) becomes a checked Scene IR.
//
//   water.surface ─► wave mesh (surfaces/) ─┐
//   bathymetry ─► Terrain (bathymetry/) ────┼─► water volume + land (water_volume.h, CGAL booleans)
//   objects ─► placed closed solids ────────┘        │
//   texture_classes ─► class map + textures ─► per-face terrain materials
//                                                     ▼
//                          every mesh checked (mesh_validity.h) ─► ir::SceneIR + validity.json
//
// IR meshes: "water" (closed; inside medium "water", outside air; materials: the air-water
// interface, seabed classes, object hull-contact faces, domain walls), "land" (open terrain surface
// above the water), and one closed mesh per object (named after it).
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "core/scene_ir.h"
#include "scenegen/scene_file.h"
#include "scenegen/texture_classes.h"

namespace littoral::scenegen {

struct AssembledScene;

struct AssembleOptions {
    std::optional<size_t> surfaceTriangles;  // overrides water.surface's triangle target
    bool checkSelfIntersections = true;
    // buildScene: run on the valid scene before anything is written (the commands pass the
    // renderer's checks, so that build, run and check-scene refuse the same scenes).
    std::function<void(const SceneSpec&, const AssembledScene&)> beforeWrite;
};

// Wall-clock seconds per stage.
struct StageSeconds {
    double parse = 0, surface = 0, terrain = 0, textures = 0, objects = 0;
    double waterPrism = 0, waterTerrain = 0, waterBoolean = 0, waterSolids = 0;
    double validity = 0, write = 0;
    double total() const {
        return parse + surface + terrain + textures + objects + waterPrism + waterTerrain + waterBoolean + waterSolids +
               validity + write;
    }
    nlohmann::json toJson() const;
};

struct AssembledScene {
    ir::SceneIR ir;
    std::optional<TextureClasses> textures;
    nlohmann::json validity;   // per mesh: the checkMesh report; plus a summary
    bool valid = false;        // every closed mesh passed every check
    StageSeconds seconds;
};

// Builds the geometry of `spec` and the IR. Throws InputError for scene mistakes (naming the
// file:line:column of the offending entry) and when a required closed mesh fails its checks.
AssembledScene assembleScene(const SceneSpec& spec, const AssembleOptions& options = {});

// Writes dir/scene.json, dir/meshes/*.ply, dir/textures/*.tif and dir/validity.json.
void writeAssembledScene(const AssembledScene& scene, const std::filesystem::path& dir);

// loadSceneFile + assembleScene + writeAssembledScene (when outDir is not empty). If the water
// body or an object fails validation, validity.json is still written to outDir (so the reasons
// can be read) and InputError is thrown; no scene.json is written.
AssembledScene buildScene(const std::filesystem::path& sceneYaml, const std::filesystem::path& outDir,
                          const AssembleOptions& options = {});

}  // namespace littoral::scenegen
