#pragma once
// The plain triangle mesh that crosses module boundaries (surfaces -> scenegen -> IR -> render).
// Modules that need topology (OpenMesh, CGAL) convert to and from this at their edges, so the
// renderer never depends on them.
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/bbox.h"
#include "core/vec.h"

namespace littoral {

struct TriMesh {
    std::vector<Point3> positions;                  // metres
    std::vector<std::array<uint32_t, 3>> triangles; // counter-clockwise seen from the outside
    // Optional per-face material slot (index into the owner's material list); empty = all slot 0.
    std::vector<uint16_t> faceMaterial;

    size_t numVertices() const { return positions.size(); }
    size_t numTriangles() const { return triangles.size(); }
    uint16_t materialOf(size_t face) const { return faceMaterial.empty() ? 0 : faceMaterial[face]; }
    BBox3 bounds() const;
    // Unnormalised geometric normal (cross product of the edges): length = 2 * area.
    Vec3 faceNormalArea(size_t face) const;
    double area() const;
    // Signed volume by the divergence theorem (positive for a closed, outward-oriented mesh).
    double signedVolume() const;
    // Appends another mesh (indices offset), keeping per-face materials consistent.
    void append(const TriMesh& other);
};

// PLY I/O. Writing: binary little-endian, double-precision vertices, face property
// "material" (ushort) when faceMaterial is set; the output is byte-for-byte deterministic and
// written atomically (core/atomic_file.h).
// Reading: ascii, binary_little_endian or binary_big_endian; any scalar vertex types; faces as
// a "vertex_indices" list (polygons are fan-triangulated, at most 1000 corners); optional face
// "material". Strict: unknown header keywords, element counts that the file is too short to
// hold (checked before anything is allocated), indices that are not whole numbers or name a
// vertex that does not exist, and truncated data are InputErrors naming the file (and for
// ascii data the line and column).
struct PlyReadOptions {
    // Keep NaN / infinite coordinates (for validity checks that name them); otherwise an error.
    bool allowNonFinite = false;
};
std::string plyBytes(const TriMesh& mesh);
void writePly(const std::filesystem::path& path, const TriMesh& mesh);
TriMesh parsePly(std::string_view data, const std::string& fileForErrors, const PlyReadOptions& options = {});
TriMesh readPly(const std::filesystem::path& path, const PlyReadOptions& options = {});

}  // namespace littoral
