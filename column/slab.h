#pragma once
// The reflection and transmission operators of one homogeneous slab, one azimuthal Fourier mode at
// a time, by the doubling method (van de Hulst 1980; Hansen and Travis 1974, section 3).
//
// Radiance of mode m at the discrete directions (column/streams.h) of each hemisphere; for a
// homogeneous slab with a symmetric phase function the operators seen from above and from below
// are equal:
//   up at the top      = R . down at the top (incident)   + su E_b
//   down at the bottom = T . down at the top (incident)   + sd E_b
// (and likewise for light incident from below), E_b the flux of the direct solar beam through a
// horizontal plane at the slab's top, t the beam's transmittance e^{-Delta/mu0}. Operators map
// radiance to radiance: the quadrature weights sit inside them.
//
// Start: a slab of optical thickness delta_0 = Delta / 2^k <= 1e-6 treated in exact single
// scattering (closed-form integrals along each direction; the neglected double scattering is of
// relative order omega delta_0 / mu_min < 1e-4 per start slab and its accumulated effect is
// checked by halving delta_0 in tests/column). Doubling: two equal slabs combine as
//   G  = (I - R R)^{-1},       T2 = T G T,            R2 = R + T G R T,
//   x  = G (sd + t R su),      y  = R x + t su,        su2 = su + T y,    sd2 = t sd + T x,   t2 = t^2,
// x and y the diffuse radiances down and up at the plane between the halves.
#include <vector>

#include "column/dense.h"
#include "column/streams.h"

namespace littoral::column {

// The scattering of one (delta-M scaled) layer, as the slab operators need it.
struct ScaledOptics {
    double omega = 0;          // single-scattering albedo omega'
    std::vector<double> chi;   // Legendre moments chi'_0 .. chi'_{L-1}
};

struct SlabOperators {
    Matrix R, T;
    std::vector<double> su, sd;
    double beamT = 1;
};

// Mode m, beam direction cosine mu0 in (0, 1] (downward), optical thickness `tau` (> 0, or
// infinity for a semi-infinite slab: then T = 0, sd = 0 and R, su are the limits of doubling).
SlabOperators slabOperators(const Streams& s, const ScaledOptics& optics, int m, double mu0, double tau);

// P^m(x, y) = sum_{l=m}^{L-1} (2l + 1) chi_l L_l^m(x) L_l^m(y): the mode-m kernel of the phase
// function, x and y cosines with sign (positive = downward).
double modeKernel(const std::vector<double>& chi, int m, double x, double y);

}  // namespace littoral::column
