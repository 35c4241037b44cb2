#pragma once
// Orthonormal frame (s, t, n): converts directions between world and a local space in which
// n is +z. Used for BSDF sampling and for camera bases.
#include "core/vec.h"

namespace littoral {

struct Frame {
    Vec3 s{1, 0, 0}, t{0, 1, 0}, n{0, 0, 1};

    // Duff et al. (2017), "Building an orthonormal basis, revisited": branchless and
    // continuous except at n.z = -1 handled by the sign.
    static Frame fromNormal(const Vec3& nIn) {
        const Vec3 n = normalize(nIn);
        const double sign = std::copysign(1.0, n.z);
        const double a = -1.0 / (sign + n.z);
        const double b = n.x * n.y * a;
        Frame f;
        f.s = {1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x};
        f.t = {b, sign + n.y * n.y * a, -n.y};
        f.n = n;
        return f;
    }
    // Frame whose n is `n` and whose s lies as close as possible to `hintS` (e.g. a wind direction).
    static Frame fromNormalAndTangent(const Vec3& nIn, const Vec3& hintS) {
        Frame f;
        f.n = normalize(nIn);
        f.s = normalize(hintS - dot(hintS, f.n) * f.n);
        f.t = cross(f.n, f.s);
        return f;
    }
    Vec3 toLocal(const Vec3& v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
    Vec3 toWorld(const Vec3& v) const { return s * v.x + t * v.y + n * v.z; }
};

}  // namespace littoral
