#pragma once
// A whole render run: Scene IR directory in, images and probe tables out (`littoral render`).
//
// Every sensor and probe is computed in memory first; files are written only after all of them
// succeeded, each through an atomic temporary, so bad input (InputError) leaves no output at all.
//
// Output files in `outDir`, per sensor S:
//   S.exr              multi-band radiance, channels named by wavelength
//   S.img + S.hdr      ENVI band-sequential float32 with the wavelength list
//   S.png              8-bit preview (band -> RGB or grey, gamma 0.65)
//   S_truth.exr        materialId, range (m), hitDepth (m) of the pixel-centre rays
//   S_material.png     false-colour material ids
// and, if the scene has probes, probes.csv and probes.json.
//
// With progressive photon mapping the images and probe values are the means over the passes
// (each pass its own photon maps, radii shrinking as r_p = r_1 p^((alpha - 1)/2)); the probes'
// standard errors are then the spread of the pass means over sqrt(passes), which includes the
// photon maps' own noise.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/scene_ir.h"
#include "render/probes.h"
#include "render/image_output.h"
#include "render/renderer.h"

namespace littoral::render {

struct RenderJobOptions {
    std::string sensor;    // render only this sensor ("" = all)
    int threads = 0;       // 0 = all cores
    bool progress = true;
    // Checkpoints. Progressive photon mapping (render.progressive.passes > 1): after every pass the
    // running sums are saved to DIR/progressive.checkpoint/. A render in one pass: its finished
    // tiles, every LITTORAL_CHECKPOINT_SECONDS (30 s), to DIR/render.checkpoint/
    // (render/tile_checkpoint.h). With `resume` a run continues from the checkpoint made by the same
    // IR and sensor selection (InputError otherwise). The checkpoint is removed when the outputs are
    // written.
    bool resume = false;
    // false: no tile checkpoint for a one-pass render (a command whose run folders belong to one
    // output set, such as the image-quality study, where an interrupt must leave nothing).
    bool tileCheckpoint = true;
    PreviewOptions preview;  // PNG display mapping: gamma, white level, Gaussian blur (image_output.h)
    // Photons a photon pass may emit while filling its maps (0: the default, at least 10^7; a map
    // still short then holds what was stored, with a warning). For tiny runs (fuzz/).
    uint64_t maxPhotonsEmitted = 0;
    // Further ENVI header lines for a sensor's images (the pipelines' georeferencing: map info and
    // coordinate system string), or none.
    std::function<std::string(const ir::SceneIR&, const ir::Sensor&)> enviHeaderLines;
};

struct RenderJobResult {
    std::vector<SensorImage> images;
    std::vector<ProbeValue> probes;
    std::vector<std::filesystem::path> written;
};

// Renders an IR already in memory (`irDir` resolves textures) and writes the outputs.
RenderJobResult runRenderJob(const ir::SceneIR& ir, const std::filesystem::path& irDir,
                             const std::filesystem::path& outDir, const RenderJobOptions& opts);
// Every check runRenderJob makes before it renders, except those on the output folder: the
// names, the memory budget, the scene on its bands (materials, media, textures, class maps,
// instance transforms), the estimator's settings, the sensor selection and every sensor's view
// (its truth image is traced), and every probe's medium, position and sample plan. InputError
// exactly as runRenderJob would throw it; nothing is written. `check-scene` runs it.
void preflightRenderJob(const ir::SceneIR& ir, const std::filesystem::path& irDir, const RenderJobOptions& opts);
// Rethrows `e`, located at `file` (scene.json) and the JSON path of the IR entry it names when it
// has no location and begins with "material 'x'", "medium 'x'", "mesh 'x'", "sensor 'x'" or
// "probe 'x'"; located at `file` as it is when it begins with a key path of scene.json
// ("render.hemisphere_samples: ...", "sun.zenith_rad: ...", "instances[0] ..."). So a hand-edited
// IR's mistake names the file and the key.
[[noreturn]] void rethrowAtIrEntry(const InputError& e, const ir::SceneIR& ir, const std::filesystem::path& file);
// Reads the IR from `irDir` (ir::readIR) and runs the job; render-time errors name scene.json and
// the entry (rethrowAtIrEntry).
RenderJobResult runRenderJob(const std::filesystem::path& irDir, const std::filesystem::path& outDir,
                             const RenderJobOptions& opts);

}  // namespace littoral::render
