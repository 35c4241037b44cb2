// Wave spectra, spreading, dispersion and Fourier synthesis with time.
#include <cmath>
#include <complex>
#include <vector>

#include <gtest/gtest.h>

#include "core/units.h"
#include "surfaces/fft2d.h"
#include "surfaces/surface_stats.h"
#include "surfaces/synthesis.h"
#include "surfaces/wave_spectra.h"

using namespace littoral;
using namespace littoral::surfaces;

namespace {
WaveSpectrum makeSpectrum(SpectrumModel m, double U, double fetch = 0, double gamma = 3.3) {
    SpectrumParams p;
    p.model = m;
    p.windSpeed = U;
    p.fetch = fetch;
    p.gamma = gamma;
    return WaveSpectrum(p);
}
}  // namespace

// Pierson-Moskowitz (1964): Hs = 0.21 U^2 / g with U at 19.5 m (the commonly quoted rounding of
// 4 sqrt(alpha / (4 beta)) = 0.2092, alpha = 8.1e-3, beta = 0.74). Required within 2%: the
// closed form, and the zeroth moment of our wavenumber spectrum by quadrature (tests the
// omega -> k mapping and the spreading's normalisation, which multiplies every moment).
TEST(Spectra, PiersonMoskowitzSignificantHeight) {
    for (double U : {5.0, 10.0, 20.0}) {
        const double ref = 0.21 * U * U / kGravity;
        EXPECT_NEAR(piersonMoskowitzHs(U) / ref, 1.0, 0.02) << U;
        const WaveSpectrum s = makeSpectrum(SpectrumModel::PiersonMoskowitz, U);
        const double hsQuad = 4.0 * std::sqrt(s.moments(1.0e4).m0);
        EXPECT_NEAR(hsQuad / ref, 1.0, 0.02) << U;
        // Quadrature against the closed form: the log-k trapezoid is accurate to 1e-4.
        EXPECT_NEAR(hsQuad / piersonMoskowitzHs(U), 1.0, 1e-3) << U;
    }
}

// The spreading functions integrate to 1 over direction (trapezoid over 4096 angles). The
// integrand is periodic, so the rule is exact to ~1e-12 for smooth functions; cos^(2s)(theta/2)
// with s < 1 (far above the peak, s = 0.23 at 30 kp) has a cusp at theta = +-pi that slows the
// convergence to O(n^-(1+2s)), about 1e-5 here, hence the 1e-4 tolerance.
TEST(Spectra, SpreadingNormalised) {
    for (auto m : {SpectrumModel::PiersonMoskowitz, SpectrumModel::Elfouhaily}) {
        const WaveSpectrum s = makeSpectrum(m, 10.0);
        for (double kr : {0.3, 1.0, 3.0, 30.0}) {
            const double k = kr * s.peakWavenumber();
            const int n = 4096;
            double sum = 0;
            for (int i = 0; i < n; ++i) sum += s.spreading(k, -kPi + 2 * kPi * i / n) * 2 * kPi / n;
            EXPECT_NEAR(sum, 1.0, 1e-4) << static_cast<int>(m) << " k/kp " << kr;
        }
    }
}

// JONSWAP with gamma = 1 and a fully developed sea is Pierson-Moskowitz (Hasselmann et al. 1973):
// identical spectrum, identical synthesised heights for the same seed. With gamma = 3.3 the
// spectrum at the peak is exactly gamma times PM's (r = 1 at omega = omega_p).
TEST(Spectra, JonswapGammaOneEqualsPiersonMoskowitz) {
    const WaveSpectrum pm = makeSpectrum(SpectrumModel::PiersonMoskowitz, 8.0);
    const WaveSpectrum j1 = makeSpectrum(SpectrumModel::Jonswap, 8.0, 0.0, 1.0);
    const WaveSpectrum j33 = makeSpectrum(SpectrumModel::Jonswap, 8.0, 0.0, 3.3);
    for (double kr : {0.5, 0.9, 1.0, 1.1, 2.0, 10.0}) {
        const double k = kr * pm.peakWavenumber();
        EXPECT_NEAR(j1.omni(k) / pm.omni(k), 1.0, 1e-12);
        EXPECT_NEAR(j1.spreading(k, 0.4) / pm.spreading(k, 0.4), 1.0, 1e-12);
    }
    EXPECT_NEAR(j33.omni(pm.peakWavenumber()) / pm.omni(pm.peakWavenumber()), 3.3, 1e-9);
    GridSpec g;
    g.nx = g.ny = 128;
    g.sizeX = g.sizeY = 256.0;
    const HeightField a = synthesizeSpectral(g, pm, 0.3, 11, 0.0, 0.0);
    const HeightField b = synthesizeSpectral(g, j1, 0.3, 11, 0.0, 0.0);
    double maxDiff = 0, maxAbs = 0;
    for (size_t i = 0; i < a.z.size(); ++i) {
        maxDiff = std::max(maxDiff, std::abs(a.z[i] - b.z[i]));
        maxAbs = std::max(maxAbs, std::abs(a.z[i]));
    }
    EXPECT_GT(maxAbs, 0.1);
    EXPECT_LT(maxDiff, 1e-12 * maxAbs * a.z.size());
}

