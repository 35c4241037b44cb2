// CGAL translation unit 2 of 2 in scenegen (the other is mesh_validity.cpp): corefinement
// booleans for the water body and for composite solids. Plain TriMesh at the interface.
#include "scenegen/water_volume.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <numeric>
#include <optional>
#include <unordered_map>

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/intersection.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Surface_mesh.h>
#include <fmt/format.h>

#include "core/error.h"
#include "core/log.h"

namespace littoral::scenegen {
namespace {

// Exact constructions: with rounded constructions (Epick) the intersection points of axis-aligned
// or flat configurations (a still surface at z = 0, a planar slope, the vertical domain walls) drift
// off their planes and the corefined result can contain slivers and self-intersections. With Epeck
// the booleans are decided exactly and only the final conversion to double rounds; points on the
// planes z = 0 and x, y = domain edge stay exactly on them.
using K = CGAL::Exact_predicates_exact_constructions_kernel;
using SM = CGAL::Surface_mesh<K::Point_3>;
using FI = SM::Face_index;
namespace PMP = CGAL::Polygon_mesh_processing;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Face tags inside this file: fixed roles first, then terrain slots, then solid material slots.
constexpr uint16_t kTagInterface = 0;
constexpr uint16_t kTagWall = 1;
constexpr uint16_t kTagPrismBottom = 2;
constexpr uint16_t kTagTerrainSkirt = 3;
constexpr uint16_t kTagTerrainBase = 4;

// ---------------------------------------------------------------- Surface_mesh conversion

const char* kTagProperty = "f:littoral_tag";

SM toSurfaceMesh(const TriMesh& m, const std::string& what) {
    SM sm;
    sm.reserve(static_cast<SM::size_type>(m.positions.size()), static_cast<SM::size_type>(3 * m.triangles.size() / 2),
               static_cast<SM::size_type>(m.triangles.size()));
    // Vertices are created on first use: isolated vertices would upset CGAL's volume queries.
    std::vector<SM::Vertex_index> v(m.positions.size(), SM::null_vertex());
    auto vertex = [&](uint32_t i) {
        if (v[i] == SM::null_vertex()) v[i] = sm.add_vertex({m.positions[i].x, m.positions[i].y, m.positions[i].z});
        return v[i];
    };
    auto tag = sm.add_property_map<FI, int>(kTagProperty, -1).first;
    for (size_t f = 0; f < m.triangles.size(); ++f) {
        const auto& t = m.triangles[f];
        const FI fi = sm.add_face(vertex(t[0]), vertex(t[1]), vertex(t[2]));
        if (fi == SM::null_face())
            throw InputError(fmt::format("{}: face {} cannot join the surface (non-manifold or inconsistently oriented "
                                         "neighbourhood); run `littoral check-mesh` on it",
                                         what, f));
        tag[fi] = m.materialOf(f);
    }
    return sm;
}

TriMesh fromSurfaceMesh(const SM& sm) {
    TriMesh out;
    auto tag = sm.property_map<FI, int>(kTagProperty).first;
    std::vector<uint32_t> index(sm.num_vertices() + sm.number_of_removed_vertices(), UINT32_MAX);
    for (auto v : sm.vertices()) {
        // Booleans can leave vertices that no face uses any more (the prism's bottom centre).
        if (sm.is_isolated(v)) continue;
        index[v.idx()] = static_cast<uint32_t>(out.positions.size());
        const auto& p = sm.point(v);
        out.positions.push_back({CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())});
    }
    out.triangles.reserve(sm.number_of_faces());
    out.faceMaterial.reserve(sm.number_of_faces());
    for (auto f : sm.faces()) {
        std::array<uint32_t, 3> t{};
        int k = 0;
        for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) {
            LITTORAL_CHECK_LT(k, 3);
            t[k++] = index[v.idx()];
        }
        out.triangles.push_back(t);
        LITTORAL_CHECK_GE(tag[f], 0);
        out.faceMaterial.push_back(static_cast<uint16_t>(tag[f]));
    }
    return out;
}

// Corefinement visitor that carries each face's tag to the faces made from it: sub-faces of a split
// face, and faces copied from one mesh into another (CGAL example
// corefinement_mesh_union_with_attributes.cpp does the same). CGAL copies visitors, so the state
// lives behind a shared pointer.
struct TagVisitor : public PMP::Corefinement::Default_visitor<SM> {
    struct State {
        int current = -1;
    };
    std::shared_ptr<State> state = std::make_shared<State>();

