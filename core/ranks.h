#pragma once
// The processes of one run, as the renderer sees them: one process (the default), or the ranks of
// an MPI job (`mpirun -np N littoral render ...`; pipelines/lib_mpi.cpp installs them). Nothing here
// depends on MPI, so render/ compiles and runs without it.
//
// The renderer splits work into numbered items (photon chunks, image tiles, probe sample chunks)
// whose results depend only on their number. Ranks claim items from a shared queue (dynamic balance),
// trace them with their threads, and exchange the results (render/distributed.h), so every rank, or
// rank 0 alone, ends up with the values a single process computes: byte for byte the same outputs
// for any number of ranks. Rank 0 writes every output.
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "core/error.h"

namespace littoral {

using Bytes = std::vector<char>;

// Successive calls on any rank return 0, 1, 2, ..., each number once across all ranks.
class WorkQueue {
public:
    virtual ~WorkQueue() = default;
    virtual uint64_t next() = 0;
};

class RankGroup {
public:
    virtual ~RankGroup() = default;
    virtual int rank() const { return 0; }
    virtual int size() const { return 1; }
    // Collectives: every rank calls them, in the same order, from the thread that started the
    // command (the MPI library is initialised for that thread alone).
    // Every rank's bytes, in rank order, on every rank.
    virtual std::vector<Bytes> allGather(const Bytes& mine) const { return {mine}; }
    // Every rank's bytes, in rank order, on rank 0; the other ranks get an empty list.
    virtual std::vector<Bytes> gatherToRoot(const Bytes& mine) const { return {mine}; }
    // A queue shared by the ranks (created and destroyed by all of them together).
    virtual std::unique_ptr<WorkQueue> workQueue() const;
};

// The current group: one process unless setRanks installed another.
const RankGroup& ranks();
void setRanks(std::unique_ptr<RankGroup> group);
inline bool isRootRank() { return ranks().rank() == 0; }
// The element-wise sums of every rank's values, on every rank (a collective).
std::vector<int64_t> sumOverRanks(const std::vector<int64_t>& mine);

// Packing plain values and arrays into Bytes for the exchanges.
class ByteWriter {
public:
    template <class T> void put(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        const size_t at = bytes_.size();
        bytes_.resize(at + sizeof(T));
        std::memcpy(bytes_.data() + at, &v, sizeof(T));
    }
    template <class T> void putArray(const T* p, size_t n) {
        static_assert(std::is_trivially_copyable_v<T>);
        put<uint64_t>(n);
        const size_t at = bytes_.size();
        bytes_.resize(at + n * sizeof(T));
        if (n > 0) std::memcpy(bytes_.data() + at, p, n * sizeof(T));
    }
    const Bytes& bytes() const { return bytes_; }

private:
    Bytes bytes_;
};

class ByteReader {
public:
    explicit ByteReader(const Bytes& b) : b_(b) {}
    bool atEnd() const { return at_ == b_.size(); }
    template <class T> T get() {
        T v;
        take(&v, sizeof(T));
        return v;
    }
    // Reads an array written by putArray into `out` (resized).
    template <class V> void getArray(V& out) {
        const uint64_t n = get<uint64_t>();
        out.resize(static_cast<size_t>(n));
        if (n > 0) take(out.data(), static_cast<size_t>(n) * sizeof(out[0]));
    }

private:
    void take(void* p, size_t n) {
        LITTORAL_CHECK(at_ + n <= b_.size());  // the ranks run one binary: a short message is a bug
        std::memcpy(p, b_.data() + at_, n);
        at_ += n;
    }
    const Bytes& b_;
    size_t at_ = 0;
};

}  // namespace littoral
