#pragma once
// The sun refracted by flat facets: every smooth triangle between the air and a denser medium
// (the water surface's facets, a floating object's dry faces) sends the sunlight it receives into
// that medium as a parallel beam, the triangle swept along its refracted direction. A point in the
// medium is lit directly by the facets whose beams contain it (several where facets focus the
// light: caustics; none in a beam's gap). FacetBeams finds them for one direction of the solar
// disc; SunConnection traces the one it picks to check visibility and weighs it (Fresnel, the
// facet's projected area, the water on the way).
//
// The index: the beam of facet f contains p iff the line through p along f's refracted direction
// d_f meets the triangle above p, i.e. iff pi_f(p), the point where that line meets z = 0, lies in
// pi_f(triangle). With the reference direction d0 (the sun refracted by a horizontal surface) and
// sigma(p) = pi_0(p), pi_f(p) = sigma(p) - p.z (k_f - k0), k = d.xy / d.z: in the sheared plane of
// sigma, f's beam at depth z is its projected triangle moved by z (k_f - k0), which drifts slowly
// because facets are tilted only moderately. A uniform grid over sigma, one per depth slab (slabs
// thin enough that a beam drifts about one cell across one), lists the facets whose footprint, for
// any direction of the solar disc, overlaps each cell. A query looks up one cell and tests its few
// candidates exactly. In a horizontally periodic domain sigma wraps around the domain's period (a
// beam that leaves through a side wall comes back through the opposite one).
#include <array>
#include <cstdint>
#include <vector>

#include "core/scene_ir.h"
#include "core/vec.h"

namespace littoral::render {

class Scene;

struct BeamFacet {
    Point3 a, b, c;  // world vertices
    Normal3 nAir;    // unit normal on the air side
    int mesh = -1, instance = -1;
    uint32_t face = 0;
    double extent = 0;   // the larger side of its plan-view bounding box, m
    bool large = false;  // wider than a quarter of the domain's period (periodic images are all tested)
};

class FacetBeams {
public:
    // The beams into `medium` (index n, the sun toward `sunDir` with half-angle `halfAngle`) from
    // every smooth interface facet whose other side is a sky medium (sky[m]: the media the sun
    // shines through, SunConnection's rule) and whose air side the disc can light. Empty if there
    // is none.
    FacetBeams(const Scene& scene, int medium, double n, const std::vector<bool>& sky, const Vec3& sunDir,
               double halfAngle);
    bool empty() const { return facets_.empty(); }
    // Does the medium share a smooth interface with another dense medium (a dielectric object in
    // the water)? Light through it reaches a point along two or more refractions, which the beams
    // do not follow: SunConnection then keeps the straight-path estimate for this medium.
    bool hasObjects() const { return objects_; }
    // Are all the facets horizontal (flat water)? Their beams are then the one beam the straight
    // path follows, which SunConnection traces instead, at the cost of one ray; they are not
    // indexed (forEachContaining finds none).
    bool allHorizontal() const { return horizontal_; }
    size_t facetCount() const { return facets_.size(); }
    size_t entryCount() const { return entries_.size(); }

    // Calls f(facet index, refracted direction d (unit, pointing into the medium), distance s from
    // p back to the facet along -d) for every facet whose beam for the sun direction ws (in air,
    // toward the sun, within the disc) contains p. Returns the number of such facets.
    template <class F> int forEachContaining(const Point3& p, const Vec3& ws, F&& f) const;
    const BeamFacet& facet(int i) const { return facets_[static_cast<size_t>(i)]; }
    // The direction into the medium along which facet i refracts light from ws (false: none).
    bool refracted(int i, const Vec3& ws, Vec3* d) const;

private:
    // Does facet i's beam along d contain p? Sets *s (distance back to the facet).
    bool contains(int i, const Point3& p, const Vec3& d, double* s) const;
    bool containsImage(const BeamFacet& f, const Point3& p, const Vec3& d, const Vec3& S, double* s) const;
    // The grid cell list of p (nullptr, 0 if p lies outside the index).
    const int32_t* cellOf(const Point3& p, int* count) const;
    void build(const Vec3& sunDir, double halfAngle, double zBottom, const ir::Domain& domain);
    // Per facet, the drift k - k0 of each of the disc directions' beams (NaN where one misses).
    struct Drifts;
    void fill(const Drifts& drifts, bool count);
    // The plan-view box, in the sheared plane, of facet i's beams between depths zLo and zHi for
    // every disc direction: {x0, x1, y0, y1}, empty (x1 < x0) if no direction makes a beam.
    std::array<double, 4> footprint(size_t i, const Drifts& drifts, double zLo, double zHi) const;

    std::vector<BeamFacet> facets_;
    double eta_ = 1;        // 1 / n: air over the medium
    bool periodic_ = false, objects_ = false, horizontal_ = true;
    double px_ = 0, py_ = 0;  // the domain's periods (periodic)
    double k0x_ = 0, k0y_ = 0;  // the reference direction's horizontal drift per unit depth
    // The grid: slab s covers z in (zTop - (s + 1) h, zTop - s h]; cell (i, j) covers sigma in
    // [x0 + i cx, x0 + (i + 1) cx) x [y0 + j cy, ...). entries_[offsets_[k] .. offsets_[k + 1]) are
    // the facets of cell k = (s ny + j) nx + i.
    double zTop_ = 0, slab_ = 1, cellX_ = 1, cellY_ = 1, x0_ = 0, y0_ = 0;
    int nx_ = 0, ny_ = 0, nz_ = 0;
    std::vector<uint32_t> offsets_;
    std::vector<int32_t> entries_;
};

template <class F> int FacetBeams::forEachContaining(const Point3& p, const Vec3& ws, F&& f) const {
    int count = 0, n = 0;
    const int32_t* list = cellOf(p, &n);
    for (int k = 0; k < n; ++k) {
        Vec3 d;
        double s = 0;
        if (!refracted(list[k], ws, &d) || !contains(list[k], p, d, &s)) continue;
        ++count;
        f(list[k], d, s);
    }
    return count;
}

}  // namespace littoral::render
