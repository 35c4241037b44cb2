// Triangulated irregular network (TIN) terrain: constrained 2D Delaunay triangulation of points
// carrying elevations, with linear (barycentric) interpolation inside each triangle.
// This is the only bathymetry translation unit that includes CGAL (compile time, see design.md).
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <unordered_map>

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Projection_traits_xy_3.h>
#include <fmt/format.h>

#include "bathymetry/tin_build.h"
#include "core/error.h"
#include "core/log.h"

namespace littoral::bathymetry {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
// Predicates on (x, y) only; the z of every vertex rides along as its elevation.
using Traits = CGAL::Projection_traits_xy_3<Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<CGAL::Triangulation_vertex_base_2<Traits>,
                                                 CGAL::Constrained_triangulation_face_base_2<Traits>>;
// Crossing constraints would need constructed intersection points (whose elevation is
// ambiguous); this tag makes CGAL throw instead, which we report as an input error.
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Traits, Tds,
                                                       CGAL::No_constraint_intersection_requiring_constructions_tag>;
using CPoint = Kernel::Point_3;

struct Segment {
    Point3 a, b;
};

class TinTerrain final : public Terrain {
public:
    TinTerrain(std::unique_ptr<Cdt> cdt, OutsideHull outside, std::string name)
        : cdt_(std::move(cdt)), outside_(outside), name_(std::move(name)) {
        for (auto v = cdt_->finite_vertices_begin(); v != cdt_->finite_vertices_end(); ++v) {
            const CPoint& p = v->point();
            bounds_.x0 = std::min(bounds_.x0, p.x());
            bounds_.y0 = std::min(bounds_.y0, p.y());
            bounds_.x1 = std::max(bounds_.x1, p.x());
            bounds_.y1 = std::max(bounds_.y1, p.y());
        }
        // Hull boundary: the finite edge of every face incident to the infinite vertex.
        auto fc = cdt_->incident_faces(cdt_->infinite_vertex()), done = fc;
        do {
            const int i = fc->index(cdt_->infinite_vertex());
            const CPoint& a = fc->vertex(Cdt::ccw(i))->point();
            const CPoint& b = fc->vertex(Cdt::cw(i))->point();
            hull_.push_back({{a.x(), a.y(), a.z()}, {b.x(), b.y(), b.z()}});
        } while (++fc != done);
        buildHintGrid();
    }

    double elevation(double x, double y) const override {
        if (!std::isfinite(x) || !std::isfinite(y))
            throw InputError(fmt::format("TIN {}: elevation asked at a non-finite point ({}, {})", name_, x, y));
        Cdt::Locate_type lt;
        int li;
        // locate() walks from a start face; in CGAL 5.5 the walk keeps its random state local, so
        // concurrent queries on the finished triangulation are safe. Starting next to the query
        // (hint grid) keeps the walk to a few triangles instead of O(sqrt n).
        const auto f = cdt_->locate(CPoint(x, y, 0), lt, li, hint(x, y)->face());
        if (lt == Cdt::OUTSIDE_CONVEX_HULL || lt == Cdt::OUTSIDE_AFFINE_HULL || cdt_->is_infinite(f))
            return outsideHull(x, y);
        if (lt == Cdt::VERTEX) return f->vertex(li)->point().z();
        // Barycentric interpolation in the triangle (a, b, c): the weights are the plan areas of
        // the sub-triangles opposite each vertex, divided by the whole (exact for a plane).
        const CPoint &a = f->vertex(0)->point(), &b = f->vertex(1)->point(), &c = f->vertex(2)->point();
        const double area = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
        const double wa = ((b.x() - x) * (c.y() - y) - (c.x() - x) * (b.y() - y)) / area;
        const double wb = ((c.x() - x) * (a.y() - y) - (a.x() - x) * (c.y() - y)) / area;
        const double wc = 1.0 - wa - wb;
        return wa * a.z() + wb * b.z() + wc * c.z();
    }

    Extent extent() const override { return bounds_; }

