#include "surfaces/facetize.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/stats.h"

namespace littoral::surfaces {

namespace {

struct OmTraits : public OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
    typedef OpenMesh::Vec3d Normal;
    // Status flags only: the decimater needs them; normals are computed after conversion.
    VertexAttributes(OpenMesh::Attributes::Status);
    FaceAttributes(OpenMesh::Attributes::Status);
    EdgeAttributes(OpenMesh::Attributes::Status);
    HalfedgeAttributes(OpenMesh::Attributes::PrevHalfedge);
};
// The Debian build of libOpenMeshCore keeps its assertions, and every status() lookup inside
// the library then builds and compares type-name strings; TriConnectivity::is_collapse_ok, which
// the decimater calls for every candidate, spent most of the decimation time there. The same
// topological tests, compiled here (templates, NDEBUG), hide it: BaseDecimaterT calls
// mesh.is_collapse_ok on the derived type.
class OmMesh : public OpenMesh::TriMesh_ArrayKernelT<OmTraits> {
public:
    using OpenMesh::TriMesh_ArrayKernelT<OmTraits>::valence;
    unsigned int valence(VertexHandle v) const {
        unsigned int n = 0;
        for (auto h : voh_range(v)) { (void)h; ++n; }
        return n;
    }
    OpenMesh::SmartHalfedgeHandle find_halfedge(VertexHandle a, VertexHandle b) const {
        for (auto h : voh_range(a))
            if (to_vertex_handle(h) == b) return h;
        return OpenMesh::SmartHalfedgeHandle();
    }
    bool is_collapse_ok(HalfedgeHandle v0v1) {
        if (status(edge_handle(v0v1)).deleted()) return false;
        const HalfedgeHandle v1v0 = opposite_halfedge_handle(v0v1);
        const VertexHandle v0 = to_vertex_handle(v1v0), v1 = to_vertex_handle(v0v1);
        if (status(v0).deleted() || status(v1).deleted()) return false;
        VertexHandle vl, vr;
        // The edges v1-vl and vl-v0 (and v0-vr, vr-v1) must not both be boundary edges.
        if (!is_boundary(v0v1)) {
            const HalfedgeHandle h1 = next_halfedge_handle(v0v1), h2 = next_halfedge_handle(h1);
            vl = to_vertex_handle(h1);
            if (is_boundary(opposite_halfedge_handle(h1)) && is_boundary(opposite_halfedge_handle(h2))) return false;
        }
        if (!is_boundary(v1v0)) {
            const HalfedgeHandle h1 = next_halfedge_handle(v1v0), h2 = next_halfedge_handle(h1);
            vr = to_vertex_handle(h1);
            if (is_boundary(opposite_halfedge_handle(h1)) && is_boundary(opposite_halfedge_handle(h2))) return false;
        }
        if (vl == vr) return false;
        // The one-rings of v0 and v1 may share only vl and vr (else the collapse is non-manifold).
        for (auto v : vv_range(v0)) status(v).set_tagged(false);
        for (auto v : vv_range(v1)) status(v).set_tagged(true);
        for (auto v : vv_range(v0))
            if (status(v).tagged() && v != vl && v != vr) return false;
        // An edge between two boundary vertices must itself be a boundary edge.
        if (is_boundary(v0) && is_boundary(v1) && !is_boundary(v0v1) && !is_boundary(v1v0)) return false;
        return true;
    }
};

// Which edges of the rectangle a vertex lies on: bit 0 x = x0, 1 x = x1, 2 y = y0, 3 y = y1.
using SideMask = unsigned char;
constexpr const char* kSidesProperty = "littoral:rectangle-sides";
constexpr size_t kMaxValence = 12;

// Binary decimation module keeping the mesh a height field over the whole rectangle.
template <class MeshT>
class ModHeightFieldBoundaryT : public OpenMesh::Decimater::ModBaseT<MeshT> {
public:
    DECIMATING_MODULE(ModHeightFieldBoundaryT, MeshT, HeightFieldBoundary);

    // DecimaterT constructs modules from the mesh alone, so the side mask is found by name.
    explicit ModHeightFieldBoundaryT(MeshT& mesh) : Base(mesh, true) {
        LITTORAL_CHECK(mesh.get_property_handle(sides_, kSidesProperty));
    }

