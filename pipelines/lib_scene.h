#pragma once
// Scene-level steps shared by the commands (check-scene, run, demo).
#include <cstdint>
#include <filesystem>
#include <string>

#include "render/image_output.h"

namespace CLI {
class App;
}

namespace littoral::pipelines {

// Adds --gamma, --white and --blur (the PNG preview's display mapping) to a subcommand.
void addPreviewOptions(CLI::App* cmd, render::PreviewOptions* preview);

}  // namespace littoral::pipelines
#include "scenegen/assemble.h"

namespace littoral::pipelines {

// Checks the render settings and the per-material solvers of a parsed scene against its
// estimator (render::makeRenderConfig) without building anything; InputError with the location.
void checkRenderSettings(const scenegen::SceneSpec& spec);

// Every check `run` makes before rendering, on a scene built in memory: the renderer's
// (render::preflightRenderJob), reading the textures and class maps the assembly made from a
// temporary folder that is removed afterwards. An InputError without a location is located at the
// scene-file entry it names (sensor, probe, material) or at the scene file.
void preflightRender(const scenegen::AssembledScene& built, const scenegen::SceneSpec& spec,
                     const std::filesystem::path& sceneFile);
// Assembly options whose beforeWrite runs preflightRender: `build` and `run` refuse what
// check-scene refuses before writing anything.
scenegen::AssembleOptions checkedAssembly(const std::filesystem::path& sceneFile);

// Parses and validates every section of a scene file, including the geometry sections' own
// parsers; throws InputError on the first mistake. Returns a short human-readable summary.
std::string checkScene(const std::filesystem::path& sceneFile);

struct RunOptions {
    std::string scene;
    std::string out;
    std::string sensor;   // "" = every sensor
    int threads = 0;
    bool progress = true;
    bool resume = false;  // continue a progressive render (render::RenderJobOptions::resume)
    render::PreviewOptions preview;
};
// Builds `scene` into out/ir and renders it into out. Returns a summary of what was written.
std::string runScene(const RunOptions& options);

// The end of a run's summary: the photons the photon passes emitted and stored (when any) and
// the process's peak memory, e.g. ", 5.1 M photons emitted (2 M surface + 2 M volume records
// stored), peak memory 353 MiB".
std::string resourceSummary();

struct DemoOptions {
    std::string out = "out/demo";
    uint64_t seed = 2010;
    int threads = 0;
    bool progress = true;
    // The dissertation's Ch. 10 post-processing: gamma 0.65, then its Gaussian kernel.
    render::PreviewOptions preview = [] {
        render::PreviewOptions p;
        p.blurSigma = render::kDissertationBlurSigma;
        return p;
    }();
};
// Writes the synthetic coastal site into out/site and runs it (runScene) into out.
std::string runDemo(const DemoOptions& options);

}  // namespace littoral::pipelines
