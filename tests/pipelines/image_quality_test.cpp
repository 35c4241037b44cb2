// The Chapter 9 image-quality study (pipelines/lib_image_quality.h, docs/image-quality.md).
//
// 1. The edge analysis against closed forms: a Gaussian-blurred edge sampled at pixel centres has
//    a Gaussian LSF whose FWHM and 10-90% width are known; SNR of added noise of known size.
// 2. The study end to end, against Chapter 9's findings (digest seed-ch08-09.md Sec. 3.7-3.8):
//    the variance of a side falls as 1/N with the photon density, the SNR grows with the search
//    radius while the mean does not move, and the FWHM stays within one GSD while the edge's
//    10-90% width (its tails) grows with the radius.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "pipelines/lib_image_quality.h"
#include "tests/support/test_support.h"

namespace fs = std::filesystem;
namespace lp = littoral::pipelines;
using littoral::testing_support::scratchDir;

namespace {

// A 5 degree slanted edge through the image centre, bright (hi) on the -n side, blurred by a
// Gaussian of standard deviation sigma, sampled at pixel centres, plus N(0, noise) per pixel.
std::vector<float> syntheticEdge(const lp::PixelGrid& g, const lp::EdgeGeometry& e, double sigma, double hi, double lo,
                                 double noise, uint32_t seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> nd(0.0, 1.0);
    std::vector<float> p(static_cast<size_t>(g.width) * g.height);
    for (int j = 0; j < g.height; ++j)
        for (int i = 0; i < g.width; ++i) {
            const double x = g.x0 + (i + 0.5) * g.pixel, y = g.y0 - (j + 0.5) * g.pixel;
            const double d = (x - e.cx) * e.nx + (y - e.cy) * e.ny;
            const double v = lo + (hi - lo) * 0.5 * std::erfc(d / (sigma * std::sqrt(2.0)));
            p[static_cast<size_t>(j) * g.width + i] = static_cast<float>(v + noise * nd(rng));
        }
    return p;
}

lp::EdgeGeometry slanted() {
    lp::EdgeGeometry e;
    const double th = 5.0 * M_PI / 180;
    e.nx = std::cos(th), e.ny = -std::sin(th);
    e.halfLength = 6;
    return e;
}

}  // namespace

TEST(ImageQuality, EdgeAnalysisRecoversAGaussianEdge) {
    const lp::PixelGrid g{64, 64, 0.25, -8, 8};
    const lp::EdgeGeometry e = slanted();
    const double sigma = 0.2;
    const lp::EdgeMeasures m = lp::analyseEdge(syntheticEdge(g, e, sigma, 100, 10, 0, 1), g, e);
    // The measured ESF is the true one averaged over a 1/16 m bin and smoothed by a 3-bin box-car:
    // two boxes of widths w1 = 0.0625 and w2 = 0.1875 m add w^2/12 each to the Gaussian's
    // variance (for sigma >> w the result stays Gaussian to well under 1%). The LSF's central
    // difference over two bins adds a third box (0.125 m). Bin edges fall on the edge itself, so the
    // sampled peak sits half a bin off the true one and is low by exp(-(w1/2)^2 / (2 s_L^2)); the
    // half-maximum is taken of that peak, widening the FWHM to 2 s_L sqrt(2 ln(1/(0.5 peak))).
    const double s = std::sqrt(sigma * sigma + (0.0625 * 0.0625 + 0.1875 * 0.1875) / 12);
    const double sL = std::sqrt(s * s + 0.125 * 0.125 / 12);
    const double peak = std::exp(-0.03125 * 0.03125 / (2 * sL * sL));
    EXPECT_NEAR(m.fwhm, 2 * sL * std::sqrt(2 * std::log(1 / (0.5 * peak))), 0.01 * 2.355 * sL);  // 1%: interpolation
    EXPECT_NEAR(m.width1090, 2 * 1.2815516 * s, 0.01 * 2.563 * s);
    // For a Gaussian edge the share of the step missing between 0.5 and 1.0 m from the centre is,
    // by symmetry, the mean of erfc(x / (sqrt 2 s)) over x in [0.5, 1] (midpoint rule, 1000 steps).
    double tail = 0;
    for (int k = 0; k < 1000; ++k) tail += std::erfc((0.5 + (k + 0.5) * 0.0005) / (std::sqrt(2.0) * s)) / 1000;
    EXPECT_NEAR(m.tailFraction, tail, 0.003);  // the window's bin-centre discreteness
    // The side regions are flat: the SNR is hi / noise. The sample standard deviation of n
    // normal values has a relative standard error 1/sqrt(2(n - 1)); 4 of them is the tolerance.
    const lp::EdgeMeasures n = lp::analyseEdge(syntheticEdge(g, e, sigma, 100, 10, 4, 2), g, e);
    EXPECT_GT(n.bright.pixels, 300);
    EXPECT_NEAR(n.bright.snr, 25.0, 25.0 * 4 / std::sqrt(2.0 * (n.bright.pixels - 1)));
    EXPECT_NEAR(n.dark.snr, 2.5, 2.5 * 4 / std::sqrt(2.0 * (n.dark.pixels - 1)));
    // An edge parallel to the pixel columns leaves ESF bins near the edge empty: refused.
    lp::EdgeGeometry straight;
    straight.halfLength = 6;
    EXPECT_THROW(lp::analyseEdge(syntheticEdge(g, straight, sigma, 100, 10, 0, 1), g, straight), littoral::InputError);
}

