#include "render/render_job.h"

#include <memory>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/colour.h"
#include "core/error.h"
#include "core/log.h"
#include "core/material_kinds.h"
#include "core/stats.h"
#include "core/output_names.h"
#include "core/ranks.h"
#include "core/render_budget.h"
#include "core/suggest.h"
#include "render/estimator.h"
#include "render/forward_tally.h"
#include "render/probes.h"
#include "render/volume_map_probes.h"
#include "render/image_output.h"
#include "render/progressive_checkpoint.h"
#include "render/tile_checkpoint.h"
#include "render/sensor_model.h"

namespace littoral::render {

namespace {

// Adds one pass's images and probe values to the running sums.
void accumulate(ProgressiveState& st, const std::vector<SensorImage>& images, const std::vector<ProbeValue>& probes) {
    // One running sum per sensor over its films end to end (the radiance, then any products).
    if (st.imageSums.empty()) st.imageSums.resize(images.size());
    for (size_t i = 0; i < images.size(); ++i) {
        auto& s = st.imageSums[i];
        const std::vector<const Film*> films = images[i].films();
        size_t size = 0;
        for (const Film* f : films) size += f->pixels.size();
        s.resize(size, 0.0);
        size_t k = 0;
        for (const Film* f : films)
            for (float v : f->pixels) s[k++] += v;
    }
    if (st.probeSums.empty()) {
        st.probeSums.resize(probes.size());
        st.probeSquares.resize(probes.size());
    }
    for (size_t i = 0; i < probes.size(); ++i) {
        st.probeSums[i].resize(probes[i].mean.size(), 0.0);
        st.probeSquares[i].resize(probes[i].mean.size(), 0.0);
        for (size_t b = 0; b < probes[i].mean.size(); ++b) {
            st.probeSums[i][b] += probes[i].mean[b];
            st.probeSquares[i][b] += probes[i].mean[b] * probes[i].mean[b];
        }
    }
    ++st.passesDone;
}

// The means over passes, written into the last pass's results (which carry the truth images,
// names and units).
void finish(const ProgressiveState& st, std::vector<SensorImage>* outImages, std::vector<ProbeValue>* outProbes,
            std::vector<SensorImage>& last, std::vector<ProbeValue>& lastProbes) {
    const double n = st.passesDone;
    for (size_t i = 0; i < last.size(); ++i) {
        size_t k = 0;
        for (Film* f : last[i].films())
            for (float& v : f->pixels) v = static_cast<float>(st.imageSums[i][k++] / n);
        // The passes' mean standard error, over sqrt(n): the error of the mean of n independent
        // passes, each as noisy as the others.
        if (last[i].standardError)
            for (float& v : last[i].standardError->pixels) v = static_cast<float>(v / std::sqrt(n));
    }
    for (size_t i = 0; i < lastProbes.size(); ++i)
        for (size_t b = 0; b < lastProbes[i].mean.size(); ++b) {
            const double mean = st.probeSums[i][b] / n;
            lastProbes[i].mean[b] = mean;
            if (st.passesDone >= 2) {
                // Passes are independent (each its own photon maps): their spread includes the
                // maps' noise, which the batches within one pass do not see.
                const double var = std::max(0.0, (st.probeSquares[i][b] - n * mean * mean) / (n - 1));
                lastProbes[i].stderr_[b] = std::sqrt(var / n);
            }
        }
    *outImages = std::move(last);
    *outProbes = std::move(lastProbes);
}

// Outputs first: a name that is not a file name, two sensors writing one file, or an output
// folder that cannot be created is found before any rendering time is spent.
void checkOutputs(const ir::SceneIR& ir, const SourceLoc& irFile, const std::filesystem::path& outDir,
                  const RenderJobOptions& opts) {
    ir::validateNamesAndPaths(ir, irFile.file);
    checkOutputFolder(outDir, "--out");
    for (const ir::Sensor& s : ir.sensors)
        if (opts.sensor.empty() || s.name == opts.sensor)
            for (const std::string& f : sensorOutputFiles(s.name)) checkOutputTarget(outDir / f);
    if (opts.sensor.empty() && !ir.probes.empty())
        for (const std::string& f : probeOutputFiles()) checkOutputTarget(outDir / f);
    checkRenderMemory(ir, opts.sensor, irFile);
}

// The sensors to render: all, or the one --sensor names (with a did-you-mean if none does).
std::vector<const ir::Sensor*> selectSensors(const ir::SceneIR& ir, const std::string& only) {
    std::vector<const ir::Sensor*> sensors;
    for (const ir::Sensor& s : ir.sensors)
        if (only.empty() || s.name == only) sensors.push_back(&s);
    if (!only.empty() && sensors.empty()) {
        std::vector<std::string> names;
        for (const ir::Sensor& s : ir.sensors) names.push_back(s.name);
        const std::string close = closestMatch(only, names);
        throw InputError(fmt::format("--sensor: no sensor named '{}' (sensors: {}){}", only, joinList(names),
                                     close.empty() ? "" : fmt::format(" (did you mean '{}'?)", close)));
    }
    if (sensors.empty() && ir.probes.empty()) throw InputError("sensors, probes: both are empty: there is nothing to render");
    return sensors;
}

RenderOptions renderOptions(const ir::SceneIR& ir, const RenderJobOptions& opts) {
    RenderOptions ro;
    // --threads wins; otherwise the scene's render.threads (0: all cores).
    ro.threads = opts.threads > 0 ? opts.threads : ir.render.threads;
    ro.progress = opts.progress;
    return ro;
}

// render.probe_photons set explicitly asks for the forward tallies, which hold only in a
// horizontally invariant scene: refused elsewhere (the default just falls back to backward paths).
void checkProbePhotons(const ir::SceneIR& ir, const RenderConfig& config) {
    const auto it = ir.render.locations.find("probe_photons");
    if (config.estimator != ir::Estimator::Path || config.probePhotons == 0 || !ir.render.settings.has("probe_photons"))
        return;
    const std::string why = horizontalInvarianceProblem(ir);
    if (why.empty()) return;
    const std::string msg = fmt::format("render.probe_photons: the forward irradiance tallies need a horizontally "
                                        "invariant scene, and here {}; remove probe_photons (the probes then use "
                                        "backward paths) or set it to 0",
                                        why);
    if (it != ir.render.locations.end()) throw InputError(it->second, msg);
    throw InputError(msg);
}

// The checks that need the scene but no radiance, before any rendering time is spent: the
// settings, every selected sensor's view (its truth image) and every probe's plan.
RenderConfig checkBeforeRendering(const ir::SceneIR& ir, const Scene& scene, const std::vector<const ir::Sensor*>& sensors,
                                  const RenderJobOptions& opts, const RenderOptions& ro) {
    RenderConfig config = makeRenderConfig(ir);
    for (const ir::Sensor* s : sensors) (void)renderTruth(scene, *s, ro);
    if (opts.sensor.empty())
        for (const ir::Probe& p : ir.probes) checkProbe(scene, config, p);
    checkProbePhotons(ir, config);
    return config;
}

// The path estimator's paths cut at render.max_bounces during this job (counters before: traced0,
// cut0): a warning with the fraction, since the radiance they would have carried is missing.
void warnIfPathsWereCut(int64_t traced0, int64_t cut0, const RenderConfig& config) {
    const int64_t traced = statCounter(kPathsTraced).value - traced0, cut = statCounter(kPathsCut).value - cut0;
    if (traced <= 0 || cut <= 0 || static_cast<double>(cut) < 1e-4 * static_cast<double>(traced)) return;
    log::warn("{:.3g} % of the path estimator's paths ({} of {}) reached render.max_bounces = {} with weight left and "
              "were cut: the radiance they would carry is missing (the images and probes are low). Raise "
              "render.max_bounces (dense, weakly absorbing water needs many bounces)",
              100.0 * static_cast<double>(cut) / static_cast<double>(traced), cut, traced, config.maxBounces);
}

// The dirsig estimator's shadow rays that crossed a dielectric object or a wave crest along the
// straight-path model during this job (counter before: straight0): a warning, since that sunlight
// is dimmed but neither displaced nor focused.
void warnIfStraightPaths(int64_t straight0) {
    const int64_t n = statCounter(kStraightPathSun).value - straight0;
    if (n <= 0) return;
    log::warn("{} sun estimates at points in the air reached the sun through a dielectric object or a wave crest "
              "along the dirsig estimator's straight-path model: that light is dimmed (Fresnel, absorption) but not "
              "displaced or focused (docs/rendering.md, \"Dielectric objects\"). The path estimator, or solver: "
              "surface-pm on the surfaces that receive it, refracts it exactly",
              n);
}

// The detector's SNR per band, and a warning when a band saturates (more than 1 % of the pixels
// at the full well).
void reportDetector(const std::string& sensor, const DetectorImage& det, const ir::SensorDetector& d,
                    const std::vector<Band>& bands) {
    for (size_t b = 0; b < det.bands.size(); ++b) {
        const DetectorBandStats& st = det.bands[b];
        if (st.clippedFraction > 0.01)
            log::warn("sensor '{}' band [{}, {}] um: {:.3g} % of the pixels reach the detector's full well ({} electrons; "
                      "the mean signal is {:.3g}): shorten integration_ms or narrow aperture_mm",
                      sensor, bands[b].lo, bands[b].hi, 100 * st.clippedFraction, d.fullWell, st.meanSignalE);
        else
            log::info("sensor '{}' band [{}, {}] um: mean signal {:.4g} e-, noise {:.3g} e-, SNR {:.3g}", sensor, bands[b].lo,
                      bands[b].hi, st.meanSignalE, st.meanNoiseE, st.snr);
    }
}

void writeWaterProducts(const SensorImage& img, const std::filesystem::path& outDir,
                        const std::vector<std::string>& files, const std::string& description, const EnviFields& envi);

// The outputs a sensor may not have (files[6] and [8..10] of sensorOutputFiles): written when it
// has them; otherwise one left by an earlier run into this folder would sit beside outputs it does
// not belong to, and is removed.
void writeOptionalOutputs(const ir::Sensor& sensor, const SensorImage& img, const std::filesystem::path& outDir,
                          const std::vector<std::string>& files, const std::map<std::string, std::string>& meta,
                          const std::string& description, const EnviFields& envi, const RenderJobOptions& opts) {
    auto optional = [&](size_t f, bool wanted, const char* what, auto&& write) {
        if (wanted) write(outDir / files[f]);
        else removeStaleOutput(outDir / files[f], what);
    };
    optional(6, spansVisible(img.film.bands), "a true-colour preview",
             [&](const std::filesystem::path& p) { writeTrueColourPng(p, img.film, opts.preview); });
    const Film blurred = sensor.psf ? applyPsf(img.film, psfKernel(*sensor.psf)) : Film{};
    optional(8, sensor.psf.has_value(), "a PSF-blurred radiance",
             [&](const std::filesystem::path& p) { writeExr(p, blurred, meta); });
    std::optional<DetectorImage> det;
    if (sensor.detector) det = applyDetector(sensor.psf ? blurred : img.film, sensor, *sensor.detector);
    optional(9, det.has_value(), "a detector image",
             [&](const std::filesystem::path& p) { writeExr(p, det->radiance, meta); });
    optional(10, det.has_value(), "a detector report", [&](const std::filesystem::path& p) {
        writeTextFileAtomic(p, detectorReportJson(*det, *sensor.detector, img.film.bands));
    });
    if (det) reportDetector(img.sensor, *det, *sensor.detector, img.film.bands);
    // The standard-error image (files[26], [27]: an ENVI pair), with two samples per pixel or more.
    if (img.standardError) {
        const EnviFields fields{"standard error of the radiance (sample spread over sqrt(samples))", kEnviRadianceUnits,
                                envi.extraHeader};
        writeEnvi(outDir / files[26], *img.standardError, description, fields);
    } else {
        removeStaleOutput(outDir / files[26], "a standard-error image");
        removeStaleOutput(outDir / files[27], "a standard-error image");
    }
    writeWaterProducts(img, outDir, files, description, envi);
}

// The water-leaving products (files[13..24] of sensorOutputFiles, ENVI pairs): the four parts of
// the radiance, Ed(0+) and Rrs = Lw / Ed(0+) (per band, after any spectral response: the ratio of
// the band-weighted means). Removed when the sensor has none, like the other optional outputs.
void writeWaterProducts(const SensorImage& img, const std::filesystem::path& outDir,
                        const std::vector<std::string>& files, const std::string& description, const EnviFields& envi) {
    struct Product {
        const char* what;
        EnviFields fields;
    };
    const std::vector<Product> products = {
        {"water-leaving radiance", {"water-leaving radiance Lw", kEnviRadianceUnits, ""}},
        {"sky-reflected radiance", {"sky-reflected radiance", kEnviRadianceUnits, ""}},
        {"sun glint", {"sun glint radiance", kEnviRadianceUnits, ""}},
        {"other radiance", {"radiance not from the sea surface", kEnviRadianceUnits, ""}},
        {"Ed(0+)", {"downwelling plane irradiance Ed(0+) at the sea point", "W m^-2 um^-1", ""}},
        {"Rrs", {"remote-sensing reflectance Rrs = Lw / Ed(0+)", "sr^-1", ""}}};
    if (!img.products) {
        for (size_t k = 0; k < products.size(); ++k)
            removeStaleOutput(outDir / files[13 + 2 * k], products[k].what),
                removeStaleOutput(outDir / files[14 + 2 * k], products[k].what);
        return;
    }
    const WaterProductFilms& p = *img.products;
    Film rrs = p.waterLeaving;
    for (size_t k = 0; k < rrs.pixels.size(); ++k) {
        const float e = p.ed0.pixels[k];
        rrs.pixels[k] = e > 0 ? p.waterLeaving.pixels[k] / e : std::numeric_limits<float>::quiet_NaN();
    }
    const Film* films[] = {&p.waterLeaving, &p.skyReflected, &p.glint, &p.other, &p.ed0, &rrs};
    for (size_t k = 0; k < products.size(); ++k) {
        EnviFields fields = products[k].fields;
        fields.extraHeader = envi.extraHeader;  // the sensor's georeferencing, as on its radiance
        writeEnvi(outDir / files[13 + 2 * k], *films[k], description, fields);
    }
}

// Bands with a spectral response: the images and probe values over the internal sub-bands become
// their weighted means. A probe's standard error is combined as sum w_i se_i, the bound for fully
// correlated sub-bands (they share their sample paths).
void applyResponseBands(const std::vector<ir::ResponseBand>& responses, RenderJobResult* res) {
    if (responses.empty()) return;
    for (SensorImage& img : res->images)
        for (Film* f : img.films()) *f = combineBands(*f, responses);
    for (ProbeValue& v : res->probes) {
        v.mean = combineValues(v.mean, responses);
        std::vector<double> se;
        for (double x : v.stderr_) se.push_back(std::abs(x));
        v.stderr_ = combineValues(se, responses);
    }
}

// The bands the outputs are labelled with: the render bands, or the response bands' nominal ones.
std::vector<Band> outputBands(const ir::SceneIR& ir, const Scene& scene) {
    return ir.render.responseBands.empty() ? scene.bands() : nominalBands(ir.render.responseBands);
}

// Writes every image set and the probe tables (the run's outputs, through atomic temporaries).
void writeOutputs(const ir::SceneIR& ir, const Scene& scene, const std::filesystem::path& outDir,
                  const RenderJobOptions& opts, RenderJobResult& res) {
    std::vector<std::string> materialNames, materialTypes;
    for (const ir::Material& m : ir.materials) {
        materialNames.push_back(m.name);
        materialTypes.push_back(materialKind(m.type).info.name);
    }
    for (const SensorImage& img : res.images) {
        const std::map<std::string, std::string> meta{{"scene", ir.name},
                                                      {"sensor", img.sensor},
                                                      {"seed", std::to_string(ir.render.seed)}};
        // File names from the one list that output_names.h checks for clashes:
        // S.exr, S.img (+ S.hdr), S.png, S_truth.exr, S_material.png, S_rgb.png (true colour),
        // S_legend.csv, S_psf.exr, S_noisy.exr, S_detector.json (the sensor model).
        const std::vector<std::string> files = sensorOutputFiles(img.sensor);
        writeExr(outDir / files[0], img.film, meta);
        const std::string description = fmt::format("Littoral render of scene {} sensor {}", ir.name, img.sensor);
        EnviFields envi;
        if (opts.enviHeaderLines) envi.extraHeader = opts.enviHeaderLines(ir, *ir.findSensor(img.sensor));
        writeEnvi(outDir / files[1], img.film, description, envi);
        PreviewOptions po = opts.preview;
        if (img.film.bandCount() < 3) po.mapping = PreviewOptions::Mapping::Grey;
        if (po.mapping == PreviewOptions::Mapping::Grey) po.greyUm = img.film.bands[0].center();
        writePngPreview(outDir / files[3], img.film, po);
        writeTruthExr(outDir / files[4], img.truth, materialNames);
        writeMaterialIdPng(outDir / files[5], img.truth);
        writeTextFileAtomic(outDir / files[7], truthLegendCsv(img.truth, materialNames, materialTypes));
        writeOptionalOutputs(*ir.findSensor(img.sensor), img, outDir, files, meta, description, envi, opts);
        for (const std::string& f : files)
            if (std::filesystem::exists(outDir / f)) res.written.push_back(outDir / f);
    }
    if (!res.probes.empty()) {
        const std::vector<std::string> files = probeOutputFiles();
        const std::vector<Band> bands = outputBands(ir, scene);
        writeTextFileAtomic(outDir / files[0], probesCsv(res.probes, bands));
        writeTextFileAtomic(outDir / files[1], probesJson(res.probes, bands));
        const std::string kd = kdCsv(res.probes, bands);
        if (!kd.empty()) writeTextFileAtomic(outDir / files[2], kd);
        else removeStaleOutput(outDir / files[2], "K_d profiles");
        for (const std::string& f : files)
            if (std::filesystem::exists(outDir / f)) res.written.push_back(outDir / f);
    }
}

// What a checkpoint of this run holds: the sensor selection, the passes, and the values of every
// selected sensor's films and of the probes (those only when every sensor is rendered).
CheckpointShape checkpointShape(const ir::SceneIR& ir, const Scene& scene, const std::vector<const ir::Sensor*>& sensors,
                                const std::string& selection, int passes) {
    CheckpointShape shape;
    shape.sensor = selection;
    shape.passes = passes;
    shape.bands = static_cast<size_t>(scene.bandCount());
    for (const ir::Sensor* s : sensors)
        shape.imageSizes.push_back(static_cast<size_t>(s->width) * s->height * shape.bands * filmCount(*s));
    if (selection.empty())
        for (const ir::Probe& p : ir.probes) shape.probeValues += p.quantities.size();
    return shape;
}

}  // namespace

RenderJobResult runRenderJob(const ir::SceneIR& ir, const std::filesystem::path& irDir,
                             const std::filesystem::path& outDir, const RenderJobOptions& opts) {
    const SourceLoc irFile{(irDir / "scene.json").string()};
    checkOutputs(ir, irFile, outDir, opts);
    const Scene scene(ir, irDir);
    const std::vector<const ir::Sensor*> sensors = selectSensors(ir, opts.sensor);

    RenderOptions ro = renderOptions(ir, opts);
    RenderJobResult res;
    const RenderConfig config = checkBeforeRendering(ir, scene, sensors, opts, ro);
    const bool probesToo = opts.sensor.empty();
    const int64_t traced0 = statCounter(kPathsTraced).value, cut0 = statCounter(kPathsCut).value;
    const int64_t straight0 = statCounter(kStraightPathSun).value;

    // Progressive passes (one unless photon maps with render.progressive.passes > 1).
    const int passes = config.usesPhotons() ? config.passes : 1;
    ProgressiveState state;
    state.irHash = std::hash<std::string>{}(ir::toJsonText(ir));
    const auto ckptDir = outDir / "progressive.checkpoint";
    int first = 1;
    const CheckpointShape shape = checkpointShape(ir, scene, sensors, opts.sensor, passes);
    // A render in one pass saves its finished tiles instead (render/tile_checkpoint.h).
    const auto tileDir = outDir / "render.checkpoint";
    std::unique_ptr<TileCheckpoint> tiles;
    if (passes < 2 && (opts.tileCheckpoint || opts.resume)) {
        std::vector<size_t> slots;
        const size_t groups = bandGroups(scene).size();
        for (const ir::Sensor* s : sensors) {
            const size_t t = static_cast<size_t>(ro.tileSize);
            slots.push_back(groups * ((static_cast<size_t>(s->width) + t - 1) / t) * ((static_cast<size_t>(s->height) + t - 1) / t));
        }
        tiles = std::make_unique<TileCheckpoint>(tileDir, state.irHash, opts.sensor, shape.imageSizes, slots);
        if (opts.resume) {
            tiles->load();
            log::info("resuming the render from its finished tiles");
        }
        ro.checkpoint = tiles.get();
    } else if (opts.resume) {
        state = loadCheckpoint(ckptDir, state.irHash, shape);
        first = state.passesDone + 1;
        log::info("resuming after pass {} of {}", state.passesDone, passes);
    }
    // The probe values the volume map's collisions answer, chosen once for every pass by a pilot.
    const CollisionPlan collisions = probesToo ? planCollisions(scene, ro.threads) : CollisionPlan{};
    for (int pass = first; pass <= passes; ++pass) {
        // One estimator per band group (and its photon maps), shared by every sensor and probe.
        const EstimatorSet estimators(scene, pass, ro.threads, opts.progress, opts.maxPhotonsEmitted);
        std::vector<SensorImage> images;
        for (size_t k = 0; k < sensors.size(); ++k) {
            ro.checkpointSensor = k;
            images.push_back(renderSensor(scene, estimators, *sensors[k], ro));
        }
        std::vector<ProbeValue> probes;
        if (probesToo) probes = evaluateProbes(scene, estimators, ro, &collisions);
        accumulate(state, images, probes);
        if (passes > 1) {
            if (opts.progress) log::info("progressive pass {} of {} done", pass, passes);  // progress: not under --quiet
            if (pass < passes && isRootRank()) saveCheckpoint(ckptDir, state, shape);  // rank 0 holds the images
        }
        if (pass == passes) finish(state, &res.images, &res.probes, images, probes);
    }
    warnIfPathsWereCut(traced0, cut0, config);
    warnIfStraightPaths(straight0);
    applyResponseBands(ir.render.responseBands, &res);
    warnAboutUncertainProbes(res.probes, outputBands(ir, scene));
    // Rank 0 alone holds the images (the other ranks rendered their share of the tiles and sent
    // them), and writes every output.
    if (!isRootRank()) return res;
    writeOutputs(ir, scene, outDir, opts, res);
    std::error_code ec;
    std::filesystem::remove_all(ckptDir, ec);  // a finished run needs no checkpoint
    std::filesystem::remove_all(tileDir, ec);
    return res;
}

namespace {
// A render-time InputError without a location that names an IR entry ("material 'sand': ...") is
// located at scene.json and that entry's JSON path ("materials[2]: material 'sand': ..."), so a
// hand-edited IR's mistake names the file and the key.
template <class T>
bool atEntry(const InputError& e, const std::vector<T>& entries, const char* what, const char* key,
             const std::filesystem::path& file) {
    for (size_t i = 0; i < entries.size(); ++i)
        if (e.message().rfind(fmt::format("{} '{}'", what, entries[i].name), 0) == 0)
            throw InputError(SourceLoc{file.string()}, fmt::format("{}[{}]: {}", key, i, e.message()));
    return false;
}

// Whether the message starts with a key path of scene.json ("render.hemisphere_samples: ...",
// "sun.half_angle_rad: ...", "instances[0] (mesh 'cube'): ...").
bool startsWithIrKey(const std::string& msg) {
    for (const std::string_view k :
         {"render", "domain", "sun", "sky", "media", "materials", "meshes", "instances", "sensors", "probes"})
        if (msg.size() > k.size() && msg.compare(0, k.size(), k) == 0 &&
            std::string_view(".[:,").find(msg[k.size()]) != std::string_view::npos)
            return true;
    return false;
}
}  // namespace

void rethrowAtIrEntry(const InputError& e, const ir::SceneIR& ir, const std::filesystem::path& file) {
    if (e.where().file.empty()) {
        atEntry(e, ir.materials, "material", "materials", file);
        atEntry(e, ir.media, "medium", "media", file);
        atEntry(e, ir.meshes, "mesh", "meshes", file);
        atEntry(e, ir.sensors, "sensor", "sensors", file);
        atEntry(e, ir.probes, "probe", "probes", file);
        if (startsWithIrKey(e.message())) throw InputError(SourceLoc{file.string()}, e.message());
    }
    throw e;
}

void preflightRenderJob(const ir::SceneIR& ir, const std::filesystem::path& irDir, const RenderJobOptions& opts) {
    ir::validateNamesAndPaths(ir, (irDir / "scene.json").string());
    checkRenderMemory(ir, opts.sensor, SourceLoc{(irDir / "scene.json").string()});
    const Scene scene(ir, irDir);
    if (ir.sensors.empty() && ir.probes.empty()) {
        // A scene may be built for its geometry alone; only a render of it is refused.
        log::warn("the scene has no sensors and no probes: `run` and `render` would have nothing to render");
        return;
    }
    const std::vector<const ir::Sensor*> sensors = selectSensors(ir, opts.sensor);
    (void)checkBeforeRendering(ir, scene, sensors, opts, renderOptions(ir, opts));
}

RenderJobResult runRenderJob(const std::filesystem::path& irDir, const std::filesystem::path& outDir,
                             const RenderJobOptions& opts) {
    const ir::SceneIR ir = ir::readIR(irDir);
    try {
        return runRenderJob(ir, irDir, outDir, opts);
    } catch (const InputError& e) {
        rethrowAtIrEntry(e, ir, irDir / "scene.json");
    }
}

}  // namespace littoral::render
