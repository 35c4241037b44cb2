#pragma once
// Counter-based random numbers. Every sample is a pure function of
// (seed, pass, index, dimension), so a render gives the same numbers whatever the thread count
// or scheduling. The mixing function is a keyed 64-bit hash built from the SplitMix64 /
// Stafford "Mix13" finalizer applied in a chain; it passes the avalanche checks in the tests.
#include <cstdint>

namespace littoral {

constexpr uint64_t mix64(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

// The chain's first three links depend only on the stream, (seed, pass, index); a stream keeps
// their result, so each draw costs one mix64 and the numbers are those of hashKey.
constexpr uint64_t streamKey(uint64_t seed, uint64_t pass, uint64_t index) {
    uint64_t h = mix64(seed + 0x9e3779b97f4a7c15ULL);
    h = mix64(h ^ (pass + 0x632be59bd9b4e019ULL));
    return mix64(h ^ (index + 0x85157af5ULL * 0x9e3779b97f4a7c15ULL));
}
constexpr uint64_t drawKey(uint64_t stream, uint64_t dim) { return mix64(stream ^ (dim + 0xd1b54a32d192ed03ULL)); }

constexpr uint64_t hashKey(uint64_t seed, uint64_t pass, uint64_t index, uint64_t dim) {
    return drawKey(streamKey(seed, pass, index), dim);
}

// Uniform double in [0, 1) from the top 53 bits.
constexpr double toUnit(uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-53; }

// A stream for one (seed, pass, index): successive calls draw successive dimensions.
class RandomStream {
public:
    constexpr RandomStream(uint64_t seed, uint64_t pass, uint64_t index, uint64_t firstDim = 0)
        : key_(streamKey(seed, pass, index)), dim_(firstDim) {}
    constexpr double uniform() { return toUnit(drawKey(key_, dim_++)); }
    constexpr uint64_t bits() { return drawKey(key_, dim_++); }
    // Random access without advancing.
    constexpr double at(uint64_t dim) const { return toUnit(drawKey(key_, dim)); }
    constexpr uint64_t dimension() const { return dim_; }
    void skipTo(uint64_t dim) { dim_ = dim; }

private:
    uint64_t key_, dim_;
};

}  // namespace littoral
