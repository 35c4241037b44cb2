#include "surfaces/synthesis.h"

#include <cmath>
#include <complex>

#include "core/error.h"
#include "core/rng.h"
#include "core/units.h"
#include "surfaces/fft2d.h"
#include "surfaces/surface_stats.h"

namespace littoral::surfaces {

namespace {
// RandomStream passes: distinct streams for the two kinds of random fields.
constexpr uint64_t kPassWhiteNoise = 0x57415645'4e4f4953ULL;   // "WAVENOIS"
constexpr uint64_t kPassSpectralAmp = 0x57415645'53504543ULL;  // "WAVESPEC"

// Box-Muller: two independent N(0, 1) samples from two uniforms of the stream.
std::pair<double, double> gaussianPair(RandomStream& rs) {
    const double u1 = 1.0 - rs.uniform();  // (0, 1]
    const double u2 = rs.uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    return {r * std::cos(2.0 * kPi * u2), r * std::sin(2.0 * kPi * u2)};
}

HeightField makeVertexField(const GridSpec& g, bool periodic) {
    HeightField f = makeHeightField(g.nx + 1, g.ny + 1, g.x0, g.y0, g.x0 + g.sizeX, g.y0 + g.sizeY);
    f.periodic = periodic;
    return f;
}

// Copies the nx x ny periodic samples into the (nx+1) x (ny+1) vertex field (wrap row/column).
void fillPeriodic(HeightField& f, const double* samples, int nx, int ny) {
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i)
            f.at(i, j) = samples[static_cast<size_t>(j % ny) * nx + (i % nx)];
}

bool isNyquist(int idx, int n) { return n % 2 == 0 && idx == n / 2; }
}  // namespace

double ModePower::kx(int m) const { return 2.0 * kPi * m / grid.sizeX; }
double ModePower::ky(int n) const {
    const int s = n <= grid.ny / 2 ? n : n - grid.ny;
    return 2.0 * kPi * s / grid.sizeY;
}

ModePower gaussianModePower(const GridSpec& g, double h, double L) {
    ModePower p;
    p.grid = g;
    const int hx = p.halfX();
    p.power.assign(static_cast<size_t>(hx) * g.ny, 0.0);
    const double dk2 = (2.0 * kPi / g.sizeX) * (2.0 * kPi / g.sizeY);  // rad^2 m^-2
    for (int n = 0; n < g.ny; ++n)
        for (int m = 0; m < hx; ++m) {
            if (m == 0 && n == 0) continue;  // mean water level exactly 0
            const double k2 = sqr(p.kx(m)) + sqr(p.ky(n));
            // C~(k) dk^2 = h^2 L^2 / (4 pi) exp(-k^2 L^2 / 4) dk^2: 2-D Fourier transform of
            // h^2 exp(-r^2/L^2) (its integral over the plane is h^2).
            p.power[static_cast<size_t>(n) * hx + m] = h * h * L * L / (4.0 * kPi) * std::exp(-k2 * L * L / 4.0) * dk2;
        }
    return p;
}

ModePower anisotropicGaussianModePower(const GridSpec& g, double h, double La, double Lc, double dir) {
    ModePower p;
    p.grid = g;
    const int hx = p.halfX();
    p.power.assign(static_cast<size_t>(hx) * g.ny, 0.0);
    const double dk2 = (2.0 * kPi / g.sizeX) * (2.0 * kPi / g.sizeY);
    const double c = std::cos(dir), s = std::sin(dir);
    for (int n = 0; n < g.ny; ++n)
        for (int m = 0; m < hx; ++m) {
            if (m == 0 && n == 0) continue;  // mean water level exactly 0
            const double ka = p.kx(m) * c + p.ky(n) * s, kc = -p.kx(m) * s + p.ky(n) * c;
            // 2-D Fourier transform of h^2 exp(-(ra^2/La^2 + rc^2/Lc^2)), times the mode's dk^2.
            p.power[static_cast<size_t>(n) * hx + m] =
                h * h * La * Lc / (4.0 * kPi) * std::exp(-(ka * ka * La * La + kc * kc * Lc * Lc) / 4.0) * dk2;
        }
    return p;
}

