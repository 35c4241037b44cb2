// The `cox-munk` wave model: its design puts Cox and Munk's mean-square slopes on the grid's facets
// (checked in closed form where one exists), and an ensemble of realisations scatters about them
// as the standard error says.
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "core/cox_munk_fit.h"
#include "core/units.h"
#include "surfaces/cox_munk_surface.h"
#include "surfaces/surface_stats.h"
#include "surfaces/synthesis.h"
#include "surfaces/wave_surface.h"

using namespace littoral;
using namespace littoral::surfaces;

namespace {
GridSpec grid(int n, double spacing) {
    GridSpec g;
    g.nx = g.ny = n;
    g.sizeX = g.sizeY = n * spacing;
    g.x0 = g.y0 = -0.5 * n * spacing;
    return g;
}
}  // namespace

// h = 0.016 U^2 / sqrt(8) (the Rayleigh RMS wave height 0.016 U^2 of the dissertation's source,
// as an RMS elevation): 0.2036 m at 6 m/s.
TEST(CoxMunkSurface, RmsHeight) {
    EXPECT_NEAR(coxMunkSurfaceRmsHeight(6.0), 0.016 * 36 / std::sqrt(8.0), 1e-15);
    EXPECT_NEAR(coxMunkSurfaceRmsHeight(6.0), 0.2036, 0.00005);
}

// With the wind along a grid axis, the triangles' slopes along the wind are forward differences,
// so the designed length solves 2 h^2 (1 - exp(-d^2 / L^2)) / d^2 = sigma_u^2 exactly:
// L = d / sqrt(-ln(1 - sigma_u^2 d^2 / (2 h^2))). The design finds it to 1e-9.
TEST(CoxMunkSurface, DesignMatchesForwardDifferencesAlongAnAxis) {
    for (double U : {1.0, 6.0, 14.0}) {
        const double d = U < 2 ? 0.02 : 0.25;
        const GridSpec g = grid(256, d);
        const CoxMunkSurfaceDesign des = designCoxMunkSurface(g, U, CoxMunkSea::Clean, 0.0);
        const double h = des.rmsHeight;
        const SlopeVariances v = coxMunkSlopeVariances(U, CoxMunkSea::Clean);
        const double Lu = d / std::sqrt(-std::log(1.0 - v.upwind * d * d / (2 * h * h)));
        const double Lc = d / std::sqrt(-std::log(1.0 - v.crosswind * d * d / (2 * h * h)));
        EXPECT_NEAR(des.lengthUpwind / Lu, 1.0, 1e-9) << U;
        EXPECT_NEAR(des.lengthCrosswind / Lc, 1.0, 1e-9) << U;
        // Shorter than the continuum length sqrt(2) h / sigma by the forward-difference loss.
        EXPECT_LT(des.lengthUpwind, des.continuumUpwind);
        EXPECT_NEAR(des.continuumUpwind, std::sqrt(2.0) * h / std::sqrt(v.upwind), 1e-15);
    }
}

// In any wind direction (the triangles then mix both axes) and for each fit, the ensemble-mean
// slope variances of the triangles (expectedSlopeStatistics, exact for the grid) are Cox-Munk's.
TEST(CoxMunkSurface, DesignMatchesCoxMunkInAnyDirection) {
    for (CoxMunkSea sea : {CoxMunkSea::Clean, CoxMunkSea::Slick, CoxMunkSea::Dissertation})
        for (double dir : {0.0, 0.4, 1.3, -2.2}) {
            const GridSpec g = grid(200, 0.25);
            const CoxMunkSurfaceDesign des = designCoxMunkSurface(g, 8.0, sea, dir);
            const ExpectedStats e = expectedSlopeStatistics(
                anisotropicGaussianModePower(g, des.rmsHeight, des.lengthUpwind, des.lengthCrosswind, dir), dir);
            const SlopeVariances v = coxMunkSlopeVariances(8.0, sea);
            EXPECT_NEAR(e.mssUpwind / v.upwind, 1.0, 1e-9) << nameOf(sea) << " " << dir;
            EXPECT_NEAR(e.mssCrosswind / v.crosswind, 1.0, 1e-9) << nameOf(sea) << " " << dir;
        }
}