    std::string describe() const override {
        return fmt::format("TIN {} ({} vertices, {} triangles, {} constrained edges)", name_,
                           cdt_->number_of_vertices(), cdt_->number_of_faces(), constrainedEdges());
    }

private:
    // A uniform grid over the bounding box, about two vertices per cell, each cell holding a vertex
    // inside it or (for empty cells) one from the nearest non-empty cell by grid distance.
    void buildHintGrid() {
        const double n = double(cdt_->number_of_vertices());
        gridN_ = std::clamp(static_cast<int>(std::ceil(std::sqrt(n / 2))), 1, 2048);
        cellW_ = std::max(bounds_.width(), 1e-9) / gridN_;
        cellH_ = std::max(bounds_.height(), 1e-9) / gridN_;
        grid_.assign(size_t(gridN_) * size_t(gridN_), Cdt::Vertex_handle());
        std::vector<int> queue;
        for (auto v = cdt_->finite_vertices_begin(); v != cdt_->finite_vertices_end(); ++v) {
            const int c = cellOf(v->point().x(), v->point().y());
            if (grid_[c] == Cdt::Vertex_handle()) {
                grid_[c] = v;
                queue.push_back(c);
            }
        }
        for (size_t k = 0; k < queue.size(); ++k) {  // breadth-first fill of the empty cells
            const int c = queue[k], i = c % gridN_, j = c / gridN_;
            const int nb[4][2] = {{i - 1, j}, {i + 1, j}, {i, j - 1}, {i, j + 1}};
            for (const auto& q : nb) {
                if (q[0] < 0 || q[0] >= gridN_ || q[1] < 0 || q[1] >= gridN_) continue;
                const int d = q[1] * gridN_ + q[0];
                if (grid_[d] == Cdt::Vertex_handle()) {
                    grid_[d] = grid_[c];
                    queue.push_back(d);
                }
            }
        }
    }
    int cellOf(double x, double y) const {
        const double top = double(gridN_ - 1);
        const int i = static_cast<int>(std::clamp((x - bounds_.x0) / cellW_, 0.0, top));
        const int j = static_cast<int>(std::clamp((y - bounds_.y0) / cellH_, 0.0, top));
        return j * gridN_ + i;
    }
    Cdt::Vertex_handle hint(double x, double y) const { return grid_[cellOf(x, y)]; }

    size_t constrainedEdges() const {
        size_t n = 0;
        for (auto e = cdt_->finite_edges_begin(); e != cdt_->finite_edges_end(); ++e)
            if (cdt_->is_constrained(*e)) ++n;
        return n;
    }

    double outsideHull(double x, double y) const {
        if (outside_ == OutsideHull::Error)
            throw InputError(fmt::format(
                "TIN {}: point ({:.3f}, {:.3f}) m lies outside the convex hull of the soundings (bounding box "
                "[{:.3f}, {:.3f}] x [{:.3f}, {:.3f}] m); shrink the domain or set outside_hull: nearest",
                name_, x, y, bounds_.x0, bounds_.x1, bounds_.y0, bounds_.y1));
        // Nearest point on the hull boundary, elevation linear along that hull edge.
        double best = std::numeric_limits<double>::infinity(), z = 0;
        for (const Segment& s : hull_) {
            const double ex = s.b.x - s.a.x, ey = s.b.y - s.a.y;
            const double len2 = ex * ex + ey * ey;
            const double t = len2 > 0 ? std::clamp(((x - s.a.x) * ex + (y - s.a.y) * ey) / len2, 0.0, 1.0) : 0.0;
            const double px = s.a.x + t * ex, py = s.a.y + t * ey;
            const double d2 = (px - x) * (px - x) + (py - y) * (py - y);
            if (d2 < best) {
                best = d2;
                z = s.a.z + t * (s.b.z - s.a.z);
            }
        }
        return z;
    }

