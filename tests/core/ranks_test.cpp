// core/ranks.h without MPI: the one-process group and the byte packing the ranks' exchanges use
// (the MPI group itself is tested by running the command under mpirun, tests/pipelines/mpi_runs_test.cpp).
#include "core/ranks.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

namespace littoral {
namespace {

TEST(Ranks, OneProcessIsRankZeroOfOneAndItsExchangesAreItsOwnBytes) {
    EXPECT_EQ(ranks().rank(), 0);
    EXPECT_EQ(ranks().size(), 1);
    EXPECT_TRUE(isRootRank());
    const Bytes mine{'a', 'b', 'c'};
    EXPECT_EQ(ranks().allGather(mine), std::vector<Bytes>{mine});
    EXPECT_EQ(ranks().gatherToRoot(mine), std::vector<Bytes>{mine});
    EXPECT_EQ(sumOverRanks({3, -4, 5}), (std::vector<int64_t>{3, -4, 5}));
    const auto queue = ranks().workQueue();
    for (uint64_t k = 0; k < 5; ++k) EXPECT_EQ(queue->next(), k);
}

TEST(Ranks, PackedValuesAndArraysReadBackBitForBit) {
    ByteWriter w;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    w.put(-0.0), w.put(nan), w.put(uint64_t{1} << 63), w.put(float(1e-40f));  // a denormal float
    const std::vector<uint16_t> halves{1, 0x7c00, 0xffff};
    w.putArray(halves.data(), halves.size());
    w.putArray<float>(nullptr, 0);
    ByteReader r(w.bytes());
    const double z = r.get<double>();
    EXPECT_TRUE(z == 0.0 && std::signbit(z));
    EXPECT_TRUE(std::isnan(r.get<double>()));
    EXPECT_EQ(r.get<uint64_t>(), uint64_t{1} << 63);
    EXPECT_EQ(r.get<float>(), 1e-40f);
    std::vector<uint16_t> back;
    r.getArray(back);
    EXPECT_EQ(back, halves);
    std::vector<float> none{1.f};
    r.getArray(none);
    EXPECT_TRUE(none.empty());
    EXPECT_TRUE(r.atEnd());
    // Reading past the end is a bug of the exchange, not bad input.
    EXPECT_THROW(r.get<char>(), InternalError);
}

}  // namespace
}  // namespace littoral
