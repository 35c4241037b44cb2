#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/rng.h"
#include "render/clearance_grid.h"

using namespace littoral;
using namespace littoral::render;

namespace {

using Tri = std::array<Point3, 3>;

// Squared distance from point p to triangle (a, b, c), by the closest-point regions (Ericson,
// Real-Time Collision Detection, 5.1.5): written separately from the grid's separating-axis test.
double pointTriangleDistance2(const Point3& p, const Point3& a, const Point3& b, const Point3& c) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return lengthSquared(p - a);
    const Vec3 bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return lengthSquared(p - b);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return lengthSquared(p - (a + ab * (d1 / (d1 - d3))));
    const Vec3 cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return lengthSquared(p - c);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return lengthSquared(p - (a + ac * (d2 / (d2 - d6))));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return lengthSquared(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
    const double den = 1.0 / (va + vb + vc);
    return lengthSquared(p - (a + ab * (vb * den) + ac * (vc * den)));
}

// Smallest distance between segment [p, q] and the triangle, by dense sampling of the segment
// refined around the best sample (ample for the assertion below, which needs only "> 0").
double segmentTriangleDistance(const Point3& p, const Point3& q, const Tri& t) {
    const int n = 64;
    double best = 1e300;
    int bi = 0;
    for (int i = 0; i <= n; ++i) {
        const double d = pointTriangleDistance2(p + (q - p) * (double(i) / n), t[0], t[1], t[2]);
        if (d < best) best = d, bi = i;
    }
    double lo = std::max(0.0, (bi - 1.0) / n), hi = std::min(1.0, (bi + 1.0) / n);
    for (int it = 0; it < 100; ++it) {  // ternary search: the distance is convex along the segment
        const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
        const double f1 = pointTriangleDistance2(p + (q - p) * m1, t[0], t[1], t[2]);
        const double f2 = pointTriangleDistance2(p + (q - p) * m2, t[0], t[1], t[2]);
        (f1 < f2 ? hi : lo) = f1 < f2 ? m2 : m1;
    }
    best = std::min(best, pointTriangleDistance2(p + (q - p) * lo, t[0], t[1], t[2]));
    return std::sqrt(best);
}

std::vector<Tri> randomTriangles() {
    std::vector<Tri> tris;
    RandomStream r(3, 0, 0);
    auto pt = [&](double s) { return Point3{s * r.uniform(), s * r.uniform(), s * r.uniform()}; };
    for (int i = 0; i < 40; ++i) {  // small triangles anywhere in [0, 10]^3
        const Point3 c = pt(10.0);
        tris.push_back({c, c + (pt(1.0) - Point3{0.5, 0.5, 0.5}), c + (pt(1.0) - Point3{0.5, 0.5, 0.5})});
    }
    // Two large sloping triangles (a seabed) and a vertical one (a wall).
    tris.push_back({Point3{0, 0, 1}, Point3{10, 0, 3}, Point3{0, 10, 2}});
    tris.push_back({Point3{10, 0, 3}, Point3{10, 10, 4}, Point3{0, 10, 2}});
    tris.push_back({Point3{10, 0, 0}, Point3{10, 10, 0}, Point3{10, 0, 10}});
    return tris;
}

ClearanceGrid gridOver(const std::vector<Tri>& tris, int64_t cells) {
    BBox3 box;
    for (const Tri& t : tris)
        for (const Point3& p : t) box.expand(p);
    ClearanceGrid g;
    g.build(box, [&](auto&& mark) { for (const Tri& t : tris) mark(t[0], t[1], t[2]); }, cells);
    return g;
}

}  // namespace

// A segment the grid calls clear must keep a positive distance from every triangle (checked by a
// separately written point-triangle distance), and the grid must call a good share of short
// segments in open space clear (it must do something).
TEST(ClearanceGrid, ClearSegmentsMissEveryTriangle) {
    const std::vector<Tri> tris = randomTriangles();
    const ClearanceGrid g = gridOver(tris, 20000);
    ASSERT_TRUE(g.built());
    int clear = 0, total = 0;
    double closest = 1e300;
    for (int k = 0; k < 20000; ++k) {
        RandomStream r(4, 0, k);
        const Point3 a{10 * r.uniform(), 10 * r.uniform(), 10 * r.uniform()};
        const double z = 2 * r.uniform() - 1, ph = 2 * M_PI * r.uniform(), s = std::sqrt(1 - z * z);
        const double len = -0.5 * std::log(1 - r.uniform());  // mean 0.5 m, a few cells
        const Point3 b = a + Vec3{s * std::cos(ph), s * std::sin(ph), z} * len;
        ++total;
        if (!g.segmentClear(a, b)) continue;
        ++clear;
        for (const Tri& t : tris) closest = std::min(closest, segmentTriangleDistance(a, b, t));
    }
    EXPECT_GT(closest, 0.0);
    std::printf("%d of %d segments clear; closest approach of a clear segment %.3g m\n", clear, total, closest);
    // Cells about 0.37 m; 43 triangles mark a minority of them: well over a third of the short
    // segments should be clear (0.74 when written; a broken transform gives 0).
    EXPECT_GT(clear, total / 3) << clear << " of " << total;
}

// The clearance of every cell, against brute force over all cells: the Chebyshev distance to the
// nearest occupied cell (occupied = clearance 0), capped.
TEST(ClearanceGrid, ClearanceIsTheCappedChebyshevDistance) {
    const std::vector<Tri> tris = randomTriangles();
    const ClearanceGrid g = gridOver(tris, 30000);
    const int nx = g.cells(0), ny = g.cells(1), nz = g.cells(2);
    std::vector<std::array<int, 3>> occupied;
    for (int z = 0; z < nz; ++z)
        for (int y = 0; y < ny; ++y)
            for (int x = 0; x < nx; ++x)
                if (g.clearance(x, y, z) == 0) occupied.push_back({x, y, z});
    ASSERT_GT(occupied.size(), 100u);
    int mismatches = 0, deep = 0;
    for (int z = 0; z < nz; ++z)
        for (int y = 0; y < ny; ++y)
            for (int x = 0; x < nx; ++x) {
                int d = ClearanceGrid::kMaxClearance;
                for (const auto& o : occupied)
                    d = std::min(d, std::max({std::abs(x - o[0]), std::abs(y - o[1]), std::abs(z - o[2])}));
                mismatches += d != g.clearance(x, y, z);
                deep += d >= 3;
            }
    EXPECT_EQ(mismatches, 0);
    EXPECT_GT(deep, 100);  // the case exercises distances beyond the first layers
}
