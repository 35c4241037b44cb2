// The STL mesh reader (scenegen/mesh_io.h).
#include "fuzz_mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    littoral::fuzz::meshTarget(data, size, littoral::scenegen::MeshFormat::Stl, "fuzz/mesh.stl");
    return 0;
}
