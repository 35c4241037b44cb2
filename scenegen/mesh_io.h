#pragma once
// Reading meshes from the common interchange formats into the plain core TriMesh.
//
// OBJ, OFF and STL (ascii or binary) are parsed here, PLY by core's reader, all into a raw indexed
// triangle list rather than a half-edge structure: a half-edge importer silently duplicates the
// vertices of any face it cannot insert manifoldly (a flipped face, a third face on an edge),
// which would hide exactly the defects `checkMesh` must report. Polygons are fan-triangulated.
// STL stores a triangle soup; exactly coincident corners are merged into one vertex, as every STL
// reader does. PLY files keep the per-face "material" property written by core writePly; OBJ
// files give each face the material slot of the `usemtl` before it (see MaterialSlotName).
//
// The parsers are strict and name the cause and place of every problem (file:line:column for the
// text formats): an unknown statement, a number that is not one, an index of a vertex that does
// not exist, an element count that the file is too short to hold (checked before allocating), a
// truncated file. NaN and infinite coordinates (including a decimal number beyond the double
// range, such as 1e400) are kept, so that checkMesh names the vertices.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"
#include "core/mesh.h"

namespace littoral::scenegen {

// The file could not be read as a mesh at all (missing, not a regular file, empty, unknown
// extension, malformed or truncated). Distinct from a readable mesh that is geometrically invalid:
// `littoral check-mesh` exits 2 for this and 1 for the latter. Derives from InputError so other
// commands report it as a user error.
class MeshReadError : public InputError {
public:
    using InputError::InputError;
};

enum class MeshFormat { Obj, Ply, Off, Stl };

// Face material slots as a mesh file names them. OBJ: each distinct `usemtl` name takes the next
// slot at its first face (slot 0 for faces before any usemtl, which has no name and line 0), so
// the slots follow the order in which the names first appear on faces. PLY gives numbers only (the
// face property "material"), OFF and STL none: the list is empty for them.
struct MaterialSlotName {
    std::string name;
    int line = 0;  // the usemtl line that starts the slot (1-based; 0 = faces before any usemtl)
};

// Extensions understood by readMeshFile, lower case with the dot.
bool isSupportedMeshExtension(const std::filesystem::path& path);

// Parses mesh data already in memory (the file readers and the fuzz targets use this).
// `fileForErrors` names the data in messages. Throws MeshReadError.
// `slotNames`, if given, receives the named material slots (OBJ usemtl; see MaterialSlotName).
TriMesh parseMeshData(std::string_view data, MeshFormat format, const std::string& fileForErrors,
                      std::vector<MaterialSlotName>* slotNames = nullptr);

// Reads OBJ/PLY/OFF/STL (format by extension). Refuses anything but a regular file (a FIFO or a
// device such as /dev/zero would block or never end). Throws MeshReadError naming the file and
// the problem. The mesh is returned as stored: no vertex merging (except STL's coincident
// corners), no orientation fix, non-finite coordinates kept.
TriMesh readMeshFile(const std::filesystem::path& path, std::vector<MaterialSlotName>* slotNames = nullptr);

// Writes a mesh; the format follows the extension (.ply through core writePly, .obj/.off/.stl
// as text). Written atomically.
void writeMeshFile(const std::filesystem::path& path, const TriMesh& mesh);

}  // namespace littoral::scenegen