// Every measure is defined for every input or marked undefined with its reason (issue 20: the
// study wrote `nan` widths and tails of -1.28 and 3.21). With no step under the noise, nothing is
// defined. With a resolved step under heavy noise (step 90, noise 20 per pixel: the tails window's
// mean has a standard error of about 0.03 of the step), the tails of a sharp edge (true share about
// 0.01) scatter around 0 and across it: each is in [0, 1] (clipped within 3 standard errors) or
// undefined, never outside.
TEST(ImageQuality, EdgeMeasuresAreDefinedOrMarkedUndefined) {
    const lp::PixelGrid g{64, 64, 0.25, -8, 8};
    const lp::EdgeGeometry e = slanted();
    const lp::EdgeMeasures flat = lp::analyseEdge(syntheticEdge(g, e, 0.2, 10, 10, 4, 3), g, e);
    EXPECT_TRUE(std::isnan(flat.fwhm) && std::isnan(flat.width1090) && std::isnan(flat.tailFraction));
    EXPECT_NE(flat.undefined.find("the step is not resolved"), std::string::npos) << flat.undefined;
    int defined = 0;
    for (uint32_t seed = 10; seed < 40; ++seed) {
        const lp::EdgeMeasures m = lp::analyseEdge(syntheticEdge(g, e, 0.2, 100, 10, 20, seed), g, e);
        if (std::isnan(m.tailFraction)) {
            EXPECT_NE(m.undefined.find("tails"), std::string::npos) << m.undefined;
            continue;
        }
        ++defined;
        EXPECT_GE(m.tailFraction, 0.0) << seed;
        EXPECT_LE(m.tailFraction, 1.0) << seed;
        EXPECT_LT(m.tailFraction, 0.01 + 4 * 0.03) << seed;  // 4 standard errors above the true share
    }
    EXPECT_GE(defined, 25);  // a 3-standard-error excursion is rare: nearly all are defined
}

