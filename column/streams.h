#pragma once
// The discrete directions of the column solver: one hemisphere's polar cosines mu in (0, 1] (the
// other hemisphere mirrors them) with quadrature weights, chosen for a flat air-water interface.
//
// Below the surface, downwelling radiance is discontinuous at the critical angle: inside the
// Snell window (mu > mu_c = sqrt(1 - 1/n^2)) it carries the refracted sky, outside it only light
// reflected back by the surface (total internal reflection). One Gauss rule over [0, 1] would
// straddle that edge, so each hemisphere is split there: n Gauss-Legendre nodes on [0, mu_c] and n
// on [mu_c, 1] ("double-Gauss" on each side of the window edge). Each half integrates polynomials
// of degree 2n - 1 exactly, so phase-function expansions to degree 2n - 1 are integrated exactly
// (energy conservation of the discrete scattering operator). Without an index step (n = 1) the
// hemisphere is one 2n-point Gauss rule.
//
// A last direction mu = 1 with weight 0 is appended: it takes part in no integral but carries the
// nadir / zenith radiance (Lu) exactly, without interpolation.
#include <vector>

namespace littoral::column {

struct Streams {
    std::vector<double> mu, w;  // per hemisphere, ascending mu; the last entry is mu = 1, w = 0
    double muCritical = 0;      // cosine of the critical angle in water (0 without an index step)
    int perHalf = 0;            // n: nodes on each side of mu_c

    int size() const { return static_cast<int>(mu.size()); }
    int nadir() const { return size() - 1; }
    // Moments 0 .. legendreOrder() - 1 of the phase function are kept (delta-M truncates the rest).
    int legendreOrder() const { return 2 * perHalf; }

    // perHalf >= 1; waterIndex >= 1.
    static Streams snellSplit(int perHalf, double waterIndex);
};

}  // namespace littoral::column