    static SM::Property_map<FI, int> tags(const SM& m) { return m.property_map<FI, int>(kTagProperty).first; }
    void before_subface_creations(FI split, SM& tm) { state->current = tags(tm)[split]; }
    void after_subface_created(FI created, SM& tm) { tags(tm)[created] = state->current; }
    void after_face_copy(FI src, const SM& tmSrc, FI tgt, SM& tmTgt) { tags(tmTgt)[tgt] = tags(tmSrc)[src]; }
};

// ---------------------------------------------------------------- clipping and closing

struct PointKey {
    uint64_t x, y, z;
    bool operator==(const PointKey&) const = default;
};
struct PointKeyHash {
    size_t operator()(const PointKey& k) const {
        return std::hash<uint64_t>()(k.x * 0x9e3779b97f4a7c15ULL ^ (k.y + 0x632be59bd9b4e019ULL) * 31 ^ k.z);
    }
};
PointKey keyOf(const Point3& p) {
    PointKey k;
    std::memcpy(&k.x, &p.x, 8);
    std::memcpy(&k.y, &p.y, 8);
    std::memcpy(&k.z, &p.z, 8);
    return k;
}

// Builds a TriMesh from polygons of explicit points, merging bitwise-identical points.
class MeshBuilder {
public:
    uint32_t vertex(const Point3& p) {
        auto [it, inserted] = index_.try_emplace(keyOf(p), static_cast<uint32_t>(mesh.positions.size()));
        if (inserted) mesh.positions.push_back(p);
        return it->second;
    }
    void triangle(uint32_t a, uint32_t b, uint32_t c, uint16_t slot) {
        mesh.triangles.push_back({a, b, c});
        mesh.faceMaterial.push_back(slot);
    }
    TriMesh mesh;

private:
    std::unordered_map<PointKey, uint32_t, PointKeyHash> index_;
};

bool lexLess(const Point3& a, const Point3& b) {
    return a.x != b.x ? a.x < b.x : (a.y != b.y ? a.y < b.y : a.z < b.z);
}

// Intersection of segment ab with the plane {axis} = c, computed from the endpoints in
// lexicographic order so both triangles sharing the edge get the same point.
Point3 cut(Point3 a, Point3 b, int axis, double c) {
    if (lexLess(b, a)) std::swap(a, b);
    const double t = (c - a[axis]) / (b[axis] - a[axis]);
    Point3 p = a + (b - a) * t;
    p[axis] = c;  // exactly on the clip line
    return p;
}

double planArea2(const std::vector<Point3>& poly) {
    double s = 0;
    for (size_t i = 0; i < poly.size(); ++i) {
        const auto& a = poly[i];
        const auto& b = poly[(i + 1) % poly.size()];
        s += a.x * b.y - b.x * a.y;
    }
    return s;
}

// Vertical walls under every boundary edge down to zLo, and a flat bottom fanned from the plan
// centre of the rectangle `rect` (the boundary must be the rectangle's outline, which is convex,
// so the fan is valid). The top is a height field with faces counter-clockwise from above.
TriMesh closeDownward(const TriMesh& top, double zLo, const bathymetry::Extent& rect, uint16_t wallTag,
                      uint16_t bottomTag) {
    MeshBuilder b;
    b.mesh.positions = top.positions;
    b.mesh.triangles = top.triangles;
    b.mesh.faceMaterial = top.faceMaterial;
    if (b.mesh.faceMaterial.empty()) b.mesh.faceMaterial.assign(top.triangles.size(), 0);
    // Register existing points so new ones merge with them only if identical (they are not: z differs).
    for (const auto& p : top.positions) b.vertex(p);
    std::map<std::pair<uint32_t, uint32_t>, int> count;
    for (const auto& t : top.triangles)
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = t[k], c = t[(k + 1) % 3];
            count[{std::min(a, c), std::max(a, c)}]++;
        }
    const uint32_t centre = b.vertex({0.5 * (rect.x0 + rect.x1), 0.5 * (rect.y0 + rect.y1), zLo});
    for (const auto& t : top.triangles)
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = t[k], c = t[(k + 1) % 3];
            if (count[{std::min(a, c), std::max(a, c)}] != 1) continue;
            const Point3 pa = top.positions[a], pc = top.positions[c];
            const uint32_t a2 = b.vertex({pa.x, pa.y, zLo}), c2 = b.vertex({pc.x, pc.y, zLo});
            // The top face runs a -> c; the wall runs c -> a so the edge is shared consistently, and
            // its normal points away from the interior (to the right of a -> c in plan view).
            b.triangle(c, a, a2, wallTag);
            b.triangle(c, a2, c2, wallTag);
            b.triangle(c2, a2, centre, bottomTag);
        }
    return std::move(b.mesh);
}

