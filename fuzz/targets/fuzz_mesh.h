#pragma once
// Shared by the mesh-reader fuzz targets (OBJ, OFF, PLY, STL): parse the bytes in one format and
// check that every index the reader returns names a vertex.
#include "core/mesh.h"
#include "fuzz_common.h"
#include "scenegen/mesh_io.h"

namespace littoral::fuzz {

inline void meshTarget(const uint8_t* data, size_t size, scenegen::MeshFormat format, const char* name) {
    run(data, size, [&](std::string_view bytes) {
        const TriMesh m = scenegen::parseMeshData(bytes, format, name);
        for (const auto& t : m.triangles)
            for (uint32_t v : t)
                if (v >= m.positions.size()) __builtin_trap();
    });
}

}  // namespace littoral::fuzz

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    littoral::fuzz::init();
    return 0;
}
