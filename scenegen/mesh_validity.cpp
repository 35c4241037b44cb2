// CGAL translation unit 1 of 2 in scenegen (the other is water_volume.cpp): validity tests and
// repair. Everything CGAL stays behind the plain TriMesh interface of mesh_validity.h.
#include "scenegen/mesh_validity.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>
#include <unordered_map>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/Box_intersection_d/Box_with_info_d.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/stitch_borders.h>
#include <CGAL/Surface_mesh.h>
#include <fmt/format.h>

#include "core/error.h"

namespace littoral::scenegen {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using CPoint = K::Point_3;
using SMesh = CGAL::Surface_mesh<CPoint>;
namespace PMP = CGAL::Polygon_mesh_processing;

struct UnionFind {
    std::vector<uint32_t> parent;
    explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
    uint32_t find(uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    }
    void unite(uint32_t a, uint32_t b) {
        a = find(a), b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
};

// One directed use of an undirected edge by a face.
struct EdgeUse {
    uint32_t lo, hi;   // vertex indices, lo < hi
    uint32_t face;
    uint8_t corner;    // the face corner at which the edge starts (0..2)
    bool forward;      // the face traverses lo -> hi
};

CPoint toC(const Point3& p) { return {p.x, p.y, p.z}; }

template <class T>
std::string listHead(const std::vector<T>& v, size_t maxListed, const std::function<std::string(const T&)>& f) {
    std::string s;
    for (size_t i = 0; i < v.size() && i < maxListed; ++i) s += (i ? ", " : "") + f(v[i]);
    if (v.size() > maxListed) s += fmt::format(", ... ({} in all)", v.size());
    return s;
}

std::string edgeStr(const EdgeKey& e) { return fmt::format("({}, {})", e[0], e[1]); }

// Do two faces that share `shared` vertex indices meet anywhere other than at what they share?
// Exact predicates throughout (Epick).
//   0 shared: the triangles intersect at all.
//   1 shared vertex v, A = (v, a1, a2), B = (v, b1, b2): A n B is convex and holds v; if it holds
//     another point p, walk from v toward p: the walk leaves one triangle first, through its edge
//     opposite v, at a point inside the other. So: segment a1a2 meets B, or segment b1b2 meets A.
//   2 shared (an edge ab, third corners c and d): two non-degenerate triangles on an edge meet only
//     along it unless they are coplanar with c and d on the same side of ab (folded onto each
//     other).
//   3 shared: the same face twice.
// This holds however many faces share the edge or vertex, so a non-manifold edge (a fin on a
// closed box) is not mistaken for intersecting faces.
bool facesIntersect(const TriMesh& m, const std::array<uint32_t, 3>& ta, const std::array<uint32_t, 3>& tb) {
    auto P = [&](uint32_t i) { return toC(m.positions[i]); };
    std::vector<uint32_t> shared;
    for (uint32_t a : ta)
        if (std::find(tb.begin(), tb.end(), a) != tb.end()) shared.push_back(a);
    auto others = [&](const std::array<uint32_t, 3>& t) {
        std::vector<uint32_t> o;
        for (uint32_t v : t)
            if (std::find(shared.begin(), shared.end(), v) == shared.end()) o.push_back(v);
        return o;
    };
    const K::Triangle_3 A(P(ta[0]), P(ta[1]), P(ta[2])), B(P(tb[0]), P(tb[1]), P(tb[2]));
    switch (shared.size()) {
        case 0: return CGAL::do_intersect(A, B);
        case 1: {
            const auto oa = others(ta), ob = others(tb);
            return CGAL::do_intersect(K::Segment_3(P(oa[0]), P(oa[1])), B) ||
                   CGAL::do_intersect(K::Segment_3(P(ob[0]), P(ob[1])), A);
        }
        case 2: {
            const uint32_t c = others(ta)[0], d = others(tb)[0];
            const CPoint a = P(shared[0]), b = P(shared[1]);
            return CGAL::orientation(a, b, P(c), P(d)) == CGAL::COPLANAR &&
                   CGAL::coplanar_orientation(a, b, P(c), P(d)) == CGAL::POSITIVE;
        }
        default: return true;
    }
}

// Self-intersecting face pairs of a triangle soup (faces with `skip` set are left out): candidate
// pairs from overlapping bounding boxes (CGAL box_self_intersection_d), then facesIntersect.
// Working on the soup's own vertex indices keeps the adjacency that a half-edge mesh would lose at
// non-manifold edges and vertices.
std::vector<FacePair> soupSelfIntersections(const TriMesh& m, const std::vector<char>& skip) {
    using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, uint32_t, CGAL::Box_intersection_d::ID_EXPLICIT>;
    std::vector<Box> boxes;
    for (size_t f = 0; f < m.triangles.size(); ++f) {
        if (skip[f]) continue;
        const auto& t = m.triangles[f];
        const CGAL::Bbox_3 b = toC(m.positions[t[0]]).bbox() + toC(m.positions[t[1]]).bbox() + toC(m.positions[t[2]]).bbox();
        boxes.emplace_back(b, static_cast<uint32_t>(f));
    }
    std::vector<FacePair> out;
    CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& a, const Box& b) {
        uint32_t fa = a.info(), fb = b.info();
        if (facesIntersect(m, m.triangles[fa], m.triangles[fb])) {
            if (fa > fb) std::swap(fa, fb);
            out.push_back({fa, fb});
        }
    });
    std::sort(out.begin(), out.end(), [](const FacePair& x, const FacePair& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; });
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

}  // namespace

