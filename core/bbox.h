#pragma once
#include <algorithm>
#include <limits>

#include "core/ray.h"

namespace littoral {

// Axis-aligned bounding box; an empty box has lo > hi.
struct BBox3 {
    Point3 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
              std::numeric_limits<double>::infinity()};
    Point3 hi{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
              -std::numeric_limits<double>::infinity()};

    bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    void expand(const Point3& p) { lo = vmin(lo, p); hi = vmax(hi, p); }
    void expand(const BBox3& b) { lo = vmin(lo, b.lo); hi = vmax(hi, b.hi); }
    Vec3 extent() const { return hi - lo; }
    Point3 center() const { return (lo + hi) * 0.5; }
    bool contains(const Point3& p) const {
        return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z;
    }
    // Slab test; on a hit returns the parametric entry and exit distances clipped to the ray.
    bool intersect(const Ray& r, double* t0, double* t1) const {
        double a = r.tMin, b = r.tMax;
        for (int i = 0; i < 3; ++i) {
            const double inv = 1.0 / r.d[i];
            double tn = (lo[i] - r.o[i]) * inv, tf = (hi[i] - r.o[i]) * inv;
            if (tn > tf) std::swap(tn, tf);
            a = std::max(a, tn);
            b = std::min(b, tf);
            if (a > b) return false;
        }
        *t0 = a;
        *t1 = b;
        return true;
    }
};

}  // namespace littoral
