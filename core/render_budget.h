#pragma once
// Memory a render of a Scene IR will need, estimated from the IR alone so that an impossible
// request (a 100000^2 sensor, 100 bands, ten billion photons) is refused before anything is
// allocated, naming the setting (core/resource_limits.h).
//
// Per sensor with P pixels and B bands the renderer keeps the radiance film (4 B bytes per pixel)
// and the truth images (material id, range, depth: 12 bytes per pixel, computed twice: once to
// validate every view first, once with the radiance) until all files are written; writing one
// sensor adds about three more copies of its film (the encoded EXR, the ENVI band-sequential
// copy and its bytes). Photon maps store photonRecordBytes() per photon (render/photon_map.h:
// position, octahedral direction and one half-float power per band of the largest band group),
// with their grid and its build buffers (photonBytesEach).
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/scene_ir.h"

namespace littoral {

inline constexpr int kPhotonGroupBandsMax = 16;      // render/spectral.h kMaxGroupBands
// Bytes of one stored photon with `bands` bands per group: 12 (position) + 4 (direction) + 2 per
// band, and 4 more (surface normal) on a surface photon.
inline double photonRecordBytes(bool surface, size_t bands) {
    const double b = static_cast<double>(std::min<size_t>(std::max<size_t>(bands, 1), kPhotonGroupBandsMax));
    return (surface ? 20.0 : 16.0) + 2.0 * b;
}
// Peak bytes per photon of a map of n photons: the records with the pass's reserve (1/16 more,
// render/photon_pass.cpp), the hash grid (one 4-byte bucket start per bucket, buckets the next power
// of two above n: at most 8 B per photon) and the grid build's working buffers (bucket and slot
// indices, 4 + 4 B, and a copy of the largest field, the 12 B position; render/photon_map.cpp).
// Counting the build buffers for both maps overstates by 20 B per photon of the smaller map, which
// is built after the other has released them: a safe side for a budget check.
inline constexpr double kPhotonGridBytes = 8.0, kPhotonBuildBytes = 20.0;
inline double photonBytesEach(bool surface, size_t bands) {
    return photonRecordBytes(surface, bands) * (17.0 / 16.0) + kPhotonGridBytes + kPhotonBuildBytes;
}

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