bool ValidityReport::valid() const {
    return !empty && nonFiniteVertices.empty() && badIndexFaces.empty() && degenerateFaces.empty() && closed &&
           manifold && consistentlyOriented && selfIntersectionTested && selfIntersections.empty() && boundsVolume &&
           outward && volume > 0.0;
}

std::vector<std::string> ValidityReport::reasons(size_t n) const {
    std::vector<std::string> r;
    const std::function<std::string(const uint32_t&)> idx = [](const uint32_t& i) { return std::to_string(i); };
    const std::function<std::string(const EdgeKey&)> edge = edgeStr;
    if (empty) r.push_back("mesh is empty: it has no faces");
    if (!nonFiniteVertices.empty())
        r.push_back(fmt::format("{} vertices have NaN or infinite coordinates: vertex {} (a number beyond the range "
                                "of a double, such as 1e400, reads as infinite)",
                                nonFiniteVertices.size(), listHead(nonFiniteVertices, n, idx)));
    if (!badIndexFaces.empty())
        r.push_back(fmt::format("{} faces refer to vertices that do not exist: face {}", badIndexFaces.size(),
                                listHead(badIndexFaces, n, idx)));
    if (!degenerateFaces.empty())
        r.push_back(fmt::format("{} faces are degenerate (repeated or collinear corners, zero area): face {}",
                                degenerateFaces.size(), listHead(degenerateFaces, n, idx)));
    if (!boundaryEdges.empty())
        r.push_back(fmt::format("not closed: {} boundary edges (used by one face only): edge {}", boundaryEdges.size(),
                                listHead(boundaryEdges, n, edge)));
    if (!nonManifoldEdges.empty())
        r.push_back(fmt::format("not manifold: {} edges are shared by three or more faces: edge {}",
                                nonManifoldEdges.size(), listHead(nonManifoldEdges, n, edge)));
    if (!nonManifoldVertices.empty())
        r.push_back(fmt::format("not manifold: {} vertices join separate fans of faces: vertex {}",
                                nonManifoldVertices.size(), listHead(nonManifoldVertices, n, idx)));
    if (!inconsistentEdges.empty()) {
        r.push_back(fmt::format("inconsistent orientation: {} edges are traversed in the same direction by both faces: "
                                "edge {}",
                                inconsistentEdges.size(), listHead(inconsistentEdges, n, edge)));
        if (!flippedFaces.empty())
            r.push_back(fmt::format("{} faces are wound against their neighbours (flipped): face {}", flippedFaces.size(),
                                    listHead(flippedFaces, n, idx)));
    }
    if (!selfIntersections.empty()) {
        const std::function<std::string(const FacePair&)> pair = [](const FacePair& p) {
            return fmt::format("{} x {}", p.a, p.b);
        };
        r.push_back(fmt::format("self-intersecting: {} face pairs intersect: faces {}", selfIntersections.size(),
                                listHead(selfIntersections, n, pair)));
    } else if (!selfIntersectionTested && !empty) {
        r.push_back("self-intersection test not run (it needs finite vertices and valid indices)");
    }
    if (!empty && nonFiniteVertices.empty() && closed && manifold && consistentlyOriented && selfIntersections.empty() &&
        selfIntersectionTested && !boundsVolume)
        r.push_back("does not bound a volume: nested components are oriented inconsistently");
    if (boundsVolume && !outward)
        r.push_back(fmt::format("oriented inward: the faces point into the solid (signed volume {:.6g} m^3); "
                                "reverse all faces",
                                volume));
    return r;
}

