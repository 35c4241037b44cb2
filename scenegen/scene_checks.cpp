#include "scenegen/scene_checks.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "core/render_budget.h"
#include "core/resource_limits.h"
#include "scenegen/water_volume.h"

namespace littoral::scenegen {

namespace {

// Möller & Trumbore (1997) ray-triangle test; counts hits with t > 0.
bool rayHitsTriangle(const Point3& o, const Vec3& d, const Point3& a, const Point3& b, const Point3& c) {
    const Vec3 e1 = b - a, e2 = c - a, p = cross(d, e2);
    const double det = dot(e1, p);
    if (std::abs(det) < 1e-300) return false;
    const double inv = 1.0 / det;
    const Vec3 s = o - a;
    const double u = dot(s, p) * inv;
    if (u < 0 || u > 1) return false;
    const Vec3 q = cross(s, e1);
    const double v = dot(d, q) * inv;
    if (v < 0 || u + v > 1) return false;
    return dot(e2, q) * inv > 0;
}

bool boxesOverlap(const BBox3& a, const BBox3& b) {
    return a.lo.x <= b.hi.x && b.lo.x <= a.hi.x && a.lo.y <= b.hi.y && b.lo.y <= a.hi.y && a.lo.z <= b.hi.z &&
           b.lo.z <= a.hi.z;
}

// Slab test: does the ray o + t d, t >= 0, meet the closed box?
bool rayHitsBox(const Point3& o, const Vec3& d, const BBox3& b) {
    double t0 = 0, t1 = std::numeric_limits<double>::infinity();
    const double oo[3] = {o.x, o.y, o.z}, dd[3] = {d.x, d.y, d.z};
    const double lo[3] = {b.lo.x, b.lo.y, b.lo.z}, hi[3] = {b.hi.x, b.hi.y, b.hi.z};
    for (int k = 0; k < 3; ++k) {
        if (dd[k] == 0) {
            if (oo[k] < lo[k] || oo[k] > hi[k]) return false;
            continue;
        }
        double a = (lo[k] - oo[k]) / dd[k], c = (hi[k] - oo[k]) / dd[k];
        if (a > c) std::swap(a, c);
        t0 = std::max(t0, a);
        t1 = std::min(t1, c);
        if (t0 > t1) return false;
    }
    return true;
}

std::string vecText(const Vec3& v) { return fmt::format("({:.6g}, {:.6g}, {:.6g})", v.x, v.y, v.z); }

}  // namespace

void checkRenderMemory(const SceneSpec& spec, const ir::SceneIR& ir) {
    const RenderMemory m = estimateRenderMemory(ir);
    if (m.items.empty() || m.total <= static_cast<double>(memoryBudget())) return;
    const MemoryItem& big = m.items.front();
    SourceLoc where{spec.file.string()};
    std::string key;
    if (big.kind == MemoryItem::Kind::Sensor) {
        if (big.index < spec.sensors.size()) where = spec.sensors[big.index].loc;
        key = fmt::format("sensors[{}]", big.index);
    } else {
        // The photon counts are not kept with a location; find them in the file again.
        key = big.kind == MemoryItem::Kind::SurfacePhotons ? "render.photons.surface" : "render.photons.volume";
        try {
            const YamlNode root = YamlNode::loadFile(spec.file);
            if (auto r = root.optional("render"))
                if (auto p = r->optional("photons"))
                    if (auto n = p->optional(big.kind == MemoryItem::Kind::SurfacePhotons ? "surface" : "volume"))
                        where = n->loc();
        } catch (const InputError&) {
        }
    }
    const std::string what = m.items.size() == 1
                                 ? fmt::format("{}: {} would", key, big.what)
                                 : fmt::format("{}: {} (with the rest of the render) would", key, big.what);
    requireMemory(m.total, what, where);
}

bool insideClosedMesh(const TriMesh& m, const Point3& p) {
    // Directions with irrational-looking components: no edge or vertex of a real mesh lies exactly
    // on all three rays.
    static const Vec3 dirs[3] = {normalize(Vec3{0.5773502691896258, 0.3141592653589793, 0.7071067811865476}),
                                 normalize(Vec3{-0.2718281828459045, 0.8660254037844386, -0.4142135623730951}),
                                 normalize(Vec3{0.1234567891011121, -0.6180339887498949, 0.2360679774997897})};
    if (m.triangles.empty() || !m.bounds().contains(p)) return false;
    int votes = 0;
    for (const Vec3& d : dirs) {
        int hits = 0;
        for (const auto& t : m.triangles)
            hits += rayHitsTriangle(p, d, m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]) ? 1 : 0;
        votes += hits % 2;
    }
    return votes >= 2;
}

