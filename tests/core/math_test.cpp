#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/bbox.h"
#include "core/frame.h"
#include "core/rng.h"
#include "core/units.h"
#include "core/vec.h"

using namespace littoral;

// Identities hold to rounding: |a x b|^2 + (a.b)^2 = |a|^2 |b|^2 (Lagrange), a.(a x b) = 0.
TEST(Vec3, LagrangeIdentityAndOrthogonality) {
    RandomStream rs(1, 0, 0);
    for (int i = 0; i < 1000; ++i) {
        const Vec3 a{rs.uniform() * 2 - 1, rs.uniform() * 2 - 1, rs.uniform() * 2 - 1};
        const Vec3 b{rs.uniform() * 2 - 1, rs.uniform() * 2 - 1, rs.uniform() * 2 - 1};
        const double lhs = lengthSquared(cross(a, b)) + sqr(dot(a, b));
        EXPECT_NEAR(lhs, lengthSquared(a) * lengthSquared(b), 1e-14);
        EXPECT_NEAR(dot(a, cross(a, b)), 0.0, 1e-15);
    }
}

// The inline fmin / fmax keep the library's rule, checked against it: the smaller (larger) of two
// numbers, the other where one is NaN, over signed values, infinities and NaN in both places.
TEST(Vec3, InlineMinMaxFollowTheLibrary) {
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    const double v[] = {-inf, -2.5, -1e-300, 0.0, 3.0, 1e300, inf, nan};
    for (double a : v)
        for (double b : v) {
            const double lo = fminInline(a, b), hi = fmaxInline(a, b);
            if (std::isnan(std::fmin(a, b))) EXPECT_TRUE(std::isnan(lo)) << a << " " << b;
            else EXPECT_EQ(lo, std::fmin(a, b)) << a << " " << b;
            if (std::isnan(std::fmax(a, b))) EXPECT_TRUE(std::isnan(hi)) << a << " " << b;
            else EXPECT_EQ(hi, std::fmax(a, b)) << a << " " << b;
        }
    EXPECT_EQ(vmin(Vec3{1, nan, -inf}, Vec3{nan, 2, 0}).y, 2.0);
    EXPECT_EQ(vmax(Vec3{1, nan, -inf}, Vec3{nan, 2, 0}).x, 1.0);
}

// Frames built from any normal (including both poles) are orthonormal and right-handed,
// and toLocal/toWorld are inverse to rounding.
TEST(Frame, OrthonormalForAllNormals) {
    RandomStream rs(2, 0, 0);
    std::vector<Vec3> normals = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}, {1e-9, 0, -1}};
    for (int i = 0; i < 1000; ++i) {
        const double z = 2 * rs.uniform() - 1, phi = 2 * kPi * rs.uniform();
        const double r = std::sqrt(1 - z * z);
        normals.push_back({r * std::cos(phi), r * std::sin(phi), z});
    }
    for (const Vec3& n : normals) {
        const Frame f = Frame::fromNormal(n);
        EXPECT_NEAR(length(f.s), 1.0, 1e-12);
        EXPECT_NEAR(length(f.t), 1.0, 1e-12);
        EXPECT_NEAR(dot(f.s, f.t), 0.0, 1e-12);
        EXPECT_NEAR(dot(f.s, f.n), 0.0, 1e-12);
        EXPECT_NEAR(dot(f.t, f.n), 0.0, 1e-12);
        EXPECT_NEAR(dot(cross(f.s, f.t), f.n), 1.0, 1e-12);
        const Vec3 v{0.3, -0.2, 0.9};
        EXPECT_NEAR(length(f.toWorld(f.toLocal(v)) - v), 0.0, 1e-12);
    }
}

// Snell's law n1 sin(t1) = n2 sin(t2) (dissertation Eq. 4.1), and total internal reflection
// beyond the critical angle asin(1/1.34) = 48.27 deg for water-to-air.
TEST(Refract, SnellAndCriticalAngle) {
    const double n = 1.34;
    for (double deg = 0; deg < 89.5; deg += 0.5) {
        const double ti = deg2rad(deg);
        const Vec3 wi{std::sin(ti), 0, std::cos(ti)};  // air side, pointing away from the surface
        Vec3 wt;
        ASSERT_TRUE(refract(wi, {0, 0, 1}, 1.0 / n, &wt));
        EXPECT_NEAR(length(wt), 1.0, 1e-12);
        EXPECT_NEAR(std::sin(ti), n * std::hypot(wt.x, wt.y), 1e-12);
        EXPECT_LT(wt.z, 0.0);
    }
    const double crit = std::asin(1.0 / n);
    EXPECT_NEAR(rad2deg(crit), 48.2682, 1e-4);
    Vec3 wt;
    const double below = crit - 1e-6, above = crit + 1e-6;
    EXPECT_TRUE(refract({std::sin(below), 0, std::cos(below)}, {0, 0, 1}, n, &wt));
    EXPECT_FALSE(refract({std::sin(above), 0, std::cos(above)}, {0, 0, 1}, n, &wt));
}

TEST(BBox, SlabIntersection) {
    BBox3 b;
    b.expand(Vec3{-1, -1, -1});
    b.expand(Vec3{1, 1, 1});
    double t0, t1;
    ASSERT_TRUE(b.intersect(Ray{{-5, 0, 0}, {1, 0, 0}}, &t0, &t1));
    EXPECT_DOUBLE_EQ(t0, 4.0);
    EXPECT_DOUBLE_EQ(t1, 6.0);
    EXPECT_FALSE(b.intersect(Ray{{-5, 2, 0}, {1, 0, 0}}, &t0, &t1));
}

// cosSinTurns(u) = (cos 2 pi u, sin 2 pi u) to within 1e-15 for u in [0, 1): its series are cut
// below 5e-17, and the rest is rounding, in the function and in the reference, whose angle 2 pi u
// itself rounds by up to 4.4e-16 rad (the largest difference seen: 7.2e-16 over 4 M angles). At 10^5
// random angles, every octant boundary and either side of it; outside [0, 1) within 3e-15 plus
// 1e-15 |u| (reducing u to one turn rounds to 2.2e-16 of a turn, 1.4e-15 rad); against libm.
TEST(CosSinTurns, MatchesTheLibraryToRounding) {
    auto check = [](double u) {
        const CosSin cs = cosSinTurns(u);
        const double a = 2.0 * kPi * (u - std::floor(u));
        const double tol = u >= 0 && u < 1 ? 1e-15 : 3e-15 + 1e-15 * std::abs(u);
        EXPECT_NEAR(cs.c, std::cos(a), tol) << u;
        EXPECT_NEAR(cs.s, std::sin(a), tol) << u;
    };
    RandomStream rs(7, 0, 0);
    for (int i = 0; i < 100000; ++i) check(rs.uniform());
    for (int k = -8; k <= 16; ++k)
        for (double d : {0.0, 1e-17, -1e-17, 1e-9, -1e-9}) check(k / 8.0 + d);
    check(0x1.fffffffffffffp-1);  // the largest uniform below 1: the reduction must give quadrant 0, not 4
    check(-3.3), check(12.625), check(-1e-300);
}
