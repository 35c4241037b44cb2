#pragma once
// Height-field synthesis: Gaussian random fields by FFT filtering of white noise (the
// Beaufort/RMS model), Fourier synthesis from a directional wave spectrum with optional time
// evolution, sinusoidal gravity waves and a flat surface.
//
// Random fields are periodic over the rectangle: they are synthesised on nx x ny unique
// samples (FFT size) and returned on (nx + 1) x (ny + 1) vertices whose last column/row repeat
// the first, so the vertices cover [x0, x0 + sizeX] x [y0, y0 + sizeY] exactly.
// Every random number comes from RandomStream(seed, pass, index): the field depends only on
// the seed and the grid, not on thread count.
#include <cstdint>
#include <vector>

#include "surfaces/height_field.h"
#include "surfaces/wave_spectra.h"

namespace littoral::surfaces {

struct GridSpec {
    int nx = 0, ny = 0;          // cells along x and y (vertices: nx + 1, ny + 1)
    double x0 = 0, y0 = 0;       // lower-left corner, m
    double sizeX = 0, sizeY = 0; // m
    double dx() const { return sizeX / nx; }
    double dy() const { return sizeY / ny; }
};

// Expected height variance carried by each Fourier mode of a periodic field, E|h_k|^2 (m^2),
// in FFTW's half-complex layout: index n * (nx/2 + 1) + m for kx = 2 pi m / sizeX (m = 0..nx/2)
// and ky = 2 pi n' / sizeY with n' = n for n <= ny/2, else n - ny. The mean (k = 0) carries
// nothing, so the mean water level is exactly z = 0.
struct ModePower {
    GridSpec grid;
    std::vector<double> power;
    int halfX() const { return grid.nx / 2 + 1; }
    double kx(int m) const;
    double ky(int n) const;
    // Multiplicity of column m in the full plane (1 for m = 0 and the even-nx Nyquist column,
    // else 2: the mode and its conjugate -k).
    double weight(int m) const { return (m == 0 || (grid.nx % 2 == 0 && m == grid.nx / 2)) ? 1.0 : 2.0; }
};

// Gaussian autocorrelation C(r) = h^2 exp(-r^2 / L^2): its wave-vector spectrum is
// C~(k) = h^2 L^2 / (4 pi) exp(-k^2 L^2 / 4) (m^4), and mode k carries C~(k) dkx dky.
ModePower gaussianModePower(const GridSpec& g, double rmsHeight, double correlationLength);
// Anisotropic Gaussian autocorrelation C(r) = h^2 exp(-(r_a^2 / La^2 + r_c^2 / Lc^2)), r_a the lag
// along `direction` (radians ccw from +x) and r_c across it: C~(k) = h^2 La Lc / (4 pi)
// exp(-(k_a^2 La^2 + k_c^2 Lc^2) / 4). Its slope variances are 2 h^2 / La^2 along and 2 h^2 / Lc^2
// across the direction (-C'' at 0).
ModePower anisotropicGaussianModePower(const GridSpec& g, double rmsHeight, double lengthAlong, double lengthAcross,
                                       double direction);
// Directional spectrum rotated to the wind direction (radians, counter-clockwise from +x,
// the direction the wind blows toward): E|h_k|^2 = (Psi(k) + Psi(-k)) dkx dky / 2 (see the
// synthesis comment in synthesis.cpp). Nyquist rows/columns are left empty.
ModePower spectralModePower(const GridSpec& g, const WaveSpectrum& s, double windDirection);

// White Gaussian noise (one N(0,1) sample per grid point from RandomStream(seed, ...)),
// r2c FFT, multiply by sqrt(M C~(k) dk^2) / M, c2r FFT: a field whose ensemble autocorrelation is
// the periodic sum of h^2 exp(-r^2/L^2) without its mean.
HeightField synthesizeGaussian(const GridSpec& g, double rmsHeight, double correlationLength, uint64_t seed);
// The same filtering of the same white noise, for any mode power (E|h_k|^2 = p.power).
HeightField synthesizeFromModePower(const ModePower& p, uint64_t seed);

// Fourier synthesis at time t (s): h(x, t) = Sum_k [a_k e^{-i w t} + conj(a_-k) e^{i w t}] e^{i k.x}
// with independent complex Gaussian a_k, E|a_k|^2 = Psi(k) dk^2 / 2, and w = dispersionOmega(|k|,
// depth) (depth <= 0: deep water). Each component travels along its wave vector.
HeightField synthesizeSpectral(const GridSpec& g, const WaveSpectrum& s, double windDirection,
                               uint64_t seed, double time, double depth);

// Sinusoidal gravity wave z = -A cos(k (u - u0) - w t), u = x cos(dir) + y sin(dir), k = 2 pi / lambda,
// w = dispersionOmega(k, depth): a trough at u = u0 when t = 0 (the DIRSIG SINUSOID convention,
// spec/seed-ch05-10.md section 1.8). Not periodic over the rectangle in general.
HeightField sinusoidField(const GridSpec& g, double amplitude, double wavelength, double phase,
                          double direction, double time, double depth);
HeightField flatField(const GridSpec& g);

// Ensemble expectations of what surfaceStatistics() measures on a field with this mode power:
// height variance, triangle-slope variances (forward differences, both triangles of each cell)
// along x, y, upwind and crosswind, and the correlation length of the expected autocorrelation.
struct ExpectedStats {
    double variance = 0;
    double mssX = 0, mssY = 0, mssUpwind = 0, mssCrosswind = 0;
    double correlationLength = 0;
};
ExpectedStats expectedStatistics(const ModePower& p, double windDirection);
// Only the height and slope moments of expectedStatistics (correlationLength NaN): no FFT.
ExpectedStats expectedSlopeStatistics(const ModePower& p, double windDirection);

}  // namespace littoral::surfaces
