#include "render/facet_beams.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/error.h"
#include "core/frame.h"
#include "core/log.h"
#include "core/units.h"
#include "render/scene.h"

namespace littoral::render {

namespace {

constexpr int kRim = 8;                 // disc rim directions sampled for a footprint's extent
constexpr double kRimMargin = 1.15;     // the rim's polygon inscribes the disc: widen it
constexpr int kMaxSlabs = 128;
constexpr double kMaxCells = 1 << 22;     // 16 MB of cell offsets
constexpr double kMaxEntries = 1 << 25;   // 128 MB of facet lists
constexpr int kMaxCellsPerAxis = 4096;
constexpr double kMinBeamSlope = 0.1;   // |d.z|: beams closer to horizontal are not indexed

// The directions whose footprints bound a facet's beams over the disc: the centre and the rim.
std::array<Vec3, kRim + 1> discDirections(const Vec3& sun, double halfAngle) {
    std::array<Vec3, kRim + 1> w;
    w[0] = sun;
    const Frame f = Frame::fromNormal(sun);
    const double a = std::min(0.5, halfAngle * kRimMargin), s = std::sin(a), c = std::cos(a);
    for (int k = 0; k < kRim; ++k) {
        const double phi = 2 * M_PI * k / kRim;
        w[static_cast<size_t>(k + 1)] = normalize(f.toWorld(Vec3{s * std::cos(phi), s * std::sin(phi), c}));
    }
    return w;
}

double wrapInto(double v, double lo, double period) { return v - period * std::floor((v - lo) / period); }

}  // namespace

FacetBeams::FacetBeams(const Scene& scene, int medium, double n, const std::vector<bool>& skyMedia, const Vec3& sunDir,
                       double halfAngle)
    : eta_(1.0 / n), periodic_(scene.domain().periodic) {
    const ir::Domain& dom = scene.domain();
    px_ = dom.x1 - dom.x0, py_ = dom.y1 - dom.y0;
    auto sky = [&](int m) { return skyMedia[static_cast<size_t>(m)]; };
    const double minCos = -std::sin(std::min(0.5, halfAngle * kRimMargin));
    scene.geometry().forEachTriangle([&](int mesh, int inst, uint32_t face, const Point3& a, const Point3& b,
                                         const Point3& c) {
        const int in = scene.insideMedium(mesh), out = scene.outsideMedium(mesh);
        if (in != medium && out != medium) return;
        SurfaceHit h;
        h.mesh = mesh, h.instance = inst, h.face = face;
        h.slot = scene.ir().meshes[static_cast<size_t>(mesh)].data.materialOf(face);
        h.p = (a + b + c) * (1.0 / 3.0);
        const MaterialData& m = scene.material(h);
        if (!m.isInterface()) return;
        const bool skyOut = sky(out) && in == medium, skyIn = sky(in) && out == medium;
        if (!skyOut && !skyIn) {
            if (in != out) objects_ = true;  // an interface to another dense medium (a dielectric object)
            return;
        }
        if (m.isRough()) return;
        const Vec3 N = cross(b - a, c - a);
        const double len = length(N);
        if (!(len > 0)) return;
        const Normal3 nAir = N * ((skyOut ? 1.0 : -1.0) / len);
        if (dot(nAir, sunDir) <= minCos) return;  // the disc cannot light this side
        const double extent = std::max({std::max({a.x, b.x, c.x}) - std::min({a.x, b.x, c.x}),
                                        std::max({a.y, b.y, c.y}) - std::min({a.y, b.y, c.y})});
        facets_.push_back({a, b, c, nAir, mesh, inst, face, extent, extent > 0.25 * std::min(px_, py_)});
        horizontal_ = horizontal_ && std::abs(nAir.z) >= 1 - 1e-12;
    });
    // Flat water is not indexed: its beams are the straight path's, which SunConnection traces.
    if (!facets_.empty() && !horizontal_) build(sunDir, halfAngle, scene.geometry().bounds().lo.z, dom);
}

bool FacetBeams::refracted(int i, const Vec3& ws, Vec3* d) const {
    const BeamFacet& f = facets_[static_cast<size_t>(i)];
    if (dot(ws, f.nAir) <= 0) return false;
    Vec3 wt;
    if (!refract(ws, f.nAir, eta_, &wt)) return false;  // (never, into a denser medium)
    *d = normalize(wt);
    return d->z < -kMinBeamSlope;
}

bool FacetBeams::containsImage(const BeamFacet& f, const Point3& p, const Vec3& d, const Vec3& S, double* s) const {
    const double dn = dot(f.nAir, d);  // < 0: d leaves the air side
    if (!(dn < 0)) return false;
    // The line p - t d meets the plane of the facet's image moved by S at t.
    const double t = dot(f.nAir, p - f.a - S) / dn;
    if (!(t > 0)) return false;
    const Point3 q = p - d * t, a = f.a + S, b = f.b + S, c = f.c + S;
    const Vec3 N = cross(b - a, c - a);
    if (dot(cross(b - a, q - a), N) < 0 || dot(cross(c - b, q - b), N) < 0 || dot(cross(a - c, q - c), N) < 0)
        return false;
    *s = t;
    return true;
}

bool FacetBeams::contains(int i, const Point3& p, const Vec3& d, double* s) const {
    const BeamFacet& f = facets_[static_cast<size_t>(i)];
    if (!periodic_) return containsImage(f, p, d, Vec3{0, 0, 0}, s);
    // The image whose centroid lies nearest the point where the line through p along d reaches the
    // centroid's height. (Not where it meets the facet's plane: under a steep facet that plane is
    // nearly parallel to the line, its crossing lies far from the facet, and the image nearest it
    // is the wrong one; those beams were lost where they crossed a periodic wall, 22 % of the
    // light under the 68-degree sinusoid.) It is the only candidate for a facet smaller than a
    // quarter period; a larger one is tested in the images around it too.
    const Point3 g = (f.a + f.b + f.c) * (1.0 / 3.0);
    const Point3 q = p + d * ((g.z - p.z) / d.z);  // d.z < -kMinBeamSlope (refracted)
    const Vec3 S{px_ * std::round((q.x - g.x) / px_), py_ * std::round((q.y - g.y) / py_), 0};
    if (!f.large) return containsImage(f, p, d, S, s);
    for (int jx = -1; jx <= 1; ++jx)
        for (int jy = -1; jy <= 1; ++jy)
            if (containsImage(f, p, d, S + Vec3{jx * px_, jy * py_, 0}, s)) return true;
    return false;
}

const int32_t* FacetBeams::cellOf(const Point3& p, int* count) const {
    *count = 0;
    if (offsets_.empty()) return nullptr;  // no facets, or flat ones (not indexed)
    const double depth = (zTop_ - p.z) / slab_;
    if (!(depth >= 0)) return nullptr;  // above every facet: no beam reaches up here
    const int s = std::min(nz_ - 1, static_cast<int>(depth));
    double sx = p.x - p.z * k0x_, sy = p.y - p.z * k0y_;
    if (periodic_) sx = wrapInto(sx, x0_, px_), sy = wrapInto(sy, y0_, py_);
    const double fi = (sx - x0_) / cellX_, fj = (sy - y0_) / cellY_;
    if (!(fi >= 0 && fj >= 0) || (!periodic_ && (fi >= nx_ || fj >= ny_))) return nullptr;
    const int i = std::min(static_cast<int>(fi), nx_ - 1), j = std::min(static_cast<int>(fj), ny_ - 1);
    const size_t k = (static_cast<size_t>(s) * ny_ + j) * nx_ + i;
    *count = static_cast<int>(offsets_[k + 1] - offsets_[k]);
    return entries_.data() + offsets_[k];
}

struct FacetBeams::Drifts {
    std::vector<std::array<Vec2, kRim + 1>> k;
};

void FacetBeams::build(const Vec3& sunDir, double halfAngle, double zBottom, const ir::Domain& dom) {
    Vec3 d0;
    if (!refract(sunDir, Vec3{0, 0, 1}, eta_, &d0)) d0 = Vec3{0, 0, -1};
    d0 = normalize(d0);
    k0x_ = d0.x / d0.z, k0y_ = d0.y / d0.z;
    const auto dirs = discDirections(sunDir, halfAngle);
    Drifts drifts;
    drifts.k.resize(facets_.size());
    double zTop = -ir::kInfinity, sizeSum = 0, maxDrift = 1e-3;
    for (size_t i = 0; i < facets_.size(); ++i) {
        const BeamFacet& f = facets_[i];
        for (size_t k = 0; k < dirs.size(); ++k) {
            Vec3 d;
            drifts.k[i][k] = Vec2{NAN, NAN};
            if (!refracted(static_cast<int>(i), dirs[k], &d)) continue;
            drifts.k[i][k] = Vec2{d.x / d.z - k0x_, d.y / d.z - k0y_};
            maxDrift = std::max({maxDrift, std::abs(drifts.k[i][k].x), std::abs(drifts.k[i][k].y)});
        }
        zTop = std::max({zTop, f.a.z, f.b.z, f.c.z});
        sizeSum += f.extent;
    }
    zTop_ = zTop;
    zBottom = std::min(zBottom, zTop - 1e-3);
    // The sheared plane: the domain's period, or the footprints' extent at the top and the bottom.
    double x0 = dom.x0, x1 = dom.x1, y0 = dom.y0, y1 = dom.y1;
    if (!periodic_) {
        x0 = y0 = ir::kInfinity, x1 = y1 = -ir::kInfinity;
        for (size_t i = 0; i < facets_.size(); ++i) {
            const BeamFacet& f = facets_[i];
            const auto b = footprint(i, drifts, zBottom, std::min({zTop, std::max({f.a.z, f.b.z, f.c.z})}));
            x0 = std::min(x0, b[0]), x1 = std::max(x1, b[1]), y0 = std::min(y0, b[2]), y1 = std::max(y1, b[3]);
        }
        if (!(x1 >= x0)) x0 = x1 = y0 = y1 = 0;
    }
    x0_ = x0, y0_ = y0;
    // Cells half a facet wide (a cell then lists about 2 (1 + 1/2)^2 = 4.5 triangles of a regular
    // grid, 8 with whole-facet cells), slabs in which a beam drifts about one cell; both coarsened
    // until the grid holds at most kMaxCells cells and kMaxEntries entries (a deep column under
    // small facets would otherwise need billions).
    const double span = std::max(dom.x1 - dom.x0, dom.y1 - dom.y0);
    const double meanExtent = sizeSum / static_cast<double>(facets_.size());
    double cell = std::max(0.5 * meanExtent, span / kMaxCellsPerAxis);
    for (;; cell *= 1.25) {
        nz_ = std::clamp(static_cast<int>(std::ceil((zTop - zBottom) * maxDrift / cell)), 1, kMaxSlabs);
        nx_ = std::clamp(static_cast<int>(std::ceil((x1 - x0) / cell)), 1, kMaxCellsPerAxis);
        ny_ = std::clamp(static_cast<int>(std::ceil((y1 - y0) / cell)), 1, kMaxCellsPerAxis);
        // Each facet lies in about (extent / cell + 2)^2 cells of each slab below it.
        const double entries = static_cast<double>(facets_.size()) * nz_ * sqr(meanExtent / cell + 2);
        if (static_cast<double>(nz_) * nx_ * ny_ <= kMaxCells && entries <= kMaxEntries) break;
    }
    slab_ = (zTop - zBottom) / nz_;
    cellX_ = std::max((x1 - x0) / nx_, 1e-12), cellY_ = std::max((y1 - y0) / ny_, 1e-12);
    offsets_.assign(static_cast<size_t>(nz_) * nx_ * ny_ + 1, 0);
    fill(drifts, true);
    for (size_t k = 1; k < offsets_.size(); ++k) offsets_[k] += offsets_[k - 1];
    entries_.resize(offsets_.back());
    fill(drifts, false);
    log::debug("facet beams: {} facets, {} slabs of {:.3g} m, {} x {} cells of {:.3g} m, {} entries", facets_.size(),
               nz_, slab_, nx_, ny_, cellX_, entries_.size());
}

std::array<double, 4> FacetBeams::footprint(size_t i, const Drifts& drifts, double zLo, double zHi) const {
    // Vertex v's beam along a direction of drift k reaches depth z at sigma = v.xy - v.z k0 + (z - v.z) k:
    // affine in z, so the slab's two ends bound it.
    const BeamFacet& f = facets_[i];
    std::array<double, 4> box{ir::kInfinity, -ir::kInfinity, ir::kInfinity, -ir::kInfinity};
    for (const Point3& v : {f.a, f.b, f.c})
        for (const Vec2& k : drifts.k[i])
            for (const double z : {zLo, zHi}) {
                if (std::isnan(k.x)) continue;
                const double sx = v.x - v.z * k0x_ + (z - v.z) * k.x, sy = v.y - v.z * k0y_ + (z - v.z) * k.y;
                box = {std::min(box[0], sx), std::max(box[1], sx), std::min(box[2], sy), std::max(box[3], sy)};
            }
    return box;
}

// Lists every facet in the cells its footprint overlaps in every slab below its top: counting
// into offsets_[k + 1] (count), or writing entries_ at offsets_[k] onward (the offsets advance and
// are restored at the end).
void FacetBeams::fill(const Drifts& drifts, bool count) {
    std::vector<uint32_t> next;
    if (!count) next.assign(offsets_.begin(), offsets_.end() - 1);
    for (size_t i = 0; i < facets_.size(); ++i) {
        const BeamFacet& f = facets_[i];
        const double fTop = std::max({f.a.z, f.b.z, f.c.z});
        for (int s = 0; s < nz_; ++s) {
            const double zb = zTop_ - s * slab_, za = zb - slab_;
            if (za >= fTop) continue;  // the whole slab lies above this facet
            const auto [x0, x1, y0, y1] = footprint(i, drifts, za, std::min(zb, fTop));
            if (!(x1 >= x0)) continue;
            // Cells overlapped (a hair wider, for points on a cell's edge), wrapped when periodic.
            const double e = 1e-9 * (1 + std::abs(x0) + std::abs(y0));
            int i0 = static_cast<int>(std::floor((x0 - e - x0_) / cellX_)), i1 = static_cast<int>(std::floor((x1 + e - x0_) / cellX_));
            int j0 = static_cast<int>(std::floor((y0 - e - y0_) / cellY_)), j1 = static_cast<int>(std::floor((y1 + e - y0_) / cellY_));
            if (periodic_) {
                if (i1 - i0 >= nx_) i0 = 0, i1 = nx_ - 1;
                if (j1 - j0 >= ny_) j0 = 0, j1 = ny_ - 1;
            } else {
                i0 = std::max(i0, 0), j0 = std::max(j0, 0), i1 = std::min(i1, nx_ - 1), j1 = std::min(j1, ny_ - 1);
            }
            for (int j = j0; j <= j1; ++j)
                for (int ii = i0; ii <= i1; ++ii) {
                    const int ci = ((ii % nx_) + nx_) % nx_, cj = ((j % ny_) + ny_) % ny_;
                    const size_t k = (static_cast<size_t>(s) * ny_ + cj) * nx_ + ci;
                    if (count) ++offsets_[k + 1];
                    else entries_[next[k]++] = static_cast<int32_t>(i);
                }
        }
    }
}

}  // namespace littoral::render