nlohmann::json ValidityReport::toJson(size_t n) const {
    auto head = [n](const auto& v) {
        nlohmann::json a = nlohmann::json::array();
        for (size_t i = 0; i < v.size() && i < n; ++i) a.push_back(v[i]);
        return a;
    };
    nlohmann::json si = nlohmann::json::array();
    for (size_t i = 0; i < selfIntersections.size() && i < n; ++i)
        si.push_back({selfIntersections[i].a, selfIntersections[i].b});
    nlohmann::json j;
    j["valid"] = valid();
    j["vertices"] = vertices;
    j["faces"] = faces;
    j["empty"] = empty;
    j["closed"] = closed;
    j["manifold"] = manifold;
    j["consistently_oriented"] = consistentlyOriented;
    j["self_intersections"] = selfIntersections.size();
    j["self_intersection_tested"] = selfIntersectionTested;
    j["self_intersecting_pairs"] = si;
    j["bounds_volume"] = boundsVolume;
    j["outward"] = outward;
    j["volume_m3"] = boundsVolume ? nlohmann::json(volume) : nlohmann::json(nullptr);  // only for a closed volume
    j["area_m2"] = area;
    j["boundary_edges"] = boundaryEdges.size();
    j["boundary_edge_list"] = head(boundaryEdges);
    j["non_manifold_edges"] = head(nonManifoldEdges);
    j["non_manifold_vertices"] = head(nonManifoldVertices);
    j["inconsistent_edges"] = head(inconsistentEdges);
    j["flipped_faces"] = head(flippedFaces);
    j["non_finite_vertices"] = head(nonFiniteVertices);
    j["bad_index_faces"] = head(badIndexFaces);
    j["degenerate_faces"] = head(degenerateFaces);
    j["components"] = components;
    j["reasons"] = reasons();
    return j;
}

namespace {

// The stages of checkMesh.

// Non-finite vertices, faces with bad indices or degenerate corners, and the area. Returns which
// faces are usable for topology (indices in range, three distinct corners); geometric tests
// additionally need finite corners.
std::vector<char> checkFacesAndVertices(const TriMesh& mesh, ValidityReport& rep) {
    const size_t nv = mesh.positions.size(), nf = mesh.triangles.size();
    for (size_t v = 0; v < nv; ++v)
        if (!isFinite(mesh.positions[v])) rep.nonFiniteVertices.push_back(static_cast<uint32_t>(v));
    std::vector<char> usable(nf, 1);
    for (size_t f = 0; f < nf; ++f) {
        const auto& t = mesh.triangles[f];
        if (t[0] >= nv || t[1] >= nv || t[2] >= nv) {
            rep.badIndexFaces.push_back(static_cast<uint32_t>(f));
            usable[f] = 0;
            continue;
        }
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
            rep.degenerateFaces.push_back(static_cast<uint32_t>(f));
            usable[f] = 0;
            continue;
        }
        const Point3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
        if (isFinite(a) && isFinite(b) && isFinite(c)) {
            // Exact orientation predicate: zero area only if truly collinear.
            if (CGAL::collinear(toC(a), toC(b), toC(c))) rep.degenerateFaces.push_back(static_cast<uint32_t>(f));
            rep.area += 0.5 * length(mesh.faceNormalArea(f));
        }
    }
    return usable;
}

// The edge uses of the usable faces, sorted by edge, then face.
std::vector<EdgeUse> edgeUses(const TriMesh& mesh, const std::vector<char>& usable) {
    std::vector<EdgeUse> uses;
    uses.reserve(3 * mesh.triangles.size());
    for (size_t f = 0; f < mesh.triangles.size(); ++f) {
        if (!usable[f]) continue;
        const auto& t = mesh.triangles[f];
        for (uint8_t k = 0; k < 3; ++k) {
            const uint32_t a = t[k], b = t[(k + 1) % 3];
            uses.push_back({std::min(a, b), std::max(a, b), static_cast<uint32_t>(f), k, a < b});
        }
    }
    std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
        return x.lo != y.lo ? x.lo < y.lo : (x.hi != y.hi ? x.hi < y.hi : x.face < y.face);
    });
    return uses;
}