// JONSWAP with gamma != 1 against published results that do not come from our code path:
//  * DNV-RP-C205 (2010) sec. 3.5.5 normalises JONSWAP to the Pierson-Moskowitz significant height
//    with A_gamma = 1 - 0.287 ln(gamma): the variance of a (fully developed, same alpha and
//    omega_p) JONSWAP spectrum is 1 / A_gamma times PM's. DNV's approximation is good to 0.33%
//    for 1.5 <= gamma <= 5 (and degrades to 1.8% at gamma = 7), so 0.5% here, with our
//    quadrature's 1e-4 well inside.
//  * Hasselmann et al. (1973): the peak width is sigma_a = 0.07 below the peak and sigma_b = 0.09
//    above, so one width away on either side, omega = 0.93 omega_p and 1.09 omega_p, the
//    enhancement is gamma^exp(-1/2): for gamma = 3.3, 3.3^0.6065307 = 2.062978 (by hand:
//    exp(0.6065307 * 1.1939225) = exp(0.7241506)). A symmetric width, or swapped widths, fail this.
TEST(Spectra, JonswapPeakEnhancementAgainstPublishedResults) {
    const WaveSpectrum pm = makeSpectrum(SpectrumModel::PiersonMoskowitz, 10.0);
    const double m0pm = pm.moments(1.0e4).m0;
    for (double gamma : {2.0, 3.3, 5.0}) {
        const WaveSpectrum j = makeSpectrum(SpectrumModel::Jonswap, 10.0, 0.0, gamma);
        EXPECT_NEAR(j.moments(1.0e4).m0 / m0pm * (1.0 - 0.287 * std::log(gamma)), 1.0, 5e-3) << gamma;
    }
    const WaveSpectrum j = makeSpectrum(SpectrumModel::Jonswap, 10.0, 0.0, 3.3);
    const double wp = pm.peakFrequency();
    for (double f : {0.93, 1.09})
        EXPECT_NEAR(j.frequencySpectrum(f * wp) / pm.frequencySpectrum(f * wp), 2.062978, 1e-6) << f;
}

// Elfouhaily et al. (1997) built their spectrum so its total mean-square slope follows Cox and
// Munk's clean-surface fit 0.003 + 5.12e-3 U (+-0.004, the rms scatter of Cox and Munk's data).
// Upwind exceeds crosswind (Cox-Munk's ratio is about 1.3-1.5 at these winds).
TEST(Spectra, ElfouhailyMeanSquareSlopeNearCoxMunk) {
    for (double U : {5.0, 10.0, 15.0}) {
        const WaveSpectrum s = makeSpectrum(SpectrumModel::Elfouhaily, U);
        const auto m = s.moments(1.0e4);
        const CoxMunkMss cm = coxMunkMss(U);
        std::printf("Elfouhaily U10 = %g: mss up %.4f cross %.4f total %.4f; Cox-Munk total %.4f\n", U, m.mssUpwind,
                    m.mssCrosswind, m.mssUpwind + m.mssCrosswind, cm.total);
        EXPECT_NEAR(m.mssUpwind + m.mssCrosswind, cm.total, 0.004 + 0.15 * cm.total) << U;
        EXPECT_GT(m.mssUpwind, m.mssCrosswind);
    }
}

