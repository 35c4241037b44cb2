#pragma once
// Memory a render of a Scene IR will need, estimated from the IR alone so that an impossible
// request (a 100000^2 sensor, 100 bands, ten billion photons) is refused before anything is
// allocated, naming the setting (core/resource_limits.h).
//
// Per sensor with P pixels and B bands the renderer keeps the radiance film (4 B bytes per pixel)
// and the truth images (material id, range, depth: 12 bytes per pixel, computed twice: once to
// validate every view first, once with the radiance) until all files are written; writing one
// sensor adds about three more copies of its film (the encoded EXR, the ENVI band-sequential
// copy and its bytes). Photon maps store kPhotonRecordBytes per photon.
#include <cstdint>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/scene_ir.h"

namespace littoral {

inline constexpr double kPhotonRecordBytes = 32.0;  // position, direction, power, flags

struct MemoryItem {
    enum class Kind { Sensor, SurfacePhotons, VolumePhotons };
    Kind kind = Kind::Sensor;
    size_t index = 0;      // sensor index (Kind::Sensor)
    double bytes = 0;
    std::string what;      // "sensor 'nadir': 20000 x 20000 px x 100 bands"
};

struct RenderMemory {
    double total = 0;                 // bytes, including the write-time peak
    std::vector<MemoryItem> items;    // what the total is made of, largest first
};

// Estimate for rendering `scene` (only the sensor named `onlySensor` when not empty; probes and
// photon maps are needed either way).
RenderMemory estimateRenderMemory(const ir::SceneIR& scene, const std::string& onlySensor = "");

// InputError at `where` if the estimate exceeds the memory budget, naming the largest item.
void checkRenderMemory(const ir::SceneIR& scene, const std::string& onlySensor, const SourceLoc& where);

}  // namespace littoral