bool viewSeesBox(const ir::Sensor& s, const BBox3& box) {
    const Vec3 f = normalize(s.forward);
    const Vec3 r = normalize(cross(f, s.up));
    const Vec3 u = cross(r, f);
    const bool pinhole = s.type == ir::Sensor::Type::Pinhole;
    const double hw = 0.5 * s.width * (pinhole ? s.pixelPitch : s.pixelSize);
    const double hh = 0.5 * s.height * (pinhole ? s.pixelPitch : s.pixelSize);
    // The four corner rays (origin, direction): from the pinhole through the sensor corners, or
    // from the orthographic image corners along the axis.
    std::array<std::pair<Point3, Vec3>, 4> corner;
    const double sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
    for (int k = 0; k < 4; ++k) {
        const Vec3 off = r * (sx[k] * hw) + u * (sy[k] * hh);
        corner[k] = pinhole ? std::make_pair(s.position, normalize(f * s.focalLength + off))
                            : std::make_pair(s.position + off, f);
    }
    for (const auto& [o, d] : corner)
        if (rayHitsBox(o, d, box)) return true;
    // The view volume as half-spaces dot(n, p - q) >= 0: the four sides and the front.
    std::array<std::pair<Vec3, Point3>, 5> planes;
    for (int k = 0; k < 4; ++k) {
        const auto& [o0, d0] = corner[k];
        const auto& [o1, d1] = corner[(k + 1) % 4];
        Vec3 n = pinhole ? cross(d0, d1) : cross(o1 - o0, f);
        const Point3 centre = pinhole ? s.position + f : s.position;
        if (dot(n, centre + f - o0) < 0) n = -n;  // point inward
        planes[k] = {n, o0};
    }
    planes[4] = {f, s.position};
    const Point3 c[8] = {{box.lo.x, box.lo.y, box.lo.z}, {box.hi.x, box.lo.y, box.lo.z}, {box.lo.x, box.hi.y, box.lo.z},
                         {box.hi.x, box.hi.y, box.lo.z}, {box.lo.x, box.lo.y, box.hi.z}, {box.hi.x, box.lo.y, box.hi.z},
                         {box.lo.x, box.hi.y, box.hi.z}, {box.hi.x, box.hi.y, box.hi.z}};
    static const int edges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                     {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    for (const auto& e : edges) {
        // Liang-Barsky clipping of the edge against every half-space.
        const Point3 a = c[e[0]], b = c[e[1]];
        double t0 = 0, t1 = 1;
        bool empty = false;
        for (const auto& [n, q] : planes) {
            const double fa = dot(n, a - q), fb = dot(n, b - q);
            if (fa < 0 && fb < 0) {
                empty = true;
                break;
            }
            if (fa < 0) t0 = std::max(t0, fa / (fa - fb));
            else if (fb < 0) t1 = std::min(t1, fa / (fa - fb));
        }
        if (!empty && t0 <= t1) return true;
    }
    return false;
}

void checkObjectPlacement(const std::vector<ObjectSpec>& specs, const std::vector<const TriMesh*>& meshes,
                          const bathymetry::Extent& d) {
    std::vector<BBox3> boxes;
    for (size_t i = 0; i < meshes.size(); ++i) {
        const BBox3 b = meshes[i]->bounds();
        boxes.push_back(b);
        if (b.lo.x < d.x0 || b.hi.x > d.x1 || b.lo.y < d.y0 || b.hi.y > d.y1) {
            const bool outside = b.hi.x < d.x0 || b.lo.x > d.x1 || b.hi.y < d.y0 || b.lo.y > d.y1;
            throw InputError(specs[i].loc, fmt::format("object '{}' spans [{:.6g}, {:.6g}] x [{:.6g}, {:.6g}] m in plan, "
                                                       "which {} the scene domain [{}, {}] x [{}, {}] m; move it or "
                                                       "enlarge scene.domain",
                                                       specs[i].name, b.lo.x, b.hi.x, b.lo.y, b.hi.y,
                                                       outside ? "lies outside" : "crosses the edge of", d.x0, d.x1,
                                                       d.y0, d.y1));
        }
    }
    for (size_t j = 0; j < meshes.size(); ++j)
        for (size_t i = 0; i < j; ++i)
            if (boxesOverlap(boxes[i], boxes[j]) && solidsOverlap(*meshes[i], *meshes[j]))
                throw InputError(specs[j].loc, fmt::format("object '{}' intersects or contains object '{}' (line {}); "
                                                           "solids in a scene must be disjoint",
                                                           specs[j].name, specs[i].name, specs[i].loc.line));
}

void checkSurfaceCoverage(const surfaces::WaveParams& w, const bathymetry::Extent& d, const SourceLoc& where) {
    const double x0 = w.centreX - 0.5 * w.sizeX, x1 = w.centreX + 0.5 * w.sizeX;
    const double y0 = w.centreY - 0.5 * w.sizeY, y1 = w.centreY + 0.5 * w.sizeY;
    if (x0 > d.x0 || x1 < d.x1 || y0 > d.y0 || y1 < d.y1)
        throw InputError(where, fmt::format("water.surface covers [{:.6g}, {:.6g}] x [{:.6g}, {:.6g}] m, which does not "
                                            "cover the scene domain [{}, {}] x [{}, {}] m; enlarge its size (or move "
                                            "its centre)",
                                            x0, x1, y0, y1, d.x0, d.x1, d.y0, d.y1));
}

namespace {
// The closed water volumes of the IR, and the height band their air-water faces span: below it a
// point is in water (or under the seabed, or in an object: checked apart), above it in air, and
// only within it does the volume need the exact inside test.
struct WaterVolumes {
    std::vector<const TriMesh*> meshes;
    double zLo = std::numeric_limits<double>::infinity(), zHi = -std::numeric_limits<double>::infinity();

    explicit WaterVolumes(const ir::SceneIR& ir) {
        for (const ir::Mesh& m : ir.meshes) {
            if (m.inside != "water" || !m.closed) continue;
            meshes.push_back(&m.data);
            for (size_t f = 0; f < m.data.triangles.size(); ++f) {
                const size_t slot = m.data.materialOf(f);
                if (slot >= m.materials.size() || m.materials[slot] != kInterfaceMaterialName) continue;
                for (uint32_t v : m.data.triangles[f]) {
                    zLo = std::min(zLo, m.data.positions[v].z);
                    zHi = std::max(zHi, m.data.positions[v].z);
                }
            }
        }
        if (zLo > zHi) {  // no face named as the interface: test every point exactly
            zLo = -std::numeric_limits<double>::infinity();
            zHi = std::numeric_limits<double>::infinity();
        }
    }
    bool contains(const Point3& p) const {
        if (p.z < zLo) return true;
        if (p.z > zHi) return false;
        for (const TriMesh* m : meshes)
            if (insideClosedMesh(*m, p)) return true;
        return false;
    }
};

// Under waves the mean water level does not say which medium a probe is in: a probe below the
// mean level in a trough is in air, one above it in a crest is in water. The closed water volume
// decides, and a probe whose medium (given, or taken from the mean level) disagrees is refused.
void checkProbeMedium(const SceneSpec& spec, const WaterVolumes& water, const ProbeSection& section,
                      const ir::Probe& p, const std::string& who) {
    if (!spec.hasWater || water.meshes.empty()) return;
    const bool inWater = water.contains(p.position), declaredWater = p.medium == "water";
    if (inWater == declaredWater) return;
    const std::string why = section.medium == "auto"
                                ? fmt::format("taken from the mean water level {:.6g} m", spec.waterLevel)
                                : fmt::format("medium: {}", section.medium);
    if (declaredWater)
        throw InputError(section.loc, fmt::format("{} at {} lies in air above the water surface{}, but its medium is "
                                                  "water ({}); move it deeper, or give medium: air",
                                                  who, vecText(p.position),
                                                  p.position.z < spec.waterLevel ? " (a wave trough there)" : "", why));
    throw InputError(section.loc, fmt::format("{} at {} lies in the water{}, but its medium is air ({}); move it, or "
                                              "give medium: water",
                                              who, vecText(p.position),
                                              p.position.z > spec.waterLevel ? " (a wave crest there)" : "", why));
}
}  // namespace

void checkSensorsAndProbes(const SceneSpec& spec, const ir::SceneIR& ir, const std::vector<ObjectSpec>& objectSpecs,
                           const std::vector<const TriMesh*>& objects,
                           const std::function<double(double, double)>& ground, const bathymetry::Extent& d) {
    BBox3 scene;
    for (const auto& m : ir.meshes) scene.expand(m.data.bounds());
    auto inObject = [&](const Point3& p) -> int {
        for (size_t i = 0; i < objects.size(); ++i)
            if (insideClosedMesh(*objects[i], p)) return static_cast<int>(i);
        return -1;
    };
    auto nameOf = [&](int i) { return objectSpecs[static_cast<size_t>(i)].name; };
    const WaterVolumes water(ir);
    for (size_t k = 0; k < spec.sensors.size() && k < ir.sensors.size(); ++k) {
        const auto& s = ir.sensors[k];
        const SourceLoc& where = spec.sensors[k].loc;
        const std::string who = fmt::format("sensor '{}'", s.name);
        if (const int o = inObject(s.position); o >= 0)
            throw InputError(where, fmt::format("{} sits at {}, inside object '{}': it would see only the inside of the "
                                                "object",
                                                who, vecText(s.position), nameOf(o)));
        if (d.contains(s.position.x, s.position.y)) {
            const double g = ground(s.position.x, s.position.y);
            if (s.position.z < g)
                throw InputError(where, fmt::format("{} sits at {}, {:.3g} m under the ground (terrain elevation {:.6g} m "
                                                    "there)",
                                                    who, vecText(s.position), g - s.position.z, g));
        }
        if (!scene.empty() && !viewSeesBox(s, scene))
            throw InputError(where, fmt::format("{} at {} looking along {} sees nothing of the scene (its field of view "
                                                "misses the whole box [{:.6g}, {:.6g}] x [{:.6g}, {:.6g}] x [{:.6g}, "
                                                "{:.6g}] m): check its position, direction and up vector",
                                                who, vecText(s.position), vecText(s.forward), scene.lo.x, scene.hi.x,
                                                scene.lo.y, scene.hi.y, scene.lo.z, scene.hi.z));
    }
    for (size_t k = 0; k < spec.probes.size() && k < ir.probes.size(); ++k) {
        const auto& p = ir.probes[k];
        const SourceLoc& where = spec.probes[k].loc;
        const std::string who = fmt::format("probe '{}'", p.name);
        if (const int o = inObject(p.position); o >= 0)
            throw InputError(where, fmt::format("{} at {} is inside object '{}': it would measure nothing", who,
                                                vecText(p.position), nameOf(o)));
        if (!d.contains(p.position.x, p.position.y))
            throw InputError(where, fmt::format("{} at {} lies outside the scene domain [{}, {}] x [{}, {}] m", who,
                                                vecText(p.position), d.x0, d.x1, d.y0, d.y1));
        const double g = ground(p.position.x, p.position.y);
        if (p.position.z < g)
            throw InputError(where, fmt::format("{} at {} is {:.3g} m under the seabed (terrain elevation {:.6g} m "
                                                "there): it would measure nothing",
                                                who, vecText(p.position), g - p.position.z, g));
        checkProbeMedium(spec, water, spec.probes[k], p, who);
    }
}

}  // namespace littoral::scenegen