// Dispersion, against values derived separately from the code's formula:
//  * deep water, omega^2 = g k: the capillary term changes omega by (k/km)^2 / 2 <= 9.2e-7 at
//    these k (km = 370 rad/m), hence 1e-6;
//  * the shallow-water limit omega = k sqrt(g d): at k d = 5e-4, tanh(kd) = kd (1 - (kd)^2 / 3),
//    a relative change of 4e-8 in omega;
//  * an intermediate depth computed by hand: k = 0.1 rad/m, d = 10 m, k d = 1,
//    omega = sqrt(9.80665 * 0.1 * tanh 1) = sqrt(0.980665 * 0.7615941560) = 0.8642157 rad/s
//    (capillarity adds 4e-8 relative), to the 7 printed digits;
//  * the textbook case T = 10 s in 10 m of water has L = 92.3 m (linear wave tables, e.g. Dean &
//    Dalrymple 1991 appendix C): omega(2 pi / 92.3 m) = 2 pi / 10 s. The wavelength's last digit
//    (0.05 m in 92.3) moves omega by cg / c * 0.05 / 92.3 < 0.06 %, hence 6e-4.
TEST(Spectra, DispersionRelation) {
    for (double k : {0.01, 0.1, 0.5}) EXPECT_NEAR(dispersionOmega(k, 0.0) / std::sqrt(9.80665 * k), 1.0, 1e-6);
    const double d = 5.0, k = 1e-4;
    EXPECT_NEAR(dispersionOmega(k, d) / (k * std::sqrt(9.80665 * d)), 1.0, 1e-6);
    EXPECT_NEAR(dispersionOmega(0.1, 10.0), 0.8642157, 5e-8);
    EXPECT_NEAR(dispersionOmega(2 * kPi / 92.3, 10.0) / (2 * kPi / 10.0), 1.0, 6e-4);
    // Capillary-gravity minimum phase speed at km = 370 rad/m: c = sqrt(2 g / km) = 0.230 m/s.
    EXPECT_NEAR(dispersionOmega(370.0, 0.0) / 370.0, 0.2303, 5e-4);
    for (double T : {4.0, 10.0}) {
        const double w = 2 * kPi / T;
        const double kk = gravityWavenumber(w, 10.0);
        EXPECT_NEAR(kGravity * kk * std::tanh(kk * 10.0), w * w, 1e-10 * w * w);
    }
    // T = 10 s at 10 m depth: wavelength 92.3 m (linear theory; deep water would be 156.1 m).
    EXPECT_NEAR(2 * kPi / gravityWavenumber(2 * kPi / 10.0, 10.0), 92.3, 0.1);
}

// Every Fourier mode of a synthesised field is a sum of e^{-i w t} and e^{+i w t}, so for any
// step tau its amplitude obeys H(t + tau) + H(t - tau) = 2 cos(w tau) H(t). Measured from fields
// at t = 0, tau, 2 tau for deep water and 4 m depth. The expected w is the linear gravity-wave
// relation w^2 = g k tanh(k d) written here, not the code's dispersionOmega (which the synthesis
// itself uses): its capillary term changes w by at most (k/km)^2 / 2 = 2.3e-6 of w <= 2.8 rad/s
// for these modes (k <= pi / 4 rad/m), so |2 cos(w tau) error| <= 2 tau dw = 9e-6, hence 2e-5. The
// depth changes w by up to 60% for these modes, so ignoring it fails the test.
TEST(Spectra, TimeEvolutionFollowsDispersion) {
    const WaveSpectrum s = makeSpectrum(SpectrumModel::Jonswap, 8.0);
    GridSpec g;
    g.nx = g.ny = 64;
    g.sizeX = g.sizeY = 256.0;
    const double tau = 0.7;
    for (double depth : {0.0, 4.0}) {
        std::vector<std::vector<std::complex<double>>> H;
        for (int step = 0; step < 3; ++step) {
            const HeightField f = synthesizeSpectral(g, s, 0.0, 3, step * tau, depth);
            Fft2dReal fft(g.nx, g.ny);
            for (int j = 0; j < g.ny; ++j)
                for (int i = 0; i < g.nx; ++i) fft.real()[j * g.nx + i] = f.at(i, j);
            fft.forward();
            H.emplace_back(fft.spectrum(), fft.spectrum() + fft.halfX() * g.ny);
        }
        ModePower geom;
        geom.grid = g;
        double maxAmp = 0;
        for (auto& v : H[1]) maxAmp = std::max(maxAmp, std::abs(v));
        int checked = 0;
        double worst = 0;
        for (int n = 0; n < g.ny; ++n)
            for (int m = 0; m < geom.halfX(); ++m) {
                const size_t idx = static_cast<size_t>(n) * geom.halfX() + m;
                if (std::abs(H[1][idx]) < 1e-3 * maxAmp) continue;
                const double k = std::hypot(geom.kx(m), geom.ky(n));
                const std::complex<double> ratio = (H[2][idx] + H[0][idx]) / H[1][idx];
                const double w = std::sqrt(9.80665 * k * (depth > 0 ? std::tanh(k * depth) : 1.0));
                worst = std::max(worst, std::abs(ratio - 2.0 * std::cos(w * tau)));
                ++checked;
            }
        EXPECT_GT(checked, 20);
        EXPECT_LT(worst, 2e-5) << "depth " << depth;
    }
}

