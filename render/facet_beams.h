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
//
// Chains (docs/rendering.md, "Beams through dielectric objects"): where the medium shares smooth
// faces with another dense medium (a dielectric object in the water, the water around an object),
// light also reaches it through two or more refractions: a beam in one dense medium meets a face
// of another and is refracted again, still as a parallel beam (the faces are flat). Every such
// chain of up to maxOrder() refractions, entering from the air only at its first face, is a
// BeamLink with its parent; the chains that end in this medium are listed in a plan-view grid of
// their beams' boxes and tested, after the grid's facets, by box, by a quick test along the beam's
// mean direction (the lit part of its last face), and exactly.
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/bbox.h"
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

// One refraction of a chain: light that reached the face through its parent's beam (or straight
// from the sun: parent -1) crosses it from medium `from` into medium `to`.
struct BeamLink {
    Point3 a, b, c;   // world vertices
    Normal3 nFrom;    // unit normal on the side the light comes from
    double eta = 1;   // n_from / n_to
    int mesh = -1, instance = -1;
    uint32_t face = 0;
    int from = -1, to = -1;
    int parent = -1;  // index in the chain's links (-1: the first face, lit by the sun)
    Vec3 shift;       // periodic domains: the parent's image that lights this face is the parent moved by shift
    int order = 1;
    BBox3 box;        // bounds this link's beam inside the scene (the links that end in the medium)
    // A quick test before the exact one: the beam's mean direction over the disc, the tangent of
    // the largest angle of a disc direction's beam from it, and the face's box.
    Vec3 mean;
    double tanSpread = 0;
    BBox3 faceBox;
};

// A face a beam's chain crosses, in order from the point back toward the sun.
struct BeamFace {
    int mesh = -1, instance = -1;
    uint32_t face = 0;
};

class FacetBeams {
public:
    // The beams into `medium` (index n, the sun toward `sunDir` with half-angle `halfAngle`) from
    // every smooth interface facet whose other side is a sky medium (sky[m]: the media the sun
    // shines through, SunConnection's rule) and whose air side the disc can light. Empty if there
    // is none.
    // With objects (hasObjects), chains of up to maxOrder refractions are indexed too (at least 1).
    // index[m]: medium m's refractive index.
    FacetBeams(const Scene& scene, int medium, const std::vector<double>& index, const std::vector<bool>& sky,
               const Vec3& sunDir, double halfAngle, int maxOrder = kMaxChainOrder);
    static constexpr int kMaxChainOrder = 3;  // air -> water -> object -> water
    // A facet's beam closer to the horizontal than this (|d.z| < kMinSlope, 5.7 deg) is not in the
    // grid (its drift per depth is unbounded): light along it is left to sampling (SunChain).
    static constexpr double kMinSlope = 0.1;
    bool empty() const { return facets_.empty() && finals_.empty(); }
    // Does the medium share a smooth interface with another dense medium (a dielectric object in
    // the water)? Light then reaches it through chains of refractions too, which are indexed.
    bool hasObjects() const { return objects_; }
    // Are all the facets horizontal (flat water)? Without objects their beams are then the one
    // beam the straight path follows, which SunConnection traces instead, at the cost of one ray;
    // they are not indexed (forEachContaining finds none). With objects they are.
    bool allHorizontal() const { return horizontal_; }
    size_t facetCount() const { return facets_.size(); }
    size_t entryCount() const { return entries_.size(); }
    size_t chainCount() const { return finals_.size(); }
    // The largest number of refractions a beam into this medium takes: 1 without objects, else
    // the chain length that was indexed completely (kMaxChainOrder unless the links overflowed).
    int maxOrder() const { return maxOrder_; }

