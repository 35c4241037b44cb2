#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>

#include "core/large_buffer.h"

using namespace littoral;

// Large buffers start on a 2 MiB boundary (so huge pages can back them from the first byte);
// small ones come from the ordinary heap. Contents survive growth across the 2 MiB threshold,
// copies and swaps (the allocator's two paths free what they allocated: the sanitizer build
// checks the pairing).
TEST(LargeBuffer, AlignmentAndContents) {
    LargeVector<uint32_t> v;
    for (uint32_t i = 0; i < 3'000'000; ++i) v.push_back(i * 7u);  // 12 MB, crosses 2 MiB while growing
    EXPECT_EQ(reinterpret_cast<uintptr_t>(v.data()) % (uintptr_t{2} << 20), 0u);
    LargeVector<uint32_t> copy = v, small(100, 5u);
    for (uint32_t i = 0; i < 3'000'000; i += 999) ASSERT_EQ(copy[i], i * 7u);
    small.swap(copy);
    EXPECT_EQ(small.size(), 3'000'000u);
    EXPECT_EQ(copy.size(), 100u);
    EXPECT_EQ(std::accumulate(copy.begin(), copy.end(), 0u), 500u);  // explicit values are kept
    copy.resize(5'000'000);  // default-initialised tail; the head is preserved
    EXPECT_EQ(copy[99], 5u);
    copy.assign(1'000'000, 0u);
    EXPECT_EQ(std::accumulate(copy.begin(), copy.end(), uint64_t{0}), 0u);
}
