// The OBJ mesh reader (scenegen/mesh_io.h).
#include "core/mesh.h"
#include "fuzz_common.h"
#include "scenegen/mesh_io.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    littoral::fuzz::init();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    littoral::fuzz::run(data, size, [](std::string_view bytes) {
        const littoral::TriMesh m =
            littoral::scenegen::parseMeshData(bytes, littoral::scenegen::MeshFormat::Obj, "fuzz/mesh.obj");
        // Every index a reader returns must name a vertex.
        for (const auto& t : m.triangles)
            for (uint32_t v : t)
                if (v >= m.positions.size()) __builtin_trap();
    });
    return 0;
}