// Terrain height field over `rect` with nx x ny cells; faces counter-clockwise from above, tagged
// by `tagAt` at their plan centroid.
TriMesh terrainGrid(const std::function<double(double, double)>& z, const bathymetry::Extent& rect, int nx, int ny,
                    const std::function<uint16_t(double, double)>& tagAt) {
    TriMesh m;
    m.positions.reserve(static_cast<size_t>(nx + 1) * (ny + 1));
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) {
            const double x = rect.x0 + rect.width() * i / nx, y = rect.y0 + rect.height() * j / ny;
            const double h = z(x, y);
            if (!std::isfinite(h)) throw InputError(fmt::format("terrain elevation at ({}, {}) m is not finite", x, y));
            m.positions.push_back({x, y, h});
        }
    auto id = [nx](int i, int j) { return static_cast<uint32_t>(j * (nx + 1) + i); };
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
            for (auto t : {std::array<uint32_t, 3>{a, b, c}, std::array<uint32_t, 3>{a, c, d}}) {
                const Point3 g = (m.positions[t[0]] + m.positions[t[1]] + m.positions[t[2]]) / 3.0;
                m.triangles.push_back(t);
                m.faceMaterial.push_back(tagAt(g.x, g.y));
            }
        }
    return m;
}

// Exact booleans rounded to doubles can leave distinct vertices a few ulps apart (two exact
// intersection points that differ by 1e-18 m) and faces spanning them, which are degenerate or fold
// over in double precision. Welding vertices closer than `eps` and dropping the faces that collapse
// (repeated corners) and the zero-volume face pairs that result (same three vertices twice) is an
// edge collapse at the sub-nanometre scale: it keeps the surface closed and removes the slivers.
void weldVertices(TriMesh& m, double eps) {
    const size_t nv = m.positions.size();
    std::vector<uint32_t> rep(nv);
    std::iota(rep.begin(), rep.end(), 0u);
    std::function<uint32_t(uint32_t)> find = [&](uint32_t x) {
        while (rep[x] != x) x = rep[x] = rep[rep[x]];
        return x;
    };
    struct CellHash {
        size_t operator()(const std::array<int64_t, 3>& c) const {
            return std::hash<int64_t>()(c[0] * 73856093LL ^ c[1] * 19349663LL ^ c[2] * 83492791LL);
        }
    };
    std::unordered_map<std::array<int64_t, 3>, std::vector<uint32_t>, CellHash> cells;
    auto cellOf = [eps](const Point3& p) {
        return std::array<int64_t, 3>{static_cast<int64_t>(std::floor(p.x / eps)), static_cast<int64_t>(std::floor(p.y / eps)),
                                      static_cast<int64_t>(std::floor(p.z / eps))};
    };
    for (uint32_t v = 0; v < nv; ++v) {
        const auto c = cellOf(m.positions[v]);
        for (int64_t dx = -1; dx <= 1; ++dx)
            for (int64_t dy = -1; dy <= 1; ++dy)
                for (int64_t dz = -1; dz <= 1; ++dz) {
                    auto it = cells.find({c[0] + dx, c[1] + dy, c[2] + dz});
                    if (it == cells.end()) continue;
                    for (uint32_t u : it->second)
                        if (distance(m.positions[u], m.positions[v]) <= eps) {
                            const uint32_t a = find(u), b = find(v);
                            if (a != b) rep[std::max(a, b)] = std::min(a, b);
                        }
                }
        cells[c].push_back(v);
    }
    std::vector<std::array<uint32_t, 3>> tris;
    std::vector<uint16_t> mats;
    std::map<std::array<uint32_t, 3>, std::vector<size_t>> byVertexSet;
    for (size_t f = 0; f < m.triangles.size(); ++f) {
        std::array<uint32_t, 3> t{find(m.triangles[f][0]), find(m.triangles[f][1]), find(m.triangles[f][2])};
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
        auto key = t;
        std::sort(key.begin(), key.end());
        byVertexSet[key].push_back(tris.size());
        tris.push_back(t);
        mats.push_back(m.materialOf(f));
    }
    std::vector<char> drop(tris.size(), 0);
    for (const auto& [key, faces] : byVertexSet)
        if (faces.size() == 2)
            for (size_t f : faces) drop[f] = 1;
    TriMesh out;
    std::vector<uint32_t> index(nv, UINT32_MAX);
    for (size_t f = 0; f < tris.size(); ++f) {
        if (drop[f]) continue;
        std::array<uint32_t, 3> t{};
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = tris[f][k];
            if (index[v] == UINT32_MAX) {
                index[v] = static_cast<uint32_t>(out.positions.size());
                out.positions.push_back(m.positions[v]);
            }
            t[k] = index[v];
        }
        out.triangles.push_back(t);
        out.faceMaterial.push_back(mats[f]);
    }
    m = std::move(out);
}

