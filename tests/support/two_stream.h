#pragma once
// Two-stream model of a homogeneous slab under uniform illumination: Speir (2010) Appendix A, as
// restated and corrected in spec/seed-ch06-07-appA.md sections 3.8-3.10. An analytic reference
// for the renderer's tests (header-only).
//
// Streams: L+_dave (upwelling) and L-_dave (downwelling) hemispheric mean radiances, one mean
// cosine mubar for both, optical depth tau from the surface (0) to the bottom (tau*). The
// single-scatter source is replaced by the boundary condition L-(0) = L_n (A.5). With backscatter
// fraction b (1/2 for isotropic scattering; the A.46 two-term value otherwise):
//   Gamma^2 = (1 - w0)(1 - w0 + 2 w0 b) / mubar^2            (A.15; b = 1/2: sqrt(1 - w0)/mubar)
//   rho     = (1 - w0 (1 - b) - mubar Gamma) / (w0 b)         (A.17; b = 1/2: (1-sqrt(1-w0))/(1+sqrt(1-w0)))
//   L+ = A e^{Gamma tau} + rho D e^{-Gamma tau},  L- = rho A e^{Gamma tau} + D e^{-Gamma tau}  (A.18, A.19)
//   rho A + D = L_n;  L+(tau*) = R_b L-(tau*)                (A.37, A.38)
//   Q = e+ - rho^2 e- - R_b rho (e+ - e-),  A = -L_n e- (rho - R_b)/Q,  D = L_n e+ (1 - R_b rho)/Q  (A.39, A.40)
// Bottom coupling R_b: the printed A.36 uses 2 pi r mubar, which lacks the Lambertian 1/pi and
// gives negative radiances for bright bottoms; the default here is the corrected 2 r mubar. The
// alternative R_b = r conserves irradiance in the two-stream sense (E+ = r E-).
// Angular radiances by formal integration of the stream sources
//   S-(tau) = w0 [(1 - b) L- + b L+],  S+(tau) = w0 [(1 - b) L+ + b L-]   (A.30, A.48, A.49):
//   L-(tau, mu) = L_n e^{-tau/mu} + Int_0^tau S-(t)/mu e^{-(tau - t)/mu} dt      (A.31; A.42 at tau*)
//   up(tau, mu) = Int_tau^tau* S+(t)/mu e^{-(t - tau)/mu} dt                     (A.44 at tau = 0)
// in closed forms rearranged so that nothing overflows for small mu and mu = 1/Gamma is not
// singular (see the comments at each). Irradiances: E_d(tau) = 2 pi Int_0^1 L-(tau, mu) mu dmu
// from the angular field, or in the two-stream sense E = 2 pi mubar L_dave.
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "core/quadrature.h"
#include "core/units.h"

namespace littoral::testing_support::two_stream {

struct Params {
    double w0 = 0.5;        // single-scattering albedo
    double mubar = 0.5;     // mean cosine of both streams
    double tauStar = 1.0;   // optical depth of the bottom
    double bottomReflectance = 0.0;  // r, Lambertian
    double Rb = std::numeric_limits<double>::quiet_NaN();  // stream coupling; NaN = 2 r mubar
    double Ln = 1.0;        // uniform downwelling radiance just below the surface
    double backscatter = 0.5;  // b; 1/2 = isotropic scattering (Appendix A.2)
};

class Solution {
public:
    explicit Solution(const Params& p) : p_(p) {
        rb_ = std::isnan(p.Rb) ? 2.0 * p.bottomReflectance * p.mubar : p.Rb;
        const double w0 = p.w0, b = p.backscatter;
        gamma_ = std::sqrt((1.0 - w0) * (1.0 - w0 + 2.0 * w0 * b)) / p.mubar;
        rho_ = b == 0.5 ? (1.0 - std::sqrt(1.0 - w0)) / (1.0 + std::sqrt(1.0 - w0))
                        : (1.0 - w0 * (1.0 - b) - p.mubar * gamma_) / (w0 * b);
        // A.39/A.40 divided through by e+ so that no e^{Gamma tau*} overflows.
        const double e2 = std::exp(-2.0 * gamma_ * p.tauStar);
        const double q = 1.0 - rho_ * rho_ * e2 - rb_ * rho_ * (1.0 - e2);
        a_ = -p.Ln * e2 * (rho_ - rb_) / q;  // = -L_n e- (rho - R_b) / Q, Q = e+ q
        d_ = p.Ln * (1.0 - rb_ * rho_) / q;                                 // = L_n e+ (1 - R_b rho) / Q
        // Coefficients of A e^{Gamma t} and D e^{-Gamma t} in the stream sources.
        sDownA_ = w0 * ((1.0 - b) * rho_ + b);
        sDownD_ = w0 * ((1.0 - b) + b * rho_);
        sUpA_ = w0 * ((1.0 - b) + b * rho_);
        sUpD_ = w0 * ((1.0 - b) * rho_ + b);
    }

    double gamma() const { return gamma_; }
    double rho() const { return rho_; }
    double A() const { return a_; }
    double D() const { return d_; }
    double Rb() const { return rb_; }
    const Params& params() const { return p_; }

