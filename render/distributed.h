#pragma once
// Work split across the ranks of a run (core/ranks.h): items [0, n) whose results depend only on
// their number, claimed in batches from a queue the ranks share, and exchanged afterwards, so the
// result is the single process's whatever rank did which item.
#include <algorithm>
#include <cstdint>

#include "core/ranks.h"

namespace littoral::render {

enum class ShareWith { AllRanks, Root };

// run(begin, end) computes items [begin, end) on this rank (with its threads). With one process that
// is run(0, n) and nothing else. With several ranks, each claims batches of `batch` items (0: about
// 8 batches per rank) until none are left; then pack(i, writer) serialises each of its items, and
// unpack(i, reader) reads every other rank's items on every rank (AllRanks) or on rank 0 (Root).
template <class Run, class Pack, class Unpack>
void distributeItems(uint64_t n, uint64_t batch, ShareWith share, Run&& run, Pack&& pack, Unpack&& unpack) {
    const RankGroup& g = ranks();
    if (g.size() == 1) {
        if (n > 0) run(uint64_t{0}, n);
        return;
    }
    if (batch == 0) batch = std::max<uint64_t>(1, n / (8 * static_cast<uint64_t>(g.size())));
    ByteWriter w;
    {
        const std::unique_ptr<WorkQueue> queue = g.workQueue();
        for (;;) {
            const uint64_t b = queue->next() * batch;
            if (b >= n) break;
            const uint64_t e = std::min(n, b + batch);
            run(b, e);
            w.put(b), w.put(e);
            for (uint64_t i = b; i < e; ++i) pack(i, w);
        }
    }
    const std::vector<Bytes> all = share == ShareWith::AllRanks ? g.allGather(w.bytes()) : g.gatherToRoot(w.bytes());
    for (size_t r = 0; r < all.size(); ++r) {
        if (static_cast<int>(r) == g.rank()) continue;
        ByteReader rd(all[r]);
        while (!rd.atEnd()) {
            const uint64_t b = rd.get<uint64_t>(), e = rd.get<uint64_t>();
            for (uint64_t i = b; i < e; ++i) unpack(i, rd);
        }
    }
}

}  // namespace littoral::render
