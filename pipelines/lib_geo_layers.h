#pragma once
// Per-pixel georeferencing layers (docs/outputs.md, "Georeferencing"): for each sensor of a scene
// with scene.origin, NAME_geo.img (+ .hdr: ENVI float64, band names) holds, for the surface each pixel's centre ray meets first,
// its latitude and longitude (WGS84, degrees), the view zenith and azimuth (the direction from
// that point toward the sensor) and the sun's zenith and azimuth there, in degrees; azimuths are
// compass bearings from true north (the UTM grid's convergence taken out). NaN where the ray
// meets nothing.
#include <filesystem>
#include <vector>

#include "core/scene_ir.h"
#include "render/render_job.h"

namespace littoral::pipelines {

// The layer names, in file order.
std::vector<std::string> geoLayerNames();

// Writes OUT/NAME_geo.img and .hdr for every rendered sensor when the IR has a geo reference, and removes
// one an earlier run left when it has none. Returns the files written.
std::vector<std::filesystem::path> writeGeoLayers(const ir::SceneIR& ir, const render::RenderJobResult& res,
                                                  const std::filesystem::path& outDir);

}  // namespace littoral::pipelines
