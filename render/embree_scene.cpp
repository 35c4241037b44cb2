#include "render/embree_scene.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "core/error.h"
#include "core/log.h"
#include "core/stats.h"
#include "render/clearance_grid.h"

namespace littoral::render {

namespace {

void embreeErrorCallback(void*, RTCError code, const char* str) {
    // Embree reports allocation failures and API misuse here; both are internal faults.
    log::error("embree error {}: {}", static_cast<int>(code), str ? str : "");
}

// Per-thread ray counts, flushed into the named counters by flushRayStats(): one atomic
// add per ray shared by all threads would cost more than a coherent Embree traversal.
struct RayCounts {
    int64_t cast = 0, hits = 0, shadow = 0, clear = 0;
};
thread_local RayCounts tlsCounts;
thread_local RayLog* tlsLog = nullptr;

}  // namespace

void flushRayStats() {
    static StatCounter& cast = statCounter("rays cast");
    static StatCounter& hits = statCounter("ray hits");
    static StatCounter& shadow = statCounter("shadow rays");
    static StatCounter& clear = statCounter("rays answered by the clearance grid (no Embree traversal)");
    RayCounts& c = tlsCounts;
    if (c.cast) cast.add(c.cast);
    if (c.hits) hits.add(c.hits);
    if (c.shadow) shadow.add(c.shadow);
    if (c.clear) clear.add(c.clear);
    c = RayCounts{};
}

Ray spawnRayTo(const Point3& p, const Normal3& ng, const Point3& q) {
    Vec3 d = q - p;
    const double len = length(d);
    Ray r = spawnRay(p, ng, d / len);
    // Stop short of the target surface by its own offset so it does not occlude itself.
    r.tMax = std::max(0.0, length(q - r.o) - offsetDistance(q));
    return r;
}

struct EmbreeScene::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::vector<RTCScene> meshScenes;   // per mesh, created only when instanced

    // Double-precision geometry for hit reconstruction.
    struct MeshRef {
        const TriMesh* mesh = nullptr;
        // Per face, in the mesh's own frame: unit normal (CCW side) and plane offset dot(n, v0),
        // double precision; the hit reconstruction needs only these (no vertex fetches).
        std::vector<Vec3> normal;
        std::vector<double> offset;
    };
    std::vector<MeshRef> meshes;
    struct Xform {
        double R[9];
        Vec3 t;
        int mesh;
    };
    std::vector<Xform> instances;
    std::vector<int> geomToMesh;      // top-level geomID -> mesh index (direct placements)
    std::vector<int> geomToInstance;  // top-level geomID -> instance index (instance geometries)
    BBox3 box;
    uint64_t triangles = 0;
    ClearanceGrid clearance;  // finite rays through empty space skip Embree (render/clearance_grid.h)

    bool clearSegment(const Ray& r) const {
        if (!(r.tMax < std::numeric_limits<double>::infinity())) return false;
        if (!clearance.segmentClear(r.at(r.tMin), r.at(r.tMax))) return false;
        ++tlsCounts.clear;
        return true;
    }


    ~Impl() {
        for (RTCScene s : meshScenes)
            if (s) rtcReleaseScene(s);
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }

