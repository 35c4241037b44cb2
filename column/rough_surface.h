#pragma once
// The Cox-Munk rough air-water interface of the column solver, with the isotropic slope
// distribution P(zx, zy) = exp(-(zx^2 + zy^2) / s2) / (pi s2), s2 the total mean-square slope
// (Cox and Munk 1954, clean sea: s2 = 0.003 + 0.00512 U). Because P does not depend on the azimuth,
// the surface couples no two azimuthal Fourier modes: it is one reflection matrix per mode.
//
// Every operator is a quadrature over facet slopes (no BRDF formula is evaluated): a ray of
// direction d meets a facet of normal n with probability P(s) |d.n| / (|d_z| n_z) over the facets
// that face it, renormalised to 1 per incident direction (each ray meets exactly one facet; no
// shadowing or masking, so no energy is lost). The facet reflects the Fresnel fraction r(|d.n|)
// specularly and transmits 1 - r by Snell's law. A ray that leaves a facet toward the wrong side of
// the mean plane (it would meet the surface again) is mirrored in the mean plane, keeping its
// energy on the side it was sent to. Multiple surface interactions are otherwise ignored.
//
// Radiance operators are built by binning: the stream cells partition each hemisphere (cell i spans
// w_i in mu, the Gauss weights laid end to end, so the Snell-window edge is a cell edge); the flux a
// facet sends into cell i becomes the cell-average radiance flux / (2 pi mu_i w_i). Flux is thus
// conserved exactly, whatever the streams; for a flat surface (s2 -> 0) the operators reduce to the
// flat ones (diag r(mu_i), the refracted beam).
#include <vector>

#include "column/dense.h"
#include "column/streams.h"

namespace littoral::column {

// The slope quadrature: facets (zx, zy) with weights summing to 1 for the isotropic Gaussian of
// mean-square slope s2 (> 0): midpoint rule in u = 1 - exp(-|z|^2 / s2) (radial) times a uniform
// rule in the slope azimuth.
struct Facet {
    double zx = 0, zy = 0, weight = 0;
};
std::vector<Facet> slopeQuadrature(double meanSquareSlope, int radial = 160, int azimuthal = 256);

// What happens to a ray of unit direction `dir` (travel; dir.z < 0 travelling down from the air,
// > 0 travelling up from the water) at the rough surface, water index nWater.
struct FacetOutcome {
    double dx = 0, dy = 0, dz = 0;  // outgoing unit direction (travel)
    double weight = 0;              // fraction of the incident flux
};
struct SurfaceScatter {
    std::vector<FacetOutcome> reflected, transmitted;
    double reflectance = 0, transmittance = 0;  // totals (sum of the weights above)
};
SurfaceScatter scatterAtSurface(const std::vector<Facet>& facets, double nWater, double dx, double dy, double dz);

struct RoughSurfaceOperators {
    // mode m: down radiance (index i) just below = R[m](i, j) x up radiance (index j) just below.
    std::vector<Matrix> reflectionFromBelow;
    std::vector<double> reflectanceFromBelow;  // per stream: hemispherical reflectance (TIR included)
    std::vector<double> skyTransmission;       // per stream: in-water radiance / sky radiance (mode 0)
    double reflectanceFromAirAtZenith = 0;     // for the water-leaving radiance toward the zenith
};
RoughSurfaceOperators roughSurfaceOperators(const Streams& s, double nWater, double meanSquareSlope, int modes);

// The solar beam after the surface: collimated sub-beams in the water, each with its flux through a
// horizontal plane just below the surface, its direction cosine and its azimuths relative to the
// refracted sun (each azimuth psi stands for the pair +-psi, the field being symmetric).
struct SubBeam {
    double mu = 1, flux = 0;
    std::vector<double> psi, fraction;  // fractions sum to 1
    double modeFactor(int m) const;     // sum fraction cos(m psi)
};
// Sun at zenith angle sunZenith (rad, in air) with irradiance e0 on a plane normal to the beam.
std::vector<SubBeam> transmittedSun(double sunZenith, double e0, double nWater, double meanSquareSlope, int muBins = 24,
                                    int psiBins = 12);

}  // namespace littoral::column
