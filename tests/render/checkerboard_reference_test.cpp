// Tests of the analytic checkerboard ray caster (tests/render/checkerboard_reference.h) against
// hand-derived geometry: it is the reference the end-to-end renderer test trusts, so it is
// checked here case by case (seed-ch01-04.md §4.5).
#include "checkerboard_reference.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace littoral::testref;

namespace {

constexpr double kN = 1.34;
const double kPiRef = std::acos(-1.0);

// A nadir camera with an odd image size so that the centre pixel's ray is exactly vertical.
CheckerboardSetup nadir(double H, double D) {
    CheckerboardSetup s;
    s.camera = {0.0, 0.0, H};
    s.width = 301;
    s.height = 301;
    s.focalLength = 0.005;
    s.pixelPitch = 1e-4;
    s.depth = D;
    s.x0 = -50; s.x1 = 50; s.y0 = -50; s.y1 = 50;
    return s;
}

}  // namespace

TEST(CheckerboardReference, ColourRuleIsParityOfFloors) {
    // Eq. 4.9: (floor(x/0.3) + floor(y/0.3)) mod 2, negative sums counting as odd.
    EXPECT_EQ(checkColour(0.1, 0.1, 0.3), 0);
    EXPECT_EQ(checkColour(0.4, 0.1, 0.3), 1);
    EXPECT_EQ(checkColour(0.4, 0.4, 0.3), 0);
    EXPECT_EQ(checkColour(-0.1, 0.1, 0.3), 1);   // floor = -1: fmod(-1, 2) = -1 -> 1
    EXPECT_EQ(checkColour(-0.1, -0.1, 0.3), 0);  // -2
    EXPECT_NEAR(checkEdgeDistance(0.31, 0.15, 0.3), 0.01, 1e-12);
    EXPECT_NEAR(checkEdgeDistance(0.15, -0.02, 0.3), 0.02, 1e-12);
}

TEST(CheckerboardReference, PixelDirectionFollowsTheSharedCameraConvention) {
    CheckerboardSetup s = nadir(20, 4.9);
    // Centre pixel of an odd image: straight down.
    const RefVec c = pixelDirection(s, 150.5, 150.5);
    EXPECT_NEAR(c.x, 0.0, 1e-15);
    EXPECT_NEAR(c.y, 0.0, 1e-15);
    EXPECT_NEAR(c.z, -1.0, 1e-15);
    // right = cross((0,0,-1), (0,1,0)) = (1,0,0); upOrtho = cross(right, forward) = (0,1,0).
    // Column + 10 -> +x by 10 pitch at focal distance; row + 10 (down the image) -> -y.
    const RefVec a = pixelDirection(s, 160.5, 140.5);
    EXPECT_NEAR(a.x / -a.z, 10 * 1e-4 / 0.005, 1e-12);
    EXPECT_NEAR(a.y / -a.z, 10 * 1e-4 / 0.005, 1e-12);  // row above centre -> +y (north)
}

TEST(CheckerboardReference, VerticalRayLandsWhereItStarted) {
    for (double D : {4.9, 9.9}) {
        CheckerboardSetup s = nadir(20, D);
        s.camera = {0.1, 0.2, 20};
        CheckerboardTrace t = traceCheckerboardPixel(s, 150, 150);
        EXPECT_EQ(t.fate, RayFate::TopThenGround);
        EXPECT_NEAR(t.landX, 0.1, 1e-12);
        EXPECT_NEAR(t.landY, 0.2, 1e-12);
        EXPECT_EQ(t.colour, 0);
        s.camera = {0.4, 0.1, 20};  // floor(0.4 / 0.3) = 1: the other colour
        t = traceCheckerboardPixel(s, 150, 150);
        EXPECT_NEAR(t.landX, 0.4, 1e-12);
        EXPECT_EQ(t.colour, 1);
        double edge = 0;
        EXPECT_EQ(checkerboardReference(s, 150, 150, &edge), 1);
        EXPECT_NEAR(edge, 0.1, 1e-12);  // x = 0.4 is 0.1 m from the edge at 0.3; y = 0.1 from 0
    }
}