// What the faces' sharing of edges tells: edge-connected components, the fans of corners around
// each vertex (corner id = 3 * face + k), and the adjacency across manifold edges for orientation
// propagation: (neighbour, sameDirection) per face.
struct EdgeIncidence {
    UnionFind faces;
    UnionFind corners;
    std::vector<std::vector<std::pair<uint32_t, bool>>> adj;
    explicit EdgeIncidence(size_t nf) : faces(nf), corners(3 * nf), adj(nf) {}
};

// Also records the boundary, non-manifold and inconsistently oriented edges in `rep`.
EdgeIncidence edgeIncidence(const TriMesh& mesh, const std::vector<EdgeUse>& uses, ValidityReport& rep) {
    EdgeIncidence inc(mesh.triangles.size());
    auto cornerOf = [&](uint32_t face, uint32_t vertex) {
        const auto& t = mesh.triangles[face];
        return 3 * face + (t[0] == vertex ? 0u : (t[1] == vertex ? 1u : 2u));
    };
    for (size_t i = 0; i < uses.size();) {
        size_t j = i;
        while (j < uses.size() && uses[j].lo == uses[i].lo && uses[j].hi == uses[i].hi) ++j;
        const size_t count = j - i;
        const EdgeKey key{uses[i].lo, uses[i].hi};
        if (count == 1) rep.boundaryEdges.push_back(key);
        if (count >= 3) rep.nonManifoldEdges.push_back(key);
        if (count == 2 && uses[i].forward == uses[i + 1].forward) rep.inconsistentEdges.push_back(key);
        for (size_t k = i + 1; k < j; ++k) {
            inc.faces.unite(uses[i].face, uses[k].face);
            // Faces meeting at an edge belong to the same fan at both its endpoints.
            for (uint32_t v : {key[0], key[1]})
                inc.corners.unite(cornerOf(uses[i].face, v), cornerOf(uses[k].face, v));
        }
        if (count == 2) {
            const bool same = uses[i].forward == uses[i + 1].forward;
            inc.adj[uses[i].face].push_back({uses[i + 1].face, same});
            inc.adj[uses[i + 1].face].push_back({uses[i].face, same});
        }
        i = j;
    }
    return inc;
}

// Non-manifold vertices: more than one fan of corners around the vertex.
void findNonManifoldVertices(const TriMesh& mesh, const std::vector<char>& usable, EdgeIncidence& inc,
                             ValidityReport& rep) {
    const size_t nv = mesh.positions.size();
    std::vector<uint32_t> firstRoot(nv, UINT32_MAX);
    std::vector<char> flagged(nv, 0);
    for (size_t f = 0; f < mesh.triangles.size(); ++f) {
        if (!usable[f]) continue;
        for (uint32_t k = 0; k < 3; ++k) {
            const uint32_t v = mesh.triangles[f][k];
            const uint32_t root = inc.corners.find(static_cast<uint32_t>(3 * f + k));
            if (firstRoot[v] == UINT32_MAX) firstRoot[v] = root;
            else if (firstRoot[v] != root) flagged[v] = 1;
        }
    }
    // Endpoints of non-manifold edges are already reported through the edge.
    for (const auto& e : rep.nonManifoldEdges) flagged[e[0]] = flagged[e[1]] = 0;
    for (size_t v = 0; v < nv; ++v)
        if (flagged[v]) rep.nonManifoldVertices.push_back(static_cast<uint32_t>(v));
}