ModePower spectralModePower(const GridSpec& g, const WaveSpectrum& s, double windDir) {
    ModePower p;
    p.grid = g;
    const int hx = p.halfX();
    p.power.assign(static_cast<size_t>(hx) * g.ny, 0.0);
    const double dk2 = (2.0 * kPi / g.sizeX) * (2.0 * kPi / g.sizeY);
    for (int n = 0; n < g.ny; ++n) {
        if (isNyquist(n, g.ny)) continue;
        for (int m = 0; m < hx; ++m) {
            if ((m == 0 && n == 0) || isNyquist(m, g.nx)) continue;
            const double kx = p.kx(m), ky = p.ky(n);
            const double k = std::hypot(kx, ky);
            const double th = std::atan2(ky, kx) - windDir;
            // Mode k gets a_k e^{ik.x} and conj(a_-k) e^{ik.x}: variance (Psi(k) + Psi(-k)) dk^2 / 2.
            p.power[static_cast<size_t>(n) * hx + m] = 0.5 * (s.density(k, th) + s.density(k, th + kPi)) * dk2;
        }
    }
    return p;
}

HeightField synthesizeGaussian(const GridSpec& g, double h, double L, uint64_t seed) {
    return synthesizeFromModePower(gaussianModePower(g, h, L), seed);
}

HeightField synthesizeFromModePower(const ModePower& p, uint64_t seed) {
    const GridSpec& g = p.grid;
    Fft2dReal fft(g.nx, g.ny);
    const size_t M = static_cast<size_t>(g.nx) * g.ny;
    double* w = fft.real();
    for (size_t idx = 0; idx < M; ++idx) {
        RandomStream rs(seed, kPassWhiteNoise, idx);
        w[idx] = gaussianPair(rs).first;
    }
    fft.forward();
    // With unit white noise E|W_k|^2 = M, so multiplying by sqrt(M P_k) / M and transforming back
    // (unnormalised) gives E|h_k|^2 = P_k.
    std::complex<double>* W = fft.spectrum();
    const double Md = static_cast<double>(M);
    for (size_t idx = 0; idx < p.power.size(); ++idx) W[idx] *= std::sqrt(Md * p.power[idx]) / Md;
    fft.backward();
    HeightField f = makeVertexField(g, true);
    fillPeriodic(f, fft.real(), g.nx, g.ny);
    return f;
}

HeightField synthesizeSpectral(const GridSpec& g, const WaveSpectrum& s, double windDir, uint64_t seed,
                               double time, double depth) {
    const int hx = g.nx / 2 + 1;
    const double dk2 = (2.0 * kPi / g.sizeX) * (2.0 * kPi / g.sizeY);
    // a_k for the full-plane mode with signed indices (ms, ns): complex Gaussian with
    // E|a|^2 = Psi(k) dk^2 / 2, keyed by the mode's index so it does not depend on time.
    auto amplitude = [&](int ms, int ns) {
        const double kx = 2.0 * kPi * ms / g.sizeX, ky = 2.0 * kPi * ns / g.sizeY;
        const double k = std::hypot(kx, ky);
        const double psi = s.density(k, std::atan2(ky, kx) - windDir);
        const uint64_t index = static_cast<uint64_t>(((ns % g.ny) + g.ny) % g.ny) * g.nx + (((ms % g.nx) + g.nx) % g.nx);
        RandomStream rs(seed, kPassSpectralAmp, index);
        const auto [a, b] = gaussianPair(rs);
        return std::complex<double>(a, b) * std::sqrt(psi * dk2 / 4.0);  // (a + ib)/sqrt2 * sqrt(Psi dk^2 / 2)
    };
    Fft2dReal fft(g.nx, g.ny);
    std::complex<double>* H = fft.spectrum();
    for (int n = 0; n < g.ny; ++n) {
        const int ns = n <= g.ny / 2 ? n : n - g.ny;
        for (int m = 0; m < hx; ++m) {
            std::complex<double>& out = H[static_cast<size_t>(n) * hx + m];
            if ((m == 0 && n == 0) || isNyquist(m, g.nx) || isNyquist(n, g.ny)) {
                out = 0.0;
                continue;
            }
            const double k = std::hypot(2.0 * kPi * m / g.sizeX, 2.0 * kPi * ns / g.sizeY);
            const double w = dispersionOmega(k, depth);
            const std::complex<double> phase = std::polar(1.0, -w * time);  // e^{-i w t}
            out = amplitude(m, ns) * phase + std::conj(amplitude(-m, -ns)) * std::conj(phase);
        }
    }
    fft.backward();
    HeightField f = makeVertexField(g, true);
    fillPeriodic(f, fft.real(), g.nx, g.ny);
    return f;
}