    // Attaches g to the top-level scene (releasing the caller's reference) and sizes the id maps.
    unsigned attach(RTCGeometry g);
    void addMesh(const ir::Mesh& mesh, size_t mi);
    void addInstance(const ir::SceneIR& ir, size_t ii);
    RTCGeometry makeTriangles(const TriMesh& m) {
        RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                              3 * sizeof(float), m.positions.size()));
        for (size_t i = 0; i < m.positions.size(); ++i) {
            v[3 * i + 0] = static_cast<float>(m.positions[i].x);
            v[3 * i + 1] = static_cast<float>(m.positions[i].y);
            v[3 * i + 2] = static_cast<float>(m.positions[i].z);
        }
        auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), m.triangles.size()));
        for (size_t i = 0; i < m.triangles.size(); ++i) {
            for (int k = 0; k < 3; ++k) {
                const uint32_t vi = m.triangles[i][k];
                if (vi >= m.positions.size())
                    throw InputError(fmt::format("mesh triangle {} references vertex {} of {}", i, vi,
                                                 m.positions.size()));
                idx[3 * i + k] = vi;
            }
        }
        rtcCommitGeometry(g);
        return g;
    }

    static void setRay(RTCRay& rr, const Ray& r) {
        rr.org_x = static_cast<float>(r.o.x);
        rr.org_y = static_cast<float>(r.o.y);
        rr.org_z = static_cast<float>(r.o.z);
        rr.dir_x = static_cast<float>(r.d.x);
        rr.dir_y = static_cast<float>(r.d.y);
        rr.dir_z = static_cast<float>(r.d.z);
        rr.tnear = static_cast<float>(r.tMin);
        rr.tfar = std::isfinite(r.tMax) ? static_cast<float>(r.tMax) : std::numeric_limits<float>::infinity();
        rr.time = 0.0f;
        rr.mask = 0xFFFFFFFFu;
        rr.id = 0;
        rr.flags = 0;
    }

    // The hit of ray r on primitive primID of Embree geometry geomID (instance instID, or
    // RTC_INVALID_GEOMETRY_ID), rebuilt in double precision: the double ray is intersected with the
    // triangle's plane dot(ng, x) = offset, precomputed per face for direct placements; for an
    // instance the plane is rebuilt from the transformed vertices (valid for any linear part, not
    // only rotations). Near-grazing rays (|cos| < 1e-9) keep Embree's single-precision distance.
    void reconstruct(const Ray& r, unsigned geomID, unsigned instID, unsigned primID, float tfar,
                     SurfaceHit* hit) const {
        int inst = -1, mesh;
        if (instID != RTC_INVALID_GEOMETRY_ID) {
            inst = geomToInstance[instID];
            mesh = instances[inst].mesh;
        } else {
            mesh = geomToMesh[geomID];
        }
        const MeshRef& mr = meshes[mesh];
        const TriMesh& m = *mr.mesh;
        const uint32_t f = primID;
        Vec3 ng = mr.normal[f];
        double offset = mr.offset[f];
        if (inst >= 0) {
            const auto& tri = m.triangles[f];
            const Point3 v0 = worldVertex(inst, m, tri[0]);
            const Vec3 n = cross(worldVertex(inst, m, tri[1]) - v0, worldVertex(inst, m, tri[2]) - v0);
            const double len = length(n);
            ng = len > 0 ? n / len : Vec3{0, 0, 1};
            offset = dot(ng, v0);
        }
        const double denom = dot(r.d, ng);
        double t = static_cast<double>(tfar);
        if (std::abs(denom) > 1e-9) {
            const double tp = (offset - dot(ng, r.o)) / denom;
            if (std::isfinite(tp) && tp >= 0) t = tp;
        }
        hit->t = t;
        hit->p = r.at(t);
        hit->ng = ng;
        hit->mesh = mesh;
        hit->instance = inst;
        hit->face = f;
        hit->slot = m.materialOf(f);
        hit->front = denom < 0;
    }

    Point3 worldVertex(int inst, const TriMesh& m, uint32_t vi) const {
        const Point3& p = m.positions[vi];
        if (inst < 0) return p;
        const Xform& x = instances[inst];
        return Point3{x.R[0] * p.x + x.R[1] * p.y + x.R[2] * p.z, x.R[3] * p.x + x.R[4] * p.y + x.R[5] * p.z,
                      x.R[6] * p.x + x.R[7] * p.y + x.R[8] * p.z} +
               x.t;
    }
};

