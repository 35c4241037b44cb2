#pragma once
// Scene-level steps shared by the commands (check-scene, build, run, demo).
#include <filesystem>
#include <string>

namespace littoral::pipelines {

// Parses and validates every section of a scene file, including the geometry sections' own
// parsers; throws InputError on the first mistake. Returns a short human-readable summary.
std::string checkScene(const std::filesystem::path& sceneFile);

}  // namespace littoral::pipelines
