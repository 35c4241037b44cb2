#include "render/render_job.h"

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/log.h"
#include "core/output_names.h"
#include "core/render_budget.h"
#include "core/suggest.h"
#include "render/image_output.h"

namespace littoral::render {

RenderJobResult runRenderJob(const ir::SceneIR& ir, const std::filesystem::path& irDir,
                             const std::filesystem::path& outDir, const RenderJobOptions& opts) {
    // Outputs first: a name that is not a file name, two sensors writing one file, or an output
    // folder that cannot be created is found before any rendering time is spent.
    const SourceLoc irFile{(irDir / "scene.json").string()};
    ir::validateNamesAndPaths(ir, irFile.file);
    checkOutputFolder(outDir, "--out");
    for (const ir::Sensor& s : ir.sensors)
        if (opts.sensor.empty() || s.name == opts.sensor)
            for (const std::string& f : sensorOutputFiles(s.name)) checkOutputTarget(outDir / f);
    if (opts.sensor.empty() && !ir.probes.empty())
        for (const std::string& f : probeOutputFiles()) checkOutputTarget(outDir / f);
    checkRenderMemory(ir, opts.sensor, irFile);

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
    // Validate every sensor's view before spending time on radiance.
    for (const ir::Sensor* s : sensors) (void)renderTruth(scene, *s, ro);
    for (const ir::Sensor* s : sensors) res.images.push_back(renderSensor(scene, *s, ro));
    if (opts.sensor.empty())
        for (size_t i = 0; i < ir.probes.size(); ++i) {
            auto v = evaluateProbe(scene, ir.probes[i], static_cast<int>(i), ro);
            res.probes.insert(res.probes.end(), v.begin(), v.end());
        }

    // Everything computed: now write.
    std::vector<std::string> materialNames;
    for (const ir::Material& m : ir.materials) materialNames.push_back(m.name);
    for (const SensorImage& img : res.images) {
        const std::map<std::string, std::string> meta{{"scene", ir.name},
                                                      {"sensor", img.sensor},
                                                      {"seed", std::to_string(ir.render.seed)}};
        // File names from the one list that output_names.h checks for clashes:
        // S.exr, S.img (+ S.hdr), S.png, S_truth.exr, S_material.png.
        const std::vector<std::string> files = sensorOutputFiles(img.sensor);
        writeExr(outDir / files[0], img.film, meta);
        writeEnvi(outDir / files[1], img.film, fmt::format("Littoral render of scene {} sensor {}", ir.name, img.sensor));
        PreviewOptions po = opts.preview;
        if (img.film.bandCount() < 3) po.mapping = PreviewOptions::Mapping::Grey;
        if (po.mapping == PreviewOptions::Mapping::Grey) po.greyUm = img.film.bands[0].center();
        writePngPreview(outDir / files[3], img.film, po);
        writeTruthExr(outDir / files[4], img.truth, materialNames);
        writeMaterialIdPng(outDir / files[5], img.truth);
        for (const std::string& f : files) res.written.push_back(outDir / f);
    }
    if (!res.probes.empty()) {
        const std::vector<std::string> files = probeOutputFiles();
        writeTextFileAtomic(outDir / files[0], probesCsv(res.probes, scene.bands()));
        writeTextFileAtomic(outDir / files[1], probesJson(res.probes, scene.bands()));
        for (const std::string& f : files) res.written.push_back(outDir / f);
    }
    return res;
}

RenderJobResult runRenderJob(const std::filesystem::path& irDir, const std::filesystem::path& outDir,
                             const RenderJobOptions& opts) {
    const ir::SceneIR ir = ir::readIR(irDir);
    return runRenderJob(ir, irDir, outDir, opts);
}

}  // namespace littoral::render
