#pragma once
// The closed water body of a scene, built with CGAL corefinement booleans.
//
// Construction (all solids closed and outward-oriented; booleans in the Epeck kernel, exact
// predicates and constructions, rounded to doubles once at the end, then vertices closer than
// 1e-8 m welded so that rounding leaves no sliver or fold):
//   1. Water prism P: the wave surface clipped in plan view to the domain rectangle (exact
//      Sutherland–Hodgman clipping; boundary vertices land exactly on the rectangle edges), closed
//      by vertical walls down to z_lo = (lowest seabed or surface sample) - 1 m and a flat bottom.
//   2. Terrain solid T: the seabed/land height field sampled on a grid over the domain grown by a
//      margin (so T's sides lie strictly outside P's walls and no faces are coplanar), closed by
//      vertical skirts down to z_lo - 1 m and a flat bottom.
//   3. Water W = P - T; land L = top faces of (T - P) clipped to the domain (the terrain exposed
//      to air: beach, dune, dry bars). Both from one corefinement.
//   4. The solid objects (hull, piling, target), checked pairwise disjoint, form one multi-component
//      solid S; one corefinement gives W - S and W n S, whose components give each object's
//      displaced volume. Each object stays a separate closed solid in the IR.
// Every face of W carries a material slot tracked through the booleans by a corefinement visitor:
//   - the air-water interface (from the wave surface),
//   - the seabed class materials (from the terrain top, per face by the classification),
//   - the object materials on the faces where water touches an object (the hull seen from the
//     water; these coincide with the object's own submerged faces and carry the same material, so
//     whichever of the two coincident hits a ray tracer reports, the surface it shades is the same),
//   - "domain wall" on the vertical sides where the scene domain cuts the ocean (see the material
//     choice in docs/scene-assembly.md: an absorbing boundary standing in for the open sea).
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "bathymetry/terrain.h"
#include "core/mesh.h"

namespace littoral::scenegen {

// The material of the water mesh's air-water faces (the IR names it; assemble.cpp defines it).
inline constexpr const char* kInterfaceMaterialName = "air-water-interface";

// A closed solid placed in world coordinates; faceMaterial slots index `materials`.
struct PlacedSolid {
    std::string name;
    TriMesh mesh;
    std::vector<std::string> materials;
    // Also return the part of the solid's surface outside the water (WaterVolumeResult::dryParts):
    // for transparent objects, whose wet faces become the water's interface with them.
    bool keepDryPart = false;
};

struct WaterVolumeInput {
    bathymetry::Extent domain;                 // plan-view scene domain, metres
    TriMesh surface;                           // air-water interface: a height field covering the domain
    std::function<double(double, double)> elevation;  // terrain z(x, y), metres (seabed < 0 < land)
    double terrainSpacing = 1.0;               // grid spacing of the terrain solid, metres
    // Seabed/land materials and the slot of a terrain face from its plan-view centroid.
    std::vector<std::string> terrainMaterials{"seabed"};
    std::function<uint16_t(double, double)> terrainMaterialAt;  // empty: slot 0 everywhere
    std::vector<PlacedSolid> solids;           // subtracted from the water
    std::string interfaceMaterial = kInterfaceMaterialName;
    std::string wallMaterial = "domain-wall";
};

struct WaterVolumeResult {
    TriMesh water;                       // closed; faceMaterial indexes `waterMaterials`
    std::vector<std::string> waterMaterials;
    TriMesh land;                        // open terrain surface above water; indexes terrainMaterials
    TriMesh terrainTop;                  // the sampled terrain over the domain (for reference/tests)
    double prismVolume = 0;              // m^3, P: water column over the whole domain down to z_lo
    double waterVolumeBeforeSolids = 0;  // m^3, P - T
    std::vector<double> displaced;       // m^3 of water removed by each solid (same order as input)
    // Per solid with keepDryPart: the faces of its surface that do not touch the water (S - W, the
    // solid's own faces only; slots index its materials), split along the waterline exactly where
    // the water mesh's faces against it end, so the two meet edge to edge. Empty otherwise.
    std::vector<TriMesh> dryParts;
    double zLo = 0;                      // m, floor of the prism
    // Face counts by role in the final water mesh.
    size_t interfaceFaces = 0, seabedFaces = 0, wallFaces = 0, objectFaces = 0;
    // Wall-clock seconds of each stage.
    double secondsPrism = 0, secondsTerrain = 0, secondsBoolean = 0, secondsSolids = 0;
};

// Builds the water body. InputError if the surface does not cover the domain, if there is no
// water in the domain, if two solids intersect each other, or if a boolean fails.
WaterVolumeResult buildWaterVolume(const WaterVolumeInput& input);

// Plan-view clipping of a triangle soup to a rectangle (Sutherland–Hodgman per triangle, z
// interpolated linearly along edges so clipped pieces stay in their triangle's plane). Points on
// shared edges are computed from the edge's endpoints in a canonical order, so neighbours stay
// conforming; coincident output vertices are merged. faceMaterial follows the faces.
TriMesh clipToRectangle(const TriMesh& mesh, const bathymetry::Extent& rect);

// Boolean operations on closed, outward-oriented meshes with per-face material slots (slots of `a`
// and `b` must already share one numbering). InputError naming `what` when CGAL refuses (a
// self-intersecting or open input) or the result is not a closed volume.
enum class BooleanOp { Union, Intersection, Difference };
TriMesh booleanSolids(const TriMesh& a, const TriMesh& b, BooleanOp op, const std::string& what);

// Do two closed meshes intersect or is one inside the other (PMP::do_intersect)?
bool solidsOverlap(const TriMesh& a, const TriMesh& b);

}  // namespace littoral::scenegen