    // Calls f(beam index, refracted direction d (unit, pointing into the medium), distance s from
    // p back to the beam's last face along -d) for every beam whose light from the sun direction ws
    // (in air, toward the sun, within the disc) contains p: facets first (index < facetCount()),
    // then chains. Returns the number of such beams.
    template <class F> int forEachContaining(const Point3& p, const Vec3& ws, F&& f) const;
    const BeamFacet& facet(int i) const { return facets_[static_cast<size_t>(i)]; }
    // The direction into the medium along which facet i refracts light from ws (false: none).
    bool refracted(int i, const Vec3& ws, Vec3* d) const;
    // Beam i's irradiance for light from ws per unit irradiance from the sun, before attenuation
    // and shadowing: the product over its refractions of the Fresnel transmittance and the face's
    // area across the beam before over after (cos_incident / cos_transmitted). 0 if none.
    double weight(int i, const Vec3& ws) const;
    // The faces beam i crosses, from the point back toward the sun; returns their number.
    int faces(int i, std::array<BeamFace, kMaxChainOrder>* out) const;

private:
    // Does facet i's beam along d contain p? Sets *s (distance back to the facet).
    bool contains(int i, const Point3& p, const Vec3& d, double* s) const;
    bool containsImage(const BeamFacet& f, const Point3& p, const Vec3& d, const Vec3& S, double* s) const;
    // The chains' grid: cells over the plan view (the domain when periodic), each listing the
    // chains whose box, moved by a periodic image (ix, iy periods), overlaps it.
    struct ChainEntry {
        int32_t final;
        int8_t ix, iy;
    };
    std::pair<const ChainEntry*, const ChainEntry*> chainCell(const Point3& p) const;
    void buildChainGrid(const ir::Domain& dom);
    // The quick test: does p (unwrapped) lie near link l's beam along its mean direction?
    static bool nearBeam(const BeamLink& l, const Point3& p);
    // Does chain link j's beam for ws contain p (unwrapped)? Sets *d and *s as forEachContaining.
    bool chainContains(int j, const Point3& p, const Vec3& ws, Vec3* d, double* s) const;
    // Link j and its ancestors, j first, root last; returns their number.
    int chainOf(int j, std::array<int, kMaxChainOrder>* links) const;
    // The travel directions of light from ws along link j's chain, first face first ([0, order)).
    bool chainDirections(int j, const Vec3& ws, std::array<Vec3, kMaxChainOrder>* d) const;
    void buildChains(const Scene& scene, int medium, const std::vector<double>& index, const std::vector<bool>& sky,
                     const Vec3& sunDir, double halfAngle, int maxOrder);
    // A grid entry: the facet and its footprint in the cell's slab (the sheared plane's box that
    // holds its beams for every disc direction, in the cell's periodic image), clipped to the cell
    // and rounded outward to 1/65535 of it. A query tests the box before it reads the facet: the
    // cell's entries are contiguous, the facets' records are not (most of a query's cache misses
    // were theirs; the test halved the lookup's time).
    struct Entry {
        int32_t facet;
        uint16_t x0, x1, y0, y1;
    };
    static constexpr double kEntryScale = 65535;
    Entry entry(int32_t facet, int ci, int cj, double x0, double x1, double y0, double y1) const;
    // The grid cell list of p and p's position in the cell in the entries' units (nullptr, 0 if p
    // lies outside the index).
    const Entry* cellOf(const Point3& p, int* count, double* sx, double* sy) const;
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
    std::vector<Entry> entries_;
    // Chains: every link (ancestors included) and the links that end in this medium.
    std::vector<BeamLink> links_;
    std::vector<int> finals_;
    int maxOrder_ = 1;
    double cx0_ = 0, cy0_ = 0, ccell_ = 1;
    int cnx_ = 0, cny_ = 0;
    std::vector<uint32_t> chainOffsets_;
    std::vector<ChainEntry> chainEntries_;
};

template <class F> int FacetBeams::forEachContaining(const Point3& p, const Vec3& ws, F&& f) const {
    int count = 0, n = 0;
    double sx = 0, sy = 0;
    const Entry* list = cellOf(p, &n, &sx, &sy);
    for (int k = 0; k < n; ++k) {
        const Entry& e = list[k];
        if (sx < e.x0 || sx > e.x1 || sy < e.y0 || sy > e.y1) continue;
        Vec3 d;
        double s = 0;
        if (!refracted(e.facet, ws, &d) || !contains(e.facet, p, d, &s)) continue;
        ++count;
        f(e.facet, d, s);
    }
    if (finals_.empty()) return count;
    const int nf = static_cast<int>(facets_.size());
    const auto [begin, end] = chainCell(p);
    for (const ChainEntry* e = begin; e != end; ++e) {
        const BeamLink& l = links_[static_cast<size_t>(finals_[static_cast<size_t>(e->final)])];
        const Point3 q{p.x + e->ix * px_, p.y + e->iy * py_, p.z};
        Vec3 d;
        double s = 0;
        if (!l.box.contains(q) || !nearBeam(l, q) || !chainContains(finals_[static_cast<size_t>(e->final)], q, ws, &d, &s))
            continue;
        ++count;
        f(nf + e->final, d, s);
    }
    return count;
}

}  // namespace littoral::render