// Components and orientation parity within each (breadth-first over manifold edges); with
// inconsistent edges, the minority parity of each component is reported as flipped.
void componentsAndParity(const std::vector<char>& usable, EdgeIncidence& inc, ValidityReport& rep) {
    const size_t nf = usable.size();
    std::vector<int8_t> parity(nf, -1);
    std::map<uint32_t, std::array<std::vector<uint32_t>, 2>> byComponent;
    for (size_t s = 0; s < nf; ++s) {
        if (!usable[s] || parity[s] >= 0) continue;
        std::vector<uint32_t> stack{static_cast<uint32_t>(s)};
        parity[s] = 0;
        auto& groups = byComponent[inc.faces.find(static_cast<uint32_t>(s))];
        while (!stack.empty()) {
            const uint32_t f = stack.back();
            stack.pop_back();
            groups[parity[f]].push_back(f);
            for (auto [g, same] : inc.adj[f]) {
                if (parity[g] >= 0) continue;
                parity[g] = static_cast<int8_t>(parity[f] ^ (same ? 1 : 0));
                stack.push_back(g);
            }
        }
    }
    rep.components = byComponent.size();
    if (!rep.inconsistentEdges.empty()) {
        for (auto& [root, groups] : byComponent) {
            if (groups[0].empty() || groups[1].empty()) continue;
            auto& minority = groups[0].size() < groups[1].size() ? groups[0] : groups[1];
            rep.flippedFaces.insert(rep.flippedFaces.end(), minority.begin(), minority.end());
        }
        std::sort(rep.flippedFaces.begin(), rep.flippedFaces.end());
    }
}

// Whether a clean surface (closed, manifold, consistently oriented, nothing degenerate or
// self-intersecting) bounds a volume, and whether outward: only then is the signed volume an
// enclosed volume.
void checkBoundsVolume(const TriMesh& mesh, ValidityReport& rep) {
    SMesh sm;
    // Only vertices that faces use: CGAL's volume tests assume no isolated vertices.
    std::vector<SMesh::Vertex_index> vmap(mesh.positions.size(), SMesh::null_vertex());
    bool inserted = true;
    for (const auto& t : mesh.triangles) {
        for (uint32_t i : t)
            if (vmap[i] == SMesh::null_vertex()) vmap[i] = sm.add_vertex(toC(mesh.positions[i]));
        inserted = inserted && sm.add_face(vmap[t[0]], vmap[t[1]], vmap[t[2]]) != SMesh::null_face();
    }
    if (inserted) {
        rep.boundsVolume = PMP::does_bound_a_volume(sm);
        rep.outward = rep.boundsVolume && PMP::is_outward_oriented(sm) && mesh.signedVolume() > 0.0;
    }
}

// Geometry through CGAL (needs finite vertices and valid indices).
void checkGeometry(const TriMesh& mesh, const CheckOptions& options, ValidityReport& rep) {
    std::vector<char> degenerate(mesh.triangles.size(), 0);
    for (uint32_t f : rep.degenerateFaces) degenerate[f] = 1;
    if (options.testSelfIntersections) {
        rep.selfIntersections = soupSelfIntersections(mesh, degenerate);
        rep.selfIntersectionTested = true;
    }
    const bool topologyClean = rep.manifold && rep.consistentlyOriented;
    if (rep.closed && topologyClean && rep.degenerateFaces.empty() && rep.selfIntersectionTested &&
        rep.selfIntersections.empty())
        checkBoundsVolume(mesh, rep);
    // A volume is reported only for a surface that encloses one; the divergence-theorem sum of an
    // open or self-intersecting surface is a number without meaning.
    rep.volume = rep.boundsVolume ? mesh.signedVolume() : 0.0;
}

}  // namespace

ValidityReport checkMesh(const TriMesh& mesh, const CheckOptions& options) {
    ValidityReport rep;
    rep.vertices = mesh.positions.size();
    rep.faces = mesh.triangles.size();
    rep.empty = rep.faces == 0;
    const std::vector<char> usable = checkFacesAndVertices(mesh, rep);

    // ---- edge incidence ----
    EdgeIncidence inc = edgeIncidence(mesh, edgeUses(mesh, usable), rep);
    findNonManifoldVertices(mesh, usable, inc, rep);
    componentsAndParity(usable, inc, rep);
    rep.closed = !rep.empty && rep.boundaryEdges.empty() && rep.badIndexFaces.empty();
    rep.manifold = !rep.empty && rep.nonManifoldEdges.empty() && rep.nonManifoldVertices.empty();
    rep.consistentlyOriented = !rep.empty && rep.inconsistentEdges.empty();

    // ---- geometry through CGAL ----
    if (rep.empty || !rep.nonFiniteVertices.empty() || !rep.badIndexFaces.empty()) return rep;
    checkGeometry(mesh, options, rep);
    return rep;
}

