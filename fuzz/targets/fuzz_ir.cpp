// The Scene IR reader (scene.json), including the name and path validation of render's input.
#include "core/scene_ir.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    littoral::fuzz::init();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    littoral::fuzz::run(data, size, [](std::string_view text) {
        const littoral::ir::SceneIR ir = littoral::ir::fromJsonText(std::string(text), "fuzz/scene.json");
        // What was read must serialise again (names were validated, numbers are numbers).
        (void)littoral::ir::toJsonText(ir);
    });
    return 0;
}