    float collapse_priority(const CollapseInfo& ci) override {
        MeshT& m = Base::mesh();
        const SideMask s0 = m.property(sides_, ci.v0), s1 = m.property(sides_, ci.v1);
        // A vertex on the boundary may only slide along an edge of the rectangle it lies on,
        // onto a vertex of the same edge (corners, on two edges, are locked beforehand).
        if (s0 != 0 && (s0 & s1) == 0) return Base::ILLEGAL_COLLAPSE;
        // Valence cap, a safeguard: on a finely sampled smooth surface many quadric errors are
        // nearly equal, and collapses piling onto a few hub vertices would ring them with
        // slivers and make every later priority update walk their large one-rings.
        const size_t shared = (ci.vl.is_valid() ? 1 : 0) + (ci.vr.is_valid() ? 1 : 0);
        if (m.valence(ci.v0) + m.valence(ci.v1) - 2 - shared > kMaxValence) return Base::ILLEGAL_COLLAPSE;
        // Moving v0 onto v1 must keep every remaining face's normal pointing up (height field).
        for (auto fh : m.vf_range(ci.v0)) {
            if (fh == ci.fl || fh == ci.fr) continue;
            OpenMesh::Vec3d p[3];
            int k = 0;
            for (auto vh : m.fv_range(fh)) p[k++] = (vh == ci.v0) ? ci.p1 : m.point(vh);
            const OpenMesh::Vec3d n = OpenMesh::cross(p[1] - p[0], p[2] - p[0]);
            if (n[2] <= 0.05 * n.norm()) return Base::ILLEGAL_COLLAPSE;
        }
        return Base::LEGAL_COLLAPSE;
    }

private:
    OpenMesh::VPropHandleT<SideMask> sides_;
};

}  // namespace

int presampleStride(const HeightField& f, size_t target) {
    const double budget = kPresampleFactor * 0.5 * static_cast<double>(target);  // vertices ~ triangles / 2
    const double ratio = static_cast<double>(f.size()) / budget;
    return std::max(1, static_cast<int>(std::floor(std::sqrt(ratio))));
}

std::vector<int> latticeIndices(int n, int stride) {
    std::vector<int> idx;
    for (int i = 0; i < n - 1; i += stride) idx.push_back(i);
    // Always end on the last sample; merge a final gap shorter than half a stride into the previous one.
    if (idx.size() > 1 && (n - 1) - idx.back() < (stride + 1) / 2) idx.pop_back();
    idx.push_back(n - 1);
    return idx;
}

TriMesh triangulate(const HeightField& f) {
    TriMesh m;
    m.positions.reserve(f.size());
    for (int j = 0; j < f.ny; ++j)
        for (int i = 0; i < f.nx; ++i) m.positions.push_back({f.x(i), f.y(j), f.at(i, j)});
    m.triangles.reserve(gridTriangles(f));
    for (int j = 0; j + 1 < f.ny; ++j)
        for (int i = 0; i + 1 < f.nx; ++i) {
            const uint32_t v00 = static_cast<uint32_t>(j * f.nx + i), v10 = v00 + 1;
            const uint32_t v01 = v00 + static_cast<uint32_t>(f.nx), v11 = v01 + 1;
            m.triangles.push_back({v00, v10, v11});
            m.triangles.push_back({v00, v11, v01});
        }
    return m;
}

