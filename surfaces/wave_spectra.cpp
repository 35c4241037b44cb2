#include "surfaces/wave_spectra.h"

#include "core/cox_munk_fit.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "core/error.h"
#include "core/log.h"
#include "core/units.h"

namespace littoral::surfaces {

namespace {
constexpr double kM = 370.0;  // rad/m, wavenumber of the gravity-capillary minimum phase speed
// Phillips constant of Pierson and Moskowitz (1964).
constexpr double kAlphaPM = 8.1e-3;
// omega_p U / g for the Pierson-Moskowitz spectrum written as exp(-0.74 (g/(U omega))^4) =
// exp(-5/4 (omega_p/omega)^4): omega_p = (0.74 / 1.25)^(1/4) g / U.
const double kPeakPM = std::pow(0.74 / 1.25, 0.25);

// Phase speed with capillarity, c(k) = sqrt(g/k (1 + (k/km)^2)) (Elfouhaily et al. 1997 eq. 24).
double phaseSpeed(double k) { return std::sqrt(kGravity / k * (1.0 + sqr(k / kM))); }
}  // namespace

double dispersionOmega(double k, double depth) {
    const double tensionTerm = kGravity / (kM * kM);  // m^3 s^-2, sigma / rho
    const double t = depth > 0 ? std::tanh(k * depth) : 1.0;
    return std::sqrt((kGravity * k + tensionTerm * k * k * k) * t);
}

double gravityWavenumber(double omega, double depth) {
    const double kDeep = omega * omega / kGravity;
    if (depth <= 0) return kDeep;
    // Newton on f(k) = g k tanh(k d) - omega^2, started from the shallow/deep blend
    // k = kDeep / sqrt(tanh(kDeep d)), which is within a few percent everywhere.
    double k = kDeep / std::sqrt(std::tanh(kDeep * depth));
    for (int it = 0; it < 50; ++it) {
        const double th = std::tanh(k * depth);
        const double f = kGravity * k * th - omega * omega;
        const double df = kGravity * (th + k * depth * (1 - th * th));
        const double step = f / df;
        k -= step;
        if (std::abs(step) < 1e-15 * k) break;
    }
    return k;
}

double piersonMoskowitzHs(double U) {
    // m0 = Int alpha g^2 w^-5 exp(-5/4 (wp/w)^4) dw = alpha g^2 / (5 wp^4).
    const double wp = kPeakPM * kGravity / U;
    const double m0 = kAlphaPM * kGravity * kGravity / (5.0 * std::pow(wp, 4));
    return 4.0 * std::sqrt(m0);
}

double frictionVelocity(double u10) {
    const double cd = (0.8 + 0.065 * u10) * 1e-3;  // Wu (1982)
    return std::sqrt(cd) * u10;
}

CoxMunkMss coxMunkMss(double U) {
    const SlopeVariances v = coxMunkSlopeVariances(U, CoxMunkSea::Clean);
    return {v.upwind, v.crosswind, coxMunkCleanTotalMss(U)};
}

WaveSpectrum::WaveSpectrum(const SpectrumParams& p) : p_(p) {
    LITTORAL_CHECK_GT(p.windSpeed, 0.0);
    const double U = p.windSpeed, g = kGravity;
    switch (p.model) {
    case SpectrumModel::PiersonMoskowitz:
        alpha_ = kAlphaPM;
        omegaP_ = kPeakPM * g / U;
        break;
    case SpectrumModel::Jonswap:
        alpha_ = kAlphaPM;
        omegaP_ = kPeakPM * g / U;
        if (p.fetch > 0) {
            // Hasselmann et al. (1973): alpha = 0.076 xi^-0.22, omega_p = 22 (g^2 / (U X))^(1/3),
            // xi = g X / U^2; clamped at the fully developed (Pierson-Moskowitz) values.
            const double xi = g * p.fetch / (U * U);
            alpha_ = std::max(kAlphaPM, 0.076 * std::pow(xi, -0.22));
            omegaP_ = std::max(kPeakPM * g / U, 22.0 * std::cbrt(g * g / (U * p.fetch)));
        }
        break;
    case SpectrumModel::Elfouhaily: {
        // Elfouhaily et al. (1997), J. Geophys. Res. 102(C7) 15781: inverse wave age Omega
        // (eq. 37), 0.84 for a fully developed sea; clamped to the spectrum's range [0.84, 5].
        omegaAge_ = 0.84;
        if (p.fetch > 0) {
            const double xi = g * p.fetch / (U * U);
            omegaAge_ = 0.84 * std::pow(std::tanh(std::pow(xi / 2.2e4, 0.4)), -0.75);
            if (omegaAge_ > 5.0) {
                log::warn("elfouhaily: fetch {:.0f} m gives inverse wave age {:.2f}; clamped to 5",
                          p.fetch, omegaAge_);
                omegaAge_ = 5.0;
            }
        }
        kp_ = g / (U * U) * omegaAge_ * omegaAge_;  // eq. 3 with k0 = g / U10^2
        cp_ = phaseSpeed(kp_);
        omegaP_ = std::sqrt(g * kp_);
        uStar_ = frictionVelocity(U);
        alphaP_ = 6e-3 * std::pow(omegaAge_, 0.55);            // eq. 34
        sigmaJ_ = 0.08 * (1.0 + 4.0 / std::pow(omegaAge_, 3));  // eq. 3
        gammaE_ = omegaAge_ < 1.0 ? 1.7 : 1.7 + 6.0 * std::log10(omegaAge_);
        const double cm = phaseSpeed(kM);
        // eq. 44; negative values (u* < cm/e, U10 below about 2.7 m/s) are set to 0.
        alphaM_ = uStar_ <= cm ? 1e-2 * (1.0 + std::log(uStar_ / cm)) : 1e-2 * (1.0 + 3.0 * std::log(uStar_ / cm));
        alphaM_ = std::max(alphaM_, 0.0);
        return;
    }
    }
    kp_ = omegaP_ * omegaP_ / g;
}

double WaveSpectrum::omegaSpectrum(double w) const {
    // JONSWAP (Hasselmann et al. 1973): S = alpha g^2 w^-5 exp(-5/4 (wp/w)^4) gamma^r,
    // r = exp(-(w - wp)^2 / (2 sigma^2 wp^2)), sigma = 0.07 below the peak and 0.09 above.
    // With gamma = 1 (and always for Pierson-Moskowitz) the enhancement factor is 1.
    if (w <= 0) return 0.0;
    const double g = kGravity;
    double s = alpha_ * g * g * std::pow(w, -5.0) * std::exp(-1.25 * std::pow(omegaP_ / w, 4));
    if (p_.model == SpectrumModel::Jonswap && p_.gamma != 1.0) {
        const double sigma = w <= omegaP_ ? 0.07 : 0.09;
        const double r = std::exp(-sqr(w - omegaP_) / (2.0 * sigma * sigma * omegaP_ * omegaP_));
        s *= std::pow(p_.gamma, r);
    }
    return s;
}

double WaveSpectrum::frequencySpectrum(double w) const {
    if (p_.model != SpectrumModel::Elfouhaily) return omegaSpectrum(w);
    const double k = w * w / kGravity;
    return omni(k) * 2.0 * w / kGravity;
}

double WaveSpectrum::omni(double k) const {
    if (k <= 0) return 0.0;
    if (p_.model != SpectrumModel::Elfouhaily) {
        // F(k) = S(omega) d omega / dk with omega = sqrt(g k): d omega / dk = g / (2 omega).
        const double w = std::sqrt(kGravity * k);
        return omegaSpectrum(w) * kGravity / (2.0 * w);
    }
    // Elfouhaily et al. (1997): F(k) = k^-3 (B_l + B_h), eqs. 30-44.
    const double c = phaseSpeed(k);
    const double cm = phaseSpeed(kM);
    const double lpm = std::exp(-1.25 * sqr(kp_ / k));                          // eq. 2
    const double gam = std::exp(-sqr(std::sqrt(k / kp_) - 1.0) / (2.0 * sqr(sigmaJ_)));
    const double jp = std::pow(gammaE_, gam);                                  // eq. 3
    const double fp = lpm * jp * std::exp(-omegaAge_ / std::sqrt(10.0) * (std::sqrt(k / kp_) - 1.0));  // eq. 32
    const double bl = 0.5 * alphaP_ * (cp_ / c) * fp;                           // eq. 31
    // eq. 41, with the L_PM J_p factor of the long-wave side applied as well (as in common use of
    // the spectrum), so the short-wave term vanishes below the peak instead of adding there.
    const double fm = lpm * jp * std::exp(-0.25 * sqr(k / kM - 1.0));
    const double bh = 0.5 * alphaM_ * (cm / c) * fm;                            // eq. 40
    return (bl + bh) / (k * k * k);
}

double WaveSpectrum::spreading(double k, double theta) const {
    if (p_.model == SpectrumModel::Elfouhaily) {
        // Elfouhaily et al. (1997) eqs. 49, 57: centrosymmetric
        // D = (1 + Delta(k) cos 2 theta) / (2 pi),
        // Delta = tanh(ln2/4 + 4 (c/cp)^2.5 + 0.13 (u*/cm) (cm/c)^2.5).
        const double c = phaseSpeed(k), cm = phaseSpeed(kM);
        const double delta = std::tanh(std::log(2.0) / 4.0 + 4.0 * std::pow(c / cp_, 2.5) +
                                       0.13 * (uStar_ / cm) * std::pow(cm / c, 2.5));
        return (1.0 + delta * std::cos(2.0 * theta)) / (2.0 * kPi);
    }
    // Mitsuyasu et al. (1975) cosine-2s spreading, waves travelling downwind:
    // D = G(s) cos^(2s)(theta/2), G(s) = Gamma(s+1) / (2 sqrt(pi) Gamma(s+1/2)),
    // s = s_p (w/wp)^5 below the peak and s_p (w/wp)^-2.5 above, s_p = 11.5 (wp U / g)^-2.5.
    const double w = std::sqrt(kGravity * k);
    const double sp = 11.5 * std::pow(omegaP_ * p_.windSpeed / kGravity, -2.5);
    const double ratio = w / omegaP_;
    const double s = ratio <= 1.0 ? sp * std::pow(ratio, 5.0) : sp * std::pow(ratio, -2.5);
    const double norm = std::exp(std::lgamma(s + 1.0) - std::lgamma(s + 0.5)) / (2.0 * std::sqrt(kPi));
    const double c = std::abs(std::cos(0.5 * theta));
    return norm * std::pow(c, 2.0 * s);
}

WaveSpectrum::Moments WaveSpectrum::moments(double kMax) const {
    // Trapezoid rule in ln k (F k d ln k) and in theta (periodic, so spectrally accurate).
    Moments m;
    const double kMin = 1e-3 * kp_;
    if (kMax <= kMin) return m;
    const int nk = 6000, nt = 256;
    const double dlk = std::log(kMax / kMin) / (nk - 1);
    const double dt = 2.0 * kPi / nt;
    for (int i = 0; i < nk; ++i) {
        const double k = kMin * std::exp(i * dlk);
        const double wk = (i == 0 || i == nk - 1 ? 0.5 : 1.0) * dlk * k;
        const double f = omni(k);
        if (f == 0.0) continue;
        double c2 = 0, s2 = 0;
        for (int t = 0; t < nt; ++t) {
            const double th = -kPi + t * dt;
            const double d = spreading(k, th) * dt;
            c2 += d * sqr(std::cos(th));
            s2 += d * sqr(std::sin(th));
        }
        m.m0 += wk * f;
        m.mssUpwind += wk * f * k * k * c2;
        m.mssCrosswind += wk * f * k * k * s2;
    }
    return m;
}

std::string WaveSpectrum::describe() const {
    switch (p_.model) {
    case SpectrumModel::PiersonMoskowitz:
        return fmt::format("Pierson-Moskowitz, U19.5 = {} m/s, peak {:.4f} rad/m", p_.windSpeed, kp_);
    case SpectrumModel::Jonswap:
        return fmt::format("JONSWAP, U10 = {} m/s, fetch {} m, gamma {}, alpha {:.5f}, peak {:.4f} rad/m",
                           p_.windSpeed, p_.fetch, p_.gamma, alpha_, kp_);
    case SpectrumModel::Elfouhaily:
        return fmt::format("Elfouhaily, U10 = {} m/s, inverse wave age {:.3f}, peak {:.4f} rad/m",
                           p_.windSpeed, omegaAge_, kp_);
    }
    return "";
}

}  // namespace littoral::surfaces
