#include "surfaces/cox_munk_surface.h"

#include <cmath>

#include "core/error.h"

namespace littoral::surfaces {

double coxMunkSurfaceRmsHeight(double U) {
    // H_rms = sqrt(8) sigma_eta for a narrow-band Gaussian sea (Rayleigh-distributed wave heights).
    return 0.016 * U * U / std::sqrt(8.0);
}

CoxMunkSurfaceDesign designCoxMunkSurface(const GridSpec& g, double U, CoxMunkSea sea, double windDirection) {
    CoxMunkSurfaceDesign d;
    d.target = coxMunkSlopeVariances(U, sea);
    d.rmsHeight = coxMunkSurfaceRmsHeight(U);
    const double h = d.rmsHeight;
    d.continuumUpwind = std::sqrt(2.0) * h / std::sqrt(d.target.upwind);
    d.continuumCrosswind = std::sqrt(2.0) * h / std::sqrt(d.target.crosswind);
    double Lu = d.continuumUpwind, Lc = d.continuumCrosswind;
    // Fixed point on L <- L sqrt(expected / target): the slope variance goes as 1/L^2 to within the
    // forward-difference factor, which changes slowly with L, so each step divides the error by
    // about (d/L)^2 / 2; 20 steps is far more than 1e-9 needs for d <= L/2.
    for (int it = 0; it < 20; ++it) {
        const ExpectedStats e = expectedSlopeStatistics(anisotropicGaussianModePower(g, h, Lu, Lc, windDirection),
                                                        windDirection);
        d.expectedOnGrid = {e.mssUpwind, e.mssCrosswind};
        const double ru = e.mssUpwind / d.target.upwind, rc = e.mssCrosswind / d.target.crosswind;
        if (std::abs(ru - 1.0) < 1e-10 && std::abs(rc - 1.0) < 1e-10) break;
        Lu *= std::sqrt(ru);
        Lc *= std::sqrt(rc);
    }
    LITTORAL_CHECK_LT(std::abs(d.expectedOnGrid.upwind / d.target.upwind - 1.0), 1e-9);
    LITTORAL_CHECK_LT(std::abs(d.expectedOnGrid.crosswind / d.target.crosswind - 1.0), 1e-9);
    d.lengthUpwind = Lu;
    d.lengthCrosswind = Lc;
    return d;
}

}  // namespace littoral::surfaces