namespace {
// An instance's linear part must be finite and well-conditioned: Embree asserts (and rays lose
// their precision) on singular or extreme transforms. Allowed: every column length in
// [1e-6, 1e6] and |det R| at least 1e-6 times the product of the column lengths (no two columns
// within about 1e-6 rad of a common plane).
void checkTransform(const ir::Instance& in, size_t ii) {
    const double* R = in.rotation;
    for (int k = 0; k < 9; ++k)
        if (!std::isfinite(R[k]))
            throw InputError(fmt::format("instances[{}] (mesh '{}'): rotation element {} is {}, not a finite number", ii,
                                         in.mesh, k, R[k]));
    if (!std::isfinite(in.translation.x) || !std::isfinite(in.translation.y) || !std::isfinite(in.translation.z))
        throw InputError(fmt::format("instances[{}] (mesh '{}'): the translation is not finite", ii, in.mesh));
    const Vec3 c0{R[0], R[3], R[6]}, c1{R[1], R[4], R[7]}, c2{R[2], R[5], R[8]};
    const double l0 = length(c0), l1 = length(c1), l2 = length(c2);
    for (double l : {l0, l1, l2})
        if (!(l >= 1e-6 && l <= 1e6))
            throw InputError(fmt::format("instances[{}] (mesh '{}'): a column of the rotation has length {}; allowed "
                                         "[1e-6, 1e6] (scale)",
                                         ii, in.mesh, l));
    const double det = dot(c0, cross(c1, c2));
    if (!(std::abs(det) >= 1e-6 * l0 * l1 * l2))
        throw InputError(fmt::format("instances[{}] (mesh '{}'): the rotation is singular (determinant {} for column "
                                     "lengths {}, {}, {}); it must map 3-D space onto itself",
                                     ii, in.mesh, det, l0, l1, l2));
}

// A vertex must be finite and within kMaxGeometryM of the origin: Embree builds its bounds in
// single precision and asserts on infinite or overflowing boxes.
// `who` is called only to name the element of a refused vertex.
template <class Who>
void checkVertex(const Point3& p, uint32_t vi, Who&& who) {
    for (double c : {p.x, p.y, p.z})
        if (!(std::abs(c) <= kMaxGeometryM))
            throw InputError(fmt::format("{}: vertex {} at ({}, {}, {}) lies beyond {:g} m from the origin; geometry must "
                                         "be finite and within {:g} m in each coordinate",
                                         who(), vi, p.x, p.y, p.z, kMaxGeometryM, kMaxGeometryM));
}
}  // namespace

unsigned EmbreeScene::Impl::attach(RTCGeometry g) {
    const unsigned id = rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    if (geomToMesh.size() <= id) {
        geomToMesh.resize(id + 1, -1);
        geomToInstance.resize(id + 1, -1);
    }
    return id;
}

void EmbreeScene::Impl::addMesh(const ir::Mesh& mesh, size_t mi) {
    const TriMesh& m = mesh.data;
    meshes[mi].mesh = &m;
    meshes[mi].normal.resize(m.triangles.size());
    meshes[mi].offset.resize(m.triangles.size());
    for (uint32_t vi = 0; vi < m.positions.size(); ++vi)
        checkVertex(m.positions[vi], vi, [&] { return fmt::format("mesh '{}'", mesh.name); });
    for (size_t f = 0; f < m.triangles.size(); ++f) {
        const auto& t = m.triangles[f];
        for (int k = 0; k < 3; ++k)
            if (t[k] >= m.positions.size())
                throw InputError(fmt::format("mesh '{}': triangle {} references vertex {} of {}", mesh.name, f, t[k],
                                             m.positions.size()));
        const Vec3 n = cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
        const double len = length(n);
        if (!(len > 0)) log::debug("mesh '{}': triangle {} is degenerate (zero area)", mesh.name, f);
        meshes[mi].normal[f] = len > 0 ? n / len : Vec3{0, 0, 1};
        meshes[mi].offset[f] = dot(meshes[mi].normal[f], m.positions[t[0]]);
    }
    if (m.triangles.empty()) return;
    geomToMesh[attach(makeTriangles(m))] = static_cast<int>(mi);
    box.expand(m.bounds());
    triangles += m.triangles.size();
}

