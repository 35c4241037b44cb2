// The PLY mesh reader (scenegen/mesh_io.h), and core's strict PLY reader used for IR meshes.
#include "fuzz_mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    littoral::fuzz::meshTarget(data, size, littoral::scenegen::MeshFormat::Ply, "fuzz/mesh.ply");
    littoral::fuzz::run(data, size, [](std::string_view bytes) { (void)littoral::parsePly(bytes, "fuzz/ir_mesh.ply"); });
    return 0;
}
