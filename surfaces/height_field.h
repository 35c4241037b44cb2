#pragma once
// A regular height field z(x, y) over the rectangle [x0, x1] x [y0, y1] (metres; z = 0 is the
// mean water level, z up). Samples sit on the (nx x ny) vertices of the grid, the first and last
// ones exactly on the rectangle's edges. Row-major: z[j * nx + i] is the height at (x(i), y(j)).
//
// A field synthesised by FFT is periodic: its last column equals its first and its last row
// equals its first (the wrap-around sample), so the rectangle is covered exactly and the
// surface tiles seamlessly. `periodic` records this so statistics do not count the duplicate
// samples twice.
#include <cstddef>
#include <vector>

namespace littoral::surfaces {

struct HeightField {
    int nx = 0, ny = 0;           // vertices along x and y (>= 2)
    double x0 = 0, y0 = 0;        // lower-left corner, m
    double x1 = 0, y1 = 0;        // upper-right corner, m
    bool periodic = false;        // last column/row duplicate the first
    std::vector<double> z;        // m

    double dx() const { return (x1 - x0) / (nx - 1); }
    double dy() const { return (y1 - y0) / (ny - 1); }
    // Vertex coordinates; the last index returns the edge coordinate exactly (no rounding drift).
    double x(int i) const { return i == nx - 1 ? x1 : x0 + i * dx(); }
    double y(int j) const { return j == ny - 1 ? y1 : y0 + j * dy(); }
    double& at(int i, int j) { return z[static_cast<size_t>(j) * nx + i]; }
    double at(int i, int j) const { return z[static_cast<size_t>(j) * nx + i]; }
    size_t size() const { return z.size(); }

    // Bilinear interpolation of the samples at (x, y); points outside the rectangle are
    // clamped to its edge. Cheap (O(1)): use it to place floating objects on the surface.
    double sample(double x, double y) const;
};

// Allocates an (nx x ny) field of zeros over the rectangle.
HeightField makeHeightField(int nx, int ny, double x0, double y0, double x1, double y1);

}  // namespace littoral::surfaces