void EmbreeScene::Impl::addInstance(const ir::SceneIR& ir, size_t ii) {
    const ir::Instance& in = ir.instances[ii];
    int mi = -1;
    for (size_t k = 0; k < ir.meshes.size(); ++k)
        if (ir.meshes[k].name == in.mesh) mi = static_cast<int>(k);
    if (mi < 0) throw InputError(fmt::format("instances[{}]: unknown mesh '{}'", ii, in.mesh));
    checkTransform(in, ii);
    Xform x;
    std::copy(in.rotation, in.rotation + 9, x.R);
    x.t = in.translation;
    x.mesh = mi;
    instances.push_back(x);
    const TriMesh& m = ir.meshes[mi].data;
    if (m.triangles.empty()) return;
    // The mesh's own vertices were checked by addMesh (every mesh is added before any instance).
    for (uint32_t vi = 0; vi < m.positions.size(); ++vi)
        checkVertex(worldVertex(static_cast<int>(ii), m, vi), vi,
                    [&] { return fmt::format("instances[{}] (mesh '{}', placed)", ii, in.mesh); });
    if (!meshScenes[mi]) {
        RTCScene sub = rtcNewScene(device);
        rtcSetSceneFlags(sub, RTC_SCENE_FLAG_ROBUST);
        rtcSetSceneBuildQuality(sub, RTC_BUILD_QUALITY_HIGH);
        RTCGeometry g = makeTriangles(m);
        rtcAttachGeometry(sub, g);
        rtcReleaseGeometry(g);
        rtcCommitScene(sub);
        meshScenes[mi] = sub;
    }
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(g, meshScenes[mi]);
    rtcSetGeometryTimeStepCount(g, 1);
    const float xf[12] = {float(x.R[0]), float(x.R[1]), float(x.R[2]), float(x.t.x),
                          float(x.R[3]), float(x.R[4]), float(x.R[5]), float(x.t.y),
                          float(x.R[6]), float(x.R[7]), float(x.R[8]), float(x.t.z)};
    rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, xf);
    rtcCommitGeometry(g);
    geomToInstance[attach(g)] = static_cast<int>(ii);
    for (uint32_t vi = 0; vi < m.positions.size(); ++vi) box.expand(worldVertex(static_cast<int>(ii), m, vi));
    triangles += m.triangles.size();
}

