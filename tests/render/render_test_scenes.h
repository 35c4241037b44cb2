#pragma once
// Geometry and Scene IR builders shared by the render tests. Meshes are generated in code and
// oriented outward (counter-clockwise seen from the outside) by construction checks below.
#include <cmath>
#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/scene_ir.h"
#include "core/units.h"
#include "render/renderer.h"

namespace littoral::render::testing {

// Render options for tests: no progress bar; threads = 0 uses all cores.
inline RenderOptions quiet(int threads = 0) {
    RenderOptions o;
    o.progress = false;
    o.threads = threads;
    return o;
}

// Flips triangles whose normal points toward `inside` (a point inside a convex shape) so every
// face is CCW seen from outside.
inline void orientAway(TriMesh& m, const Point3& inside) {
    for (auto& t : m.triangles) {
        const Vec3 a = m.positions[t[0]], b = m.positions[t[1]], c = m.positions[t[2]];
        const Vec3 n = cross(b - a, c - a);
        if (dot(n, (a + b + c) * (1.0 / 3.0) - inside) < 0) std::swap(t[1], t[2]);
    }
}

// Upper hemisphere z >= 0 of a sphere of radius R centred at c: nTheta rings from the pole to
// the equator, nPhi segments, outward normals. Open (no floor).
inline TriMesh dome(const Point3& c, double R, int nTheta, int nPhi) {
    TriMesh m;
    m.positions.push_back(c + Vec3{0, 0, R});
    for (int k = 1; k <= nTheta; ++k) {
        const double th = 0.5 * kPi * k / nTheta;
        for (int j = 0; j < nPhi; ++j) {
            const double ph = 2 * kPi * j / nPhi;
            m.positions.push_back(c + Vec3{R * std::sin(th) * std::cos(ph), R * std::sin(th) * std::sin(ph),
                                           R * std::cos(th)});
        }
    }
    auto idx = [&](int k, int j) -> uint32_t { return k == 0 ? 0u : 1u + (k - 1) * nPhi + (j % nPhi); };
    for (int j = 0; j < nPhi; ++j) m.triangles.push_back({idx(0, 0), idx(1, j), idx(1, j + 1)});
    for (int k = 1; k < nTheta; ++k)
        for (int j = 0; j < nPhi; ++j) {
            m.triangles.push_back({idx(k, j), idx(k + 1, j), idx(k + 1, j + 1)});
            m.triangles.push_back({idx(k, j), idx(k + 1, j + 1), idx(k, j + 1)});
        }
    orientAway(m, c);
    return m;
}

// Axis-aligned box [lo, hi]; faceMaterial: slot `topSlot` on the +z face, `otherSlot` elsewhere.
inline TriMesh box(const Point3& lo, const Point3& hi, uint16_t topSlot = 0, uint16_t otherSlot = 0) {
    TriMesh m;
    for (int i = 0; i < 8; ++i)
        m.positions.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
    const uint32_t q[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};
    for (int f = 0; f < 6; ++f) {
        m.triangles.push_back({q[f][0], q[f][1], q[f][2]});
        m.triangles.push_back({q[f][0], q[f][2], q[f][3]});
        const uint16_t s = f == 1 ? topSlot : otherSlot;
        m.faceMaterial.push_back(s);
        m.faceMaterial.push_back(s);
    }
    orientAway(m, (lo + hi) * 0.5);
    return m;
}

// Horizontal rectangle [x0, x1] x [y0, y1] at height z, normal +z, split into nx x ny cells
// (two triangles each); slotOf(i, j) gives each cell's material slot.
template <class SlotFn>
inline TriMesh grid(double x0, double x1, double y0, double y1, double z, int nx, int ny, SlotFn slotOf) {
    TriMesh m;
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) m.positions.push_back({x0 + (x1 - x0) * i / nx, y0 + (y1 - y0) * j / ny, z});
    auto idx = [&](int i, int j) { return static_cast<uint32_t>(j * (nx + 1) + i); };
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            m.triangles.push_back({idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)});
            m.triangles.push_back({idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)});
            const uint16_t s = static_cast<uint16_t>(slotOf(i, j));
            m.faceMaterial.push_back(s);
            m.faceMaterial.push_back(s);
        }
    return m;
}
inline TriMesh plane(double x0, double x1, double y0, double y1, double z) {
    return grid(x0, x1, y0, y1, z, 1, 1, [](int, int) { return 0; });
}

