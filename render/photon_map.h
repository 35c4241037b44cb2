#pragma once
// A photon map: compact photon records and a spatial hash grid for fixed-radius queries.
//
// Record layout (structure of arrays, bytes per photon for n bands of the group):
//   position       3 x float32                         12
//   direction      octahedral, 2 x 16-bit unit normals  4   (direction of travel)
//   surface normal octahedral, 2 x 16-bit (surface maps) 4
//   power          n x float16 (binary16)              2 n (relative to fluxScale[band])
// = 16 + 2n bytes for a volume map and 20 + 2n for a surface map: 24 and 28 bytes for 4 bands.
// Positions in float keep 10 um at 100 m from the origin; directions keep 1e-4 rad; powers, which
// equal-flux tracing keeps near 1, keep 3 significant digits (rounding to nearest, so errors
// average out over the hundreds of photons of a density estimate).
//
// The grid groups cells of side `cellSize` in blocks of 4 x 4 x 4, each block a run of 64 buckets
// (bucketOf). Where the photons' bounding box holds few enough blocks (at most 2 buckets per
// photon), every block has its own run: the grid is dense and no two cells share a bucket; its
// cells are half the search radius it was built for where that fits and the photons are many per
// cell of the radius (build()), else the radius. Otherwise blocks are hashed into a table of about
// as many buckets as photons, and cells of distant blocks may share one (their photons are tested
// and rejected by distance). Photons are stored sorted by bucket, so a query walks the few bucket runs
// of the cells it overlaps (each bucket once) and tests actual distances. Building sorts by bucket
// with a counting sort whose order is fixed (it does not depend on threads).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>
#include <vector>

#include "core/bbox.h"
#include "core/large_buffer.h"
#include "core/ranks.h"
#include "core/vec.h"
#include "render/spectral.h"

namespace littoral::render {

// IEEE binary16 conversions (round to nearest even; overflow to infinity).
uint16_t floatToHalf(float f);
float halfToFloatSlow(uint16_t h);  // every binary16 value (zero, subnormal, inf, NaN included)
// Inline, as density estimates decode every photon they gather: normal numbers directly.
inline float halfToFloat(uint16_t h) {
    const uint32_t exp = (h >> 10) & 0x1fu;
    if (exp == 0 || exp == 31) return halfToFloatSlow(h);
    const uint32_t x = (static_cast<uint32_t>(h & 0x8000u) << 16) | ((exp + 127 - 15) << 23) | ((h & 0x3ffu) << 13);
    float f;
    std::memcpy(&f, &x, 4);
    return f;
}
// Octahedral encoding of a unit vector in 32 bits (Meyer et al. 2010): worst error ~1e-4 rad.
uint32_t encodeOctahedral(const Vec3& v);
// Inline, like halfToFloat: each 16-bit half maps to [-1, 1] by a product (not a division).
inline Vec3 decodeOctahedral(uint32_t e) {
    const double px = static_cast<double>(e & 0xffffu) * (2.0 / 65535.0) - 1.0;
    const double py = static_cast<double>(e >> 16) * (2.0 / 65535.0) - 1.0;
    Vec3 v{px, py, 1 - std::abs(px) - std::abs(py)};
    if (v.z < 0) {
        const double ox = (1 - std::abs(v.y)) * (v.x >= 0 ? 1.0 : -1.0), oy = (1 - std::abs(v.x)) * (v.y >= 0 ? 1.0 : -1.0);
        v.x = ox;
        v.y = oy;
    }
    return v * (1.0 / std::sqrt(lengthSquared(v)));  // one division, not three
}

class PhotonMap {
public:
    PhotonMap() = default;
    PhotonMap(int bands, bool withNormals) : bands_(bands), normals_(withNormals) {}

    // Appends one photon (before build()). `power` holds bands() values, relative to fluxScale.
    void add(const Point3& p, const Vec3& dir, const Vec3& normal, const Spec& power);
    // Appends all photons of another map (same bands and layout), in order.
    void append(const PhotonMap& other);
    // The records (before build()) as bytes, for moving a chunk's photons between ranks; unpack
    // replaces this map's records with those packed (same bands and layout).
    void pack(ByteWriter& w) const;
    void unpack(ByteReader& r);
    // Capacity for n photons (no reallocation while adding up to n); clear() keeps the capacity.
    void reserve(size_t n);
    void clear();
    // Sorts the photons into a grid for queries of radius up to `searchRadius` (> 0): cells of half
    // that radius in a dense grid of full cells, else of the radius (dense or hashed: see above).
    void build(double searchRadius);