TEST(ImageQuality, StudyReproducesChapter9) {
    // Coastal water (a 0.038, b 0.35 m^-1, HG 0.92), target 1 m deep, 48 x 48 px at 0.25 m GSD.
    lp::ImageQualityOptions o;
    o.out = scratchDir("image_quality", "density").string();
    o.depths = {1.0};
    o.radii = {0.25, 0.5};
    o.densities = {1000, 3000};
    o.pixels = 48;
    o.samplesPerPixel = 2;
    o.progress = false;
    const auto rows = lp::runImageQualityStudy(o);
    ASSERT_EQ(rows.size(), 4u);
    auto row = [&](double density, double radius) -> const lp::ImageQualityRow& {
        for (const auto& r : rows)
            if (r.density == density && r.radius == radius) return r;
        throw std::runtime_error("missing row");
    };
    // (a) Variance ~ 1/N (Fig. 9.6: ratios "cluster near 3" for a 3x density). Photon-map noise is
    // correlated over a search disc, so a side of area A holds about A / (pi r^2) independent
    // values (n_eff); the relative standard error of a sample variance is sqrt(2 / (n_eff - 1)),
    // of a ratio of two independent ones sqrt 2 times that. Tolerance: 3 of those.
    {
        const auto &lo = row(1000, 0.25), &hi = row(3000, 0.25);
        const double ratio = std::pow(lo.m.bright.stddev / hi.m.bright.stddev, 2);
        const double nEff = lo.m.bright.pixels * 0.25 * 0.25 / (M_PI * 0.25 * 0.25);
        const double rel = std::sqrt(2.0) * std::sqrt(2.0 / (nEff - 1));
        EXPECT_NEAR(ratio, 3.0, 3 * 3.0 * rel) << "n_eff " << nEff;
        // ... while the mean does not depend on the density (Sec. 3.7): within 3 standard errors of
        // the two region means (std / sqrt(n_eff) each).
        const double se = std::hypot(lo.m.bright.stddev, hi.m.bright.stddev) / std::sqrt(nEff);
        EXPECT_NEAR(lo.m.bright.mean, hi.m.bright.mean, 3 * se);
    }
    // (b) The SNR grows with the search radius on both sides and at both densities (Fig. 9.2);
    // the growth must exceed 3 standard errors of the SNR ratio (each SNR's relative error is
    // that of its standard deviation, 1/sqrt(2(n_eff - 1))).
    for (double density : {1000.0, 3000.0}) {
        const auto &a = row(density, 0.25), &b = row(density, 0.5);
        for (const auto& [sa, sb] : {std::pair{a.m.bright, b.m.bright}, std::pair{a.m.dark, b.m.dark}}) {
            const double na = sa.pixels / M_PI, nb = sb.pixels * 0.0625 / (M_PI * 0.25);
            const double rel = std::hypot(1 / std::sqrt(2 * (na - 1)), 1 / std::sqrt(2 * (nb - 1)));
            EXPECT_GT(sb.snr / sa.snr, 1 + 3 * rel) << "density " << density;
        }
    }
    // (c) The FWHM stays within one GSD (0.25 m) of the pixel-limited value across radii and
    // densities (Fig. 9.12: "the FWHM stays nearly constant").
    for (const auto& r : rows) {
        EXPECT_GT(r.m.fwhm, 0.15) << r.radius;
        EXPECT_LT(r.m.fwhm, 0.25 + 0.25) << r.radius;
    }
    // (d) The figures are drawn (matplotlib, pipelines/lib_plot.h), and the tail fractions they
    // plot are shares: in [0, 1] or left out (null).
    for (const char* f : {"snr_vs_radius.png", "fwhm_vs_radius.png", "tails_vs_radius.png", "snr_vs_density.png",
                          "esf_d1.png", "lsf_d1.png"})
        EXPECT_GT(littoral::testing_support::pngSize(fs::path(o.out) / f).first, 300u) << f;
    const auto charts = nlohmann::json::parse(littoral::readTextFile(fs::path(o.out) / "charts.json"));
    int tails = 0;
    for (const auto& c : charts)
        if (c["file"] == "tails_vs_radius.png")
            for (const auto& s : c["series"])
                for (const auto& y : s["y"])
                    if (!y.is_null()) {
                        ++tails;
                        EXPECT_GE(y.get<double>(), 0.0);
                        EXPECT_LE(y.get<double>(), 1.0);
                    }
    EXPECT_GE(tails, 1);
}

TEST(ImageQuality, LargerRadiusWidensTheEdgeTailsNotItsFwhm) {
    // Fig. 9.12: a larger SR shows first in the tails of the edge response. Here SR 1.0 against
    // SR 0.25 (1000 photons/m^3, target 1 m deep).
    lp::ImageQualityOptions o;
    o.out = scratchDir("image_quality", "radius").string();
    o.depths = {1.0};
    o.radii = {0.25, 1.0};
    o.densities = {1000};
    o.pixels = 48;
    o.samplesPerPixel = 2;
    o.progress = false;
    const auto rows = lp::runImageQualityStudy(o);
    ASSERT_EQ(rows.size(), 2u);
    const auto &small = rows[0].radius == 0.25 ? rows[0] : rows[1], &large = rows[0].radius == 0.25 ? rows[1] : rows[0];
    // The FWHM moves by less than one GSD ...
    EXPECT_LT(std::abs(large.m.fwhm - small.m.fwhm), 0.25);
    // ... while the 10-90% width grows: the volume map spreads the bright half's forward-scattered
    // upwelling light over the search sphere (radius 1 m = 4 GSD); the surface map adds no edge
    // blur (reflectance is applied where the camera ray lands). Noise of the width: a smoothed ESF
    // point averages ~24 pixels, ~8 independent at SR = 1 GSD, so its noise is about
    // std / sqrt(8) = 3.4% of the step at SR 0.25 m; over the ESF's slope (80% of the step in
    // 0.29 m) that moves each crossing by ~0.012 m, the width by ~0.017 m and the difference of two
    // widths by ~0.025 m. The growth must exceed 4 of those, 0.1 m (measured: 0.29 -> 0.57 m).
    EXPECT_GT(large.m.width1090 - small.m.width1090, 0.1);
    EXPECT_GT(large.m.tailFraction, small.m.tailFraction);  // the tails' share (noisier; reported in the CSV)
    // The region means agree (the mean is SR-independent, Sec. 3.7): 3 standard errors as above.
    const double nEff = small.m.bright.pixels / M_PI;
    EXPECT_NEAR(large.m.bright.mean, small.m.bright.mean, 3 * std::hypot(small.m.bright.stddev, large.m.bright.stddev) / std::sqrt(nEff));
    // Bad settings are refused before anything renders.
    o.radii = {3.0};
    EXPECT_THROW(lp::runImageQualityStudy(o), littoral::InputError);
}
