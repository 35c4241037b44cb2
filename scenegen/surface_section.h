#pragma once
// The scene file's `water.surface` section: the same choices as `littoral waves`, read strictly
// (every key checked, ranges enforced, errors at file:line:column). Keys are documented in
// docs/waves.md, "Scene file: water.surface".
#include "scenegen/yaml_reader.h"
#include "surfaces/wave_surface.h"

namespace littoral::scenegen {

// Parses and validates the section (including the checks that need the whole parameter set:
// grid memory, triangle target, resolution of the model's length scales). Throws InputError.
surfaces::WaveParams parseWaterSurface(const YamlNode& node);

}  // namespace littoral::scenegen