EmbreeScene::EmbreeScene(const ir::SceneIR& ir) : impl_(std::make_unique<Impl>()) {
    Impl& s = *impl_;
    s.device = rtcNewDevice(nullptr);
    if (!s.device) throw InternalError("embree: rtcNewDevice failed");
    rtcSetDeviceErrorFunction(s.device, embreeErrorCallback, nullptr);
    s.scene = rtcNewScene(s.device);
    // ROBUST: no traversal shortcuts that lose rays through shared triangle edges (closed
    // water volumes must not leak).
    rtcSetSceneFlags(s.scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(s.scene, RTC_BUILD_QUALITY_HIGH);
    s.meshes.resize(ir.meshes.size());
    s.meshScenes.assign(ir.meshes.size(), nullptr);
    for (size_t mi = 0; mi < ir.meshes.size(); ++mi) s.addMesh(ir.meshes[mi], mi);
    for (size_t ii = 0; ii < ir.instances.size(); ++ii) s.addInstance(ir, ii);
    rtcCommitScene(s.scene);
    // Every triangle where Embree places it: each mesh's own placement, then each instance.
    s.clearance.build(s.box, [&](auto&& mark) {
        auto placed = [&](int inst, const TriMesh& m) {  // inst -1: the mesh's own placement
            for (const auto& t : m.triangles)
                mark(s.worldVertex(inst, m, t[0]), s.worldVertex(inst, m, t[1]), s.worldVertex(inst, m, t[2]));
        };
        for (const Impl::MeshRef& mr : s.meshes) placed(-1, *mr.mesh);
        for (size_t ii = 0; ii < s.instances.size(); ++ii)
            placed(static_cast<int>(ii), *s.meshes[s.instances[ii].mesh].mesh);
    });
}

EmbreeScene::~EmbreeScene() = default;

void EmbreeScene::forEachTriangle(
    const std::function<void(int, int, uint32_t, const Point3&, const Point3&, const Point3&)>& f) const {
    const Impl& s = *impl_;
    auto placed = [&](int inst, int mesh) {
        const TriMesh* m = s.meshes[static_cast<size_t>(mesh)].mesh;
        if (!m) return;
        for (uint32_t fi = 0; fi < m->triangles.size(); ++fi) {
            const auto& t = m->triangles[fi];
            f(mesh, inst, fi, s.worldVertex(inst, *m, t[0]), s.worldVertex(inst, *m, t[1]), s.worldVertex(inst, *m, t[2]));
        }
    };
    for (size_t mi = 0; mi < s.meshes.size(); ++mi) placed(-1, static_cast<int>(mi));
    for (size_t ii = 0; ii < s.instances.size(); ++ii) placed(static_cast<int>(ii), s.instances[ii].mesh);
}

bool EmbreeScene::intersect(const Ray& r, SurfaceHit* hit) const {
    const Impl& s = *impl_;
    ++tlsCounts.cast;
    if (tlsLog) [[unlikely]] tlsLog->closest.push_back(r);
    if (s.clearSegment(r)) return false;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    Impl::setRay(rh.ray, r);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(s.scene, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    ++tlsCounts.hits;
    s.reconstruct(r, rh.hit.geomID, rh.hit.instID[0], rh.hit.primID, rh.ray.tfar, hit);
    return true;
}

void EmbreeScene::intersectCoherent(const Ray* rays, int n, SurfaceHit* hits, bool* found) const {
    const Impl& s = *impl_;
    tlsCounts.cast += n;
    if (tlsLog) [[unlikely]] tlsLog->closest.insert(tlsLog->closest.end(), rays, rays + n);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    for (int base = 0; base < n; base += 8) {
        const int m = std::min(8, n - base);
        RTCRayHit8 rh;  // RTC_ALIGN(32) in Embree's header
        alignas(32) int valid[8];
        for (int k = 0; k < 8; ++k) {
            valid[k] = k < m ? -1 : 0;
            const Ray& r = rays[base + std::min(k, m - 1)];  // inactive lanes: a copy of a valid ray
            rh.ray.org_x[k] = static_cast<float>(r.o.x);
            rh.ray.org_y[k] = static_cast<float>(r.o.y);
            rh.ray.org_z[k] = static_cast<float>(r.o.z);
            rh.ray.dir_x[k] = static_cast<float>(r.d.x);
            rh.ray.dir_y[k] = static_cast<float>(r.d.y);
            rh.ray.dir_z[k] = static_cast<float>(r.d.z);
            rh.ray.tnear[k] = static_cast<float>(r.tMin);
            rh.ray.tfar[k] = std::isfinite(r.tMax) ? static_cast<float>(r.tMax) : std::numeric_limits<float>::infinity();
            rh.ray.time[k] = 0.0f;
            rh.ray.mask[k] = 0xFFFFFFFFu;
            rh.ray.id[k] = 0;
            rh.ray.flags[k] = 0;
            rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect8(valid, s.scene, &ctx, &rh);
        for (int k = 0; k < m; ++k) {
            const int i = base + k;
            found[i] = rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
            if (!found[i]) continue;
            ++tlsCounts.hits;
            s.reconstruct(rays[i], rh.hit.geomID[k], rh.hit.instID[0][k], rh.hit.primID[k], rh.ray.tfar[k], &hits[i]);
        }
    }
}

bool EmbreeScene::occluded(const Ray& r) const {
    const Impl& s = *impl_;
    ++tlsCounts.shadow;
    if (tlsLog) [[unlikely]] tlsLog->occlusion.push_back(r);
    if (s.clearSegment(r)) return false;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay rr;
    Impl::setRay(rr, r);
    rtcOccluded1(s.scene, &ctx, &rr);
    return rr.tfar == -std::numeric_limits<float>::infinity();
}

BBox3 EmbreeScene::bounds() const { return impl_->box; }
uint64_t EmbreeScene::triangleCount() const { return impl_->triangles; }
bool EmbreeScene::empty() const { return impl_->triangles == 0; }

void setThreadRayLog(RayLog* log) { tlsLog = log; }

uint64_t EmbreeScene::rawOccludedCount(const Ray* rays, size_t n) const {
    const Impl& s = *impl_;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    uint64_t occ = 0;
    for (size_t i = 0; i < n; ++i) {
        RTCRay rr;
        Impl::setRay(rr, rays[i]);
        rtcOccluded1(s.scene, &ctx, &rr);
        occ += rr.tfar == -std::numeric_limits<float>::infinity();
    }
    return occ;
}

uint64_t EmbreeScene::rawIntersectCount(const Ray* rays, size_t n) const {
    const Impl& s = *impl_;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    uint64_t hits = 0;
    for (size_t i = 0; i < n; ++i) {
        RTCRayHit rh;
        Impl::setRay(rh.ray, rays[i]);
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(s.scene, &ctx, &rh);
        hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    }
    return hits;
}

}  // namespace littoral::render
