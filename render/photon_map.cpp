#include "render/photon_map.h"

#include <bit>
#include <algorithm>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <cstring>

#include "core/error.h"

namespace littoral::render {

uint16_t floatToHalf(float f) {
    uint32_t x;
    std::memcpy(&x, &f, 4);
    const uint32_t sign = (x >> 16) & 0x8000u;
    const int32_t exp = static_cast<int32_t>((x >> 23) & 0xff) - 127 + 15;
    uint32_t mant = x & 0x7fffffu;
    if (((x >> 23) & 0xff) == 0xff) return static_cast<uint16_t>(sign | 0x7c00u | (mant ? 0x200u : 0));  // inf / nan
    if (exp >= 31) return static_cast<uint16_t>(sign | 0x7c00u);                                       // overflow
    if (exp <= 0) {
        if (exp < -10) return static_cast<uint16_t>(sign);  // underflow to zero
        mant |= 0x800000u;
        const int shift = 14 - exp;
        uint32_t h = mant >> shift;
        const uint32_t rem = mant & ((1u << shift) - 1), half = 1u << (shift - 1);
        if (rem > half || (rem == half && (h & 1u))) ++h;  // round to nearest even
        return static_cast<uint16_t>(sign | h);
    }
    uint32_t h = (static_cast<uint32_t>(exp) << 10) | (mant >> 13);
    const uint32_t rem = mant & 0x1fffu;
    if (rem > 0x1000u || (rem == 0x1000u && (h & 1u))) ++h;  // may carry into the exponent: correct
    return static_cast<uint16_t>(sign | h);
}

float halfToFloatSlow(uint16_t h) {
    const uint32_t sign = static_cast<uint32_t>(h & 0x8000u) << 16;
    const uint32_t exp = (h >> 10) & 0x1fu, mant = h & 0x3ffu;
    uint32_t x;
    if (exp == 0) {
        if (mant == 0) {
            x = sign;
        } else {  // subnormal: renormalise
            int e = -1;
            uint32_t m = mant;
            do {
                ++e;
                m <<= 1;
            } while (!(m & 0x400u));
            x = sign | (static_cast<uint32_t>(127 - 15 - e) << 23) | ((m & 0x3ffu) << 13);
        }
    } else if (exp == 31) {
        x = sign | 0x7f800000u | (mant << 13);
    } else {
        x = sign | ((exp + 127 - 15) << 23) | (mant << 13);
    }
    float f;
    std::memcpy(&f, &x, 4);
    return f;
}

namespace {
double signNotZero(double v) { return v >= 0 ? 1.0 : -1.0; }
uint32_t quantise(double v) {  // [-1, 1] -> 16 bits, to nearest (the argument is >= 0: no lround call)
    return static_cast<uint32_t>((std::clamp(v, -1.0, 1.0) * 0.5 + 0.5) * 65535.0 + 0.5);
}
}  // namespace

uint32_t encodeOctahedral(const Vec3& v) {
    const double l1 = std::abs(v.x) + std::abs(v.y) + std::abs(v.z);
    double px = v.x / l1, py = v.y / l1;
    if (v.z < 0) {
        const double ox = (1 - std::abs(py)) * signNotZero(px), oy = (1 - std::abs(px)) * signNotZero(py);
        px = ox;
        py = oy;
    }
    return quantise(px) | (quantise(py) << 16);
}

void PhotonMap::add(const Point3& p, const Vec3& dir, const Vec3& normal, const Spec& power) {
    pos_.push_back(static_cast<float>(p.x));
    pos_.push_back(static_cast<float>(p.y));
    pos_.push_back(static_cast<float>(p.z));
    dir_.push_back(encodeOctahedral(dir));
    if (normals_) nrm_.push_back(encodeOctahedral(normal));
    for (int b = 0; b < bands_; ++b) pow_.push_back(floatToHalf(static_cast<float>(power[b])));
}

void PhotonMap::append(const PhotonMap& o) {
    LITTORAL_CHECK_EQ(o.bands_, bands_);
    LITTORAL_CHECK_EQ(o.normals_, normals_);
    pos_.insert(pos_.end(), o.pos_.begin(), o.pos_.end());
    dir_.insert(dir_.end(), o.dir_.begin(), o.dir_.end());
    nrm_.insert(nrm_.end(), o.nrm_.begin(), o.nrm_.end());
    pow_.insert(pow_.end(), o.pow_.begin(), o.pow_.end());
}

void PhotonMap::pack(ByteWriter& w) const {
    w.putArray(pos_.data(), pos_.size());
    w.putArray(dir_.data(), dir_.size());
    w.putArray(nrm_.data(), nrm_.size());
    w.putArray(pow_.data(), pow_.size());
}

void PhotonMap::unpack(ByteReader& r) {
    r.getArray(pos_), r.getArray(dir_), r.getArray(nrm_), r.getArray(pow_);
    LITTORAL_CHECK(dir_.size() * 3 == pos_.size() && pow_.size() == dir_.size() * static_cast<size_t>(bands_));
}

void PhotonMap::reserve(size_t n) {
    pos_.reserve(3 * n), dir_.reserve(n);
    if (normals_) nrm_.reserve(n);
    pow_.reserve(n * static_cast<size_t>(bands_));
}

void PhotonMap::clear() {
    pos_.clear(), dir_.clear(), nrm_.clear(), pow_.clear();
    bucketStart_.clear();
    cell_ = 0;
    mask_ = 0;
    dense_ = false;
}

namespace {

using Ranges = std::vector<std::pair<size_t, size_t>>;

// v[slot[i]] = v[i] (records of `stride` elements) for the i of every range, one task per range:
// each task reads its range sequentially.
template <class V> void permuteRanges(V& v, size_t stride, const Ranges& ranges, const LargeVector<uint32_t>& slot) {
    if (v.empty()) return;
    V out(v.size());
    tbb::parallel_for(size_t{0}, ranges.size(), [&](size_t r) {
        for (size_t i = ranges[r].first; i < ranges[r].second; ++i)
            std::copy_n(v.begin() + i * stride, stride, out.begin() + size_t{slot[i]} * stride);
    });
    v.swap(out);
}

constexpr int kPartBits = 10;
constexpr double kFineCellPhotons = 16;  // see build()
constexpr size_t kParts = size_t{1} << kPartBits;

// Step 1 of the sort: every photon's slot in partition order (stable), from per-block counts of
// the photons per partition (the top kPartBits bits of the bucket) scanned in (partition, block)
// order. Returns the blocks; *partStart gets each partition's first slot (and n at the end).
Ranges partitionSlots(const LargeVector<uint32_t>& bucket, int shift, LargeVector<uint32_t>* slot,
                      std::vector<size_t>* partStart) {
    const size_t n = bucket.size();
    const size_t blockSize = std::max<size_t>(size_t{1} << 16, (n + 255) / 256);
    const size_t blocks = (n + blockSize - 1) / blockSize;
    Ranges ranges;
    for (size_t k = 0; k < blocks; ++k) ranges.emplace_back(k * blockSize, std::min(n, (k + 1) * blockSize));
    std::vector<size_t> counts(blocks * kParts, 0);  // [block][partition]
    tbb::parallel_for(size_t{0}, blocks, [&](size_t k) {
        size_t* cnt = &counts[k * kParts];
        for (size_t i = ranges[k].first; i < ranges[k].second; ++i) ++cnt[bucket[i] >> shift];
    });
    partStart->assign(kParts + 1, 0);
    size_t sum = 0;
    for (size_t p = 0; p < kParts; ++p) {
        (*partStart)[p] = sum;
        for (size_t k = 0; k < blocks; ++k) {
            const size_t c = counts[k * kParts + p];
            counts[k * kParts + p] = sum;  // becomes the block's write offset
            sum += c;
        }
    }
    (*partStart)[kParts] = sum;
    tbb::parallel_for(size_t{0}, blocks, [&](size_t k) {
        size_t* off = &counts[k * kParts];
        for (size_t i = ranges[k].first; i < ranges[k].second; ++i) (*slot)[i] = static_cast<uint32_t>(off[bucket[i] >> shift]++);
    });
    return ranges;
}

// Step 2: inside each partition (buckets in partition order), a counting sort by bucket: slot[k]
// becomes the final position of the photon now at k, and bucketStart[b] the first photon of
// bucket b. Returns the partitions as ranges.
Ranges bucketSlots(const LargeVector<uint32_t>& bucket, int shift, const std::vector<size_t>& partStart,
                   LargeVector<uint32_t>* slot, LargeVector<uint32_t>* bucketStart) {
    const size_t perPart = size_t{1} << shift;
    tbb::parallel_for(size_t{0}, kParts, [&](size_t p) {
        const size_t b0 = p * perPart, s0 = partStart[p], s1 = partStart[p + 1];
        std::vector<uint32_t> next(perPart, 0);
        for (size_t k = s0; k < s1; ++k) ++next[bucket[k] - b0];
        uint32_t sum = static_cast<uint32_t>(s0);
        for (size_t j = 0; j < perPart; ++j) {
            const uint32_t c = next[j];
            (*bucketStart)[b0 + j] = next[j] = sum;
            sum += c;
        }
        for (size_t k = s0; k < s1; ++k) (*slot)[k] = next[bucket[k] - b0]++;  // stable within the partition
    });
    Ranges ranges;
    for (size_t p = 0; p < kParts; ++p) ranges.emplace_back(partStart[p], partStart[p + 1]);
    return ranges;
}

}  // namespace

void PhotonMap::build(double searchRadius) {
    LITTORAL_CHECK(searchRadius > 0);
    const size_t n = size();
    LITTORAL_CHECK(n < (size_t{1} << 32));
    // About one bucket per photon (a power of two, at least 1024), or a dense grid of the photons'
    // box where that takes at most 2 buckets per photon (a power of two too, for the sort below):
    // the table stays within the 8 B per photon the memory budget counts (core/render_budget.h).
    // Where the photons are many per cell of the radius (kFineCellPhotons on average over their
    // box), the dense grid is tried with cells of half the radius first: a query then tests about
    // half as many photons, for 8 times the cells (which costs more than it saves in sparse maps).
    uint64_t buckets = 1024;
    while (buckets < n) buckets <<= 1;
    dense_ = false;
    const BBox3 box = n > 0 ? positionBox() : BBox3{};
    for (const double cell : {0.5 * searchRadius, searchRadius}) {
        cell_ = cell;
        if (n == 0 || !denseGridBox(box, 1.0 / cell_)) continue;
        if (cell < searchRadius) {
            double cellsOfRadius = 1;  // the box's volume in cells of the radius
            for (int k = 0; k < 3; ++k) cellsOfRadius *= static_cast<double>(cellHi_[k] - cellLo_[k] + 1) * 0.5;
            if (static_cast<double>(n) < kFineCellPhotons * cellsOfRadius) continue;
        }
        const uint64_t blocks = blockN_[0] * blockN_[1] * blockN_[2];
        uint64_t denseBuckets = 1024;
        while (denseBuckets < 64 * blocks) denseBuckets <<= 1;
        if (denseBuckets <= std::max<uint64_t>(buckets, 2 * n) && denseBuckets <= (uint64_t{1} << 32)) {
            dense_ = true;
            buckets = denseBuckets;
            break;
        }
    }
    const double inv = 1.0 / cell_;  // the cells chosen above (the radius's when the grid is hashed)
    mask_ = buckets - 1;
    // A stable two-level counting sort by bucket, in parallel and deterministic (the result does
    // not depend on the threads), that moves the records in streaming passes instead of gathering
    // them in random order (a cache miss per field and photon once the map outgrows the caches):
    // (1) each block of photons counts its photons per partition (the top 10 bits of the bucket);
    // a scan in (partition, block) order gives every photon its slot in partition order, and each
    // field is scattered there (sequential reads, 1024 sequential write streams); (2) each
    // partition, a contiguous range small enough for the cache, is counting-sorted by bucket and
    // each field permuted inside it.
    const int shift = std::countr_zero(buckets) - kPartBits;  // buckets >= 1024
    LargeVector<uint32_t> bucket(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1 << 16), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i != r.end(); ++i)
            bucket[i] = static_cast<uint32_t>(bucketOf(static_cast<int64_t>(std::floor(pos_[3 * i] * inv)),
                                                       static_cast<int64_t>(std::floor(pos_[3 * i + 1] * inv)),
                                                       static_cast<int64_t>(std::floor(pos_[3 * i + 2] * inv))));
    });
    LargeVector<uint32_t> slot(n);
    std::vector<size_t> partStart;
    const Ranges blocks = partitionSlots(bucket, shift, &slot, &partStart);
    permuteRanges(bucket, 1, blocks, slot);
    permuteRanges(pos_, 3, blocks, slot);
    permuteRanges(dir_, 1, blocks, slot);
    permuteRanges(nrm_, 1, blocks, slot);
    permuteRanges(pow_, static_cast<size_t>(bands_), blocks, slot);
    bucketStart_.assign(buckets + 2, 0);
    const Ranges parts = bucketSlots(bucket, shift, partStart, &slot, &bucketStart_);
    // Bucket b holds [bucketStart_[b], bucketStart_[b + 1]); the last bucket ends at n.
    bucketStart_[buckets] = bucketStart_[buckets + 1] = static_cast<uint32_t>(n);
    permuteRanges(pos_, 3, parts, slot);
    permuteRanges(dir_, 1, parts, slot);
    permuteRanges(nrm_, 1, parts, slot);
    permuteRanges(pow_, static_cast<size_t>(bands_), parts, slot);
}