TEST(CheckerboardReference, OffAxisRayThroughTopFollowsSnell) {
    // Meridional ray at nadir angle a: lands at x = (H - D) tan a + D tan(asin(sin a / n)).
    for (double D : {4.9, 9.9}) {
        const double H = 20.0;
        CheckerboardSetup s = nadir(H, D);
        for (int k : {1, 7, 40, 120}) {  // k = 120: 67 deg, still lands inside the 100 m box
            const double a = std::atan(k * 1e-4 / 0.005);
            const double b = std::asin(std::sin(a) / kN);
            const double expected = (H - D) * std::tan(a) + D * std::tan(b);
            const CheckerboardTrace t = traceCheckerboardPixel(s, 150 + k, 150);
            EXPECT_EQ(t.fate, RayFate::TopThenGround) << k;
            EXPECT_NEAR(t.landX, expected, 1e-9) << "D " << D << " k " << k;
            EXPECT_NEAR(t.landY, 0.0, 1e-12);
            // Along y too (row above the centre looks north, +y).
            const CheckerboardTrace u = traceCheckerboardPixel(s, 150, 150 - k);
            EXPECT_NEAR(u.landY, expected, 1e-9);
        }
        // Without water the same ray lands at H tan a.
        s.hasWater = false;
        const double a = std::atan(40 * 1e-4 / 0.005);
        const CheckerboardTrace t = traceCheckerboardPixel(s, 190, 150);
        EXPECT_EQ(t.fate, RayFate::Ground);
        EXPECT_NEAR(t.landX, H * std::tan(a), 1e-9);
    }
}

TEST(CheckerboardReference, ParaxialMagnificationMatchesDigest) {
    // seed-ch01-04.md §4.5: near the axis, checks seen through water are magnified by
    // M = H / (H - D + D / n) (H = 20: 1.0663 for D = 4.9, 1.1436 for D = 9.9). Ground offset per
    // pixel without water / with water -> M; one pixel off axis is 0.02 rad, where
    // tan-vs-sin differences are 1e-4 relative.
    for (auto [D, M] : {std::pair{4.9, 1.0663}, std::pair{9.9, 1.1436}}) {
        CheckerboardSetup s = nadir(20.0, D);
        const double withWater = traceCheckerboardPixel(s, 151, 150).landX;
        s.hasWater = false;
        const double without = traceCheckerboardPixel(s, 151, 150).landX;
        EXPECT_NEAR(without / withWater, M, 2e-4);
        EXPECT_NEAR(20.0 / (20.0 - D + D / kN), M, 5e-5);  // the digest's rounding
    }
}

TEST(CheckerboardReference, TotalInternalReflectionAtWall) {
    // Box wall at x1 = 7.0. A ray at nadir angle a enters the top at xe = (H - D) tan a, travels at
    // b = asin(sin a / n) from vertical and meets the wall at depth (x1 - xe) / tan b below the top.
    // Its incidence on the wall is 90 deg - b; with b < 41.73 deg that exceeds the critical
    // 48.27 deg: TIR, after which x decreases at the same rate until the ground:
    //   x_land = x1 - (D - (x1 - xe) / tan b) tan b = 2 x1 - xe - D tan b.
    const double H = 20.0, D = 9.9;
    CheckerboardSetup s = nadir(H, D);
    s.x1 = 7.0;
    const int k = 30;  // tan a = 0.6, a = 30.96 deg, b = 22.59 deg; enters at xe = 6.06 m
    const double a = std::atan(k * 1e-4 / 0.005), b = std::asin(std::sin(a) / kN);
    const double xe = (H - D) * std::tan(a);
    ASSERT_LT(xe, s.x1);                              // enters through the top
    ASSERT_LT((s.x1 - xe) / std::tan(b), D);          // meets the wall above the ground
    ASSERT_GT(std::cos(b), 1.0 / kN);                 // sin(90 - b) > 1/n: TIR predicted
    const CheckerboardTrace t = traceCheckerboardPixel(s, 150 + k, 150);
    EXPECT_EQ(t.fate, RayFate::TopTirThenGround);
    EXPECT_EQ(t.tirCount, 1);
    EXPECT_EQ(t.wallExits, 0);
    EXPECT_NEAR(t.landX, 2 * s.x1 - xe - D * std::tan(b), 1e-9);
    EXPECT_EQ(t.colour, checkColour(2 * s.x1 - xe - D * std::tan(b), 0.0, 0.3));
}

