#include <gtest/gtest.h>

#include "core/error.h"
#include "core/spectrum.h"

using namespace littoral;

// Linear interpolation is exact for a linear function, and the band average of a linear
// function equals its value at the band centre.
TEST(Spectrum, InterpolationAndBandAverageExactForLinear) {
    auto f = [](double w) { return 3.0 * w - 0.5; };
    std::vector<double> wl, v;
    for (double w = 0.35; w <= 0.801; w += 0.05) { wl.push_back(w); v.push_back(f(w)); }
    const auto s = Spectrum::tabulated(wl, v);
    for (double w = 0.36; w < 0.8; w += 0.0137) EXPECT_NEAR(s.at(w), f(w), 1e-12);
    for (const auto& b : uniformBands(0.4, 0.7, 7)) EXPECT_NEAR(s.bandAverage(b), f(b.center()), 1e-12);
}

// Band integration of a piecewise-linear table is exact: a tent 0 -> 1 -> 0 over [0.4, 0.6]
// integrates to 0.1 um; half of it lies in [0.4, 0.5].
TEST(Spectrum, IntegrationOfTent) {
    const auto s = Spectrum::tabulated({0.4, 0.5, 0.6}, {0.0, 1.0, 0.0});
    EXPECT_NEAR(s.integrate(0.4, 0.6), 0.1, 1e-15);
    EXPECT_NEAR(s.integrate(0.4, 0.5), 0.05, 1e-15);
    EXPECT_NEAR(s.integrate(0.45, 0.55), 0.075, 1e-15);  // 0.1 - 2 * (0.5 * 0.05 * 0.5)
    EXPECT_NEAR(s.bandAverage({0.45, 0.55}), 0.75, 1e-12);
}

TEST(Spectrum, ConstantCoversEverything) {
    const auto s = Spectrum::constant(0.25);
    EXPECT_TRUE(s.covers(0.1, 15));
    EXPECT_DOUBLE_EQ(s.bandAverage({2.0, 2.5}), 0.25);
}

TEST(Spectrum, BandOutsideTableIsAnInputError) {
    const auto s = Spectrum::tabulated({0.4, 0.5, 0.6}, {0.1, 0.2, 0.3});
    try {
        s.bandAverage({0.55, 0.65}, "reflectance of 'sand'");
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("reflectance of 'sand'"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("[0.4, 0.6]"), std::string::npos);
    }
}

TEST(Spectrum, MalformedTablesRejected) {
    EXPECT_THROW(Spectrum::tabulated({0.5, 0.4}, {1, 2}), InputError);
    EXPECT_THROW(Spectrum::tabulated({0.4, 0.5}, {1}), InputError);
    EXPECT_THROW(Spectrum::tabulated({}, {}), InputError);
}

TEST(Bands, UniformBandsTileTheRange) {
    const auto b = uniformBands(0.4, 0.7, 3);
    ASSERT_EQ(b.size(), 3u);
    EXPECT_DOUBLE_EQ(b[0].lo, 0.4);
    EXPECT_DOUBLE_EQ(b[2].hi, 0.7);
    EXPECT_DOUBLE_EQ(b[1].lo, b[0].hi);
    EXPECT_NEAR(b[1].center(), 0.55, 1e-15);
}