    double LplusDave(double tau) const { return a_ * std::exp(gamma_ * tau) + rho_ * d_ * std::exp(-gamma_ * tau); }
    double LminusDave(double tau) const { return rho_ * a_ * std::exp(gamma_ * tau) + d_ * std::exp(-gamma_ * tau); }
    double sourceDown(double tau) const { return sDownA_ * a_ * std::exp(gamma_ * tau) + sDownD_ * d_ * std::exp(-gamma_ * tau); }
    double sourceUp(double tau) const { return sUpA_ * a_ * std::exp(gamma_ * tau) + sUpD_ * d_ * std::exp(-gamma_ * tau); }
    // Two-stream irradiances, E = 2 pi mubar L_dave.
    double EdTwoStream(double tau) const { return 2.0 * kPi * p_.mubar * LminusDave(tau); }
    double EuTwoStream(double tau) const { return 2.0 * kPi * p_.mubar * LplusDave(tau); }

    // A.42 generalised to any depth: downwelling radiance at tau in direction mu (cosine from
    // the downward vertical). The terms
    //   (1/mu) Int_0^tau e^{Gamma t} e^{-(tau-t)/mu} dt  = (e^{Gamma tau} - e^{-tau/mu}) / (1 + mu Gamma),
    //   (1/mu) Int_0^tau e^{-Gamma t} e^{-(tau-t)/mu} dt = e^{-Gamma tau} (tau/mu) (1 - e^{-x})/x,
    //   x = (1/mu - Gamma) tau,
    // never overflow and have no singularity at mu = 1/Gamma ((1 - e^{-x})/x -> 1).
    double LminusAngular(double tau, double mu) const {
        if (mu <= 1e-12) return tau > 0 ? sourceDown(tau) : p_.Ln;  // the limit mu -> 0
        const double eTau = std::exp(-tau / mu);
        const double termA = (std::exp(gamma_ * tau) - eTau) / (1.0 + mu * gamma_);
        const double x = (1.0 / mu - gamma_) * tau;
        const double phi = x == 0.0 ? 1.0 : -std::expm1(-x) / x;
        const double termD = std::exp(-gamma_ * tau) * (tau / mu) * phi;
        return p_.Ln * eTau + sDownA_ * a_ * termA + sDownD_ * d_ * termD;
    }

    // A.44 generalised: upwelling radiance scattered into direction mu (cosine from the upward
    // vertical) between tau and the bottom, without the bottom's own contribution. With
    // h = tau* - tau and y = (Gamma - 1/mu) h:
    //   (1/mu) Int_tau^tau* e^{Gamma t} e^{-(t-tau)/mu} dt  = e^{Gamma tau} (h/mu) expm1(y)/y,
    //   (1/mu) Int_tau^tau* e^{-Gamma t} e^{-(t-tau)/mu} dt = e^{-Gamma tau} (1 - e^{-(Gamma+1/mu) h}) / (1 + mu Gamma).
    double inscatterUp(double tau, double mu) const {
        const double h = p_.tauStar - tau;
        if (mu <= 1e-12) return h > 0 ? sourceUp(tau) : 0.0;
        const double y = (gamma_ - 1.0 / mu) * h;
        const double psi = y == 0.0 ? 1.0 : std::expm1(y) / y;
        const double termA = std::exp(gamma_ * tau) * (h / mu) * psi;
        const double termD = std::exp(-gamma_ * tau) * -std::expm1(-(gamma_ + 1.0 / mu) * h) / (1.0 + mu * gamma_);
        return sUpA_ * a_ * termA + sUpD_ * d_ * termD;
    }

    // E_d(tau) = 2 pi Int_0^1 L-(tau, mu) mu dmu from the angular field (8 panels of 16-point
    // Gauss-Legendre: the integrand is smooth on [0, 1], converged to ~1e-14).
    double Ed(double tau) const {
        double s = 0;
        for (int k = 0; k < 8; ++k) {
            const double lo = k / 8.0, hi = (k + 1) / 8.0;
            for (size_t i = 0; i < nodes().size(); ++i) {
                const double mu = 0.5 * (lo + hi) + 0.5 * (hi - lo) * nodes()[i];
                s += 0.5 * (hi - lo) * weights()[i] * LminusAngular(tau, mu) * mu;
            }
        }
        return 2.0 * kPi * s;
    }

    // Radiance leaving the Lambertian bottom, r E_d(tau*) / pi, with E_d from the angular field
    // (the digest's reading of "the result of A.42 reflected from the bottom"), and the same
    // attenuated up to tau plus the in-scatter: the full upwelling radiance at tau in direction mu.
    double bottomRadiance() const { return p_.bottomReflectance * Ed(p_.tauStar) / kPi; }
    double LplusAngular(double tau, double mu) const {
        const double h = p_.tauStar - tau;
        return inscatterUp(tau, mu) + bottomRadiance() * (mu > 1e-12 ? std::exp(-h / mu) : (h > 0 ? 0.0 : 1.0));
    }

private:
    // 16-point Gauss-Legendre on [-1, 1] (core/quadrature.h), computed once.
    static const GaussLegendre& rule() {
        static const GaussLegendre r(16);
        return r;
    }
    static const std::vector<double>& nodes() { return rule().x; }
    static const std::vector<double>& weights() { return rule().w; }

    Params p_;
    double rb_ = 0, gamma_ = 0, rho_ = 0, a_ = 0, d_ = 0;
    double sDownA_ = 0, sDownD_ = 0, sUpA_ = 0, sUpD_ = 0;
};

}  // namespace littoral::testing_support::two_stream
