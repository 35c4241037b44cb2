#pragma once
// Independent analytic ray caster for the refraction checkerboard test (seed-ch01-04.md §4.5,
// dissertation Sec. 4.3, flowchart Fig. 4.24).
//
// Deliberately self-contained: plain doubles and its own 3-vector, Snell's law and slab
// intersection written here, nothing from render/ (no Embree, no BSDF code) and not even
// core/vec.h's refract(), so that a bug in the renderer's geometry cannot hide in both.
//
// Scene:
//   * ground plane z = 0, checks of side `checkSize` (0.3 m): colour of (x, y) is
//     (floor(x/s) + floor(y/s)) mod 2 taken as "non-zero -> 1" (dissertation Eq. 4.9/4.10:
//     fmod(-1, 2) = -1 counts as 1, i.e. plain parity);
//   * optional water box [x0, x1] x [y0, y1] x [0, depth], index n (1.34), standing on the ground;
//   * air (n = 1) elsewhere.
// Camera: pinhole at `camera`, looking along `forward` with up hint `up`, using the convention
// shared with render-core:
//   right = normalize(cross(forward, up)), upOrtho = cross(right, forward),
//   d(i, j) = normalize(f forward + ((i + 0.5) - W/2) p right - ((j + 0.5) - H/2) p upOrtho),
// i = column, j = row from the top. (i + 0.5) generalises to (i + u) for sub-pixel offsets u.
//
// Ray fates (Fig. 4.23): rays that miss the box land on the ground; rays through the top face
// refract (Snell, eta = 1/n) and then (a) reach the ground, (b) meet a vertical wall at more than
// the critical angle asin(1/n) = 48.27 deg and are totally internally reflected (the horizontal
// component normal to the wall flips; repeated as often as needed), or (c) refract out through a
// wall (eta = n) and continue in air to the ground. Rays from outside may also enter through a
// vertical wall. Exactly at the critical angle the transmitted ray would graze the wall; we treat
// sin(theta_t) >= 1 as TIR (a set of measure zero that no pixel centre hits in practice).
// Fresnel-reflected branches are not followed: the test compares binarised check colours, and
// the reflected part (2% at normal incidence) cannot flip a binarised pixel.
#include <algorithm>
#include <cmath>
#include <limits>

