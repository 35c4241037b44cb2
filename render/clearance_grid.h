#pragma once
// A coarse grid over the scene's bounds that answers, in constant time, "can this segment touch
// any triangle?" for the short rays of scattering media (a photon's free flight, a path vertex's
// next segment: about a metre, in open water far from any surface). EmbreeScene asks it before
// tracing a ray of finite length and skips Embree when the answer is no.
//
// Each cell stores its clearance: the Chebyshev distance, in cells and capped at kMaxClearance,
// to the nearest cell that some triangle overlaps (0 for such a cell). A cell counts as overlapped
// when the triangle meets the cell's box grown by a margin (exact separating-axis test, Akenine-
// Moeller 2001), so Embree's single-precision traversal cannot find a hit the grid does not know.
// A segment from a to b, both inside the grid, lies in the box of cells between cell(a) and
// cell(b); if the largest per-axis index difference is smaller than cell(a)'s clearance, every
// one of those cells is empty, so the segment meets no triangle.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "core/bbox.h"

// The grid's size (about this many cells). The rendered-IR fuzzer (fuzz/CMakeLists.txt) builds the
// renderer with 4096: its scenes are tiny, and building 2^18 cells under the sanitizers took a
// fifth of each execution.
#ifndef LITTORAL_CLEARANCE_CELLS
#define LITTORAL_CLEARANCE_CELLS (int64_t{1} << 18)
#endif

namespace littoral::render {

class ClearanceGrid {
public:
    static constexpr int kMaxClearance = 15;

    ClearanceGrid() = default;
    // Covers `bounds` (the scene's, padded slightly) with about targetCells cells; then calls
    // forEachTriangle(mark), where mark(a, b, c) is to be called for every world-space triangle.
    template <class F> void build(const BBox3& bounds, F&& forEachTriangle, int64_t targetCells = LITTORAL_CLEARANCE_CELLS);

    // True only if no triangle can meet the closed segment [a, b]: every cell of the box of cells
    // between cell(a) and cell(b) is within Chebyshev distance d of cell(a), and within e of the
    // midpoint's cell (about half of d); the segment is clear when d is below a's clearance or e
    // below the midpoint cell's.
    bool segmentClear(const Point3& a, const Point3& b) const {
        if (clear_.empty()) return false;
        int ia[3], ib[3], im[3];
        if (!cellOf(a, ia) || !cellOf(b, ib)) return false;
        int d = 0;
        for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(ia[k] - ib[k]));
        if (d < clear_[index(ia)]) return true;
        if (d == 0 || !cellOf((a + b) * 0.5, im)) return false;
        int e = 0;
        for (int k = 0; k < 3; ++k)
            e = std::max({e, im[k] - std::min(ia[k], ib[k]), std::max(ia[k], ib[k]) - im[k]});
        return e < clear_[index(im)];
    }

    bool built() const { return !clear_.empty(); }
    int cells(int axis) const { return n_[axis]; }
    // Clearance of a cell (for tests and statistics).
    int clearance(int ix, int iy, int iz) const { const int i[3] = {ix, iy, iz}; return clear_[index(i)]; }

private:
    void init(const BBox3& bounds, int64_t targetCells);
    void mark(const Point3& a, const Point3& b, const Point3& c);
    void finish();  // occupancy -> clearance (separable Chebyshev distance transform)
    bool cellOf(const Point3& p, int* i) const {
        for (int k = 0; k < 3; ++k) {
            const double u = (p[k] - lo_[k]) * inv_[k];
            if (!(u >= 0 && u < n_[k])) return false;  // outside, or NaN
            i[k] = static_cast<int>(u);
        }
        return true;
    }
    size_t index(const int* i) const {
        return (static_cast<size_t>(i[2]) * static_cast<size_t>(n_[1]) + static_cast<size_t>(i[1])) * static_cast<size_t>(n_[0]) +
               static_cast<size_t>(i[0]);
    }

    Point3 lo_;
    double h_[3] = {0, 0, 0}, inv_[3] = {0, 0, 0};
    int n_[3] = {0, 0, 0};
    double margin_ = 0;
    std::vector<uint8_t> clear_;
};

template <class F> void ClearanceGrid::build(const BBox3& bounds, F&& forEachTriangle, int64_t targetCells) {
    clear_.clear();
    // No grid (every query answered by Embree) for an empty scene or non-finite bounds.
    if (bounds.empty() || !std::isfinite(bounds.lo.x + bounds.lo.y + bounds.lo.z + bounds.hi.x + bounds.hi.y + bounds.hi.z))
        return;
    init(bounds, targetCells);
    forEachTriangle([this](const Point3& a, const Point3& b, const Point3& c) { mark(a, b, c); });
    finish();
}

}  // namespace littoral::render
