#pragma once
// Mesh validity for the renderer: a water body or a solid object must be a closed, manifold,
// non-self-intersecting, outward-oriented triangle surface enclosing a positive volume, or every
// radiometric number computed inside it is wrong (a ray leaks through a hole, a medium boundary
// is crossed an odd number of times).
//
// checkMesh() works on the raw indexed triangles so that defects an half-edge structure cannot
// even represent (a third face on an edge, a face wound against its neighbours) are named at the
// element level; the geometric tests (self-intersections, volume bounding, outward orientation)
// use exact predicates (Epick): self-intersections on the triangle soup itself (faces that share
// only an edge or a vertex do not count, at manifold and non-manifold edges alike), volume
// bounding and orientation through CGAL Polygon Mesh Processing. repairMesh() is the explicit,
// opt-in fix-up: merge coincident vertices, drop degenerate faces, make orientation consistent,
// stitch borders, orient every component to bound a volume; it reports each change.
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/mesh.h"

namespace littoral::scenegen {

using EdgeKey = std::array<uint32_t, 2>;  // vertex indices, smaller first

struct FacePair {
    uint32_t a = 0, b = 0;
    bool operator==(const FacePair&) const = default;
};

struct ValidityReport {
    size_t vertices = 0, faces = 0;

    // Element-level findings (complete lists; messages truncate them).
    std::vector<uint32_t> nonFiniteVertices;     // NaN or infinite coordinates
    std::vector<uint32_t> badIndexFaces;         // refer to a vertex that does not exist
    std::vector<uint32_t> degenerateFaces;       // repeated vertex or collinear corners (zero area)
    std::vector<EdgeKey> boundaryEdges;          // used by exactly one face (holes)
    std::vector<EdgeKey> nonManifoldEdges;       // used by three or more faces
    std::vector<uint32_t> nonManifoldVertices;   // faces around the vertex form more than one fan
    std::vector<EdgeKey> inconsistentEdges;      // two faces traverse the edge in the same direction
    std::vector<uint32_t> flippedFaces;          // the minority orientation within a component
    std::vector<FacePair> selfIntersections;     // face pairs that intersect other than along shared edges
    bool selfIntersectionTested = false;         // false if the geometry was too broken to test

    size_t components = 0;         // edge-connected face components
    bool empty = true;             // no faces
    bool closed = false;           // no boundary edges (and at least one face)
    bool manifold = false;         // no non-manifold edges or vertices
    bool consistentlyOriented = false;
    bool boundsVolume = false;     // CGAL does_bound_a_volume: closed, manifold, no self-intersection, nesting-consistent
    bool outward = false;          // orientation makes the enclosed volume positive
    double volume = 0.0;           // enclosed volume, m^3 (divergence theorem); 0 unless boundsVolume
    double area = 0.0;             // m^2

    // A closed volume that the renderer may trust.
    bool valid() const;
    // One line per failed property, naming elements (at most `maxListed` per list).
    std::vector<std::string> reasons(size_t maxListed = 10) const;
    // {"closed","manifold","self_intersections","bounds_volume","outward","volume_m3",
    //  "boundary_edges","components", ...}; lists truncated to `maxListed` entries each.
    nlohmann::json toJson(size_t maxListed = 100) const;
};

struct CheckOptions {
    bool testSelfIntersections = true;  // the only super-linear test; on by default
};

ValidityReport checkMesh(const TriMesh& mesh, const CheckOptions& options = {});

// What repairMesh changed.
struct RepairReport {
    size_t verticesMerged = 0;        // exactly coincident vertices unified
    size_t degenerateFacesRemoved = 0;
    size_t duplicateFacesRemoved = 0;
    size_t facesReversedForConsistency = 0;
    size_t bordersStitched = 0;       // pairs of border edges joined
    size_t facesReversedOutward = 0;  // faces reversed so that components bound a volume
    size_t facesReversedNet = 0;      // faces whose final orientation differs from the input's
    std::vector<std::string> changes() const;  // human-readable, one line per non-zero item
    nlohmann::json toJson() const;
};

// Repairs in place (non-finite vertices are not repairable and raise InputError naming them).
// Per-face materials follow their faces.
RepairReport repairMesh(TriMesh& mesh);

}  // namespace littoral::scenegen