// Weld distance: far below any feature of a scene (m), far above the rounding of exact points.
constexpr double kWeldEps = 1e-8;

void checkClosedSM(const SM& sm, const std::string& what) {
    if (!CGAL::is_closed(sm)) throw InternalError(what + " is not closed after construction");
}

}  // namespace

TriMesh clipToRectangle(const TriMesh& mesh, const bathymetry::Extent& r) {
    MeshBuilder b;
    std::vector<Point3> poly, next;
    for (size_t f = 0; f < mesh.triangles.size(); ++f) {
        const auto& t = mesh.triangles[f];
        poly = {mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]};
        bool clipped = false;
        // Four half-planes: x >= x0, x <= x1, y >= y0, y <= y1 (inclusive).
        const struct { int axis; double c; double sign; } planes[4] = {{0, r.x0, 1}, {0, r.x1, -1}, {1, r.y0, 1}, {1, r.y1, -1}};
        for (const auto& pl : planes) {
            if (poly.empty()) break;
            auto inside = [&](const Point3& p) { return pl.sign * (p[pl.axis] - pl.c) >= 0; };
            next.clear();
            for (size_t i = 0; i < poly.size(); ++i) {
                const Point3& cur = poly[i];
                const Point3& nxt = poly[(i + 1) % poly.size()];
                const bool ci = inside(cur), ni = inside(nxt);
                if (ci) next.push_back(cur);
                if (ci != ni) {
                    // A strictly outside endpoint exists, so the denominator is non-zero.
                    next.push_back(cut(cur, nxt, pl.axis, pl.c));
                    clipped = true;
                }
                if (!ci) clipped = true;
            }
            poly.swap(next);
        }
        // Drop consecutive duplicates (a vertex exactly on the line produces one).
        std::vector<Point3> clean;
        for (const auto& p : poly)
            if (clean.empty() || !(clean.back() == p)) clean.push_back(p);
        while (clean.size() > 1 && clean.front() == clean.back()) clean.pop_back();
        if (clean.size() < 3 || planArea2(clean) == 0.0) continue;
        const uint16_t slot = mesh.materialOf(f);
        if (!clipped || clean.size() == 3) {
            b.triangle(b.vertex(clean[0]), b.vertex(clean[1]), b.vertex(clean[2]), slot);
            continue;
        }
        // A clipped convex polygon may hold collinear runs along the clip line; a fan from its
        // centroid never produces a zero-area triangle there (the centroid is strictly inside).
        Point3 c;
        for (const auto& p : clean) c += p;
        c = c / static_cast<double>(clean.size());
        const uint32_t ci = b.vertex(c);
        for (size_t i = 0; i < clean.size(); ++i)
            b.triangle(ci, b.vertex(clean[i]), b.vertex(clean[(i + 1) % clean.size()]), slot);
    }
    return std::move(b.mesh);
}

TriMesh booleanSolids(const TriMesh& a, const TriMesh& b, BooleanOp op, const std::string& what) {
    SM ma = toSurfaceMesh(a, what + " (first operand)");
    SM mb = toSurfaceMesh(b, what + " (second operand)");
    TagVisitor vis;
    bool ok = false;
    try {
        const auto np = PMP::parameters::visitor(vis).throw_on_self_intersection(true);
        switch (op) {
            case BooleanOp::Union: ok = PMP::corefine_and_compute_union(ma, mb, ma, np, PMP::parameters::default_values(), PMP::parameters::default_values()); break;
            case BooleanOp::Intersection: ok = PMP::corefine_and_compute_intersection(ma, mb, ma, np, PMP::parameters::default_values(), PMP::parameters::default_values()); break;
            case BooleanOp::Difference: ok = PMP::corefine_and_compute_difference(ma, mb, ma, np, PMP::parameters::default_values(), PMP::parameters::default_values()); break;
        }
    } catch (const PMP::Corefinement::Self_intersection_exception&) {
        throw InputError(what + ": an operand intersects itself; run `littoral check-mesh` on it");
    }
    if (!ok) throw InputError(what + ": the boolean result would not be a manifold closed surface");
    TriMesh out = fromSurfaceMesh(ma);
    weldVertices(out, kWeldEps);
    return out;
}

bool solidsOverlap(const TriMesh& a, const TriMesh& b) {
    const SM ma = toSurfaceMesh(a, "solid"), mb = toSurfaceMesh(b, "solid");
    return PMP::do_intersect(ma, mb);
}

