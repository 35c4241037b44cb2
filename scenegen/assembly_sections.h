#pragma once
// Parsers for the scene-file sections that scenegen assembles into geometry: `bathymetry`,
// `objects` and `texture_classes`. Called by the top-level parser (scene_file.h) with the YAML
// nodes it kept; every mistake is an InputError at file:line:column naming the key and what is
// allowed. Keys are documented in docs/scene-assembly.md.
#include <vector>

#include "scenegen/assembly_spec.h"
#include "scenegen/yaml_reader.h"

namespace littoral::scenegen {

BathymetrySpec parseBathymetry(const YamlNode& node);
std::vector<ObjectSpec> parseObjects(const YamlNode& node);
TextureClassesSpec parseTextureClasses(const YamlNode& node);


}  // namespace littoral::scenegen