    size_t size() const { return pos_.size() / 3; }
    int bands() const { return bands_; }
    bool hasNormals() const { return normals_; }
    double cellSize() const { return cell_; }
    bool denseGrid() const { return dense_; }  // every block its own bucket run (see above)
    size_t bytesPerPhoton() const { return 16 + (normals_ ? 4 : 0) + 2 * static_cast<size_t>(bands_); }
    static size_t bytesPerPhoton(int bands, bool normals) { return 16 + (normals ? 4 : 0) + 2 * static_cast<size_t>(bands); }
    size_t memoryBytes() const;  // records plus the grid

    Point3 position(size_t i) const { return {pos_[3 * i], pos_[3 * i + 1], pos_[3 * i + 2]}; }
    Vec3 direction(size_t i) const { return decodeOctahedral(dir_[i]); }
    Vec3 normal(size_t i) const { return decodeOctahedral(nrm_[i]); }
    float power(size_t i, int band) const { return halfToFloat(pow_[i * bands_ + band]); }

    // Flux of a photon of relative power 1 in each band, W um^-1 (set by the photon pass).
    std::vector<double> fluxScale;

    // Calls f(i) for every photon within distance r of p (any r; the grid is built for the radius
    // it will be queried with).
    template <class F> void forEachInSphere(const Point3& p, double r, F&& f) const;
    // Calls f(i, t) for every photon whose perpendicular distance to the segment
    // o + t d, t in [t0, t1) (d unit) is at most r, with t its projection onto the ray.
    template <class F> void forEachNearSegment(const Point3& o, const Vec3& d, double t0, double t1, double r, F&& f) const;

private:
    uint64_t bucketOf(int64_t ix, int64_t iy, int64_t iz) const;
    BBox3 positionBox() const;  // the photons' bounding box
    // Sets the dense grid's cells and blocks for that box and cells of side 1 / inv; false where
    // they would not fit the indices.
    bool denseGridBox(const BBox3& box, double inv);
    // Calls f(begin, end) once per distinct bucket of the cells in [lo, hi] whose centre lies in the
    // query's convex region. The region is given by rows: rowRange(y, z, &xa, &xb) sets the interval
    // of x where the line (x, y, z) meets it (false: none), so that only the cells of each row that
    // the region reaches are visited, not every cell of the box (a march step's box held about 5
    // times the cells its cylinder reaches, and testing them was 30 % of a photon-mapped column).
    struct CellRow {  // cells [first, second] of a row; uninitialised on purpose (a query's stack array)
        int64_t first, second;
    };
    template <class Rows, class F> void forEachBucketInBox(const Point3& lo, const Point3& hi, Rows&& rowRange, F&& f) const;
    // The cells [ix0, ix1] of each row kept by rowRange, for rows (iy, iz) in [y0, y1] x [z0, z1]
    // (row (iy, iz) at index (iz - z0) * (y1 - y0 + 1) + iy - y0; an empty row has ix0 > ix1).
    template <class Rows>
    void keptRows(int64_t x0, int64_t x1, int64_t y0, int64_t y1, int64_t z0, int64_t z1, Rows&& rowRange,
                  CellRow* rows) const;
    // The dense grid's part of forEachBucketInBox, for the rows of keptRows.
    template <class F>
    void forEachDenseRun(int64_t y0, int64_t y1, int64_t z0, int64_t z1, const CellRow* rows,
                         F&& f) const;

