// Terrain meshing and the volume of water above a height-field mesh.
#include "bathymetry/terrain.h"

#include <array>
#include <cmath>

#include <fmt/format.h>

#include "core/error.h"

namespace littoral::bathymetry {

namespace {

// Cell count along one axis: ceil(length / spacing), but a ratio that is an integer up to
// round-off (90 / 0.3 = 300.00000000000006) must not gain a sliver cell.
long cellCount(double length, double spacing) {
    const double r = length / spacing;
    const double n = std::ceil(r - 1e-9 * std::max(1.0, r));
    return std::max(1L, static_cast<long>(n));
}

}  // namespace

TriMesh terrainMesh(const Terrain& t, const Extent& e, double spacing) {
    if (!(std::isfinite(e.x0) && std::isfinite(e.x1) && std::isfinite(e.y0) && std::isfinite(e.y1)) || !e.valid())
        throw InputError(fmt::format("terrain mesh: extent [{}, {}] x [{}, {}] m is empty or not finite; "
                                     "need x0 < x1 and y0 < y1", e.x0, e.x1, e.y0, e.y1));
    if (!(spacing > 0) || !std::isfinite(spacing))
        throw InputError(fmt::format("terrain mesh: spacing {} m must be a positive finite number", spacing));
    const long nx = cellCount(e.width(), spacing), ny = cellCount(e.height(), spacing);
    const double vertices = double(nx + 1) * double(ny + 1);
    if (vertices > 50e6)
        throw InputError(fmt::format("terrain mesh: spacing {} m over {} x {} m gives {:.0f} vertices; "
                                     "the limit is 50 million, use a coarser spacing", spacing, e.width(),
                                     e.height(), vertices));
    TriMesh m;
    m.positions.reserve(size_t(vertices));
    m.triangles.reserve(size_t(2 * nx * ny));
    const double dx = e.width() / double(nx), dy = e.height() / double(ny);
    for (long j = 0; j <= ny; ++j) {
        // The last row and column are set to the extent edge exactly, not accumulated.
        const double y = j == ny ? e.y1 : e.y0 + double(j) * dy;
        for (long i = 0; i <= nx; ++i) {
            const double x = i == nx ? e.x1 : e.x0 + double(i) * dx;
            const double z = t.elevation(x, y);
            if (!std::isfinite(z))
                throw InputError(fmt::format("terrain mesh: {} gives a non-finite elevation at x = {} m, y = {} m",
                                             t.describe(), x, y));
            m.positions.push_back({x, y, z});
        }
    }
    const auto index = [nx](long i, long j) { return static_cast<uint32_t>(j * (nx + 1) + i); };
    for (long j = 0; j < ny; ++j)
        for (long i = 0; i < nx; ++i) {
            const uint32_t a = index(i, j), b = index(i + 1, j), c = index(i + 1, j + 1), d = index(i, j + 1);
            // x east, y north: a -> b -> c turns left, i.e. counter-clockwise seen from +z.
            m.triangles.push_back({a, b, c});
            m.triangles.push_back({a, c, d});
        }
    return m;
}

double volumeBelow(const TriMesh& mesh, double level) {
    // For each triangle, clip its plan-view projection to the part where the depth
    // d = level - z >= 0 (d is linear over the triangle), then integrate d exactly:
    // over a triangle, Int d dA = area * (d0 + d1 + d2) / 3. The clipped polygon has at most
    // four vertices and is fanned into triangles. Signed plan areas make clockwise faces negative.
    double total = 0;
    for (size_t f = 0; f < mesh.numTriangles(); ++f) {
        const auto& tri = mesh.triangles[f];
        std::array<Point3, 3> p{mesh.positions[tri[0]], mesh.positions[tri[1]], mesh.positions[tri[2]]};
        std::array<double, 3> d{level - p[0].z, level - p[1].z, level - p[2].z};
        std::array<Vec3, 4> poly;  // (x, y, depth)
        int n = 0;
        for (int k = 0; k < 3; ++k) {
            const int k1 = (k + 1) % 3;
            if (d[k] >= 0) poly[n++] = {p[k].x, p[k].y, d[k]};
            if ((d[k] >= 0) != (d[k1] >= 0)) {
                const double s = d[k] / (d[k] - d[k1]);  // depth crosses zero here
                poly[n++] = {p[k].x + s * (p[k1].x - p[k].x), p[k].y + s * (p[k1].y - p[k].y), 0.0};
            }
        }
        for (int k = 1; k + 1 < n; ++k) {
            const Vec3 &a = poly[0], &b = poly[k], &c = poly[k + 1];
            const double area2 = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);  // 2 * signed area
            total += area2 * (a.z + b.z + c.z) / 6.0;
        }
    }
    return total;
}

}  // namespace littoral::bathymetry
