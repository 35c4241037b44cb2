#pragma once
// Facetization of a height field: the regular grid triangulated (two triangles per cell,
// diagonal (i,j)-(i+1,j+1), counter-clockwise seen from above so normals point up), optionally
// reduced to a target triangle count with OpenMesh's decimater (quadric error metric of Garland
// and Heckbert 1997, halfedge collapses so surviving vertices keep their exact positions).
//
// The rectangle's boundary is kept: the four corners are locked, a boundary vertex may only
// collapse along its own edge of the rectangle, and no collapse may tip a triangle past
// vertical (its normal must keep n_z > 0.05 |n|), so the result is still a height field whose
// boundary vertices lie exactly on the rectangle's edges.
#include <cstddef>
#include <filesystem>
#include <vector>

#include "core/mesh.h"
#include "core/vec.h"
#include "surfaces/height_field.h"

namespace littoral::surfaces {

// Full-resolution triangulation, 2 (nx-1)(ny-1) triangles, without OpenMesh.
TriMesh triangulate(const HeightField& f);

struct Facets {
    TriMesh mesh;
    std::vector<Normal3> vertexNormals;  // unit, area-weighted average of the face normals
};

// Builds the OpenMesh mesh (from the presampled lattice, see below), decimates it to at most targetTriangles (if smaller than the
// grid's count; otherwise the full grid is kept) and converts back. The decimater may stop
// above the target when the constraints allow no further collapse.
Facets facetize(const HeightField& f, size_t targetTriangles);

// Triangles the full grid has: 2 (nx-1)(ny-1).
inline size_t gridTriangles(const HeightField& f) { return 2ull * (f.nx - 1) * (f.ny - 1); }
// Smallest triangle count decimation can reach: the rectangle as two triangles.
constexpr size_t kMinTriangles = 2;

// Decimation starts from a lattice of every stride-th grid sample (plus the last row and column)
// holding at least kPresampleFactor times the target's vertex count; see facetize.cpp.
inline constexpr double kPresampleFactor = 4.0;
int presampleStride(const HeightField& f, size_t targetTriangles);
// 0, stride, 2 stride, ..., n-1 (a final gap shorter than half a stride is merged).
std::vector<int> latticeIndices(int n, int stride);

// Wavefront OBJ with vertex normals (if given), written atomically.
void writeObj(const std::filesystem::path& path, const TriMesh& mesh, const std::vector<Normal3>& normals);

// Approximate bytes the decimation needs per lattice vertex (OpenMesh connectivity, normals,
// quadrics, decimation heap); an upper bound used by the memory estimate.
constexpr size_t kFacetizeBytesPerVertex = 600;

}  // namespace littoral::surfaces
