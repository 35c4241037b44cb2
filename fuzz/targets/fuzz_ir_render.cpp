// A hand-edited Scene IR, read and rendered as `littoral render IR --out OUT` does: scene.json and
// its meshes (and any other file, e.g. a texture) packed into one input (fuzz_folder.h), unpacked
// into a scratch folder, read by ir::readIR, then rendered by render::runRenderJob inside an output
// set and an output-folder lock, with render-time errors located at their IR entry
// (rethrowAtIrEntry) -- the path of pipelines/cmd_render.cpp and main.cpp.
//
// So that every execution stays tiny, the IR is capped after it is read (never refused: a valid
// input must reach the renderer): sensors at most kMaxPixels x kMaxPixels pixels and
// kMaxSamplesPerPixel samples, probes at most kMaxProbeSamples samples, at most kMaxBands bands;
// photons stored, passes, bounces, hemisphere samples and probe batches capped, at most
// kMaxPhotonsEmitted photons emitted per photon pass; the ray-march step at least kMinMarchStep;
// one thread (--threads 1, and TBB limited to one worker). A cap only lowers a value that is set
// and of its type (or sets a setting the estimator reads anyway), so the IR's own mistakes are
// still found by the renderer's checks.
//
// InputError (exit 1 in `littoral`) and std::filesystem::filesystem_error (also exit 1) are
// expected outcomes. Anything else is a finding: a crash, a sanitizer report, a leak, an
// InternalError or other exception (exit 2). With LITTORAL_FUZZ_RECORD_INTERNAL=DIR set, an
// escaping InternalError is instead printed and its input saved as DIR/internal-<hash>, and
// fuzzing goes on (for long campaigns; every recorded input is a bug to fix).
//
// With LITTORAL_FUZZ_VERBOSE set, each input's outcome is printed (the images and probe values
// rendered, or the error): `fuzz_ir_render corpus/*` shows which inputs reach the renderer.
//
// Built only with -DLITTORAL_FUZZ_RENDER=ON (it compiles the renderer with the sanitizers).
#include <tbb/global_control.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <memory>
#include <set>
#include <string>

#include "core/atomic_file.h"
#include "core/log.h"
#include "core/progress.h"
#include "core/scene_ir.h"
#include "fuzz_common.h"
#include "fuzz_folder.h"
#include "render/estimator_settings.h"
#include "render/render_job.h"

