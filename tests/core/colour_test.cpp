// The colorimetry of the true-colour previews (core/colour.h) against properties of the CIE 1931
// observer and the sRGB standard that hold independently of the code.
#include "core/colour.h"

#include <gtest/gtest.h>

namespace littoral {
namespace {

// The CIE 1931 functions are normalised so that an equal-energy spectrum has X = Y = Z (CIE 15):
// their 5 nm sums over 380-780 nm agree to 1e-5 relative (21.3716, 21.3713, 21.3715).
TEST(Colour, EqualEnergyIntegralsOfTheObserverAgree) {
    Xyz s;
    for (int nm = 380; nm <= 780; nm += 5) {
        const Xyz c = cieCmf(nm * 1e-3);
        s.x += c.x, s.y += c.y, s.z += c.z;
    }
    EXPECT_NEAR(s.x / s.y, 1.0, 2e-5);
    EXPECT_NEAR(s.z / s.y, 1.0, 2e-5);
    EXPECT_NEAR(s.y, 21.3713, 1e-3);  // sum of ybar at 5 nm; ybar(555 nm) = 1 by definition
    EXPECT_EQ(cieCmf(0.555).y, 1.0);
    EXPECT_EQ(cieCmf(0.3).x, 0.0);
}

// A flat spectrum is reproduced by any bands: Y equals its radiance and x = y = 1/3.
TEST(Colour, FlatSpectrumIsTheEqualEnergyWhiteForAnyBands) {
    for (const std::vector<Band>& bands :
         {std::vector<Band>{{0.4, 0.5}, {0.5, 0.6}, {0.6, 0.7}}, std::vector<Band>{{0.45, 0.47}, {0.55, 0.56}, {0.66, 0.68}},
          std::vector<Band>{{0.38, 0.78}}}) {
        const std::vector<Xyz> w = xyzBandWeights(bands);
        Xyz c;
        for (const Xyz& b : w) c.x += 7 * b.x, c.y += 7 * b.y, c.z += 7 * b.z;
        EXPECT_NEAR(c.y, 7.0, 1e-9);
        EXPECT_NEAR(chromaticity(c)[0], 1.0 / 3.0, 1e-4);
        EXPECT_NEAR(chromaticity(c)[1], 1.0 / 3.0, 1e-4);
    }
}

// sRGB (IEC 61966-2-1): the D65 white (x, y) = (0.3127, 0.3290) is R = G = B, the transfer curve
// meets 0.0031308 -> 0.04045 continuously, and decode inverts encode.
TEST(Colour, SrgbWhitePointAndTransferCurve) {
    const double x = 0.3127, y = 0.3290;
    const std::array<double, 3> rgb = xyzToLinearSrgb({x / y, 1.0, (1 - x - y) / y});
    EXPECT_NEAR(rgb[0], 1.0, 1e-3);
    EXPECT_NEAR(rgb[1], 1.0, 1e-3);
    EXPECT_NEAR(rgb[2], 1.0, 1e-3);
    const Xyz back = linearSrgbToXyz(rgb);
    EXPECT_NEAR(chromaticity(back)[0], x, 2e-4);
    EXPECT_NEAR(chromaticity(back)[1], y, 2e-4);
    EXPECT_NEAR(srgbEncode(0.0031308), 0.04045, 1e-5);
    for (double v : {0.0, 0.002, 0.01, 0.18, 0.5, 1.0}) EXPECT_NEAR(srgbDecode(srgbEncode(v)), v, 1e-12);
    EXPECT_NEAR(srgbEncode(0.18), 0.4614, 1e-4);  // mid grey
}

// The preview needs bands that reach across the visible: three bands over 0.4-0.7 um do (the
// range holds > 97 % of each function), the dissertation's two bands over 0.4-0.6 um do not
// (xbar's long-wave lobe lies mostly beyond 0.6 um).
TEST(Colour, BandsSpanTheVisibleOnlyAcrossBlueToRed) {
    EXPECT_TRUE(spansVisible({{0.4, 0.5}, {0.5, 0.6}, {0.6, 0.7}}));
    EXPECT_GT(visibleCoverage({{0.4, 0.5}, {0.5, 0.6}, {0.6, 0.7}}), 0.97);
    EXPECT_FALSE(spansVisible({{0.4, 0.5}, {0.5, 0.6}}));
    EXPECT_FALSE(spansVisible({{0.40, 0.45}, {0.45, 0.5}, {0.5, 0.6}}));
    EXPECT_LT(visibleCoverage({{0.4, 0.5}, {0.5, 0.6}}), 0.7);
    EXPECT_FALSE(spansVisible({{0.4, 0.7}, {0.4, 0.7}}));  // fewer than 3 bands
}

}  // namespace
}  // namespace littoral