BBox3 PhotonMap::positionBox() const {
    return tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, size(), 1 << 16), BBox3{},
        [&](const tbb::blocked_range<size_t>& r, BBox3 b) {
            for (size_t i = r.begin(); i != r.end(); ++i) b.expand(position(i));
            return b;
        },
        [](BBox3 a, const BBox3& b) {
            a.expand(b);
            return a;
        });
}

bool PhotonMap::denseGridBox(const BBox3& box, double inv) {
    double blocks = 1;
    for (int k = 0; k < 3; ++k) {
        const double lo = std::floor(box.lo[k] * inv), hi = std::floor(box.hi[k] * inv);
        if (!(lo >= -1e15 && hi <= 1e15)) return false;  // far out (or not finite): hash
        cellLo_[k] = static_cast<int64_t>(lo), cellHi_[k] = static_cast<int64_t>(hi);
        blockLo_[k] = cellLo_[k] >> 2;
        blockN_[k] = static_cast<uint64_t>((cellHi_[k] >> 2) - blockLo_[k] + 1);
        blocks *= static_cast<double>(blockN_[k]);
    }
    return blocks <= 1e12;
}

size_t PhotonMap::memoryBytes() const { return size() * bytesPerPhoton() + bucketStart_.size() * sizeof(uint32_t); }

}  // namespace littoral::render
