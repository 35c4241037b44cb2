#include "column/column_problem.h"

#include <cmath>

#include <fmt/format.h>

#include "core/error.h"

namespace littoral::column {

int ColumnBand::layerAt(double depth) const {
    int k = 0;
    for (size_t i = 1; i < layers.size(); ++i)
        if (depth >= layers[i].top) k = static_cast<int>(i);
    return k;
}

namespace {

ColumnLayer layerFromIr(const ir::Layer& l, const Band& band, double top, const std::string& who) {
    ColumnLayer c;
    c.top = top;
    c.a = l.absorption.bandAverage(band, who + " absorption");
    std::vector<std::pair<double, PhaseFunction>> parts;
    for (const auto& s : l.scatterers) {
        const double b = s.scattering.bandAverage(band, who + " scatterer '" + s.name + "'");
        if (b <= 0) continue;
        parts.emplace_back(b, makePhaseFunction(s.phase.type, s.phase.params, who + " scatterer '" + s.name + "'"));
        c.b += b;
    }
    if (!parts.empty()) c.phase = PhaseFunction::mixture(parts);
    return c;
}

}  // namespace

ColumnBand columnBandFromIr(const ir::SceneIR& scene, double waterLevel, const IrBottom& bottom, int bandIndex) {
    const ir::Medium* water = scene.findMedium("water");
    if (!water) throw InputError("the column solver needs water: the scene has no water medium");
    LITTORAL_CHECK(bandIndex >= 0 && static_cast<size_t>(bandIndex) < scene.render.bands.size());
    ColumnBand c;
    c.band = scene.render.bands[static_cast<size_t>(bandIndex)];
    c.waterIndex = water->refractiveIndex.bandAverage(c.band, "water refractive index");
    for (size_t i = 0; i < water->layers.size(); ++i) {
        const ir::Layer& l = water->layers[i];
        const double top = std::isinf(l.zTop) ? 0.0 : waterLevel - l.zTop;
        if (c.layers.empty() && top > 0) LITTORAL_CHECK(!"first water layer must reach the surface");
        if (!c.layers.empty() && top <= 0) continue;  // a layer entirely above the surface
        if (bottom.depth && top >= *bottom.depth) break;
        c.layers.push_back(layerFromIr(l, c.band, std::max(0.0, top), fmt::format("water layer {}", i + 1)));
    }
    if (scene.sun.enabled) {
        c.sunZenith = scene.sun.zenith;
        c.sunAzimuth = scene.sun.azimuth;
        c.sunIrradiance = scene.sun.irradiance.bandAverage(c.band, "sun irradiance");
    }
    c.skyRadiance = scene.sky.radiance.bandAverage(c.band, "sky radiance");
    c.bottomDepth = bottom.depth;
    if (bottom.depth) c.bottomReflectance = bottom.reflectance.bandAverage(c.band, "bottom reflectance");
    return c;
}

}  // namespace littoral::column
