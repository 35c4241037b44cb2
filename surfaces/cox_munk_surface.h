#pragma once
// The `cox-munk` wave model: a Gaussian random surface whose facet slopes have Cox and Munk's
// (1954) mean-square slopes at a given wind, for users who want physical rather than historical
// (the dissertation's `beaufort`) slope statistics; see docs/waves.md.
//
// Field: anisotropic Gaussian autocorrelation C(r) = h^2 exp(-(r_u^2 / L_u^2 + r_c^2 / L_c^2)),
// r_u along the wind and r_c across it, synthesised by FFT filtering of white noise like the
// `beaufort` field (surfaces/synthesis.h). Its slope variances are 2 h^2 / L_u^2 along and
// 2 h^2 / L_c^2 across the wind, so
//   L_u = sqrt(2) h / sigma_u,  L_c = sqrt(2) h / sigma_c
// puts the Cox-Munk variances sigma_u^2, sigma_c^2 (core/cox_munk_fit.h, any of the clean, slick or
// dissertation fits) on the continuous surface. The mesh's facets are the grid's triangles, whose
// slopes are forward differences and see 2 h^2 (1 - exp(-d^2 / L^2)) / d^2 instead (0.7 % less at
// 6 m/s on the default 0.25 m grid); designCoxMunkSurface() therefore shrinks L_u and L_c until the
// ensemble mean of the triangle slopes (expectedSlopeStatistics, exact for the grid) equals the
// Cox-Munk variances (to 1e-9 relative). The facets of a decimated mesh are larger and smoother:
// keep the full grid (the model's default, `triangles: 0`).
//
// RMS elevation: a single-scale Gaussian surface cannot have both the heights of the long waves
// and the slopes of the short ones. We take h = 0.016 U^2 / sqrt(8): the dissertation's 0.016 U^2
// is a Rayleigh RMS wave *height* (crest to trough) in its source, and a narrow-band Gaussian sea
// of RMS elevation h has H_rms = sqrt(8) h. At 6 m/s: h = 0.204 m, L_u = 2.09 m, L_c = 2.39 m
// (clean sea), slopes 0.138 and 0.121 RMS.
#include "core/cox_munk_fit.h"
#include "surfaces/synthesis.h"

namespace littoral::surfaces {

// h = 0.016 U^2 / sqrt(8), m (U at 12.5 m, m/s).
double coxMunkSurfaceRmsHeight(double windSpeed);

struct CoxMunkSurfaceDesign {
    double rmsHeight = 0;                           // h, m
    double lengthUpwind = 0, lengthCrosswind = 0;   // L_u, L_c after the grid correction, m
    double continuumUpwind = 0, continuumCrosswind = 0;  // sqrt(2) h / sigma, before it, m
    SlopeVariances target;                          // Cox-Munk sigma_u^2, sigma_c^2
    SlopeVariances expectedOnGrid;                  // ensemble mean of the triangle slopes
};

// L_u, L_c for grid `g` (windDirection: radians ccw from +x, the direction the wind blows toward).
// Requires a resolvable design (spacing <= min(continuum lengths) / 2; validateWaveParams checks).
CoxMunkSurfaceDesign designCoxMunkSurface(const GridSpec& g, double windSpeed, CoxMunkSea sea, double windDirection);

}  // namespace littoral::surfaces
