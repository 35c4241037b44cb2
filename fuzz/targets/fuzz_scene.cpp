// The scene-file reader: strict YAML (yaml_reader), every section parser of scene_file, and the
// geometry-section parsers of assembly_sections (bathymetry, objects, texture classes).
#include "fuzz_common.h"
#include "scenegen/assembly_sections.h"
#include "scenegen/scene_file.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    littoral::fuzz::init();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace littoral::scenegen;
    littoral::fuzz::run(data, size, [](std::string_view text) {
        const YamlNode root = YamlNode::loadString(std::string(text), "fuzz/scene.yaml");
        const SceneSpec spec = parseScene(root, "fuzz/scene.yaml");
        if (spec.bathymetry) parseBathymetry(*spec.bathymetry);
        if (spec.objects) parseObjects(*spec.objects);
        if (spec.textureClasses) parseTextureClasses(*spec.textureClasses);
        littoral::ir::SceneIR ir;
        applyCommonSections(spec, &ir);
    });
    return 0;
}