std::vector<std::string> RepairReport::changes() const {
    std::vector<std::string> c;
    if (verticesMerged) c.push_back(fmt::format("merged {} coincident vertices", verticesMerged));
    if (degenerateFacesRemoved) c.push_back(fmt::format("removed {} faces with repeated corners", degenerateFacesRemoved));
    if (duplicateFacesRemoved) c.push_back(fmt::format("removed {} duplicated faces", duplicateFacesRemoved));
    if (facesReversedForConsistency)
        c.push_back(fmt::format("reversed {} faces to make the orientation consistent", facesReversedForConsistency));
    if (bordersStitched) c.push_back(fmt::format("stitched {} pairs of border edges", bordersStitched));
    if (facesReversedOutward)
        c.push_back(fmt::format("reversed {} faces so that every component bounds its volume outward",
                                facesReversedOutward));
    if (c.empty()) c.push_back("nothing changed");
    return c;
}

nlohmann::json RepairReport::toJson() const {
    return {{"vertices_merged", verticesMerged},
            {"degenerate_faces_removed", degenerateFacesRemoved},
            {"duplicate_faces_removed", duplicateFacesRemoved},
            {"faces_reversed_for_consistency", facesReversedForConsistency},
            {"borders_stitched", bordersStitched},
            {"faces_reversed_outward", facesReversedOutward},
            {"faces_reversed_net", facesReversedNet},
            {"changes", changes()}};
}

namespace {

// The stages of repairMesh.

void requireRepairable(const TriMesh& mesh) {
    for (size_t v = 0; v < mesh.positions.size(); ++v)
        if (!isFinite(mesh.positions[v]))
            throw InputError(fmt::format("cannot repair: vertex {} has a non-finite coordinate {}", v,
                                         fmt::format("({}, {}, {})", mesh.positions[v].x, mesh.positions[v].y,
                                                     mesh.positions[v].z)));
    for (size_t f = 0; f < mesh.triangles.size(); ++f)
        for (uint32_t v : mesh.triangles[f])
            if (v >= mesh.positions.size())
                throw InputError(fmt::format("cannot repair: face {} refers to vertex {} which does not exist", f, v));
}

// 1. Merges exactly coincident vertices (STL-style soups, split seams): the distinct points, and
// `remap` from the mesh's vertices to them.
std::vector<Point3> mergeCoincidentVertices(const TriMesh& mesh, std::vector<uint32_t>* remap, RepairReport& rep) {
    std::map<std::array<double, 3>, uint32_t> firstAt;
    remap->resize(mesh.positions.size());
    std::vector<Point3> merged;
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
        const auto& p = mesh.positions[v];
        auto [it, inserted] = firstAt.try_emplace({p.x, p.y, p.z}, static_cast<uint32_t>(merged.size()));
        if (inserted) merged.push_back(p);
        else ++rep.verticesMerged;
        (*remap)[v] = it->second;
    }
    return merged;
}

// A polygon soup over the merged points, with each polygon's material slot.
struct Soup {
    std::vector<std::array<size_t, 3>> polys;
    std::vector<uint16_t> mats;
};

// 2. Drops faces with repeated corners and exact duplicates (same vertex set).
Soup dropDegenerateAndDuplicateFaces(const TriMesh& mesh, const std::vector<uint32_t>& remap, RepairReport& rep) {
    Soup soup;
    std::map<std::array<uint32_t, 3>, size_t> seen;
    for (size_t f = 0; f < mesh.triangles.size(); ++f) {
        std::array<uint32_t, 3> t{remap[mesh.triangles[f][0]], remap[mesh.triangles[f][1]], remap[mesh.triangles[f][2]]};
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
            ++rep.degenerateFacesRemoved;
            continue;
        }
        auto sorted = t;
        std::sort(sorted.begin(), sorted.end());
        if (!seen.try_emplace(sorted, f).second) {
            ++rep.duplicateFacesRemoved;
            continue;
        }
        soup.polys.push_back({t[0], t[1], t[2]});
        soup.mats.push_back(mesh.materialOf(f));
    }
    return soup;
}

