#pragma once
// Directional wave spectra and the dispersion relation for Fourier synthesis of sea surfaces.
//
// Conventions (SI units):
//   * The wave-vector spectrum Psi(kx, ky) (m^4) is the height variance per unit wave-vector
//     area: Int Psi d^2k = m0 = <z^2>. A component with wave vector k travels along +k.
//   * Psi(k, theta) = F(k) D(k, theta) / k, with F the omnidirectional wavenumber spectrum
//     (m^3, Int F dk = m0) and D the spreading function (rad^-1, Int D dtheta = 1 over 2 pi).
//   * theta is measured from the wind direction (the direction the wind blows toward).
//   * Significant wave height Hs = 4 sqrt(m0).
// Frequency spectra S(omega) (Pierson-Moskowitz, JONSWAP) are mapped to wavenumber with the
// deep-water gravity-wave relation omega^2 = g k: F(k) = S(omega) d omega/dk.
#include <string>

namespace littoral::surfaces {

enum class SpectrumModel { PiersonMoskowitz, Jonswap, Elfouhaily };

struct SpectrumParams {
    SpectrumModel model = SpectrumModel::PiersonMoskowitz;
    // Wind speed, m/s, at the model's reference height: 19.5 m for Pierson-Moskowitz (1964),
    // 10 m for JONSWAP (Hasselmann et al. 1973) and Elfouhaily et al. (1997).
    double windSpeed = 10.0;
    // Fetch, m. 0 = fully developed sea. JONSWAP: alpha and omega_p follow Hasselmann et al.
    // (1973) and are clamped at their Pierson-Moskowitz values, so a fully developed JONSWAP
    // with gamma = 1 is exactly Pierson-Moskowitz. Elfouhaily: inverse wave age from fetch.
    double fetch = 0.0;
    double gamma = 3.3;  // JONSWAP peak enhancement (1 = Pierson-Moskowitz)
};

class WaveSpectrum {
public:
    explicit WaveSpectrum(const SpectrumParams& p);

    const SpectrumParams& params() const { return p_; }
    // Omnidirectional wavenumber spectrum F(k), m^3 (k in rad/m, k > 0).
    double omni(double k) const;
    // Spreading D(k, theta), rad^-1, theta from the downwind direction.
    double spreading(double k, double theta) const;
    // Psi(k, theta) = F(k) D(k, theta) / k, m^4.
    double density(double k, double theta) const { return omni(k) * spreading(k, theta) / k; }
    // Spectral peak wavenumber (rad/m) and angular frequency (rad/s).
    double peakWavenumber() const { return kp_; }
    double peakFrequency() const { return omegaP_; }
    // For frequency-domain models: S(omega), m^2 s (Elfouhaily: obtained from F(k) by the
    // deep-water mapping, for reporting only).
    double frequencySpectrum(double omega) const;

    // Moments of the full (unresolved) spectrum by numerical quadrature on a logarithmic
    // wavenumber grid from 1e-3 kp to kMax: m0 = Int F dk and the mean-square slopes
    // mss_upwind = Int Int kx'^2 Psi, mss_crosswind = Int Int ky'^2 Psi (primed: wind axes).
    struct Moments { double m0 = 0, mssUpwind = 0, mssCrosswind = 0; };
    Moments moments(double kMax) const;

    std::string describe() const;

private:
    SpectrumParams p_;
    double alpha_ = 0, omegaP_ = 0, kp_ = 0;
    // Elfouhaily parameters
    double omegaAge_ = 0.84, uStar_ = 0, alphaP_ = 0, alphaM_ = 0, sigmaJ_ = 0, gammaE_ = 0, cp_ = 0;
    double omegaSpectrum(double omega) const;  // PM / JONSWAP S(omega)
};

// Linear dispersion relation with capillarity, omega^2 = (g k + T k^3) tanh(k d), T = g / km^2
// (surface tension over density, km = 370 rad/m as in Elfouhaily et al. 1997). depth <= 0 means
// deep water (tanh = 1). Returns rad/s.
double dispersionOmega(double k, double depth);
// Gravity-wave wavenumber for angular frequency omega at depth (deep water if depth <= 0),
// solving omega^2 = g k tanh(k d) by Newton iteration. rad/m.
double gravityWavenumber(double omega, double depth);

// Pierson-Moskowitz significant wave height from the spectrum's zeroth moment:
// Hs = 4 sqrt(alpha / (5 a^4)) U^2 / g with a = omega_p U / g = (0.74 / 1.25)^(1/4), i.e. about
// 0.209 U^2/g (the commonly quoted 0.21 U^2/g, wind at 19.5 m).
double piersonMoskowitzHs(double windSpeed19_5);

// Friction velocity u* (m/s) from the 10 m wind with the drag coefficient of Wu (1982),
// Cd = (0.8 + 0.065 U10) 1e-3.
double frictionVelocity(double u10);

// Cox and Munk (1954) clean-surface mean-square slopes, U at 12.5 m (core/cox_munk_fit.h):
// upwind 3.16e-3 U, crosswind 0.003 + 1.92e-3 U, total 0.003 + 5.12e-3 U (their separate fit).
struct CoxMunkMss { double upwind = 0, crosswind = 0, total = 0; };
CoxMunkMss coxMunkMss(double windSpeed);

}  // namespace littoral::surfaces