namespace {

namespace ir = littoral::ir;

constexpr int kMaxPixels = 4;
constexpr int kMaxSamplesPerPixel = 2;
constexpr int kMaxProbeSamples = 32;
constexpr int kMaxProbeBatches = 4;
constexpr size_t kMaxBands = 3;
constexpr int64_t kMaxPhotons = 2000;
constexpr uint64_t kMaxPhotonsEmitted = 16384;  // one chunk of the photon pass (render/photon_pass.cpp)
constexpr int64_t kMaxPasses = 3;
constexpr int64_t kMaxBounces = 8;
constexpr int64_t kMaxSpecularDepth = 16;
constexpr int64_t kMaxPhotonBounces = 16;
constexpr int64_t kMaxHemisphereSamples = 4;
constexpr double kMinMarchStep = 0.5;  // m; rays through water are cut after at most 10^4 m

// Lowers the integer setting `key` to `cap` if it is set to more; with `always`, sets it to `cap`
// when it is unset (for a setting the estimator reads whatever the scene, whose default is larger).
void capInteger(ir::RenderSettings& r, const std::string& key, int64_t cap, bool always) {
    const littoral::ParamValue* v = r.settings.find(key);
    if (!v) {
        if (always) r.settings.set(key, cap);
    } else if (const auto* i = std::get_if<int64_t>(v); i && *i > cap) {
        r.settings.set(key, cap);
    }
}

void capForATinyRender(ir::SceneIR& s) {
    for (ir::Sensor& c : s.sensors) {
        c.width = std::min(c.width, kMaxPixels);
        c.height = std::min(c.height, kMaxPixels);
        c.samplesPerPixel = std::min(c.samplesPerPixel, kMaxSamplesPerPixel);
    }
    for (ir::Probe& p : s.probes)
        if (p.samples) p.samples = std::min(*p.samples, kMaxProbeSamples);
    ir::RenderSettings& r = s.render;
    if (r.bands.size() > kMaxBands) r.bands.resize(kMaxBands);
    const bool dirsig = r.estimator == ir::Estimator::Dirsig;
    // Read by every estimator (a probe's samples can then still be refused against the batches,
    // as before the caps: min(samples, 32) >= min(batches, 4) when samples >= batches).
    capInteger(r, "probe_samples", kMaxProbeSamples, true);
    capInteger(r, "probe_batches", kMaxProbeBatches, true);
    capInteger(r, "max_bounces", kMaxBounces, true);
    capInteger(r, "max_specular_depth", kMaxSpecularDepth, true);
    if (dirsig) capInteger(r, "hemisphere_samples", kMaxHemisphereSamples, true);
    // The path estimator's forward probe tallies (default 10^6 photons in a column scene).
    if (!dirsig) capInteger(r, "probe_photons", kMaxPhotons, true);
    // Read only with a photon-map solver: lowered when set, never added, except photon_max_bounces
    // (default 200) when photons are set (read with them, or the photons' own key is refused as unread).
    const bool photons = r.settings.has("surface_photons") || r.settings.has("volume_photons");
    capInteger(r, "surface_photons", kMaxPhotons, false);
    capInteger(r, "volume_photons", kMaxPhotons, false);
    capInteger(r, "progressive_passes", kMaxPasses, false);
    capInteger(r, "photon_max_bounces", kMaxPhotonBounces, dirsig && photons);
    // The ray-march step: read by the path estimator, and by dirsig's volume photon map.
    const littoral::ParamValue* step = r.settings.find("march_step_m");
    if (step && !std::holds_alternative<bool>(*step)) {
        if (littoral::numberOf(*step) < kMinMarchStep) r.settings.set("march_step_m", kMinMarchStep);
    } else if (!step && (!dirsig || r.settings.has("volume_photons"))) {
        r.settings.set("march_step_m", kMinMarchStep);
    }
}

// `littoral render IR --out OUT --threads 1`, with the caps between reading and rendering.
void renderIr(const std::filesystem::path& irDir, const std::filesystem::path& outDir, bool verbose) {
    littoral::OutputSet outputs;
    {
        const littoral::OutputFolderLock lock(outDir);
        const auto t0 = std::chrono::steady_clock::now();
        ir::SceneIR s = ir::readIR(irDir);
        capForATinyRender(s);
        littoral::render::RenderJobOptions jo;
        jo.threads = 1;
        jo.progress = false;
        jo.maxPhotonsEmitted = kMaxPhotonsEmitted;
        try {
            const auto res = littoral::render::runRenderJob(s, irDir, outDir, jo);
            if (verbose)
                std::fprintf(stderr, "rendered %zu image(s), %zu probe value(s) in %.3f s\n", res.images.size(),
                             res.probes.size(), std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        } catch (const littoral::InputError& e) {
            littoral::render::rethrowAtIrEntry(e, s, irDir / "scene.json");
        }
    }
    outputs.commit();
}

void recordInternalError(const char* dir, const std::string& what, std::string_view bytes) {
    static std::set<std::string> seen;
    const std::string name = "internal-" + std::to_string(std::hash<std::string_view>{}(bytes));
    std::ofstream(std::filesystem::path(dir) / name, std::ios::binary).write(bytes.data(),
                                                                            static_cast<std::streamsize>(bytes.size()));
    if (seen.insert(what).second) std::fprintf(stderr, "LITTORAL-FUZZ internal error (%s): %s\n", name.c_str(), what.c_str());
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    littoral::fuzz::init();
    littoral::render::registerEstimatorKinds();  // as main() does
    littoral::log::setLevel(littoral::log::Level::Quiet);
    littoral::Progress::setEnabled(false);
    // One worker: the photon map's parallel loops run in TBB's default arena, not the render's.
    static tbb::global_control oneThread(tbb::global_control::max_allowed_parallelism, 1);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    const std::filesystem::path scratch = littoral::fuzz::scratchFolder("ir-render");
    const std::filesystem::path irDir = scratch / "ir", outDir = scratch / "out";
    std::filesystem::create_directories(irDir);
    littoral::fuzz::unpackFolder(bytes, irDir, "scene.json");
    static const bool verbose = std::getenv("LITTORAL_FUZZ_VERBOSE") != nullptr;
    try {
        renderIr(irDir, outDir, verbose);
    } catch (const littoral::InputError& e) {
        // Expected for most inputs.
        if (verbose) std::fprintf(stderr, "input error: %s\n", e.what());
    } catch (const std::filesystem::filesystem_error& e) {
        // The file system refused something: exit 1 in `littoral` (main.cpp), as for the user.
        if (verbose) std::fprintf(stderr, "file system error: %s\n", e.what());
    } catch (const littoral::InternalError& e) {
        const char* dir = std::getenv("LITTORAL_FUZZ_RECORD_INTERNAL");
        if (!dir) throw;
        recordInternalError(dir, e.what(), bytes);
    }
    // One process, many runs: this run's inputs are gone (and a run that keeps memory is re-run by
    // libFuzzer to look for a leak).
    littoral::clearNotedInputs();
    return 0;
}