    int bands_ = 1;
    bool normals_ = false;
    // Records and grid in huge-page-backed storage (core/large_buffer.h): fewer page faults while
    // filling, fewer TLB misses in queries of large maps.
    LargeVector<float> pos_;  // x, y, z per photon, together: a query touches one cache line, not three
    LargeVector<uint32_t> dir_, nrm_;
    LargeVector<uint16_t> pow_;
    double cell_ = 0;
    uint64_t mask_ = 0;
    LargeVector<uint32_t> bucketStart_;  // size mask_ + 2
    // A dense grid: the photons' cells span cellLo_..cellHi_ (inclusive), their blocks
    // blockLo_ + [0, blockN_).
    bool dense_ = false;
    int64_t cellLo_[3] = {0, 0, 0}, cellHi_[3] = {0, 0, 0}, blockLo_[3] = {0, 0, 0};
    uint64_t blockN_[3] = {0, 0, 0};
};

// ---------------------------------------------------------------------------------------------

inline uint64_t PhotonMap::bucketOf(int64_t ix, int64_t iy, int64_t iz) const {
    // Cells are grouped in blocks of 4 x 4 x 4. A block has a run of 64 consecutive buckets (its
    // own in a dense grid, hashed (Teschner et al. 2003) otherwise), and its cells take them in
    // Morton order. The 27 cells of a query then fall in 1 to 8 blocks (3.4 on average), whose photons lie together in memory: a large
    // map's query reads a few runs of records instead of 27 scattered ones.
    const uint64_t cx = static_cast<uint64_t>(ix) & 3, cy = static_cast<uint64_t>(iy) & 3, cz = static_cast<uint64_t>(iz) & 3;
    const uint64_t morton = (cx & 1) | ((cy & 1) << 1) | ((cz & 1) << 2) | ((cx & 2) << 2) | ((cy & 2) << 3) | ((cz & 2) << 4);
    if (dense_) {  // the block's index in the grid's box (the cell lies in it: see forEachBucketInBox)
        const uint64_t bx = static_cast<uint64_t>((ix >> 2) - blockLo_[0]), by = static_cast<uint64_t>((iy >> 2) - blockLo_[1]),
                       bz = static_cast<uint64_t>((iz >> 2) - blockLo_[2]);
        return (((bz * blockN_[1] + by) * blockN_[0] + bx) << 6) | morton;
    }
    const uint64_t bx = static_cast<uint64_t>(ix >> 2), by = static_cast<uint64_t>(iy >> 2), bz = static_cast<uint64_t>(iz >> 2);
    uint64_t h = (bx * 73856093ull) ^ (by * 19349663ull) ^ (bz * 83492791ull);
    h ^= h >> 29;
    return ((h << 6) | morton) & mask_;
}

// The interval of x where the line (x, y, z) lies within distance sqrt(R2) of c: false if none.
inline bool sphereRow(const Point3& c, double R2, double y, double z, double* xa, double* xb) {
    const double q = R2 - (y - c.y) * (y - c.y) - (z - c.z) * (z - c.z);
    if (q < 0) return false;
    const double h = std::sqrt(q);
    *xa = c.x - h, *xb = c.x + h;
    return true;
}

// The rows of a capsule: the points within distance sqrt(R2) of the segment o + t d, t in [t0, t1]
// (d unit). rows(y, z, &xa, &xb) sets the interval of x where the line (x, y, z) meets it (false:
// none). The capsule is the union of the spheres at the two ends and the cylinder between them; it
// is convex, so the line meets it in one interval, the hull of the line's intervals in the three
// parts.
class CapsuleRows {
public:
    CapsuleRows(const Point3& o, const Vec3& d, double t0, double t1, double R2)
        : o_(o), d_(d), a_(o + d * t0), b_(o + d * t1), t0_(t0), t1_(t1), R2_(R2), A_(d.y * d.y + d.z * d.z),
          alongX_(!(A_ > 1e-12)), slab_(std::abs(d.x) > 1e-12), invDx_(slab_ ? 1.0 / d.x : 0),
          inv2A_(alongX_ ? 0 : 0.5 / A_) {}
    bool operator()(double y, double z, double* xa, double* xb) const {
        constexpr double kInf = std::numeric_limits<double>::infinity();
        double lo = kInf, hi = -kInf, a, b;
        if (sphereRow(a_, R2_, y, z, &a, &b)) lo = std::min(lo, a), hi = std::max(hi, b);
        if (sphereRow(b_, R2_, y, z, &a, &b)) lo = std::min(lo, a), hi = std::max(hi, b);
        // The cylinder: with u = x - o.x, t(u) = u d.x + k and the squared distance to the axis is
        // A u^2 + B u + C + R2 (A = 1 - d.x^2); t in [t0, t1] bounds u where d.x != 0.
        const double wy = y - o_.y, wz = z - o_.z, k = wy * d_.y + wz * d_.z;
        const double B = -2 * d_.x * k, C = wy * wy + wz * wz - k * k - R2_;
        // (An empty part is a flag, not ua = inf: with ub = inf too, ua <= ub would hold.)
        double ua = -kInf, ub = kInf;
        bool empty = false;
        if (slab_) {
            ua = (t0_ - k) * invDx_, ub = (t1_ - k) * invDx_;
            if (ua > ub) std::swap(ua, ub);
        } else if (k < t0_ || k > t1_) {
            empty = true;  // the row's plane misses the slab between the ends
        }
        if (!alongX_) {
            const double disc = B * B - 4 * A_ * C;
            if (disc < 0) {
                empty = true;
            } else {
                const double s = std::sqrt(disc);
                ua = std::max(ua, (-B - s) * inv2A_), ub = std::min(ub, (-B + s) * inv2A_);
            }
        } else if (C > 0) {  // the segment runs along x: its distance to the row does not vary with u
            empty = true;
        }
        if (!empty && ua <= ub) lo = std::min(lo, o_.x + ua), hi = std::max(hi, o_.x + ub);
        if (!(lo <= hi)) return false;
        *xa = lo, *xb = hi;
        return true;
    }

private:
    Point3 o_;
    Vec3 d_;
    Point3 a_, b_;
    double t0_, t1_, R2_, A_;
    bool alongX_, slab_;
    double invDx_, inv2A_;
};

template <class Rows>
void PhotonMap::keptRows(int64_t x0, int64_t x1, int64_t y0, int64_t y1, int64_t z0, int64_t z1, Rows&& rowRange,
                         CellRow* rows) const {
    const double inv = 1.0 / cell_;
    size_t n = 0;
    for (int64_t iz = z0; iz <= z1; ++iz)
        for (int64_t iy = y0; iy <= y1; ++iy) {
            double xa, xb;
            CellRow& r = rows[n++];
            r = CellRow{1, 0};
            if (!rowRange((iy + 0.5) * cell_, (iz + 0.5) * cell_, &xa, &xb)) continue;
            // Cells whose centre (ix + 0.5) cell lies in [xa, xb], within [x0, x1]. Compared as doubles
            // before the conversion, which an infinite or NaN bound would make undefined (a NaN
            // keeps the whole row: the photons are tested one by one anyway).
            const double fa = std::ceil(xa * inv - 0.5), fb = std::floor(xb * inv - 0.5);
            r.first = fa > static_cast<double>(x0) ? (fa <= static_cast<double>(x1) ? static_cast<int64_t>(fa) : x1 + 1) : x0;
            r.second = fb < static_cast<double>(x1) ? (fb >= static_cast<double>(x0) ? static_cast<int64_t>(fb) : x0 - 1) : x1;
        }
}

template <class Rows, class F>
void PhotonMap::forEachBucketInBox(const Point3& lo, const Point3& hi, Rows&& rowRange, F&& f) const {
    if (pos_.empty()) return;
    const double inv = 1.0 / cell_;
    int64_t x0 = static_cast<int64_t>(std::floor(lo.x * inv)), x1 = static_cast<int64_t>(std::floor(hi.x * inv));
    int64_t y0 = static_cast<int64_t>(std::floor(lo.y * inv)), y1 = static_cast<int64_t>(std::floor(hi.y * inv));
    int64_t z0 = static_cast<int64_t>(std::floor(lo.z * inv)), z1 = static_cast<int64_t>(std::floor(hi.z * inv));
    if (dense_) {  // cells outside the grid's box hold no photon
        x0 = std::max(x0, cellLo_[0]), x1 = std::min(x1, cellHi_[0]);
        y0 = std::max(y0, cellLo_[1]), y1 = std::min(y1, cellHi_[1]);
        z0 = std::max(z0, cellLo_[2]), z1 = std::min(z1, cellHi_[2]);
        if (x0 > x1 || y0 > y1 || z0 > z1) return;
    }
    // The kept cells of each row; a march step's box has some 8 x 8 rows: those fit the stack.
    CellRow localRows[256];
    std::vector<CellRow> manyRows;
    const uint64_t nRows = static_cast<uint64_t>(y1 - y0 + 1) * static_cast<uint64_t>(z1 - z0 + 1);
    CellRow* rows = localRows;
    if (nRows > 256) {
        manyRows.resize(nRows);
        rows = manyRows.data();
    }
    keptRows(x0, x1, y0, y1, z0, z1, rowRange, rows);
    if (dense_) {
        forEachDenseRun(y0, y1, z0, z1, rows, f);
        return;
    }
    // Distinct buckets only (two cells may share one). A segment query of a march step keeps some
    // hundred cells: those fit the stack, and only a longer one allocates.
    uint64_t local[1024];
    std::vector<uint64_t> many;
    size_t n = 0, cells = 0;
    for (uint64_t k = 0; k < nRows; ++k) cells += static_cast<size_t>(std::max<int64_t>(0, rows[k].second - rows[k].first + 1));
    uint64_t* buf = local;
    if (cells > 1024) {
        many.resize(cells);
        buf = many.data();
    }
    size_t k = 0;
    for (int64_t iz = z0; iz <= z1; ++iz)
        for (int64_t iy = y0; iy <= y1; ++iy, ++k)
            for (int64_t ix = rows[k].first; ix <= rows[k].second; ++ix) buf[n++] = bucketOf(ix, iy, iz);
    std::sort(buf, buf + n);
    n = static_cast<size_t>(std::unique(buf, buf + n) - buf);
    // Runs of consecutive buckets are one range of records.
    for (size_t j = 0; j < n;) {
        size_t e = j + 1;
        while (e < n && buf[e] == buf[e - 1] + 1) ++e;
        if (bucketStart_[buf[j]] != bucketStart_[buf[e - 1] + 1]) f(bucketStart_[buf[j]], bucketStart_[buf[e - 1] + 1]);
        j = e;
    }
}

template <class F>
void PhotonMap::forEachDenseRun(int64_t y0, int64_t y1, int64_t z0, int64_t z1, const CellRow* rows,
                                F&& f) const {
    // A dense grid's buckets are (block index << 6) | Morton code, and the block index grows with
    // bx, then by, then bz: visiting the blocks in that order and each block's kept cells as the set
    // bits of a 64-bit mask gives the buckets in increasing order without sorting them (the sort
    // was 8 % of a photon-mapped column's render), and in the same order as before, so the sums
    // are the same to the last bit.
    uint64_t runB = 0, runE = 0;
    bool open = false;
    auto emit = [&](uint64_t b, uint64_t e) {
        if (open && b == runE) {
            runE = e;
            return;
        }
        if (open && bucketStart_[runB] != bucketStart_[runE]) f(bucketStart_[runB], bucketStart_[runE]);
        runB = b, runE = e, open = true;
    };
    // The blocks' x range: the kept cells' hull over every row.
    int64_t x0 = INT64_MAX, x1 = INT64_MIN;
    const size_t ny = static_cast<size_t>(y1 - y0 + 1), nRows = ny * static_cast<size_t>(z1 - z0 + 1);
    for (size_t k = 0; k < nRows; ++k)
        if (rows[k].first <= rows[k].second) x0 = std::min(x0, rows[k].first), x1 = std::max(x1, rows[k].second);
    if (x0 > x1) return;
    for (int64_t bz = z0 >> 2; bz <= (z1 >> 2); ++bz)
        for (int64_t by = y0 >> 2; by <= (y1 >> 2); ++by)
            for (int64_t bx = x0 >> 2; bx <= (x1 >> 2); ++bx) {
                uint64_t mask = 0;
                for (int64_t iz = std::max(z0, 4 * bz); iz <= std::min(z1, 4 * bz + 3); ++iz)
                    for (int64_t iy = std::max(y0, 4 * by); iy <= std::min(y1, 4 * by + 3); ++iy) {
                        const auto& r = rows[static_cast<size_t>(iz - z0) * ny + static_cast<size_t>(iy - y0)];
                        for (int64_t ix = std::max(r.first, 4 * bx); ix <= std::min(r.second, 4 * bx + 3); ++ix)
                            mask |= uint64_t{1} << (bucketOf(ix, iy, iz) & 63);
                    }
                const uint64_t base = bucketOf(4 * bx, 4 * by, 4 * bz) & ~uint64_t{63};
                while (mask) {  // each run of set bits is a run of consecutive buckets
                    const int lo = std::countr_zero(mask);
                    const uint64_t rest = mask >> lo;
                    const int len = rest == ~uint64_t{0} ? 64 - lo : std::countr_zero(~rest);
                    emit(base + static_cast<uint64_t>(lo), base + static_cast<uint64_t>(lo + len));
                    mask = lo + len >= 64 ? 0 : mask & (~uint64_t{0} << (lo + len));
                }
            }
    if (open && bucketStart_[runB] != bucketStart_[runE]) f(bucketStart_[runB], bucketStart_[runE]);
}

template <class F> void PhotonMap::forEachInSphere(const Point3& p, double r, F&& f) const {
    const double r2 = r * r;
    // Only cells whose centre lies within r + half a cell diagonal of p can hold a photon within r
    // (a hair more, so that rounding never drops one).
    const double reach = (r + 0.8660254037844386 * cell_) * (1 + 1e-9), reach2 = reach * reach;
    auto rows = [&](double y, double z, double* xa, double* xb) { return sphereRow(p, reach2, y, z, xa, xb); };
    forEachBucketInBox(p - Vec3{r, r, r}, p + Vec3{r, r, r}, rows, [&](uint32_t b, uint32_t e) {
        for (uint32_t i = b; i < e; ++i) {
            const float* q = &pos_[3 * size_t{i}];
            const double dx = q[0] - p.x, dy = q[1] - p.y, dz = q[2] - p.z;
            if (dx * dx + dy * dy + dz * dz <= r2) f(static_cast<size_t>(i));
        }
    });
}

template <class F>
void PhotonMap::forEachNearSegment(const Point3& o, const Vec3& d, double t0, double t1, double r, F&& f) const {
    const Point3 a = o + d * t0, b = o + d * t1;
    const Point3 lo{std::min(a.x, b.x) - r, std::min(a.y, b.y) - r, std::min(a.z, b.z) - r};
    const Point3 hi{std::max(a.x, b.x) + r, std::max(a.y, b.y) + r, std::max(a.z, b.z) + r};
    const double r2 = r * r;
    // Only cells whose centre lies within r + half a cell diagonal of the segment can hold a photon
    // within r of it (a hair more, so that rounding never drops one).
    const double reach = (r + 0.8660254037844386 * cell_) * (1 + 1e-9), reach2 = reach * reach;
    const CapsuleRows rows(o, d, t0, t1, reach2);
    // The segment in locals: f is opaque to the compiler, which would otherwise reload every
    // captured value after each call.
    const double ox = o.x, oy = o.y, oz = o.z, dx = d.x, dy = d.y, dz = d.z, ta = t0, tb = t1;
    const float* pos = pos_.data();
    // The photons found are handed to f in batches, in the order found: each one's direction and
    // power lie in arrays of their own, and fetching them ahead while the positions are still
    // being tested hides the memory latency f would otherwise wait for (the loads were the two
    // slowest instructions of a photon-mapped column's gather).
    constexpr int kBatch = 32;
    uint32_t found[kBatch];
    double foundT[kBatch];
    int n = 0;
    auto flush = [&] {
        for (int k = 0; k < n; ++k) f(static_cast<size_t>(found[k]), foundT[k]);
        n = 0;
    };
    forEachBucketInBox(lo, hi, rows, [&, ox, oy, oz, dx, dy, dz, ta, tb, r2, pos](uint32_t bb, uint32_t e) {
        for (uint32_t i = bb; i < e; ++i) {
            const float* q = pos + 3 * size_t{i};
            const double vx = q[0] - ox, vy = q[1] - oy, vz = q[2] - oz;
            const double t = vx * dx + vy * dy + vz * dz;
            if (t < ta || t >= tb) continue;
            if (vx * vx + vy * vy + vz * vz - t * t <= r2) {
                __builtin_prefetch(&dir_[i]);
                __builtin_prefetch(&pow_[size_t{i} * static_cast<size_t>(bands_)]);
                found[n] = i, foundT[n] = t;
                if (++n == kBatch) flush();
            }
        }
    });
    flush();
}

}  // namespace littoral::render
