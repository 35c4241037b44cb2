#pragma once
// Scene-level steps shared by the commands (check-scene, run, demo).
#include <cstdint>
#include <filesystem>
#include <string>

namespace littoral::pipelines {

// Parses and validates every section of a scene file, including the geometry sections' own
// parsers; throws InputError on the first mistake. Returns a short human-readable summary.
std::string checkScene(const std::filesystem::path& sceneFile);

struct RunOptions {
    std::string scene;
    std::string out;
    std::string sensor;   // "" = every sensor
    int threads = 0;
    bool progress = true;
};
// Builds `scene` into out/ir and renders it into out. Returns a summary of what was written.
std::string runScene(const RunOptions& options);

struct DemoOptions {
    std::string out = "out/demo";
    uint64_t seed = 2010;
    int threads = 0;
    bool progress = true;
};
// Writes the synthetic coastal site into out/site and runs it (runScene) into out.
std::string runDemo(const DemoOptions& options);

}  // namespace littoral::pipelines