namespace littoral::testref {

struct RefVec {
    double x = 0, y = 0, z = 0;
};
inline RefVec operator+(RefVec a, RefVec b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline RefVec operator-(RefVec a, RefVec b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline RefVec operator*(double s, RefVec a) { return {s * a.x, s * a.y, s * a.z}; }
inline double refDot(RefVec a, RefVec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline RefVec refCross(RefVec a, RefVec b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline RefVec refNormalize(RefVec a) { return (1.0 / std::sqrt(refDot(a, a))) * a; }

struct CheckerboardSetup {
    // Camera (metres). Default: nadir view with image "up" toward +y (north), so column i grows
    // toward +x and row j grows toward -y.
    RefVec camera{0.0, 0.0, 20.0};
    RefVec forward{0.0, 0.0, -1.0};
    RefVec up{0.0, 1.0, 0.0};
    int width = 400, height = 400;   // pixels
    double focalLength = 0.035;      // m
    double pixelPitch = 20e-6;       // m
    // Water box.
    bool hasWater = true;
    double x0 = -5.0, x1 = 5.0, y0 = -5.0, y1 = 5.0;  // m
    double depth = 4.9;                               // m (box top at z = depth)
    double n = 1.34;                                  // seed-ch01-04.md §4.0
    // Ground.
    double checkSize = 0.3;  // m
    int maxEvents = 64;      // wall interactions before giving up (deep, narrow boxes)
};

enum class RayFate {
    Ground,            // missed the box entirely
    TopThenGround,     // (a)
    TopTirThenGround,  // (b) one or more TIR at the walls
    TopExitThenGround, // (c) refracted out through a wall (possibly after TIRs)
    WallEntry,         // entered through a vertical wall from outside
    Sky,               // never reached the ground (looked up, or left through the top)
};

struct CheckerboardTrace {
    int colour = -1;                 // 0 / 1 check colour at the landing point, -1 = sky
    double landX = 0, landY = 0;     // landing point on z = 0
    double edgeDistance = std::numeric_limits<double>::infinity();  // landing point to nearest check edge, m
    // Smallest distance from any interface crossing (top face or wall) to the boundary of the
    // face it crossed, m: a small value means a nearby ray takes another path (a box-edge pixel).
    double boxEdgeDistance = std::numeric_limits<double>::infinity();
    int tirCount = 0;     // total internal reflections at walls
    int wallExits = 0;    // refractions out through a wall
    RayFate fate = RayFate::Sky;
};

// Check colour of a ground point (Eq. 4.9): parity of floor(x/s) + floor(y/s).
inline int checkColour(double x, double y, double s) {
    const long long k = static_cast<long long>(std::floor(x / s)) + static_cast<long long>(std::floor(y / s));
    return (k % 2 != 0) ? 1 : 0;
}

// Distance from (x, y) to the nearest check edge line (x = k s or y = k s), m.
inline double checkEdgeDistance(double x, double y, double s) {
    auto d1 = [s](double v) {
        const double r = v / s - std::floor(v / s);  // in [0, 1)
        return std::min(r, 1.0 - r) * s;
    };
    return std::min(d1(x), d1(y));
}

// Snell refraction of unit direction d at a surface with unit normal nrm facing the incoming ray
// (dot(d, nrm) < 0), eta = n_incident / n_transmitted. Returns false on total internal reflection.
inline bool refSnell(RefVec d, RefVec nrm, double eta, RefVec* t) {
    const double cosI = -refDot(d, nrm);
    const double sin2T = eta * eta * (1.0 - cosI * cosI);
    if (sin2T >= 1.0) return false;
    const double cosT = std::sqrt(1.0 - sin2T);
    *t = refNormalize(eta * d + (eta * cosI - cosT) * nrm);
    return true;
}

// Pixel ray direction for image position (i + u, j + v), u, v in [0, 1] (0.5 = pixel centre).
inline RefVec pixelDirection(const CheckerboardSetup& s, double iu, double jv) {
    const RefVec f = refNormalize(s.forward);
    const RefVec right = refNormalize(refCross(f, s.up));
    const RefVec upOrtho = refCross(right, f);
    return refNormalize(s.focalLength * f + ((iu - s.width / 2.0) * s.pixelPitch) * right -
                        ((jv - s.height / 2.0) * s.pixelPitch) * upOrtho);
}

// Traces one ray from `o` along unit `d` through the scene.
inline CheckerboardTrace traceCheckerboardRay(const CheckerboardSetup& s, RefVec o, RefVec d) {
    CheckerboardTrace r;
    const double inf = std::numeric_limits<double>::infinity();
    const double eps = 1e-12;  // m, to step off a face just crossed (box sizes are 0.1-100 m)
    bool inWater = false;
    bool enteredTop = false, enteredWall = false;
    auto faceEdgeDistance = [&](int axis, RefVec p) {
        // In-plane distance from p to the border of the face perpendicular to `axis`.
        const double dx = std::min(p.x - s.x0, s.x1 - p.x), dy = std::min(p.y - s.y0, s.y1 - p.y);
        const double dz = std::min(p.z, s.depth - p.z);
        if (axis == 0) return std::min(dy, dz);
        if (axis == 1) return std::min(dx, dz);
        return std::min(dx, dy);
    };
    auto land = [&](RefVec p) {
        r.landX = p.x;
        r.landY = p.y;
        r.colour = checkColour(p.x, p.y, s.checkSize);
        r.edgeDistance = checkEdgeDistance(p.x, p.y, s.checkSize);
        if (!enteredTop && !enteredWall) r.fate = RayFate::Ground;
        else if (enteredWall) r.fate = RayFate::WallEntry;
        else if (r.wallExits > 0) r.fate = RayFate::TopExitThenGround;
        else if (r.tirCount > 0) r.fate = RayFate::TopTirThenGround;
        else r.fate = RayFate::TopThenGround;
        return r;
    };
    for (int event = 0; event <= s.maxEvents; ++event) {
        if (!inWater) {
            // Air: the ground (z = 0) or the box, whichever comes first.
            const double tGround = d.z < 0 ? -o.z / d.z : inf;
            double tBox = inf;
            int axis = -1;
            RefVec nrm;
            if (s.hasWater) {
                // Slab method for the entry point into [x0,x1] x [y0,y1] x [0,depth].
                double tNear = -inf, tFar = inf;
                int nearAxis = -1;
                double nearSign = 0;
                const double lo[3] = {s.x0, s.y0, 0.0}, hi[3] = {s.x1, s.y1, s.depth};
                const double oo[3] = {o.x, o.y, o.z}, dd[3] = {d.x, d.y, d.z};
                bool miss = false;
                for (int a = 0; a < 3; ++a) {
                    if (dd[a] == 0.0) {
                        if (oo[a] < lo[a] || oo[a] > hi[a]) miss = true;
                        continue;
                    }
                    double t0 = (lo[a] - oo[a]) / dd[a], t1 = (hi[a] - oo[a]) / dd[a];
                    double sign = -1.0;  // entering through the low face: outward normal -axis
                    if (t0 > t1) { std::swap(t0, t1); sign = 1.0; }
                    if (t0 > tNear) { tNear = t0; nearAxis = a; nearSign = sign; }
                    tFar = std::min(tFar, t1);
                }
                if (!miss && tNear <= tFar && tNear > eps && nearAxis >= 0) {
                    tBox = tNear;
                    axis = nearAxis;
                    nrm = {axis == 0 ? nearSign : 0.0, axis == 1 ? nearSign : 0.0, axis == 2 ? nearSign : 0.0};
                }
            }
            if (tGround <= tBox) {
                if (tGround == inf) return r;  // sky
                return land(o + tGround * d);
            }
            const RefVec p = o + tBox * d;
            if (axis == 2 && nrm.z < 0) return land(p);  // box bottom is the ground itself
            r.boxEdgeDistance = std::min(r.boxEdgeDistance, faceEdgeDistance(axis, p));
            RefVec t;
            refSnell(d, nrm, 1.0 / s.n, &t);  // air -> water never totally reflects
            if (axis == 2) enteredTop = true;
            else enteredWall = true;
            o = p;
            d = t;
            inWater = true;
            continue;
        }
        // Water: leave through the ground, the top or a wall, whichever comes first.
        double tExit = inf;
        int axis = -1;
        RefVec nrm;
        const double lo[3] = {s.x0, s.y0, 0.0}, hi[3] = {s.x1, s.y1, s.depth};
        const double oo[3] = {o.x, o.y, o.z}, dd[3] = {d.x, d.y, d.z};
        for (int a = 0; a < 3; ++a) {
            if (dd[a] == 0.0) continue;
            const double t = dd[a] > 0 ? (hi[a] - oo[a]) / dd[a] : (lo[a] - oo[a]) / dd[a];
            if (t > eps && t < tExit) {
                tExit = t;
                axis = a;
                const double sgn = dd[a] > 0 ? 1.0 : -1.0;
                nrm = {a == 0 ? sgn : 0.0, a == 1 ? sgn : 0.0, a == 2 ? sgn : 0.0};  // outward
            }
        }
        if (axis < 0) return r;  // cannot happen for a unit direction
        const RefVec p = o + tExit * d;
        if (axis == 2 && nrm.z < 0) return land(p);  // reached the ground inside the box
        r.boxEdgeDistance = std::min(r.boxEdgeDistance, faceEdgeDistance(axis, p));
        RefVec t;
        const RefVec inward = -1.0 * nrm;  // faces the incoming ray
        if (refSnell(d, inward, s.n, &t)) {
            // Refracted out into air; a ray leaving a convex box never re-enters it.
            if (axis != 2) ++r.wallExits;
            o = p;
            d = t;
            inWater = false;
            if (d.z >= 0) return r;  // left through the top, or horizontal: sky
            const double tGround = -o.z / d.z;
            return land(o + tGround * d);
        }
        // Total internal reflection: mirror the component along the face normal.
        if (axis != 2) ++r.tirCount;
        const double dn = refDot(d, nrm);
        d = d - (2.0 * dn) * nrm;
        o = p;
    }
    return r;  // too many events: reported as sky (colour -1)
}

// The trace of pixel (i, j) through its centre.
inline CheckerboardTrace traceCheckerboardPixel(const CheckerboardSetup& s, int i, int j) {
    return traceCheckerboardRay(s, s.camera, pixelDirection(s, i + 0.5, j + 0.5));
}

// The interface asked for by render-core: colour of pixel (i, j) (0/1, -1 = sky) and, if
// edgeDistance is given, the smaller of the landing point's distance to a check edge and the
// distance of any interface crossing to a box edge (m).
inline int checkerboardReference(const CheckerboardSetup& s, int i, int j, double* edgeDistance) {
    const CheckerboardTrace t = traceCheckerboardPixel(s, i, j);
    if (edgeDistance) *edgeDistance = std::min(t.edgeDistance, t.boxEdgeDistance);
    return t.colour;
}

// Whether the pixel's footprint is all one colour: traces an n x n grid of rays spread over the
// pixel (offsets (k + 0.5) / n) plus its four corners; true if they all land on the same colour.
// Pixels for which this is false straddle a check edge (or a box edge) and may legitimately
// differ from a renderer that samples the pixel differently.
inline bool checkerboardPixelUniform(const CheckerboardSetup& s, int i, int j, int n = 4) {
    const int c0 = traceCheckerboardPixel(s, i, j).colour;
    auto same = [&](double u, double v) {
        return traceCheckerboardRay(s, s.camera, pixelDirection(s, i + u, j + v)).colour == c0;
    };
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b)
            if (!same((a + 0.5) / n, (b + 0.5) / n)) return false;
    return same(0, 0) && same(1, 0) && same(0, 1) && same(1, 1);
}

}  // namespace littoral::testref