// An ensemble of 24 realisations (6 m/s, clean sea, wind from 300 degrees, i.e. not along a grid
// axis; 64 m square at 0.25 m): the measured per-axis slope variances along and across the wind are
// unbiased estimates of Cox-Munk's. Each realisation's relative standard deviation is about
// sqrt(3 pi L_u L_c / (4 A)) = 4.8 % (the area mean of z_u^2 over A for a Gaussian slope field
// whose covariance is -C''(r): 2 Int C_zu^2 d^2r / A = (3 pi / 4) L_u L_c sigma_u^4 / A), so the
// ensemble mean has a standard error of about 1 %; we use the sample's own SE and reject beyond
// 4 SE (two quantities: a false alarm about 1e-4). The sample SD must agree with the formula
// within the 0.1 % - 99.9 % range of a chi-square with 23 degrees of freedom (ratio of SDs 0.57 to
// 1.47).
TEST(CoxMunkSurface, EnsembleSlopeVariancesMatchCoxMunk) {
    const double U = 6.0;
    const double dir = directionFromCompass(300.0);
    const GridSpec g = grid(256, 0.25);
    const CoxMunkSurfaceDesign des = designCoxMunkSurface(g, U, CoxMunkSea::Clean, dir);
    const ModePower power = anisotropicGaussianModePower(g, des.rmsHeight, des.lengthUpwind, des.lengthCrosswind, dir);
    const int K = 24;
    std::vector<double> mu, mc;
    for (int k = 0; k < K; ++k) {
        const SurfaceStats m = measureHeightField(synthesizeFromModePower(power, 700 + k), dir);
        mu.push_back(m.mssUpwind);
        mc.push_back(m.mssCrosswind);
    }
    const double rel = std::sqrt(3.0 * kPi * des.continuumUpwind * des.continuumCrosswind / (4.0 * g.sizeX * g.sizeY));
    for (int axis = 0; axis < 2; ++axis) {
        const std::vector<double>& v = axis == 0 ? mu : mc;
        const double target = axis == 0 ? des.target.upwind : des.target.crosswind;
        double mean = 0, s2 = 0;
        for (double x : v) mean += x;
        mean /= K;
        for (double x : v) s2 += sqr(x - mean);
        const double sd = std::sqrt(s2 / (K - 1)), se = sd / std::sqrt(double(K));
        std::printf("[ info ] cox-munk ensemble %s: mean mss %.5f (Cox-Munk %.5f), SE %.5f, SD/mean %.4f (formula %.4f)\n",
                    axis == 0 ? "upwind" : "crosswind", mean, target, se, sd / mean, rel);
        EXPECT_NEAR(mean, target, 4 * se) << axis;
        EXPECT_GT(sd / (rel * target), 0.57) << axis;
        EXPECT_LT(sd / (rel * target), 1.47) << axis;
    }
}

// Through the public entry point: stats carry the target and the fit, and a realisation's grid
// slopes are within 5 of its relative standard deviations (the formula above: 3.3 % on this 256 m
// square at 6 m/s, slick sea, L_u = 2.9 m, L_c = 3.2 m), which would catch slopes from the wrong
// fit (the clean sea's are 96 % and 81 % larger) or the beaufort model's (8 times smaller).
TEST(CoxMunkSurface, GenerateWaveSurface) {
    WaveParams p;
    p.model = WaveModel::CoxMunk;
    p.windSpeed = 6.0;
    p.windDirection = directionFromCompass(200.0);
    p.sea = CoxMunkSea::Slick;
    p.sizeX = p.sizeY = 256.0;
    p.spacing = 0.5;
    p.triangles = 0;
    const WaveSurface s = generateWaveSurface(p);
    const SlopeVariances v = coxMunkSlopeVariances(6.0, CoxMunkSea::Slick);
    EXPECT_EQ(s.predicted.mssUpwind, v.upwind);
    EXPECT_EQ(s.predicted.mssCrosswind, v.crosswind);
    EXPECT_EQ(s.predicted.coxMunkSea, CoxMunkSea::Slick);
    EXPECT_NEAR(s.predicted.coxMunkTotal, v.total(), 1e-15);
    const double h = coxMunkSurfaceRmsHeight(6.0);
    const double Lu = std::sqrt(2.0) * h / std::sqrt(v.upwind), Lc = std::sqrt(2.0) * h / std::sqrt(v.crosswind);
    const double rel = std::sqrt(3.0 * kPi * Lu * Lc / (4.0 * p.sizeX * p.sizeY));
    EXPECT_NEAR(s.grid.mssUpwind / v.upwind, 1.0, 5 * rel);
    EXPECT_NEAR(s.grid.mssCrosswind / v.crosswind, 1.0, 5 * rel);
    // The full-resolution mesh has the grid's facets.
    EXPECT_NEAR(s.actual.mssUpwind / s.grid.mssUpwind, 1.0, 1e-9);
    // The model is static, and the fit applies to it only.
    p.time = 1.0;
    EXPECT_THROW(validateWaveParams(p), InputError);
    p.time = 0.0;
    p.model = WaveModel::Beaufort;
    EXPECT_THROW(validateWaveParams(p), InputError);
}

// Compass "from" directions and the internal "toward, ccw from east" direction.
TEST(CoxMunkSurface, CompassConversion) {
    EXPECT_NEAR(directionFromCompass(270.0), 0.0, 1e-15);
    EXPECT_NEAR(directionFromCompass(0.0), -kPi / 2, 1e-15);
    EXPECT_NEAR(directionFromCompass(90.0), kPi, 1e-15);
    EXPECT_NEAR(directionFromCompass(180.0), kPi / 2, 1e-15);
    for (double from = 0; from < 360; from += 7.5)
        EXPECT_NEAR(compassFromDirection(directionFromCompass(from)), from, 1e-9) << from;
}
