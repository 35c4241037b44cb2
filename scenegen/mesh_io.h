#pragma once
// Reading meshes from the common interchange formats into the plain core TriMesh.
//
// OBJ, OFF, STL (ascii or binary) and PLY are read through OpenMesh's readers, but into a raw
// indexed triangle soup rather than an OpenMesh half-edge structure: OpenMesh's own importer
// silently duplicates the vertices of any face it cannot insert manifoldly (a flipped face, a third
// face on an edge), which would hide exactly the defects `checkMesh` must report. Polygons are
// fan-triangulated. PLY files that carry the per-face "material" property written by core
// writePly are read by core readPly so the material slots survive.
#include <filesystem>
#include <string>

#include "core/error.h"
#include "core/mesh.h"

namespace littoral::scenegen {

// The file could not be read as a mesh at all (missing, empty, unknown extension, malformed).
// Distinct from a readable mesh that is geometrically invalid: `littoral check-mesh` exits 2 for
// this and 1 for the latter. Derives from InputError so other commands report it as a user error.
class MeshReadError : public InputError {
public:
    using InputError::InputError;
};

// Extensions understood by readMeshFile, lower case with the dot.
bool isSupportedMeshExtension(const std::filesystem::path& path);

// Reads OBJ/PLY/OFF/STL. Throws MeshReadError naming the file and the problem. The mesh is
// returned as stored: no vertex merging, no orientation fix, non-finite coordinates kept (so the
// validity check can name them).
TriMesh readMeshFile(const std::filesystem::path& path);

// Writes a mesh; the format follows the extension (.ply through core writePly, .obj/.off/.stl
// through OpenMesh). Written atomically.
void writeMeshFile(const std::filesystem::path& path, const TriMesh& mesh);

}  // namespace littoral::scenegen
