// Tests of render/film: layout, band lookup, statistics, truth image initialisation.
#include "render/film.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.h"

using namespace littoral;
using namespace littoral::render;

TEST(Film, LayoutIsBandInterleavedByPixelTopRowFirst) {
    Film f(3, 2, {Band{0.4, 0.5}, Band{0.5, 0.6}});
    ASSERT_EQ(f.pixels.size(), 3u * 2u * 2u);
    f.at(2, 1, 1) = 7.0f;  // last pixel, last band: index (1*3 + 2)*2 + 1 = 11
    f.at(1, 0, 0) = 3.0f;  // index (0*3 + 1)*2 + 0 = 2
    EXPECT_EQ(f.pixels[11], 7.0f);
    EXPECT_EQ(f.pixels[2], 3.0f);
    const Film& c = f;
    EXPECT_EQ(c.at(2, 1, 1), 7.0f);
    const std::vector<float> plane = f.bandPlane(1);
    EXPECT_EQ(plane[1 * 3 + 2], 7.0f);
    std::vector<float> p0(6, 2.0f);
    f.setBandPlane(0, p0);
    EXPECT_EQ(f.at(1, 0, 0), 2.0f);
    EXPECT_EQ(f.at(2, 1, 1), 7.0f);  // the other band is untouched
}

TEST(Film, OutOfRangeAccessIsInternalError) {
    Film f(2, 2, {Band{0.4, 0.6}});
    EXPECT_THROW(f.at(2, 0, 0), InternalError);
    EXPECT_THROW(f.at(0, -1, 0), InternalError);
    EXPECT_THROW(f.at(0, 0, 1), InternalError);
}

TEST(Film, InvalidConstructionIsInputError) {
    EXPECT_THROW(Film(0, 4, {Band{0.4, 0.6}}), InputError);
    EXPECT_THROW(Film(4, -1, {Band{0.4, 0.6}}), InputError);
    EXPECT_THROW(Film(4, 4, {}), InputError);
    EXPECT_THROW(Film(4, 4, {Band{0.6, 0.4}}), InputError);
    EXPECT_THROW(TruthImages(0, 3), InputError);
}

TEST(Film, BandLookupByWavelength) {
    Film f(1, 1, uniformBands(0.4, 0.7, 3));  // [0.4,0.5) [0.5,0.6) [0.6,0.7], centres 0.45 0.55 0.65
    EXPECT_EQ(f.nearestBand(0.45), 0);
    EXPECT_EQ(f.nearestBand(0.56), 1);
    EXPECT_EQ(f.nearestBand(0.90), 2);
    EXPECT_EQ(f.nearestBand(0.10), 0);
    EXPECT_EQ(f.nearestBand(0.50), 0);  // tie between centres 0.45 and 0.55: lower index
    EXPECT_EQ(f.bandContaining(0.40), 0);
    EXPECT_EQ(f.bandContaining(0.5), 1);  // half-open intervals
    EXPECT_EQ(f.bandContaining(0.7), 2);  // the last band includes its upper edge
    EXPECT_EQ(f.bandContaining(0.71), -1);
    EXPECT_EQ(f.bandContaining(0.39), -1);
}

TEST(Film, BandStatisticsAgainstHandValues) {
    // Values 1, 2, 3, 4 and a NaN and +inf: mean 2.5, population variance 1.25, sd 1.1180340.
    Film f(6, 1, {Band{0.4, 0.6}});
    const float v[6] = {1, 2, 3, 4, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()};
    for (int x = 0; x < 6; ++x) f.at(x, 0, 0) = v[x];
    const BandStats s = bandStats(f, 0);
    EXPECT_EQ(s.finite, 4u);
    EXPECT_EQ(s.nonFinite, 2u);
    EXPECT_DOUBLE_EQ(s.min, 1.0);
    EXPECT_DOUBLE_EQ(s.max, 4.0);
    EXPECT_NEAR(s.mean, 2.5, 1e-15);
    EXPECT_NEAR(s.stddev, std::sqrt(1.25), 1e-15);
    // Type-7 quantiles of {1,2,3,4}: q = 0.5 -> h = 1.5 -> 2.5; q = 0.9 -> h = 2.7 -> 3.7.
    EXPECT_NEAR(bandQuantile(f, 0, 0.5), 2.5, 1e-12);
    EXPECT_NEAR(bandQuantile(f, 0, 0.9), 3.7, 1e-6);
    EXPECT_DOUBLE_EQ(bandQuantile(f, 0, 0.0), 1.0);
    EXPECT_DOUBLE_EQ(bandQuantile(f, 0, 1.0), 4.0);
    EXPECT_THROW(bandQuantile(f, 0, 1.5), InputError);
}

TEST(Film, StatisticsAreStableForLargeOffsets) {
    // 10^6 values 1e4 + (0 or 1) alternating: mean 1e4 + 0.5, sd exactly 0.5. A naive
    // sum-of-squares in float would lose the 0.5 entirely (1e8 needs 27 bits).
    Film f(1000, 1000, {Band{0.4, 0.6}});
    for (std::size_t p = 0; p < f.pixels.size(); ++p) f.pixels[p] = 1.0e4f + static_cast<float>(p % 2);
    const BandStats s = bandStats(f, 0);
    EXPECT_NEAR(s.mean, 1.0e4 + 0.5, 1e-9);
    EXPECT_NEAR(s.stddev, 0.5, 1e-9);
}

TEST(TruthImages, InitialisedToNothingHit) {
    TruthImages t(4, 3);
    ASSERT_EQ(t.materialId.size(), 12u);
    EXPECT_EQ(t.materialId[5], -1);
    EXPECT_TRUE(std::isinf(t.range[5]) && t.range[5] > 0);
    EXPECT_TRUE(std::isnan(t.hitDepth[5]));
    EXPECT_EQ(t.index(3, 2), 11u);
}