    std::unique_ptr<Cdt> cdt_;
    OutsideHull outside_;
    std::string name_;
    Extent bounds_{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                   -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
    std::vector<Segment> hull_;
    int gridN_ = 1;
    double cellW_ = 1, cellH_ = 1;
    std::vector<Cdt::Vertex_handle> grid_;
};

std::string labelOf(const detail::TinInput& in, size_t i) {
    return i < in.labels.size() && !in.labels[i].empty() ? in.labels[i] : fmt::format("point {}", i + 1);
}

// Merge points closer than `dist` in plan into one at the first point's position and the mean
// elevation. A hash grid of cell size `dist` keeps this O(n).
std::vector<CPoint> mergeClose(const detail::TinInput& in) {
    struct Cluster {
        double x, y, zSum;
        int n;
    };
    std::vector<Cluster> clusters;
    clusters.reserve(in.points.size());
    const double d = in.mergeDistance;
    std::unordered_map<uint64_t, std::vector<size_t>> grid;
    std::map<std::pair<double, double>, size_t> exact;  // used when d == 0
    const auto key = [](int64_t i, int64_t j) { return (uint64_t(i) << 32) ^ (uint64_t(j) & 0xffffffffu); };
    size_t merged = 0;
    std::string example;
    for (size_t k = 0; k < in.points.size(); ++k) {
        const Point3& p = in.points[k];
        long found = -1;
        if (d > 0) {
            const int64_t ci = int64_t(std::floor(p.x / d)), cj = int64_t(std::floor(p.y / d));
            for (int64_t di = -1; di <= 1 && found < 0; ++di)
                for (int64_t dj = -1; dj <= 1 && found < 0; ++dj) {
                    auto it = grid.find(key(ci + di, cj + dj));
                    if (it == grid.end()) continue;
                    for (size_t c : it->second)
                        if (std::hypot(clusters[c].x - p.x, clusters[c].y - p.y) <= d) {
                            found = long(c);
                            break;
                        }
                }
            if (found < 0) grid[key(ci, cj)].push_back(clusters.size());
        } else {
            auto [it, inserted] = exact.try_emplace({p.x, p.y}, clusters.size());
            if (!inserted) found = long(it->second);
        }
        if (found >= 0) {
            clusters[found].zSum += p.z;
            clusters[found].n += 1;
            if (merged++ == 0) example = labelOf(in, k);
        } else {
            clusters.push_back({p.x, p.y, p.z, 1});
        }
    }
    if (merged > 0)
        log::warn("TIN {}: merged {} point(s) lying within {} m of an earlier one (first: {}); each merged vertex "
                  "takes the mean elevation", in.sourceName, merged, d, example);
    std::vector<CPoint> out;
    out.reserve(clusters.size());
    for (const Cluster& c : clusters) out.emplace_back(c.x, c.y, c.zSum / c.n);
    return out;
}

}  // namespace

namespace detail {

std::unique_ptr<Terrain> buildTin(TinInput in) {
    if (in.sourceName.empty()) in.sourceName = "(points)";
    const std::string name = in.sourceName;
    if (!(in.mergeDistance >= 0) || !std::isfinite(in.mergeDistance))
        throw InputError(fmt::format("TIN {}: merge distance {} m must be a finite number >= 0", name, in.mergeDistance));
    for (size_t i = 0; i < in.points.size(); ++i)
        if (!isFinite(in.points[i]))
            throw InputError(fmt::format("TIN {}: {} has a non-finite coordinate ({}, {}, {})", name,
                                         labelOf(in, i), in.points[i].x, in.points[i].y, in.points[i].z));
    size_t total = in.points.size();
    for (const auto& line : in.constraints) total += line.size();
    if (total < 3)
        throw InputError(fmt::format("TIN {}: {} point(s) including constraint vertices; at least 3 non-collinear "
                                     "points are needed", name, total));

    std::vector<CPoint> pts = mergeClose(in);
    auto cdt = std::make_unique<Cdt>();
    cdt->insert(pts.begin(), pts.end());  // spatially sorted bulk insertion
    for (size_t c = 0; c < in.constraints.size(); ++c) {
        const auto& line = in.constraints[c];
        if (line.size() < 2)
            throw InputError(fmt::format("TIN {}: constraint polyline {} has {} vertex; at least 2 are needed", name,
                                         c + 1, line.size()));
        for (size_t k = 0; k < line.size(); ++k)
            if (!isFinite(line[k]))
                throw InputError(fmt::format("TIN {}: constraint polyline {} vertex {} is not finite", name, c + 1, k + 1));
        try {
            for (size_t k = 0; k + 1 < line.size(); ++k) {
                const CPoint a(line[k].x, line[k].y, line[k].z), b(line[k + 1].x, line[k + 1].y, line[k + 1].z);
                if (a.x() == b.x() && a.y() == b.y()) continue;  // repeated vertex: no segment
                cdt->insert_constraint(a, b);
            }
        } catch (const Cdt::Intersection_of_constraints_exception&) {
            throw InputError(fmt::format("TIN {}: constraint polyline {} crosses an earlier constraint polyline (or "
                                         "itself); shoreline polylines may touch at shared vertices but not cross",
                                         name, c + 1));
        }
    }
    if (cdt->dimension() < 2)
        throw InputError(fmt::format("TIN {}: all {} distinct points are collinear (or coincident); a terrain needs "
                                     "points spread over an area", name, cdt->number_of_vertices()));
    LITTORAL_CHECK(cdt->is_valid());
    return std::make_unique<TinTerrain>(std::move(cdt), in.outside, name);
}

}  // namespace detail

std::unique_ptr<Terrain> fromLocalPoints(const std::vector<Point3>& points,
                                         const std::vector<std::vector<Point3>>& constraints, OutsideHull outside,
                                         const std::string& sourceName, double mergeDistance) {
    detail::TinInput in;
    in.points = points;
    in.constraints = constraints;
    in.outside = outside;
    in.sourceName = sourceName;
    in.mergeDistance = mergeDistance;
    return detail::buildTin(std::move(in));
}

}  // namespace littoral::bathymetry
