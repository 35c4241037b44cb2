#pragma once
// Legendre expansion of a phase function and the normalised associated Legendre functions that
// split it into azimuthal Fourier modes (the addition theorem).
//
//   4 pi p(cos Theta) = sum_l (2l + 1) chi_l P_l(cos Theta),   chi_l = 2 pi Int_{-1}^{1} p(x) P_l(x) dx,
//   P_l(cos Theta)    = sum_m (2 - delta_m0) L_l^m(mu) L_l^m(mu') cos(m (phi - phi')),
// with L_l^m = sqrt((l - m)!/(l + m)!) P_l^m (the sign convention cancels in the products).
#include <vector>

#include "core/phase_functions.h"

namespace littoral::column {

// chi_0 .. chi_{count-1} of p, chi_0 = 1. Integrated in t = 1 - cos Theta on logarithmically spaced
// panels from t = 1e-12 to 2 (Gauss-Legendre, 16 points each) so that a forward peak as sharp as
// Petzold's (p ~ t^-0.67 below 0.1 deg) is resolved; the cone t < 1e-12 adds its scattered fraction
// with P_l = 1 there (its error is below l^2 x 1e-12).
std::vector<double> legendreMoments(const PhaseFunction& p, int count);

// L_l^m(x) for l = 0 .. lmax (zero for l < m).
std::vector<double> normalizedAssociatedLegendre(int m, int lmax, double x);

}  // namespace littoral::column
