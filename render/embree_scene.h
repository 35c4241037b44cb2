#pragma once
// The ray-tracing kernel: an Embree 3 BVH over the Scene IR's meshes and instances.
//
// This header and embree_scene.cpp are the only files that know Embree exists (the
// implementation hides behind a pimpl). Embree traverses in single precision; every hit is
// then rebuilt in double precision against the hit triangle's plane, so hit points, distances
// (Beer–Lambert path lengths) and normals carry double accuracy.
//
// Self-intersection: a ray leaving a surface starts from the hit point pushed off the
// triangle along the geometric normal, toward the side the ray leaves into, by
// offsetDistance(p) = 2^-18 * max(1 m, max|p_i|). Embree's float traversal places a triangle
// plane to within a few ulp of the largest coordinate involved (2^-24 relative per ulp), so
// this margin (64 ulp) keeps spawned rays from re-hitting their own triangle while staying far
// below any scene feature (0.4 mm at 100 m from the origin).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "core/bbox.h"
#include "core/ray.h"
#include "core/scene_ir.h"

namespace littoral::render {

// One closest hit.
struct SurfaceHit {
    double t = 0.0;          // metres along the (unit) ray direction
    Point3 p;                // world hit point, double precision
    Normal3 ng;              // unit geometric normal of the triangle, on its outward (CCW) side
    int mesh = -1;           // index into SceneIR::meshes
    int instance = -1;       // index into SceneIR::instances; -1 = the mesh's own placement
    uint32_t face = 0;       // triangle index within the mesh
    uint16_t slot = 0;       // per-face material slot (index into the mesh's material list)
    bool front = true;       // the ray arrived from the outside (against ng), i.e. dot(d, ng) < 0
};

// Ray statistics ("rays cast", "ray hits", "shadow rays") are counted per thread and added to
// the named counters when the thread calls flushRayStats() (the renderer does after every tile).
void flushRayStats();

// Benchmark support: while a RayLog is installed on a thread, every ray that thread traces through
// any EmbreeScene is appended to it (closest-hit and occlusion queries separately), so the
// renderer's actual ray mix can be replayed through bare Embree. Pass nullptr to stop.
struct RayLog {
    std::vector<Ray> closest, occlusion;
};
void setThreadRayLog(RayLog* log);

// Mesh vertices (placed, for instances) must lie within this distance of the origin in each
// coordinate; farther, single-precision bounds overflow or keep no useful precision (1 m at 1e7).
inline constexpr double kMaxGeometryM = 1e7;
// Distance by which spawned rays are pushed off their surface (see the header comment).
// 2^-18: 64 float ulp of the coordinate scale.
inline constexpr double kOffsetRelative = 0x1.0p-18;
inline double offsetDistance(const Point3& p) {
    const double m = std::max({1.0, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    return kOffsetRelative * m;
}
// A ray leaving the surface point p (geometric normal ng) in unit direction dir: the origin is
// offset along +-ng toward the side dir points into; tMin = 0. (Inline: called once per ray.)
inline Ray spawnRay(const Point3& p, const Normal3& ng, const Vec3& dir) {
    const double eps = offsetDistance(p);
    Ray r;
    r.o = p + ng * (dot(dir, ng) >= 0 ? eps : -eps);
    r.d = dir;
    r.tMin = 0.0;
    return r;
}
// A ray from surface point p toward target point q that stops just short of q (shadow rays).
Ray spawnRayTo(const Point3& p, const Normal3& ng, const Point3& q);

class EmbreeScene {
public:
    // Builds the BVH from every mesh's `data` and every instance (world = R local + t).
    // Meshes without triangles are skipped. InputError on an instance naming an unknown mesh.
    explicit EmbreeScene(const ir::SceneIR& scene);
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    // Closest hit with t in [r.tMin, r.tMax]; r.d must be unit length. Counts "rays cast" and
    // "ray hits" (see flushRayStats).
    bool intersect(const Ray& r, SurfaceHit* hit) const;
    // Closest hits of rays[0..n) (any n), traced as Embree packets of 8: for coherent rays such as
    // the hemisphere rays leaving one diffuse vertex. found[i] tells whether rays[i] hit; hits[i]
    // is then the same hit intersect() gives. Counts like intersect().
    void intersectCoherent(const Ray* rays, int n, SurfaceHit* hits, bool* found) const;
    // Any hit with t in [r.tMin, r.tMax]. Counts "shadow rays".
    bool occluded(const Ray& r) const;

    BBox3 bounds() const;             // world bounds of all geometry (instances included)
    // Calls f(mesh, instance, face, a, b, c) for every triangle where the BVH places it, in world
    // coordinates: each mesh's own placement (instance -1), then each instance.
    void forEachTriangle(
        const std::function<void(int, int, uint32_t, const Point3&, const Point3&, const Point3&)>& f) const;
    uint64_t triangleCount() const;   // instanced triangles counted per instance
    bool empty() const;

    // Benchmark baseline: traces rays[0..n) with bare rtcIntersect1 (same BVH, no hit
    // reconstruction, no counters) and returns how many hit something.
    uint64_t rawIntersectCount(const Ray* rays, size_t n) const;
    // The same with bare rtcOccluded1; returns how many are occluded.
    uint64_t rawOccludedCount(const Ray* rays, size_t n) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace littoral::render
