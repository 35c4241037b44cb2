// tests/support/sinusoid_caustics.h against spec/seed-ch05-10.md section 1.8 and test CH5-G: the
// landing shifts of vertical rays under A = 2.0 m, lambda = 5.0 m for water depths 6.0 and 10.0 m
// in both conventions of the digest, the crest focal depth, that a refracted ray never meets the
// surface again, and that the caustic lines found as folds of the landing map are where a dense
// fan of rays piles up.
#include "tests/support/sinusoid_caustics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

using namespace littoral::testing_support::sinusoid;

namespace {
Wave wave(double depth, double trough) {
    Wave w;
    w.amplitude = 2.0;
    w.wavelength = 5.0;
    w.depth = depth;
    w.trough = trough;
    return w;
}
// Distance between positions on a circle of circumference lambda (the pattern repeats).
double periodicDistance(double a, double b, double lambda) {
    const double d = std::fmod(std::abs(a - b), lambda);
    return std::min(d, lambda - d);
}
}  // namespace

// Digest table (shift X_d - X, 3 decimals, rays at X = 0, 2, 4, 6, 8): the literal Eq. 5.21
// Y = A sin(kX) is our profile with its trough at X0 = -lambda/4; DIRSIG's puts it at 0.
TEST(SinusoidCaustics, LandingShiftsMatchDigest) {
    struct Row { double X0, D; double shift[5]; };
    const Row rows[] = {
        {-1.25, 6.0, {2.722, -2.866, 0.766, 1.478, -1.927}},
        {-1.25, 10.0, {4.537, -4.463, 1.514, 2.226, -3.524}},
        {0.0, 6.0, {0.000, 2.436, -2.373, 2.373, -2.436}},
        {0.0, 10.0, {0.000, 3.716, -4.136, 4.136, -3.716}},
    };
    for (const Row& r : rows) {
        const Wave w = wave(r.D, r.X0);
        for (int i = 0; i < 5; ++i) {
            const double X = 2.0 * i;
            EXPECT_NEAR(w.landing(X) - X, r.shift[i], 0.0005 + 1e-12) << "X0 " << r.X0 << " D " << r.D << " X " << X;
        }
        // The pattern repeats every 10 m (5 samples at 2 m): rays 5 samples apart shift alike.
        for (int i = 0; i < 9; ++i) EXPECT_NEAR(w.landing(2.0 * (i + 5)) - 2.0 * (i + 5), w.landing(2.0 * i) - 2.0 * i, 1e-9);
    }
    // The digest's worked example, literal form, X = 0: slope 2.513, theta_i = 68.30 deg,
    // theta_r = 43.90 deg, deviation 24.40 deg.
    const Wave lit = wave(6.0, -1.25);
    EXPECT_NEAR(lit.slope(0.0), 2.513, 0.0005);
    EXPECT_NEAR(lit.deviation(lit.slope(0.0)) * 180 / kPi, 24.40, 0.005);
}

// Section 1.8: focal depth below a crest 1 / ((1 - n_i/n_t) A k^2) ~ 1.25 m for A = 2, lambda = 5;
// ~133 m for the Zhai case A = 0.3, lambda = 20 (both printed to 3 significant figures). And the
// landing map's derivative at a crest is exactly 1 - H / f there, so it vanishes at H = f.
TEST(SinusoidCaustics, CrestFocalDepth) {
    Wave w = wave(6.0, 0.0);
    EXPECT_NEAR(w.crestFocalDepth(), 1.25, 0.005);
    Wave z = w;
    z.amplitude = 0.3;
    z.wavelength = 20.0;
    EXPECT_NEAR(z.crestFocalDepth(), 133.0, 0.5);
    const double crest = w.trough + 0.5 * w.wavelength;
    w.depth = w.crestFocalDepth() - w.amplitude;  // H = D + A at the crest
    EXPECT_NEAR(w.landingDerivative(crest), 0.0, 1e-12);
    // The analytic derivative against a central difference of the landing map (step 1e-5 m:
    // truncation ~ h^2 |X_d'''| < 1e-8, rounding ~ 1e-16 / h = 1e-11).
    const Wave v = wave(6.0, 0.0);
    for (double X = 0.05; X < 5.0; X += 0.1) {
        const double h = 1e-5;
        EXPECT_NEAR(v.landingDerivative(X), (v.landing(X + h) - v.landing(X - h)) / (2 * h), 1e-6) << X;
    }
}