// Components travel downwind: the cross-correlation of h(x, 0) and h(x + D, tau) along the wind
// (+x) peaks at D > 0, near the peak phase speed times tau (cp = g / omega_p = 11.6 m/s for a
// fully developed 10 m/s sea; the broad spectrum spreads it, so allow 0.5 to 1.5 cp tau).
TEST(Spectra, WavesTravelDownwind) {
    const WaveSpectrum s = makeSpectrum(SpectrumModel::Jonswap, 10.0);
    GridSpec g;
    g.nx = g.ny = 256;
    g.sizeX = g.sizeY = 512.0;
    const double tau = 1.0;
    const HeightField a = synthesizeSpectral(g, s, 0.0, 5, 0.0, 0.0);
    const HeightField b = synthesizeSpectral(g, s, 0.0, 5, tau, 0.0);
    int best = 0;
    double bestC = -1e300;
    for (int shift = -20; shift <= 20; ++shift) {
        double c = 0;
        for (int j = 0; j < g.ny; ++j)
            for (int i = 0; i < g.nx; ++i) c += a.at(i, j) * b.at(((i + shift) % g.nx + g.nx) % g.nx, j);
        if (c > bestC) { bestC = c; best = shift; }
    }
    const double cp = kGravity / s.peakFrequency();
    const double D = best * g.dx();
    EXPECT_GT(D, 0.5 * cp * tau);
    EXPECT_LT(D, 1.5 * cp * tau);
}

// Synthesised significant wave height (ensemble of seeds) matches the spectrum: the mean of the
// measured mean-square heights equals the discrete mode power sum within 3 SE, and that sum
// is within 2% of 0.21 U^2 / g (the grid resolves the peak with dk = 0.08 kp and loses < 0.5% of
// the variance beyond its Nyquist wavenumber).
TEST(Spectra, SynthesisedPiersonMoskowitzHeight) {
    const double U = 5.0;
    const WaveSpectrum s = makeSpectrum(SpectrumModel::PiersonMoskowitz, U);
    GridSpec g;
    g.nx = g.ny = 512;
    g.sizeX = g.sizeY = 256.0;
    const ExpectedStats e = expectedStatistics(spectralModePower(g, s, 0.0), 0.0);
    const int K = 12;
    double sum = 0, sum2 = 0;
    for (int k = 0; k < K; ++k) {
        const SurfaceStats m = measureHeightField(synthesizeSpectral(g, s, 0.0, 100 + k, 0.0, 0.0), 0.0);
        sum += sqr(m.rmsHeight);
        sum2 += sqr(sqr(m.rmsHeight));
    }
    const double mean = sum / K, sd = std::sqrt((sum2 - K * mean * mean) / (K - 1)), se = sd / std::sqrt(K);
    EXPECT_NEAR(mean, e.variance, 3 * se);
    EXPECT_NEAR(4 * std::sqrt(e.variance) / (0.21 * U * U / kGravity), 1.0, 0.02);
}