// A vertical wall on the arc of radius rho around (cx, cy) from azimuth phi0 to phi1, from z = 0
// to z = h, in n segments (single sheet, normals toward the centre).
inline TriMesh arcWall(double cx, double cy, double rho, double phi0, double phi1, double h, int n) {
    TriMesh m;
    for (int i = 0; i <= n; ++i) {
        const double p = phi0 + (phi1 - phi0) * i / n;
        m.positions.push_back({cx + rho * std::cos(p), cy + rho * std::sin(p), 0.0});
        m.positions.push_back({cx + rho * std::cos(p), cy + rho * std::sin(p), h});
    }
    for (int i = 0; i < n; ++i) {
        const uint32_t a = 2 * i, b = 2 * i + 1, c = 2 * i + 2, d = 2 * i + 3;
        m.triangles.push_back({a, b, d});
        m.triangles.push_back({a, d, c});
    }
    return m;
}

inline ir::Material material(const std::string& name, ir::Material::Type type, ir::Material::Solver solver,
                             double reflectance = 0.0) {
    ir::Material m;
    m.name = name;
    m.type = type;
    // Only materials that have a radiometry solver take one (the dirsig estimator refuses a solver
    // on a black material).
    if (type != ir::Material::Type::Black && type != ir::Material::Type::Periodic) m.solver = solver;
    m.reflectance = Spectrum::constant(reflectance);
    return m;
}

// A material with its type only: no solver, no reflectance (interfaces and periodic walls).
inline ir::Material typedMaterial(const std::string& name, ir::Material::Type type) {
    ir::Material m;
    m.name = name;
    m.type = type;
    return m;
}

inline ir::Medium water(double a, double b, double n = 1.34, ir::PhaseFunction phase = {}) {
    return ir::Medium::homogeneous("water", n, Spectrum::constant(a), Spectrum::constant(b), phase);
}

inline ir::Mesh meshOf(const std::string& name, TriMesh data, std::vector<std::string> materials,
                       std::string inside = "", std::string outside = "", bool closed = false) {
    ir::Mesh m;
    m.name = name;
    m.file = "meshes/" + name + ".ply";
    m.materials = std::move(materials);
    m.inside = std::move(inside);
    m.outside = std::move(outside);
    m.closed = closed;
    m.data = std::move(data);
    return m;
}

// A scene lit by a uniform sky of hemisphere irradiance E_h = 1 (skyfraction 1: L_sky = 1/pi),
// no sun, one band 0.4-0.6 um (the thesis' panchromatic band).
inline ir::SceneIR uniformSkyScene() {
    ir::SceneIR s;
    s.name = "test";
    s.render.bands = {Band{0.4, 0.6}};
    s.sun.enabled = false;
    s.sky.radiance = Spectrum::constant(1.0 / kPi);
    return s;
}

inline ir::Sensor pinhole(const std::string& name, Point3 pos, Vec3 fwd, Vec3 up, int w, int h, double f,
                          double pitch, std::string medium = "") {
    ir::Sensor s;
    s.name = name;
    s.type = ir::Sensor::Type::Pinhole;
    s.position = pos;
    s.forward = fwd;
    s.up = up;
    s.width = w;
    s.height = h;
    s.focalLength = f;
    s.pixelPitch = pitch;
    s.medium = std::move(medium);
    return s;
}

inline ir::Sensor ortho(const std::string& name, Point3 pos, Vec3 fwd, Vec3 up, int w, int h, double size) {
    ir::Sensor s;
    s.name = name;
    s.type = ir::Sensor::Type::Orthographic;
    s.position = pos;
    s.forward = fwd;
    s.up = up;
    s.width = w;
    s.height = h;
    s.pixelSize = size;
    return s;
}

// Unpolarised Fresnel reflectance in the thesis' form, Eq. 4.2, with Snell (Eq. 4.1):
// r = 1/2 [sin^2(ti - tr)/sin^2(ti + tr) + tan^2(ti - tr)/tan^2(ti + tr)]; Eq. 4.3 at normal
// incidence; 1 beyond the critical angle. Independent of render/materials.cpp on purpose.
inline double fresnelEq42(double thetaI, double n1, double n2) {
    const double s = n1 / n2 * std::sin(thetaI);
    if (s >= 1.0) return 1.0;
    if (thetaI < 1e-7) return sqr((n2 - n1) / (n2 + n1));
    const double tr = std::asin(s);
    return 0.5 * (sqr(std::sin(thetaI - tr) / std::sin(thetaI + tr)) + sqr(std::tan(thetaI - tr) / std::tan(thetaI + tr)));
}

}  // namespace littoral::render::testing

