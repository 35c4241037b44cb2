// `littoral render IR_DIR --out DIR [--sensor NAME] [--threads N]`: renders every sensor of a
// Scene IR (or the one named) and evaluates its probes. Writes EXR + ENVI + PNG previews + truth
// images per sensor and probes.csv/probes.json (see render/render_job.h). Bad input (unknown
// sensor, camera inside an opaque object, empty view, zero image size, a band outside a
// spectrum's table ...) exits with status 1 and writes nothing.
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "core/atomic_file.h"
#include "core/log.h"
#include "core/progress.h"
#include "core/ranks.h"
#include "pipelines/command_registry.h"
#include "pipelines/lib_geo_layers.h"
#include "pipelines/lib_scene.h"
#include "render/render_job.h"

namespace {

struct RenderCmdOptions {
    std::string irDir, outDir, sensor;
    int threads = 0;
    bool resume = false;
    littoral::render::PreviewOptions preview;
};

littoral::CommandRegistrar registerRender{"render", [](CLI::App& app) {
    auto* cmd = app.add_subcommand("render", "Render the sensors and probes of a Scene IR directory");
    auto o = std::make_shared<RenderCmdOptions>();
    cmd->add_option("IR_DIR", o->irDir, "Scene IR directory (scene.json + meshes)")->required();
    cmd->add_option("--out", o->outDir, "Output directory")->required();
    cmd->add_option("--sensor", o->sensor, "Render only this sensor");
    cmd->add_option("--threads", o->threads, "Worker threads (0 = all cores; at most 1024)")->check(CLI::Range(0, 1024));
    cmd->add_flag("--resume", o->resume,
                  "Continue an interrupted render from its checkpoint: a progressive one after its last saved pass "
                  "(DIR/progressive.checkpoint), any other from its finished tiles (DIR/render.checkpoint)");
    littoral::pipelines::addPreviewOptions(cmd, &o->preview);
    cmd->callback([o] {
        const littoral::OutputFolderLock lock(o->outDir);  // one command per output folder
        littoral::render::RenderJobOptions jo;
        jo.resume = o->resume;
        jo.sensor = o->sensor;
        jo.threads = o->threads;
        jo.preview = o->preview;
        jo.progress = !littoral::globalOptions().quiet;
        jo.enviHeaderLines = [](const littoral::ir::SceneIR& ir, const littoral::ir::Sensor& s) {
            return littoral::pipelines::enviGeoHeaderLines(ir, s);
        };
        littoral::Progress::setEnabled(jo.progress);
        const auto t0 = std::chrono::steady_clock::now();
        auto res = littoral::render::runRenderJob(o->irDir, o->outDir, jo);
        if (!littoral::isRootRank()) return;  // rank 0 of an MPI run writes the outputs and reports
        for (const auto& p : littoral::pipelines::writeGeoLayers(littoral::ir::readIR(o->irDir), res, o->outDir))
            res.written.push_back(p);
        for (const auto& p : res.written) littoral::log::info("wrote {}", p.string());
        std::printf("rendered %zu sensor(s), %zu probe value(s) into %s (%.1f s%s)\n", res.images.size(), res.probes.size(),
                    o->outDir.c_str(), std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
                    littoral::pipelines::resourceSummary().c_str());
    });
}};

}  // namespace