HeightField sinusoidField(const GridSpec& g, double A, double lambda, double u0, double dir, double time,
                          double depth) {
    HeightField f = makeVertexField(g, false);
    const double k = 2.0 * kPi / lambda;
    const double w = dispersionOmega(k, depth);
    const double c = std::cos(dir), s = std::sin(dir);
    for (int j = 0; j < f.ny; ++j)
        for (int i = 0; i < f.nx; ++i) {
            const double u = f.x(i) * c + f.y(j) * s;
            f.at(i, j) = -A * std::cos(k * (u - u0) - w * time);
        }
    return f;
}

HeightField flatField(const GridSpec& g) { return makeVertexField(g, false); }

ExpectedStats expectedSlopeStatistics(const ModePower& p, double windDir) {
    const GridSpec& g = p.grid;
    const int hx = p.halfX();
    const double dx = g.dx(), dy = g.dy();
    const double cu = std::cos(windDir), su = std::sin(windDir);
    ExpectedStats e;
    for (int n = 0; n < g.ny; ++n)
        for (int m = 0; m < hx; ++m) {
            const double P = p.power[static_cast<size_t>(n) * hx + m] * p.weight(m);
            if (P == 0.0) continue;
            e.variance += P;
            // Triangle gradients of the mode e^{ik.x}, relative to its value at the cell's corner:
            // lower triangle (i,j),(i+1,j),(i+1,j+1); upper triangle (i,j),(i+1,j+1),(i,j+1).
            const std::complex<double> ex = std::polar(1.0, p.kx(m) * dx), ey = std::polar(1.0, p.ky(n) * dy);
            const std::complex<double> zx1 = (ex - 1.0) / dx, zy1 = ex * (ey - 1.0) / dy;
            const std::complex<double> zx2 = ey * (ex - 1.0) / dx, zy2 = (ey - 1.0) / dy;
            e.mssX += P * 0.5 * (std::norm(zx1) + std::norm(zx2));
            e.mssY += P * 0.5 * (std::norm(zy1) + std::norm(zy2));
            e.mssUpwind += P * 0.5 * (std::norm(cu * zx1 + su * zy1) + std::norm(cu * zx2 + su * zy2));
            e.mssCrosswind += P * 0.5 * (std::norm(-su * zx1 + cu * zy1) + std::norm(-su * zx2 + cu * zy2));
        }
    e.correlationLength = std::nan("");
    return e;
}

ExpectedStats expectedStatistics(const ModePower& p, double windDir) {
    const GridSpec& g = p.grid;
    ExpectedStats e = expectedSlopeStatistics(p, windDir);
    const double dx = g.dx(), dy = g.dy();
    // Expected circular autocorrelation = inverse transform of the mode power.
    Fft2dReal fft(g.nx, g.ny);
    for (size_t idx = 0; idx < p.power.size(); ++idx) fft.spectrum()[idx] = p.power[idx];
    fft.backward();
    Autocorrelation a;
    a.px = g.nx;
    a.py = g.ny;
    a.maxLagX = g.nx / 2;
    a.maxLagY = g.ny / 2;
    a.dx = dx;
    a.dy = dy;
    a.c.assign(fft.real(), fft.real() + static_cast<size_t>(g.nx) * g.ny);
    const double c0 = a.c[0];
    if (c0 > 0) {
        for (double& v : a.c) v /= c0;
        e.correlationLength = correlationLengthRadial(a);
    } else {
        e.correlationLength = std::nan("");
    }
    return e;
}

}  // namespace littoral::surfaces
