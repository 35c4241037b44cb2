// The sensor model (render/sensor_model.h): the PSF on the radiance and the detector's noise,
// against the kernel itself, conservation of the total, and the shot-plus-read noise model
// computed here from the photon energy h c / lambda (CODATA 2019 exact constants).
#include "render/sensor_model.h"

#include <cmath>

#include <gtest/gtest.h>

#include "core/error.h"

namespace littoral::render {
namespace {

Film pointSource(int w, int h, int x, int y, float v = 1.0f) {
    Film f(w, h, {Band{0.5, 0.6}});
    std::fill(f.pixels.begin(), f.pixels.end(), 0.0f);
    f.pixels[static_cast<size_t>(y) * w + x] = v;
    return f;
}

double total(const Film& f) {
    double s = 0;
    for (float v : f.pixels) s += v;
    return s;
}

// A point source in the interior gives the kernel: for a Gaussian of FWHM 3 px, sigma = 3 /
// 2.3548 = 1.2740 px, and the blurred image's second moment about the source is 2 sigma^2 within
// the sampled kernel's 0.2 % (gaussianKernel: truncation at 4 sigma, integer sampling).
TEST(SensorModel, GaussianPsfOfAPointSourceIsTheKernel) {
    EXPECT_NEAR(gaussianSigmaFromFwhm(3.0), 1.27398, 1e-5);
    const Film out = applyPsf(pointSource(41, 41, 20, 20), psfKernel({"gaussian", 3.0, 0, 0, {}}));
    double m2 = 0, peak = 0;
    for (int y = 0; y < 41; ++y)
        for (int x = 0; x < 41; ++x) {
            const double v = out.at(x, y, 0);
            m2 += v * ((x - 20) * (x - 20) + (y - 20) * (y - 20));
            peak = std::max(peak, v);
            EXPECT_NEAR(v, out.at(40 - x, y, 0), 1e-7);  // symmetric
            EXPECT_NEAR(v, out.at(y, x, 0), 1e-7);
        }
    EXPECT_NEAR(total(out), 1.0, 1e-6);
    const double s = gaussianSigmaFromFwhm(3.0);
    EXPECT_NEAR(m2, 2 * s * s, 0.002 * 2 * s * s);
    EXPECT_EQ(peak, out.at(20, 20, 0));
}

// A Gaussian is applied as two flux-conserving 1-D passes: the 2-D share of the kernel inside the
// image is the product of the 1-D shares, so the result is the 2-D scatter's, corners included.
TEST(SensorModel, SeparableGaussianEqualsTheTwoDimensionalScatter) {
    PsfKernel g = psfKernel({"gaussian", 4.0, 0, 0, {}});
    ASSERT_FALSE(g.separable.empty());
    PsfKernel full = g;
    full.separable.clear();
    Film f(19, 13, {Band{0.4, 0.5}, Band{0.5, 0.6}});
    for (size_t p = 0; p < f.pixels.size(); ++p) f.pixels[p] = static_cast<float>((p * 37) % 101);
    const Film a = applyPsf(f, g), b = applyPsf(f, full);
    for (size_t p = 0; p < a.pixels.size(); ++p) EXPECT_NEAR(a.pixels[p], b.pixels[p], 1e-4) << p;
}

TEST(SensorModel, TabulatedKernelIsNormalisedAndCentred) {
    const ir::SensorPsf psf{"kernel", 0, 3, 1, {1, 2, 1}};
    const Film out = applyPsf(pointSource(9, 3, 4, 1, 8.0f), psfKernel(psf));
    EXPECT_FLOAT_EQ(out.at(3, 1, 0), 2.0f);
    EXPECT_FLOAT_EQ(out.at(4, 1, 0), 4.0f);
    EXPECT_FLOAT_EQ(out.at(5, 1, 0), 2.0f);
    EXPECT_FLOAT_EQ(out.at(4, 0, 0), 0.0f);
}

// Light is neither made nor lost: a source in a corner keeps its total (the kernel's share that
// would leave the image is spread over its part inside), and so does a random image.
TEST(SensorModel, PsfConservesTheImageTotal) {
    const auto k = psfKernel({"gaussian", 5.0, 0, 0, {}});
    EXPECT_NEAR(total(applyPsf(pointSource(20, 15, 0, 0, 3.0f), k)), 3.0, 1e-6);
    Film f(23, 17, {Band{0.4, 0.5}, Band{0.5, 0.6}});
    uint64_t h = 12345;
    for (float& v : f.pixels) v = static_cast<float>(((h = h * 6364136223846793005ULL + 1442695040888963407ULL) >> 40) % 1000);
    const Film out = applyPsf(f, k);
    EXPECT_NEAR(total(out), total(f), 1e-9 * total(f) + 1e-3);
}

ir::Sensor pinhole() {
    ir::Sensor s;
    s.name = "cam";
    s.type = ir::Sensor::Type::Pinhole;
    s.width = 32;
    s.height = 32;
    s.focalLength = 0.1;   // m
    s.pixelPitch = 10e-6;  // m: Omega = 1e-8 sr
    return s;
}

ir::SensorDetector detector(uint64_t seed) {
    return {0.05, 1e-3, 0.5, 20.0, 1e6, 16, seed};  // 50 mm aperture, 1 ms, QE 0.5, 20 e- read, 16 bits
}

// Electrons per radiance at 0.55 um over 0.1 um: E_photon = h c / lambda = 3.61174e-19 J;
// L dLambda A Omega t = 0.1 x pi 0.025^2 x 1e-8 x 1e-3 = 1.96350e-15 J per unit radiance, so
// k = 0.5 x 1.96350e-15 / 3.61174e-19 = 2718.2 electrons per W m^-2 sr^-1 um^-1.
TEST(SensorModel, ElectronsPerRadianceFromThePhotonEnergy) {
    const auto k = electronsPerRadiance(pinhole(), detector(1), {Band{0.5, 0.6}});
    EXPECT_NEAR(k[0], 2718.2, 0.2);
    ir::Sensor ortho = pinhole();
    ortho.type = ir::Sensor::Type::Orthographic;
    EXPECT_THROW(electronsPerRadiance(ortho, detector(1), {Band{0.5, 0.6}}), InputError);
}

// Over 100 seeds each pixel's noisy radiance averages to the noiseless one (the fraction of pixels
// outside 3 standard errors stays near the normal 0.27 %: at most 1 %), and the variance follows
// N + read^2 + g^2 / 12 electrons^2 (pooled over 102,400 samples its relative standard error is
// sqrt(2 / n) = 0.44 %: 2 % is 4.5 of them).
TEST(SensorModel, NoiseIsUnbiasedAndFollowsTheShotPlusReadModel) {
    const ir::Sensor s = pinhole();
    Film f(32, 32, {Band{0.5, 0.6}});
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) f.pixels[static_cast<size_t>(y) * 32 + x] = static_cast<float>(20 + 5 * x);  // 5e4-4.8e5 e-
    const double k = electronsPerRadiance(s, detector(1), f.bands)[0];
    const double g = 1e6 / 65535.0;
    const int seeds = 100;
    std::vector<double> sum(f.pixels.size(), 0.0), sq(f.pixels.size(), 0.0);
    for (int i = 0; i < seeds; ++i) {
        const DetectorImage d = applyDetector(f, s, detector(1000 + i));
        for (size_t p = 0; p < f.pixels.size(); ++p) {
            sum[p] += d.radiance.pixels[p];
            sq[p] += double(d.radiance.pixels[p]) * d.radiance.pixels[p];
        }
    }
    int outside = 0;
    double ratio = 0;
    for (size_t p = 0; p < f.pixels.size(); ++p) {
        const double mean = sum[p] / seeds, var = (sq[p] - seeds * mean * mean) / (seeds - 1);
        if (std::abs(mean - f.pixels[p]) > 3 * std::sqrt(var / seeds)) ++outside;
        const double n = k * f.pixels[p];
        ratio += var * k * k / (n + 20.0 * 20.0 + g * g / 12.0);
    }
    EXPECT_LE(outside, 10) << "of 1024";
    EXPECT_NEAR(ratio / f.pixels.size(), 1.0, 0.02);
    // The same seed gives the same noise; another seed other noise.
    EXPECT_EQ(applyDetector(f, s, detector(7)).radiance.pixels, applyDetector(f, s, detector(7)).radiance.pixels);
    EXPECT_NE(applyDetector(f, s, detector(7)).radiance.pixels, applyDetector(f, s, detector(8)).radiance.pixels);
    const DetectorImage d = applyDetector(f, s, detector(7));
    EXPECT_NEAR(d.bands[0].snr, d.bands[0].meanSignalE / d.bands[0].meanNoiseE, 1e-9);
}

}  // namespace
}  // namespace littoral::render
