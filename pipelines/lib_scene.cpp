#include "pipelines/lib_scene.h"

#include <fmt/format.h>

#include "scenegen/scene_file.h"

namespace littoral::pipelines {

std::string checkScene(const std::filesystem::path& sceneFile) {
    const auto spec = scenegen::loadSceneFile(sceneFile);
    std::string s;
    s += fmt::format("  scene '{}': domain [{}, {}] x [{}, {}] m\n", spec.scene.name, spec.scene.x0, spec.scene.x1,
                     spec.scene.y0, spec.scene.y1);
    s += fmt::format("  {} band(s), {} sensor(s), {} probe(s), {} material(s){}\n", spec.render.settings.bands.size(),
                     spec.sensors.size(), spec.probes.size(), spec.materials.size(),
                     spec.hasWater ? ", water" : "");
    return s;
}

}  // namespace littoral::pipelines
