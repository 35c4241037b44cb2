#pragma once
// Measured statistics of a realised surface, on the height field (its full-resolution
// triangulation) and on the final (decimated) mesh. Units: metres; slopes are dimensionless
// (dz/dx, "radians" in the dissertation's tables).
//
// What is measured:
//  * heights: mean and RMS about the mean. Grid: over the unique samples (the wrap-around
//    row/column of a periodic field is not counted twice). Mesh: exact integrals of the
//    piecewise-linear surface over its horizontal projection (area-weighted).
//  * slopes: each triangle's gradient (zx, zy) = (-nx/nz, -ny/nz), weighted by projected area.
//    The grid is triangulated as the mesh is (two triangles per cell, diagonal (i,j)-(i+1,j+1)),
//    so grid slopes are forward differences and equal the full-resolution mesh's slopes.
//    rmsSlopeX/Y = sqrt(<zx^2>), sqrt(<zy^2>); rmsSlope = sqrt((<zx^2> + <zy^2>) / 2), the per-axis
//    RMS slope that the dissertation's s predicts; rmsSlopeTotal = sqrt(<zx^2 + zy^2>);
//    mssUpwind/Crosswind = <(slope along / across the wind)^2>.
//  * correlation length: the lag at which the normalised autocorrelation first falls to 1/e,
//    found by linear interpolation. correlationLength uses the azimuthally averaged
//    autocorrelation; the upwind/crosswind values follow the autocorrelation along those axes.
//    The autocorrelation is circular for a periodic field and zero-padded (normalised by the
//    number of overlapping samples at each lag) otherwise. NaN when undefined (flat surface,
//    or no crossing within half the domain).
#include <vector>

#include "core/mesh.h"
#include "surfaces/height_field.h"

namespace littoral::surfaces {

struct SurfaceStats {
    double meanHeight = 0, rmsHeight = 0;
    double rmsSlopeX = 0, rmsSlopeY = 0, rmsSlope = 0, rmsSlopeTotal = 0;
    double mssUpwind = 0, mssCrosswind = 0;
    double correlationLength = 0, correlationLengthUpwind = 0, correlationLengthCrosswind = 0;
};

// windDirection: radians counter-clockwise from +x (the direction the wind blows toward).
SurfaceStats measureHeightField(const HeightField& f, double windDirection);

// Statistics of a height-field mesh covering the rectangle of `reference`. The correlation
// length is measured on the mesh rasterised (barycentric interpolation) at the vertices of
// `reference`; *maxDeviation (if given) receives max |mesh(x, y) - reference(x, y)| over them.
SurfaceStats measureMesh(const TriMesh& mesh, const HeightField& reference, double windDirection,
                         double* maxDeviation = nullptr);

// The mesh resampled at the vertices of `reference` (same rectangle and vertex count).
HeightField rasterizeMesh(const TriMesh& mesh, const HeightField& reference);

// Normalised autocorrelation (value 1 at lag 0) on integer lags, with its lag spacing.
struct Autocorrelation {
    int px = 0, py = 0;          // array size (lags are taken modulo px, py)
    int maxLagX = 0, maxLagY = 0;
    double dx = 0, dy = 0;
    std::vector<double> c;
    double at(int li, int lj) const {
        const int i = ((li % px) + px) % px, j = ((lj % py) + py) % py;
        return c[static_cast<size_t>(j) * px + i];
    }
};
// Autocorrelation of the field about its mean; empty (px = 0) if the field has zero variance.
Autocorrelation autocorrelation(const HeightField& f);
// 1/e crossing of the azimuthal average, and along a direction (radians from +x). NaN if none.
double correlationLengthRadial(const Autocorrelation& a);
double correlationLengthAlong(const Autocorrelation& a, double direction);

}  // namespace littoral::surfaces
