#pragma once
// The scene file's `water.surface` section: the same choices as `littoral waves`, read strictly
// (every key checked, ranges enforced, errors at file:line:column). The keys of each model, their
// defaults and ranges are its descriptor's (surfaces/wave_kinds.h); docs/scene-format.md lists
// them, docs/waves.md, "Scene file: water.surface", explains them.
#include <algorithm>
#include <optional>

#include "core/scene_ir.h"
#include "scenegen/yaml_reader.h"
#include "surfaces/wave_surface.h"

namespace littoral::scenegen {

// Parses and validates the section (including the checks that need the whole parameter set:
// grid memory, triangle target, resolution of the model's length scales). Throws InputError.
surfaces::WaveParams parseWaterSurface(const YamlNode& node);
// The first half of parseWaterSurface: the keys alone (the model, each key's type and range, the
// defaults), as the model's descriptor (surfaces/wave_kinds.h) gives them; no check that combines
// keys. Throws InputError at the key.
surfaces::WaveParams readWaterSurfaceKeys(const YamlNode& node);
// The grid of a flat surface, which needs no resolution: four cells across the shorter side of
// p's size, kept whole (32 triangles that hold the plane exactly). An omitted water.surface has it,
// and so has `model: flat` where the file gives no `spacing` or `triangles`.
constexpr double kFlatCellsAcross = 4;
inline double flatSpacing(const surfaces::WaveParams& p) { return std::min(p.sizeX, p.sizeY) / kFlatCellsAcross; }

// `water.surface.roughness`: roughness below the mesh's resolution (the dissertation's sub-pixel
// capillary waves), as the Cox–Munk microfacet interface of render/rough_dielectric.h on every
// facet of the surface. Returns the air–water interface material `name` (type RoughDielectric)
// when the section has `roughness`, nullopt otherwise. The wind defaults to the surface's own for
// the wind-driven models; it must lie in Cox and Munk's range (InputError at the key otherwise).
// `surface` is the water.surface node, `waves` what parseWaterSurface made of it.
std::optional<ir::Material> parseSurfaceRoughness(const YamlNode& surface, const surfaces::WaveParams& waves,
                                                  const std::string& name);

}  // namespace littoral::scenegen