TEST(CheckerboardReference, NarrowBoxGivesRepeatedTir) {
    // Box 0.1 m wide ([-0.05, 0.05] in x), 9.9 m deep, camera 0.1 m above the water. Mirror
    // reflections at parallel walls unfold into a straight line: the ray lands where the unfolded
    // coordinate u = (H - D) tan a + D tan b folds back into the box (period 2w, w = 0.1 m), after
    // floor((u - x0) / w) reflections. Pixel 4 off axis: tan a = 0.08, tan b = 0.05962, so
    // u = 0.008 + 0.5902 = 0.5982 m: 6 reflections, landing at x = -0.0018 m.
    const double H = 10.0, D = 9.9, w = 0.1, x0 = -0.05;
    CheckerboardSetup s = nadir(H, D);
    s.x0 = x0; s.x1 = x0 + w;
    const int k = 4;
    const double a = std::atan(k * 1e-4 / 0.005), b = std::asin(std::sin(a) / kN);
    const double unfolded = (H - D) * std::tan(a) + D * std::tan(b);
    const double u = std::fmod(unfolded - x0, 2 * w);
    const double folded = x0 + (u <= w ? u : 2 * w - u);
    const int bounces = static_cast<int>(std::floor((unfolded - x0) / w));
    ASSERT_EQ(bounces, 6);
    const CheckerboardTrace t = traceCheckerboardPixel(s, 150 + k, 150);
    EXPECT_EQ(t.fate, RayFate::TopTirThenGround);
    EXPECT_EQ(t.tirCount, bounces);
    EXPECT_NEAR(t.landX, folded, 1e-9);
    EXPECT_NEAR(t.landX, -0.0018, 1e-4);  // the hand value above
}

TEST(CheckerboardReference, RefractionOutThroughWallAboveCriticalNadirAngle) {
    // Exit through a wall needs sin a > sqrt(n^2 - 1) = 0.89196 (a > 63.12 deg). Camera 0.1 m above
    // the water (H = 10, D = 9.9), box wall at x1 = 0.5, pixel with tan a = 2.8 (a = 70.35 deg).
    const double H = 10.0, D = 9.9;
    CheckerboardSetup s = nadir(H, D);
    s.x1 = 0.5;
    const int k = 140;
    const double a = std::atan(k * 1e-4 / 0.005);
    const double sb = std::sin(a) / kN, cb = std::sqrt(1 - sb * sb);
    const double xe = (H - D) * std::tan(a);
    const double zWall = D - (s.x1 - xe) * cb / sb;  // height where it meets the wall
    ASSERT_GT(zWall, 0.0);
    // At the wall (normal +x) the incidence sine is cos b; below 1/n: refraction out. Snell:
    // tangential (vertical) component scales by n: dz_out = -n cos b, dx_out = sqrt(1 - dz_out^2).
    ASSERT_LT(cb, 1.0 / kN);
    const double dzOut = kN * cb, dxOut = std::sqrt(1 - dzOut * dzOut);
    const double expected = s.x1 + zWall * dxOut / dzOut;
    const CheckerboardTrace t = traceCheckerboardPixel(s, 150 + k, 150);
    EXPECT_EQ(t.fate, RayFate::TopExitThenGround);
    EXPECT_EQ(t.wallExits, 1);
    EXPECT_EQ(t.tirCount, 0);
    EXPECT_NEAR(t.landX, expected, 1e-9);
    // Just below the threshold (a = 62 deg < 63.12) the same geometry gives TIR instead.
    const double kT = std::tan(62.0 * kPiRef / 180.0) * 0.005 / 1e-4;  // 94.04: use pixel 94
    const CheckerboardTrace u = traceCheckerboardPixel(s, 150 + static_cast<int>(kT), 150);
    EXPECT_EQ(u.wallExits, 0);
    EXPECT_GE(u.tirCount, 1);
}

