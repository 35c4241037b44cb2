#include "core/render_budget.h"

#include <algorithm>

#include <fmt/format.h>

#include "core/resource_limits.h"

namespace littoral {

RenderMemory estimateRenderMemory(const ir::SceneIR& s, const std::string& onlySensor) {
    RenderMemory m;
    const double bands = static_cast<double>(std::max<size_t>(1, s.render.bands.size()));
    double largestFilm = 0;
    for (size_t i = 0; i < s.sensors.size(); ++i) {
        const auto& c = s.sensors[i];
        if (!onlySensor.empty() && c.name != onlySensor) continue;
        const double pixels = static_cast<double>(std::max(c.width, 0)) * static_cast<double>(std::max(c.height, 0));
        const double film = 4.0 * bands * pixels;
        largestFilm = std::max(largestFilm, film);
        MemoryItem it;
        it.kind = MemoryItem::Kind::Sensor;
        it.index = i;
        it.bytes = film + 2 * 12.0 * pixels;
        it.what = fmt::format("sensor '{}' ({} x {} px x {:.0f} bands)", c.name, c.width, c.height, bands);
        m.items.push_back(it);
    }
    for (const bool surface : {true, false}) {
        // The photon counts as set (render.photons.surface / volume; makeRenderConfig checks their
        // ranges, this estimate may run on an unchecked IR too).
        const ParamValue* v = s.render.settings.find(surface ? "surface_photons" : "volume_photons");
        const double count = v ? numberOf(*v) : 0.0;
        if (!(count >= 1.0)) continue;
        const uint64_t n = static_cast<uint64_t>(std::min(count, 1.8e19));
        const double each = photonBytesEach(surface, s.render.bands.size());
        m.items.push_back({surface ? MemoryItem::Kind::SurfacePhotons : MemoryItem::Kind::VolumePhotons, 0,
                           each * static_cast<double>(n),
                           fmt::format("{} {} photons ({:.0f} B each with the search grid and its build buffers)", n,
                                       surface ? "surface" : "volume", each)});
    }
    for (const auto& it : m.items) m.total += it.bytes;
    // Writing one sensor: encoded EXR, ENVI copy and its bytes, about three films.
    m.total += 3.0 * largestFilm;
    std::stable_sort(m.items.begin(), m.items.end(), [](const MemoryItem& a, const MemoryItem& b) { return a.bytes > b.bytes; });
    return m;
}

void checkRenderMemory(const ir::SceneIR& s, const std::string& onlySensor, const SourceLoc& where) {
    const RenderMemory m = estimateRenderMemory(s, onlySensor);
    if (m.items.empty()) return;
    const std::string what = m.items.size() == 1
                                 ? fmt::format("rendering {} would", m.items[0].what)
                                 : fmt::format("rendering this scene (largest part: {}) would", m.items[0].what);
    requireMemory(m.total, what, where);
}

}  // namespace littoral