Facets facetize(const HeightField& f, size_t target) {
    LITTORAL_CHECK_GE(target, kMinTriangles);
    Facets out;
    if (target >= gridTriangles(f)) {
        out.mesh = triangulate(f);
    } else {
        // Stage 1: the vertex lattice the decimater starts from. The quadric decimater costs tens of
        // microseconds per collapse, so starting from the dissertation's 1.4 million vertices would
        // take most of a minute. Starting instead from every stride-th sample (exact samples of
        // the field; the last row and column always kept so the rectangle is intact) with at
        // least kPresampleFactor times the target's vertex count leaves the choice of the final
        // vertices to the quadric error while cutting the work by stride^2. The fine field's
        // detail below the stride is finer than the final mesh can hold anyway; the final
        // mesh's deviation from the full field is measured and reported (max_deviation).
        const int stride = presampleStride(f, target);
        const std::vector<int> xs = latticeIndices(f.nx, stride), ys = latticeIndices(f.ny, stride);
        const int lx = static_cast<int>(xs.size()), ly = static_cast<int>(ys.size());
        OmMesh om;
        om.reserve(static_cast<size_t>(lx) * ly, 3ull * lx * ly, 2ull * lx * ly);
        OpenMesh::VPropHandleT<SideMask> sides;
        om.add_property(sides, kSidesProperty);
        {
            std::vector<OmMesh::VertexHandle> vh(static_cast<size_t>(lx) * ly);
            for (int b = 0; b < ly; ++b)
                for (int a = 0; a < lx; ++a) {
                    const int i = xs[a], j = ys[b];
                    const size_t idx = static_cast<size_t>(b) * lx + a;
                    vh[idx] = om.add_vertex(OmMesh::Point(f.x(i), f.y(j), f.at(i, j)));
                    om.property(sides, vh[idx]) = static_cast<SideMask>((a == 0 ? 1 : 0) | (a == lx - 1 ? 2 : 0) |
                                                                        (b == 0 ? 4 : 0) | (b == ly - 1 ? 8 : 0));
                }
            for (int b = 0; b + 1 < ly; ++b)
                for (int a = 0; a + 1 < lx; ++a) {
                    const size_t v00 = static_cast<size_t>(b) * lx + a, v10 = v00 + 1, v01 = v00 + lx, v11 = v01 + 1;
                    om.add_face(vh[v00], vh[v10], vh[v11]);
                    om.add_face(vh[v00], vh[v11], vh[v01]);
                }
            // Lock the corners: they define the rectangle.
            for (int b : {0, ly - 1})
                for (int a : {0, lx - 1}) om.status(vh[static_cast<size_t>(b) * lx + a]).set_locked(true);
        }
        {
            OpenMesh::Decimater::DecimaterT<OmMesh> dec(om);
            OpenMesh::Decimater::ModQuadricT<OmMesh>::Handle quadric;
            OpenMesh::Decimater::ModHandleT<ModHeightFieldBoundaryT<OmMesh>> boundary;
            dec.add(quadric);
            dec.add(boundary);
            dec.module(quadric).unset_max_err();
            LITTORAL_CHECK(dec.initialize());
            dec.decimate_to_faces(0, target);
        }
        om.garbage_collection();
        statCounter("waves: decimated faces").add(static_cast<int64_t>(om.n_faces()));
        out.mesh.positions.reserve(om.n_vertices());
        for (auto v : om.vertices()) {
            const auto& p = om.point(v);
            out.mesh.positions.push_back({p[0], p[1], p[2]});
        }
        out.mesh.triangles.reserve(om.n_faces());
        for (auto fh : om.faces()) {
            std::array<uint32_t, 3> t{};
            int k = 0;
            for (auto v : om.fv_range(fh)) t[k++] = static_cast<uint32_t>(v.idx());
            out.mesh.triangles.push_back(t);
        }
    }
    // Vertex normals: area-weighted mean of the incident faces' normals (the cross product's
    // length is twice the area), normalised.
    out.vertexNormals.assign(out.mesh.positions.size(), Normal3{});
    for (size_t t = 0; t < out.mesh.triangles.size(); ++t) {
        const Vec3 n = out.mesh.faceNormalArea(t);
        for (uint32_t v : out.mesh.triangles[t]) out.vertexNormals[v] += n;
    }
    for (auto& n : out.vertexNormals) n = normalize(n);
    return out;
}

void writeObj(const std::filesystem::path& path, const TriMesh& m, const std::vector<Normal3>& normals) {
    const bool withNormals = normals.size() == m.positions.size();
    std::string out = fmt::format("# written by Littoral: {} vertices, {} triangles\n", m.positions.size(),
                                  m.triangles.size());
    auto it = std::back_inserter(out);
    for (const auto& p : m.positions) fmt::format_to(it, "v {:.17g} {:.17g} {:.17g}\n", p.x, p.y, p.z);
    if (withNormals)
        for (const auto& n : normals) fmt::format_to(it, "vn {:.9g} {:.9g} {:.9g}\n", n.x, n.y, n.z);
    for (const auto& t : m.triangles) {
        if (withNormals)
            fmt::format_to(it, "f {}//{} {}//{} {}//{}\n", t[0] + 1, t[0] + 1, t[1] + 1, t[1] + 1, t[2] + 1, t[2] + 1);
        else
            fmt::format_to(it, "f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    writeFileAtomic(path, out);
}

}  // namespace littoral::surfaces