TEST(CheckerboardReference, RayEnteringThroughAWallCrossesTheBoxLikeASlab) {
    // Camera outside the box (x = -1, H = 10) looking 45 deg toward +x; box [0, 2] x [-50, 50] x
    // [0, 9.9]. The ray meets the wall x = 0 at z = 9 (below the top), refracts in (sin b = sin 45 /
    // 1.34 measured from the wall normal), crosses 2 m of water, leaves through x = 2 with its
    // original direction (parallel faces), and lands displaced:
    //   z after crossing = 9 - 2 / tan(b_n), where b_n is the in-water angle from the x axis,
    //   x_land = 2 + z.
    CheckerboardSetup s = nadir(10.0, 9.9);
    s.camera = {-1.0, 0.0, 10.0};
    s.x0 = 0.0; s.x1 = 2.0;
    const RefVec d = refNormalize({1.0, 0.0, -1.0});
    const CheckerboardTrace t = traceCheckerboardRay(s, s.camera, d);
    const double sinIn = std::sin(kPiRef / 4) / kN, cosIn = std::sqrt(1 - sinIn * sinIn);
    const double zExit = 9.0 - 2.0 * sinIn / cosIn;
    EXPECT_EQ(t.fate, RayFate::WallEntry);
    EXPECT_EQ(t.wallExits, 1);
    EXPECT_NEAR(t.landX, 2.0 + zExit, 1e-9);
    EXPECT_NEAR(t.boxEdgeDistance, 0.9, 1e-9);  // entry 0.9 m below the top edge of the wall
}

TEST(CheckerboardReference, WholeImageCountsAndEdgeFlags) {
    // A 400 x 400 nadir view (20 um pitch, 33 mm lens, 20 m up: 12.12 mm per pixel on the ground
    // in air) over a 10 m box of 4.9 m water. Paraxially the water magnifies by
    // M = 20 / (20 - 4.9 + 4.9/1.34) = 1.0663, so a 0.3 m check spans p = 0.3 M / 0.01212 = 26.39 px.
    // (The lens is chosen so that p is far from an integer: at p = 28.0 every check edge falls at
    // the same phase within a pixel and the fractions below stop being uniform averages.)
    // The camera is offset so that no edge lines up with the optical axis. Expected fractions,
    // for edges uniformly placed relative to pixel centres:
    //   landing within q = 0.25 px of an edge in x or y:  1 - (1 - 2q/p)^2 = 3.75%;
    //   footprint straddling an edge (any of 4x4 + 4 corner rays differs): 1 - (1 - 1/p)^2 = 7.43%.
    // Tolerance +-15%: the view is only 15 checks wide, so the phases are sampled ~30 times per axis.
    CheckerboardSetup s;
    s.focalLength = 0.033;
    s.camera = {0.01234, 0.04567, 20.0};
    int sky = 0, nearEdge = 0, mixed = 0, tir = 0;
    const double M = 20.0 / (20.0 - 4.9 + 4.9 / 1.34);
    const double footprintWater = (20.0 * 20e-6 / 0.033) / M;
    for (int j = 0; j < s.height; ++j)
        for (int i = 0; i < s.width; ++i) {
            const CheckerboardTrace t = traceCheckerboardPixel(s, i, j);
            double e = 0;
            const int c = checkerboardReference(s, i, j, &e);
            EXPECT_EQ(c, t.colour);
            if (c < 0) ++sky;
            if (e < 0.25 * footprintWater) ++nearEdge;
            if (t.tirCount > 0) ++tir;
            if (!checkerboardPixelUniform(s, i, j)) ++mixed;
        }
    EXPECT_EQ(sky, 0);
    EXPECT_EQ(tir, 0);  // half-angle 7 deg: every ray in the box reaches the ground directly
    const double fracEdge = nearEdge / 160000.0, fracMixed = mixed / 160000.0;
    EXPECT_NEAR(fracEdge, 0.0375, 0.15 * 0.0375);
    EXPECT_NEAR(fracMixed, 0.0743, 0.15 * 0.0743);
}