// The claim behind Eq. 5.26's exactness: the refracted ray, leaning toward the rising surface,
// stays below the surface all the way to the floor. Marched in 1 mm steps of height for rays
// every 1 cm over a period, both depths.
TEST(SinusoidCaustics, RefractedRayNeverMeetsSurfaceAgain) {
    for (double D : {6.0, 10.0}) {
        const Wave w = wave(D, 0.0);
        for (double X = 0.0; X < w.wavelength; X += 0.01) {
            const double Y = w.height(X), dev = w.deviation(w.slope(X));
            const double H = D + Y;
            for (double dz = 0.001; dz < H; dz += 0.001) {
                const double x = X + dz * std::tan(dev), y = Y - dz;
                ASSERT_LT(y, w.height(x) + 1e-12) << "D " << D << " X " << X << " dz " << dz;
            }
        }
    }
}

// Caustic lines: the folds found analytically are where a dense, uniform fan of vertical rays
// (10^6 per period) piles up. Check that the two brightest 0.05 m bins (the dissertation's GSD)
// of the landing histogram, away from each other, lie within one bin of the two fold landings;
// the folds are symmetric about the trough below which they form (X0 = 0 here).
TEST(SinusoidCaustics, CausticLinesAreWhereRaysPileUp) {
    const double gsd = 0.05;
    for (double D : {6.0, 10.0}) {
        const Wave w = wave(D, 0.0);
        const auto lines = w.causticLines();
        ASSERT_EQ(lines.size(), 2u) << D;
        std::printf("[ info ] D = %.1f m: caustic lines on the floor at %.4f and %.4f m (rays entering at %.4f, %.4f)\n",
                    D, lines[0].landing, lines[1].landing, lines[0].X, lines[1].X);
        EXPECT_NEAR(periodicDistance(lines[0].landing, -lines[1].landing, w.wavelength), 0.0, 1e-9);
        // Histogram over one period of the floor, with rays from several periods of the surface.
        const int n = 1000000;
        std::vector<double> entries;
        entries.reserve(n);
        for (int i = 0; i < n; ++i) entries.push_back(-2 * w.wavelength + 4 * w.wavelength * (i + 0.5) / n);
        const auto counts = landingHistogram(w, entries, -0.5 * w.wavelength, 0.5 * w.wavelength, gsd);
        const int nb = static_cast<int>(counts.size());
        const int b1 = static_cast<int>(std::max_element(counts.begin(), counts.end()) - counts.begin());
        int b2 = -1;
        for (int b = 0; b < nb; ++b)
            if (std::abs(b - b1) > 3 && (b2 < 0 || counts[b] > counts[b2])) b2 = b;
        const double c1 = -0.5 * w.wavelength + (b1 + 0.5) * gsd, c2 = -0.5 * w.wavelength + (b2 + 0.5) * gsd;
        for (double c : {c1, c2}) {
            const double d = std::min(periodicDistance(c, lines[0].landing, w.wavelength),
                                      periodicDistance(c, lines[1].landing, w.wavelength));
            EXPECT_LE(d, gsd) << "D " << D << " bright bin at " << c;
        }
        // The rays span 4 periods, so a flat surface would put n / 4 rays in the 5 m window, 2500 per
        // bin; a fold bin collects several times that (the irradiance diverges as 1/sqrt(distance)
        // at the fold; measured 3.2 x at 6 m depth).
        EXPECT_GT(counts[b1], 2 * 2500);
    }
}

// The dissertation's ray set (CH5-G): 14 rays at 2.0 m spacing from X = 0, binned at 0.05 m. With
// 14 distinct landing points each bin holds at most one or two rays; the test confirms the
// histogram holds every ray that lands inside the window and none twice.
TEST(SinusoidCaustics, DissertationRaySet) {
    for (double D : {6.0, 10.0}) {
        const Wave w = wave(D, 0.0);
        std::vector<double> entries;
        for (int i = 0; i < 14; ++i) entries.push_back(2.0 * i);
        const auto counts = landingHistogram(w, entries, -10.0, 40.0, 0.05);
        int total = 0;
        for (int c : counts) total += c;
        EXPECT_EQ(total, 14) << D;
    }
}