namespace littoral::render::testing {

// A horizontally periodic water slab over [-L, L]^2, from z = -depth to the surface z = 0: the top
// face is material slot 0 (the interface), the floor slot 1, the four side walls slot 2 (a
// Periodic material), closed, with `water` inside. Adds the domain to the scene.
inline TriMesh periodicSlab(double L, double depth) {
    TriMesh m;
    for (int i = 0; i < 8; ++i) m.positions.push_back({(i & 1) ? L : -L, (i & 2) ? L : -L, (i & 4) ? 0.0 : -depth});
    const uint32_t q[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};
    for (int f = 0; f < 6; ++f) {
        m.triangles.push_back({q[f][0], q[f][1], q[f][2]});
        m.triangles.push_back({q[f][0], q[f][2], q[f][3]});
        const uint16_t s = f == 1 ? 0 : f == 0 ? 1 : 2;
        m.faceMaterial.push_back(s);
        m.faceMaterial.push_back(s);
    }
    orientAway(m, {0, 0, -0.5 * depth});
    return m;
}

// A closed, horizontally periodic water body over [-L, L]^2 whose top is the height field h(x, y)
// (periodic over 2L) on an n x n grid, its floor at z = -depth: top slot 0, floor slot 1, side walls
// slot 2.
template <class H> TriMesh heightSlab(double L, double depth, int n, H h) {
    TriMesh m;
    auto x = [&](int i) { return -L + 2 * L * i / n; };
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) m.positions.push_back({x(i), x(j), h(x(i), x(j))});
    const uint32_t base = static_cast<uint32_t>(m.positions.size());
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) m.positions.push_back({x(i), x(j), -depth});
    auto top = [&](int i, int j) { return static_cast<uint32_t>(j * (n + 1) + i); };
    auto bot = [&](int i, int j) { return base + top(i, j); };
    auto quad = [&](uint32_t a, uint32_t b, uint32_t c, uint32_t d, uint16_t slot) {
        m.triangles.push_back({a, b, c});
        m.triangles.push_back({a, c, d});
        m.faceMaterial.push_back(slot);
        m.faceMaterial.push_back(slot);
    };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            quad(top(i, j), top(i + 1, j), top(i + 1, j + 1), top(i, j + 1), 0);
            quad(bot(i, j), bot(i, j + 1), bot(i + 1, j + 1), bot(i + 1, j), 1);
        }
    for (int k = 0; k < n; ++k) {
        quad(top(k, 0), bot(k, 0), bot(k + 1, 0), top(k + 1, 0), 2);
        quad(top(k + 1, n), bot(k + 1, n), bot(k, n), top(k, n), 2);
        quad(top(0, k + 1), bot(0, k + 1), bot(0, k), top(0, k), 2);
        quad(top(n, k), bot(n, k), bot(n, k + 1), top(n, k + 1), 2);
    }
    // Outward by part: the surface up, the floor down, the walls away from the axis. (Orienting
    // away from a centre point flipped surface facets near the corners that tilt toward it; rays
    // through them took the wrong medium: a path tracer then found the floor "in the air".)
    for (size_t f = 0; f < m.triangles.size(); ++f) {
        auto& t = m.triangles[f];
        const Vec3 a = m.positions[t[0]], b = m.positions[t[1]], c = m.positions[t[2]];
        const Vec3 n = cross(b - a, c - a), g = (a + b + c) * (1.0 / 3.0);
        const double out = m.faceMaterial[f] == 0 ? n.z : m.faceMaterial[f] == 1 ? -n.z : n.x * g.x + n.y * g.y;
        if (out < 0) std::swap(t[1], t[2]);
    }
    return m;
}

// Adds a periodic water slab (surface material "surface" Dielectric, floor `floorMaterial`, walls
// "periodic-wall") to `s`, with the domain set to match.
inline void addPeriodicSlab(ir::SceneIR& s, const ir::Medium& water, double L, double depth,
                            const std::string& floorMaterial) {
    s.domain = {-L, L, -L, L, true};
    s.media.push_back(water);
    s.materials.push_back(typedMaterial("surface", ir::Material::Type::Dielectric));
    s.materials.push_back(typedMaterial("periodic-wall", ir::Material::Type::Periodic));
    s.meshes.push_back(meshOf("water", periodicSlab(L, depth), {"surface", floorMaterial, "periodic-wall"}, water.name,
                              "", true));
}

}  // namespace littoral::render::testing