// 3. Orients the soup consistently (may duplicate vertices at non-manifold spots) and counts the
// faces it reversed; then drops the points no polygon uses (CGAL's volume queries assume no
// isolated vertices).
void orientSoup(std::vector<CPoint>& pts, Soup& soup, RepairReport& rep) {
    const auto before = soup.polys;
    PMP::orient_polygon_soup(pts, soup.polys);
    auto samePoint = [&](size_t a, size_t b) { return pts[a] == pts[b]; };
    for (size_t i = 0; i < soup.polys.size(); ++i) {
        // A reversed triangle (a, b, c) -> (a, c, b) up to rotation: compare the cyclic successor of corner 0.
        const auto& o = before[i];
        const auto& n = soup.polys[i];
        int k = 0;
        while (k < 3 && !samePoint(n[k], o[0])) ++k;
        if (k < 3 && !samePoint(n[(k + 1) % 3], o[1])) ++rep.facesReversedForConsistency;
    }
    std::vector<size_t> used(pts.size(), SIZE_MAX);
    std::vector<CPoint> kept;
    for (auto& t : soup.polys)
        for (auto& i : t) {
            if (used[i] == SIZE_MAX) {
                used[i] = kept.size();
                kept.push_back(pts[i]);
            }
            i = used[i];
        }
    pts.swap(kept);
}

K::Vector_3 faceNormal(const SMesh& sm, SMesh::Face_index f) {
    auto h = sm.halfedge(f);
    const auto& a = sm.point(sm.source(h));
    const auto& b = sm.point(sm.target(h));
    const auto& c = sm.point(sm.target(sm.next(h)));
    return CGAL::cross_product(b - a, c - a);
}

// 4. Stitches borders whose endpoints coincide geometrically; 5. orients each closed component
// outward (nested components inward). Counts the faces step 5 reversed, and those reversed in
// all against `inputNormal` (the input faces' normals, in face order).
void stitchAndOrientOutward(SMesh& sm, const std::vector<K::Vector_3>& inputNormal, RepairReport& rep) {
    rep.bordersStitched = PMP::stitch_borders(sm);
    std::vector<K::Vector_3> n0;
    for (auto f : sm.faces()) n0.push_back(faceNormal(sm, f));
    if (CGAL::is_closed(sm)) {
        PMP::orient_to_bound_a_volume(sm);
        size_t i = 0;
        for (auto f : sm.faces()) rep.facesReversedOutward += (n0[i++] * faceNormal(sm, f) < 0) ? 1 : 0;
    }
    size_t i = 0;
    for (auto f : sm.faces()) rep.facesReversedNet += (inputNormal[i++] * faceNormal(sm, f) < 0) ? 1 : 0;
}

// Back to the plain mesh; faces keep their order (no garbage collection happened on faces), and
// their material slots when `withMaterials`.
TriMesh toTriMesh(const SMesh& sm, const std::vector<uint16_t>& mats, bool withMaterials) {
    TriMesh out;
    std::unordered_map<uint32_t, uint32_t> vIndex;
    for (auto v : sm.vertices()) {
        vIndex[v.idx()] = static_cast<uint32_t>(out.positions.size());
        const auto& p = sm.point(v);
        out.positions.push_back({p.x(), p.y(), p.z()});
    }
    size_t i = 0;
    for (auto f : sm.faces()) {
        std::array<uint32_t, 3> t{};
        int k = 0;
        for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) t[k++] = vIndex.at(v.idx());
        out.triangles.push_back(t);
        if (withMaterials) out.faceMaterial.push_back(mats[i]);
        ++i;
    }
    return out;
}

}  // namespace

RepairReport repairMesh(TriMesh& mesh) {
    RepairReport rep;
    requireRepairable(mesh);
    std::vector<uint32_t> remap;
    const std::vector<Point3> merged = mergeCoincidentVertices(mesh, &remap, rep);
    Soup soup = dropDegenerateAndDuplicateFaces(mesh, remap, rep);
    std::vector<CPoint> pts;
    for (const auto& p : merged) pts.push_back(toC(p));
    std::vector<K::Vector_3> inputNormal;
    for (const auto& t : soup.polys)
        inputNormal.push_back(CGAL::cross_product(pts[t[1]] - pts[t[0]], pts[t[2]] - pts[t[0]]));
    orientSoup(pts, soup, rep);
    SMesh sm;
    PMP::polygon_soup_to_polygon_mesh(pts, soup.polys, sm);
    LITTORAL_CHECK_EQ(sm.number_of_faces(), soup.polys.size());
    stitchAndOrientOutward(sm, inputNormal, rep);
    mesh = toTriMesh(sm, soup.mats, !mesh.faceMaterial.empty());
    return rep;
}

}  // namespace littoral::scenegen
