#include "render/clearance_grid.h"

#include <algorithm>
#include <cmath>

namespace littoral::render {

namespace {

// Separating-axis test of a triangle against an axis-aligned box (centre c, half-sizes e): the
// box's three axes, the triangle's normal and the nine edge-axis cross products (Akenine-Moeller,
// "Fast 3D triangle-box overlap testing", 2001). A degenerate axis (zero vector) never separates.
bool triangleMeetsBox(const Point3& c, const Vec3& e, const Point3& p0, const Point3& p1, const Point3& p2) {
    const Vec3 v[3] = {p0 - c, p1 - c, p2 - c};
    auto separates = [&](const Vec3& ax) {
        const double d0 = dot(v[0], ax), d1 = dot(v[1], ax), d2 = dot(v[2], ax);
        const double r = e.x * std::abs(ax.x) + e.y * std::abs(ax.y) + e.z * std::abs(ax.z);
        return std::min({d0, d1, d2}) > r || std::max({d0, d1, d2}) < -r;
    };
    const Vec3 edges[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
    const Vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const Vec3& a : axes)
        if (separates(a)) return false;
    if (separates(cross(edges[0], edges[1]))) return false;
    for (const Vec3& ed : edges)
        for (const Vec3& a : axes)
            if (separates(cross(ed, a))) return false;
    return true;
}

}  // namespace

void ClearanceGrid::init(const BBox3& bounds, int64_t targetCells) {
    const Vec3 ext0 = bounds.extent();
    const double diag = std::max(length(ext0), 1e-3);
    const double pad = 1e-2 * diag;
    lo_ = bounds.lo - Vec3{pad, pad, pad};
    const Vec3 ext = ext0 + Vec3{2 * pad, 2 * pad, 2 * pad};
    const double h = std::cbrt(ext.x * ext.y * ext.z / static_cast<double>(std::max<int64_t>(targetCells, 1)));
    for (int k = 0; k < 3; ++k) {
        n_[k] = static_cast<int>(std::clamp(std::lround(ext[k] / h), 1L, 1024L));
        h_[k] = ext[k] / n_[k];
        inv_[k] = 1.0 / h_[k];
    }
    // Embree traverses in single precision (about 6e-8 relative of the coordinates) and the
    // reconstruction offsets hit points by 2^-18 of them (render/embree_scene.h); a margin far above
    // both keeps every triangle Embree could report inside the cells it is marked in.
    const double scale = std::max({1.0, std::abs(bounds.lo.x), std::abs(bounds.lo.y), std::abs(bounds.lo.z),
                                   std::abs(bounds.hi.x), std::abs(bounds.hi.y), std::abs(bounds.hi.z)});
    margin_ = 1e-3 * std::min({h_[0], h_[1], h_[2]}) + 1e-5 * scale;
    clear_.assign(static_cast<size_t>(n_[0]) * n_[1] * n_[2], 0);  // 0 = empty while marking
}

void ClearanceGrid::mark(const Point3& a, const Point3& b, const Point3& c) {
    int i0[3], i1[3];
    for (int k = 0; k < 3; ++k) {
        const double lo = std::min({a[k], b[k], c[k]}) - margin_, hi = std::max({a[k], b[k], c[k]}) + margin_;
        if (!std::isfinite(lo) || !std::isfinite(hi)) return;  // Embree cannot hit such a triangle either
        i0[k] = static_cast<int>(std::clamp(std::floor((lo - lo_[k]) * inv_[k]), 0.0, n_[k] - 1.0));
        i1[k] = static_cast<int>(std::clamp(std::floor((hi - lo_[k]) * inv_[k]), 0.0, n_[k] - 1.0));
    }
    const Vec3 half{0.5 * h_[0] + margin_, 0.5 * h_[1] + margin_, 0.5 * h_[2] + margin_};
    for (int z = i0[2]; z <= i1[2]; ++z)
        for (int y = i0[1]; y <= i1[1]; ++y)
            for (int x = i0[0]; x <= i1[0]; ++x) {
                const int i[3] = {x, y, z};
                uint8_t& cell = clear_[index(i)];
                if (cell) continue;
                const Point3 centre{lo_.x + (x + 0.5) * h_[0], lo_.y + (y + 0.5) * h_[1], lo_.z + (z + 0.5) * h_[2]};
                if (triangleMeetsBox(centre, half, a, b, c)) cell = 1;
            }
}

void ClearanceGrid::finish() {
    // D(c) = min over occupied o of max_k |c_k - o_k|, capped at K, axis by axis: the distance
    // along x within each row, then f(y) = min_y' max(|y - y'|, f_x(y')) (only |y - y'| <= K can
    // matter once capped), then the same along z.
    constexpr int K = kMaxClearance;
    const int nx = n_[0], ny = n_[1], nz = n_[2];
    std::vector<uint8_t> d(clear_.size()), tmp(clear_.size());
    auto at = [&](int x, int y, int z) { return (static_cast<size_t>(z) * ny + y) * nx + x; };
    for (int z = 0; z < nz; ++z)
        for (int y = 0; y < ny; ++y) {
            int run = K;
            for (int x = 0; x < nx; ++x) {
                run = clear_[at(x, y, z)] ? 0 : std::min(K, run + 1);
                d[at(x, y, z)] = static_cast<uint8_t>(run);
            }
            run = K;
            for (int x = nx - 1; x >= 0; --x) {
                run = clear_[at(x, y, z)] ? 0 : std::min(K, run + 1);
                d[at(x, y, z)] = static_cast<uint8_t>(std::min<int>(d[at(x, y, z)], run));
            }
        }
    // f(c) = min over |dd| < f_in(c) of max(|dd|, f_in(c + dd along the axis)): an offset of dd or
    // more cannot lower the value below dd.
    auto along = [&](const std::vector<uint8_t>& in, std::vector<uint8_t>& out, int axis) {
        const size_t stride = axis == 1 ? static_cast<size_t>(nx) : static_cast<size_t>(nx) * ny;
        for (int z = 0; z < nz; ++z)
            for (int y = 0; y < ny; ++y)
                for (int x = 0; x < nx; ++x) {
                    const size_t i = at(x, y, z);
                    const int c = axis == 1 ? y : z;
                    int best = in[i];
                    for (int dd = 1; dd < best; ++dd) {
                        if (c - dd >= 0) best = std::min(best, std::max<int>(dd, in[i - dd * stride]));
                        if (c + dd < n_[axis]) best = std::min(best, std::max<int>(dd, in[i + dd * stride]));
                    }
                    out[i] = static_cast<uint8_t>(best);
                }
    };
    along(d, tmp, 1);
    along(tmp, d, 2);
    clear_.swap(d);
}

}  // namespace littoral::render