namespace {

// The stages of buildWaterVolume.

void checkWaterVolumeInput(const WaterVolumeInput& in) {
    const auto& d = in.domain;
    if (!d.valid()) throw InputError(fmt::format("scene domain [{}, {}] x [{}, {}] m is empty", d.x0, d.x1, d.y0, d.y1));
    if (!in.elevation) throw InternalError("buildWaterVolume: no terrain elevation function");
    if (in.terrainMaterials.empty()) throw InternalError("buildWaterVolume: no terrain materials");
    if (!(in.terrainSpacing > 0)) throw InputError(fmt::format("terrain spacing {} m must be positive", in.terrainSpacing));
}

// 1. The top of the water prism: the surface clipped to the domain, which it must cover.
TriMesh waterPrismTop(const WaterVolumeInput& in) {
    const auto& d = in.domain;
    TriMesh surf = in.surface;
    surf.faceMaterial.assign(surf.triangles.size(), kTagInterface);
    TriMesh top = clipToRectangle(surf, d);
    // Each triangle is clipped on its own, so a domain corner inside a triangle and on its
    // neighbour's edge is computed twice, at heights a few ulps apart: the two points would make a
    // vertical sliver of zero width in the prism's wall, which no mesh library accepts (a Beaufort
    // surface decimated to 30 000 triangles over 300 m, clipped to 16 m, did). Weld them.
    weldVertices(top, kWeldEps);
    double a2 = 0;
    for (size_t f = 0; f < top.triangles.size(); ++f) a2 += top.faceNormalArea(f).z;
    const double domainArea = d.width() * d.height();
    // Twice the plan area from the cross products; a height field seen from above has all
    // z-components positive, so the sum is exactly the covered area (up to rounding ~1e-12).
    if (std::abs(0.5 * a2 - domainArea) > 1e-9 * domainArea)
        throw InputError(fmt::format("the water surface covers {:.6g} m^2 of the {:.6g} m^2 scene domain; it must "
                                     "cover all of [{}, {}] x [{}, {}] m (and face upward)",
                                     0.5 * a2, domainArea, d.x0, d.x1, d.y0, d.y1));
    return top;
}

// 2. The terrain grid: the domain grown by 1.5 cells, cells no wider than the terrain spacing.
struct TerrainGridSpec {
    bathymetry::Extent grown;
    int nx = 0, ny = 0;  // cells across `grown`
};

TerrainGridSpec terrainGridSpec(const WaterVolumeInput& in) {
    const auto& d = in.domain;
    const int nxIn = std::max(1, static_cast<int>(std::ceil(d.width() / in.terrainSpacing - 1e-9)));
    const int nyIn = std::max(1, static_cast<int>(std::ceil(d.height() / in.terrainSpacing - 1e-9)));
    const double sx = d.width() / nxIn, sy = d.height() / nyIn;
    if (static_cast<double>(nxIn) * nyIn > 2.0e7)
        throw InputError(fmt::format("terrain spacing {} m gives {} x {} cells; use a coarser spacing", in.terrainSpacing,
                                     nxIn, nyIn));
    // Half-cell offset: the domain edges fall in the middle of grid cells, never on grid lines, so
    // no terrain edge lies in the prism's wall planes (no coplanar configurations for the booleans).
    return {{d.x0 - 1.5 * sx, d.y0 - 1.5 * sy, d.x1 + 1.5 * sx, d.y1 + 1.5 * sy}, nxIn + 3, nyIn + 3};
}

// The tag of a terrain face from its plan-view centroid (clamped into the domain).
uint16_t terrainTag(const WaterVolumeInput& in, double x, double y) {
    const auto& d = in.domain;
    const uint16_t slot =
        in.terrainMaterialAt ? in.terrainMaterialAt(std::clamp(x, d.x0, d.x1), std::clamp(y, d.y0, d.y1)) : 0;
    if (slot >= in.terrainMaterials.size())
        throw InternalError(fmt::format("terrain material slot {} out of range", slot));
    return static_cast<uint16_t>(kTagTerrainBase + slot);
}

// 3. water = prism - terrain (in place on `prism`), land = terrain - prism (in place on
// `terrain`): one corefinement.
void corefinePrismAndTerrain(SM& prism, SM& terrain) {
    TagVisitor vis;
    std::array<boost::optional<SM*>, 4> outputs;
    outputs[PMP::Corefinement::TM1_MINUS_TM2] = &prism;
    outputs[PMP::Corefinement::TM2_MINUS_TM1] = &terrain;
    std::array<bool, 4> ok{};
    try {
        ok = PMP::corefine_and_compute_boolean_operations(
            prism, terrain, outputs, PMP::parameters::visitor(vis).throw_on_self_intersection(true),
            PMP::parameters::default_values());
    } catch (const PMP::Corefinement::Self_intersection_exception&) {
        throw InputError("water volume: the wave surface or the terrain intersects itself");
    }
    if (!ok[PMP::Corefinement::TM1_MINUS_TM2] || !ok[PMP::Corefinement::TM2_MINUS_TM1])
        throw InputError("water volume: the boolean of the water prism and the terrain is not a manifold closed "
                         "surface (the surface touches the seabed along an edge?)");
}

// Land: the terrain top faces of terrain - prism, clipped to the domain; slots index the terrain
// materials.
TriMesh landOf(const SM& terrainMinusPrism, size_t nTerrain, const bathymetry::Extent& domain) {
    TriMesh landAll = fromSurfaceMesh(terrainMinusPrism);
    weldVertices(landAll, kWeldEps);
    TriMesh tops;
    tops.positions = landAll.positions;
    for (size_t f = 0; f < landAll.triangles.size(); ++f) {
        const uint16_t tag = landAll.faceMaterial[f];
        if (tag < kTagTerrainBase || tag >= kTagTerrainBase + nTerrain) continue;
        tops.triangles.push_back(landAll.triangles[f]);
        tops.faceMaterial.push_back(static_cast<uint16_t>(tag - kTagTerrainBase));
    }
    return clipToRectangle(tops, domain);
}

// 4. Solids.
void checkSolidsDisjoint(const std::vector<PlacedSolid>& solids) {
    for (size_t i = 0; i < solids.size(); ++i)
        for (size_t j = i + 1; j < solids.size(); ++j) {
            const BBox3 bi = solids[i].mesh.bounds(), bj = solids[j].mesh.bounds();
            const bool boxes = bi.lo.x <= bj.hi.x && bj.lo.x <= bi.hi.x && bi.lo.y <= bj.hi.y && bj.lo.y <= bi.hi.y &&
                               bi.lo.z <= bj.hi.z && bj.lo.z <= bi.hi.z;
            if (boxes && solidsOverlap(solids[i].mesh, solids[j].mesh))
                throw InputError(fmt::format("objects '{}' and '{}' intersect or one contains the other; solids in a "
                                             "scene must be disjoint",
                                             solids[i].name, solids[j].name));
        }
}

using TagRange = std::pair<uint16_t, uint16_t>;  // [first, last) face tag of one solid

// All solids in one mesh, each solid's material slots tagged after `names` (which gains the
// solids' materials); `ranges` receives each solid's tags.
TriMesh tagSolids(const std::vector<PlacedSolid>& solids, std::vector<std::string>* names,
                  std::vector<TagRange>* ranges) {
    TriMesh all;
    for (const auto& s : solids) {
        const uint16_t base = static_cast<uint16_t>(names->size());
        TriMesh sm = s.mesh;
        if (sm.faceMaterial.empty()) sm.faceMaterial.assign(sm.triangles.size(), 0);
        for (auto& m : sm.faceMaterial) {
            if (m >= s.materials.size())
                throw InputError(fmt::format("object '{}': face material slot {} has no material (it lists {})", s.name,
                                             m, s.materials.size()));
            m = static_cast<uint16_t>(m + base);
        }
        for (const auto& n : s.materials) names->push_back(n);
        ranges->push_back({base, static_cast<uint16_t>(names->size())});
        if (!CGAL::is_closed(toSurfaceMesh(sm, "object '" + s.name + "'")))
            throw InputError("object '" + s.name + "' is not a closed solid");
        all.append(sm);
    }
    return all;
}

// Per solid with keepDryPart, its own faces (its tags) of S - W; the faces W contributed there
// (the water surface and seabed inside the solid) are not surfaces of the object.
std::vector<TriMesh> dryPartsOf(const SM& dry, const std::vector<PlacedSolid>& solids,
                                const std::vector<TagRange>& ranges) {
    TriMesh all = fromSurfaceMesh(dry);
    weldVertices(all, kWeldEps);
    std::vector<TriMesh> parts(solids.size());
    for (size_t k = 0; k < solids.size(); ++k) {
        if (!solids[k].keepDryPart) continue;
        TriMesh part;
        std::vector<uint32_t> remap(all.positions.size(), UINT32_MAX);
        for (size_t f = 0; f < all.triangles.size(); ++f) {
            const uint16_t tag = all.faceMaterial[f];
            if (tag < ranges[k].first || tag >= ranges[k].second) continue;
            std::array<uint32_t, 3> t{};
            for (int c = 0; c < 3; ++c) {
                uint32_t& r = remap[all.triangles[f][c]];
                if (r == UINT32_MAX) {
                    r = static_cast<uint32_t>(part.positions.size());
                    part.positions.push_back(all.positions[all.triangles[f][c]]);
                }
                t[c] = r;
            }
            part.triangles.push_back(t);
            part.faceMaterial.push_back(static_cast<uint16_t>(tag - ranges[k].first));
        }
        parts[k] = std::move(part);
    }
    return parts;
}

// Displacement per solid: volumes of the components of W n S (divergence theorem per face), each
// credited to the solid whose faces it holds.
std::vector<double> displacedVolumes(const SM& removedWater, const std::vector<TagRange>& ranges) {
    TriMesh removed = fromSurfaceMesh(removedWater);
    weldVertices(removed, kWeldEps);
    std::vector<uint32_t> parent(removed.positions.size());
    std::iota(parent.begin(), parent.end(), 0u);
    std::function<uint32_t(uint32_t)> find = [&](uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    for (const auto& t : removed.triangles) {
        parent[find(t[1])] = find(t[0]);
        parent[find(t[2])] = find(t[0]);
    }
    std::map<uint32_t, double> volumeOf;
    std::map<uint32_t, int> ownerOf;
    for (size_t f = 0; f < removed.triangles.size(); ++f) {
        const auto& t = removed.triangles[f];
        const Point3 &a = removed.positions[t[0]], &b = removed.positions[t[1]], &c = removed.positions[t[2]];
        const uint32_t root = find(t[0]);
        volumeOf[root] += dot(a, cross(b, c)) / 6.0;
        const uint16_t tag = removed.faceMaterial[f];
        for (size_t k = 0; k < ranges.size(); ++k)
            if (tag >= ranges[k].first && tag < ranges[k].second) ownerOf[root] = static_cast<int>(k);
    }
    std::vector<double> displaced(ranges.size(), 0.0);
    for (const auto& [root, v] : volumeOf) {
        auto it = ownerOf.find(root);
        if (it == ownerOf.end()) throw InternalError("water volume: a region removed by the objects has no object face");
        displaced[it->second] += v;
    }
    return displaced;
}

// The solids are pairwise disjoint (checked before), so together they form one valid closed
// multi-component mesh S, and one corefinement gives both W - S (in place on W) and the removed
// water W n S (in place on S). Each component of W n S lies in exactly one object; its volume is
// that object's displacement. `names` gains the solids' materials.
void subtractSolids(const std::vector<PlacedSolid>& solids, SM& W, std::vector<std::string>* names,
                    WaterVolumeResult* res) {
    std::vector<TagRange> ranges;
    SM S = toSurfaceMesh(tagSolids(solids, names, &ranges), "objects");
    TagVisitor vis;
    std::array<boost::optional<SM*>, 4> outputs;
    outputs[PMP::Corefinement::TM1_MINUS_TM2] = &W;
    outputs[PMP::Corefinement::INTERSECTION] = &S;
    // S - W: the solids' surfaces outside the water, wanted for transparent objects.
    bool wantDry = false;
    for (const auto& s : solids) wantDry = wantDry || s.keepDryPart;
    SM dry;
    dry.add_property_map<FI, int>(kTagProperty, -1);
    if (wantDry) outputs[PMP::Corefinement::TM2_MINUS_TM1] = &dry;
    std::array<bool, 4> ok{};
    try {
        ok = PMP::corefine_and_compute_boolean_operations(W, S, outputs,
                                                          PMP::parameters::visitor(vis).throw_on_self_intersection(true),
                                                          PMP::parameters::default_values());
    } catch (const PMP::Corefinement::Self_intersection_exception&) {
        throw InputError("an object mesh intersects itself; run `littoral check-mesh` on the object meshes");
    }
    if (!ok[PMP::Corefinement::TM1_MINUS_TM2] || !ok[PMP::Corefinement::INTERSECTION] ||
        (wantDry && !ok[PMP::Corefinement::TM2_MINUS_TM1]))
        throw InputError("subtracting the objects from the water does not give a manifold closed surface (does an "
                         "object touch the seabed, the water surface or the domain wall exactly along an edge?)");
    if (wantDry) res->dryParts = dryPartsOf(dry, solids, ranges);
    res->displaced = displacedVolumes(S, ranges);
}

// The final water mesh: faces re-slotted to a compact list of material names (several objects may
// share a material, the step targets), counted by role.
void finishWaterMesh(const SM& W, const std::vector<std::string>& names, size_t nTerrain, WaterVolumeResult* res) {
    TriMesh out = fromSurfaceMesh(W);
    weldVertices(out, kWeldEps);
    std::vector<int> newSlot(names.size(), -1);
    std::map<std::string, int> slotOfName;
    for (auto& m : out.faceMaterial) {
        if (m == kTagPrismBottom || m == kTagTerrainSkirt)
            throw InternalError("water volume: a construction face (prism bottom or terrain skirt) survived the booleans");
        if (newSlot[m] < 0) {
            auto [it, inserted] = slotOfName.try_emplace(names[m], static_cast<int>(res->waterMaterials.size()));
            if (inserted) res->waterMaterials.push_back(names[m]);
            newSlot[m] = it->second;
        }
        if (m == kTagInterface) ++res->interfaceFaces;
        else if (m == kTagWall) ++res->wallFaces;
        else if (m < kTagTerrainBase + nTerrain) ++res->seabedFaces;
        else ++res->objectFaces;
        m = static_cast<uint16_t>(newSlot[m]);
    }
    res->water = std::move(out);
}

}  // namespace

WaterVolumeResult buildWaterVolume(const WaterVolumeInput& in) {
    WaterVolumeResult res;
    const auto& d = in.domain;
    checkWaterVolumeInput(in);
    const size_t nTerrain = in.terrainMaterials.size();

    // ---- 1. water prism (clip now, close once z_lo is known) ----
    auto t0 = Clock::now();
    const TriMesh top = waterPrismTop(in);

    // ---- 2. terrain solid over the domain grown by 1.5 cells ----
    const TerrainGridSpec grid = terrainGridSpec(in);
    res.secondsPrism = secondsSince(t0);
    auto t1 = Clock::now();
    const TriMesh terrain = terrainGrid(in.elevation, grid.grown, grid.nx, grid.ny,
                                        [&in](double x, double y) { return terrainTag(in, x, y); });
    double zMin = std::numeric_limits<double>::infinity();
    for (const auto& p : terrain.positions) zMin = std::min(zMin, p.z);
    for (const auto& p : top.positions) zMin = std::min(zMin, p.z);
    res.zLo = std::floor(zMin) - 1.0;
    res.secondsTerrain = secondsSince(t1);
    auto tp = Clock::now();
    TriMesh prism = closeDownward(top, res.zLo, d, kTagWall, kTagPrismBottom);
    res.prismVolume = prism.signedVolume();
    res.secondsPrism += secondsSince(tp);
    t1 = Clock::now();
    TriMesh terrainSolid = closeDownward(terrain, res.zLo - 1.0, grid.grown, kTagTerrainSkirt, kTagTerrainSkirt);
    res.terrainTop = clipToRectangle(terrain, d);
    for (auto& m : res.terrainTop.faceMaterial) m = static_cast<uint16_t>(m - kTagTerrainBase);
    res.secondsTerrain += secondsSince(t1);

    // ---- 3. water = prism - terrain; land = terrain - prism (one corefinement) ----
    auto t2 = Clock::now();
    SM P = toSurfaceMesh(prism, "water prism");
    SM T = toSurfaceMesh(terrainSolid, "terrain solid");
    checkClosedSM(P, "water prism");
    checkClosedSM(T, "terrain solid");
    corefinePrismAndTerrain(P, T);
    if (P.number_of_faces() == 0)
        throw InputError(fmt::format("there is no water in the scene domain: the terrain lies above the water surface "
                                     "everywhere in [{}, {}] x [{}, {}] m",
                                     d.x0, d.x1, d.y0, d.y1));
    TriMesh water = fromSurfaceMesh(P);
    weldVertices(water, kWeldEps);
    res.waterVolumeBeforeSolids = water.signedVolume();
    res.land = landOf(T, nTerrain, d);
    res.secondsBoolean = secondsSince(t2);

    // ---- 4. solids ----
    auto t3 = Clock::now();
    std::vector<std::string> names(kTagTerrainBase + nTerrain);
    names[kTagInterface] = in.interfaceMaterial;
    names[kTagWall] = in.wallMaterial;
    for (size_t k = 0; k < nTerrain; ++k) names[kTagTerrainBase + k] = in.terrainMaterials[k];
    checkSolidsDisjoint(in.solids);
    SM W = toSurfaceMesh(water, "water volume");
    if (!in.solids.empty()) subtractSolids(in.solids, W, &names, &res);
    res.secondsSolids = secondsSince(t3);

    // ---- final mesh with compacted material list ----
    finishWaterMesh(W, names, nTerrain, &res);
    return res;
}

}  // namespace littoral::scenegen
