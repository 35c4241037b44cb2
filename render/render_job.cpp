#include "render/render_job.h"

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/log.h"
#include "core/suggest.h"
#include "render/image_output.h"

namespace littoral::render {

RenderJobResult runRenderJob(const ir::SceneIR& ir, const std::filesystem::path& irDir,
                             const std::filesystem::path& outDir, const RenderJobOptions& opts) {
    const Scene scene(ir, irDir);
    std::vector<const ir::Sensor*> sensors;
    for (const ir::Sensor& s : ir.sensors)
        if (opts.sensor.empty() || s.name == opts.sensor) sensors.push_back(&s);
    if (!opts.sensor.empty() && sensors.empty()) {
        std::vector<std::string> names;
        for (const ir::Sensor& s : ir.sensors) names.push_back(s.name);
        const std::string close = closestMatch(opts.sensor, names);
        throw InputError(fmt::format("--sensor: no sensor named '{}' (sensors: {}){}", opts.sensor, joinList(names),
                                     close.empty() ? "" : fmt::format(" (did you mean '{}'?)", close)));
    }
    if (sensors.empty() && ir.probes.empty())
        throw InputError("the scene has no sensors and no probes: nothing to render");

    RenderOptions ro;
    ro.threads = opts.threads;
    ro.progress = opts.progress;
    RenderJobResult res;
    // One estimator per band group, shared by every sensor and probe (settings checked here).
    const EstimatorSet estimators(scene);
    // Validate every sensor's view before spending time on radiance.
    for (const ir::Sensor* s : sensors) (void)renderTruth(scene, *s, ro);
    for (const ir::Sensor* s : sensors) res.images.push_back(renderSensor(scene, estimators, *s, ro));
    if (opts.sensor.empty())
        for (size_t i = 0; i < ir.probes.size(); ++i) {
            auto v = evaluateProbe(scene, estimators, ir.probes[i], static_cast<int>(i), ro);
            res.probes.insert(res.probes.end(), v.begin(), v.end());
        }

    // Everything computed: now write.
    std::error_code ec;
    std::filesystem::create_directories(outDir, ec);
    if (ec) throw InputError(fmt::format("{}: cannot create output directory: {}", outDir.string(), ec.message()));
    std::vector<std::string> materialNames;
    for (const ir::Material& m : ir.materials) materialNames.push_back(m.name);
    for (const SensorImage& img : res.images) {
        const std::map<std::string, std::string> meta{{"scene", ir.name},
                                                      {"sensor", img.sensor},
                                                      {"seed", std::to_string(ir.render.seed)}};
        const auto base = outDir / img.sensor;
        writeExr(base.string() + ".exr", img.film, meta);
        writeEnvi(base.string() + ".img", img.film, fmt::format("Littoral render of scene {} sensor {}", ir.name, img.sensor));
        PreviewOptions po = opts.preview;
        if (img.film.bandCount() < 3) po.mapping = PreviewOptions::Mapping::Grey;
        if (po.mapping == PreviewOptions::Mapping::Grey) po.greyUm = img.film.bands[0].center();
        writePngPreview(base.string() + ".png", img.film, po);
        writeTruthExr(base.string() + "_truth.exr", img.truth, materialNames);
        writeMaterialIdPng(base.string() + "_material.png", img.truth);
        for (const char* suffix : {".exr", ".img", ".hdr", ".png", "_truth.exr", "_material.png"})
            res.written.push_back(base.string() + suffix);
    }
    if (!res.probes.empty()) {
        writeTextFileAtomic(outDir / "probes.csv", probesCsv(res.probes, scene.bands()));
        writeTextFileAtomic(outDir / "probes.json", probesJson(res.probes, scene.bands()));
        res.written.push_back(outDir / "probes.csv");
        res.written.push_back(outDir / "probes.json");
    }
    return res;
}

RenderJobResult runRenderJob(const std::filesystem::path& irDir, const std::filesystem::path& outDir,
                             const RenderJobOptions& opts) {
    const ir::SceneIR ir = ir::readIR(irDir);
    return runRenderJob(ir, irDir, outDir, opts);
}

}  // namespace littoral::render
