#pragma once
// One band of a plane-parallel (horizontally homogeneous) water column, as the column solver takes
// it: layers of constant IOPs below a flat air-water interface, a point sun and a uniform sky
// above, and a Lambertian bottom at a finite depth or none (infinitely deep).
//
// Depths are metres below the still-water level, increasing downward. columnBandFromIr() reads
// the water medium of a Scene IR (core/scene_ir.h), its sun and sky, on one of its bands.
#include <optional>
#include <string>
#include <vector>

#include "core/phase_functions.h"
#include "core/scene_ir.h"

namespace littoral::column {

struct ColumnLayer {
    double top = 0;                 // m below the surface
    double a = 0, b = 0;            // absorption and scattering coefficients, m^-1
    PhaseFunction phase;            // the layer's mixture sum b_i p_i / b (isotropic when b = 0)
};

struct ColumnBand {
    Band band;
    std::vector<ColumnLayer> layers;  // top to bottom, the first at depth 0; the last reaches down
    double waterIndex = 1.34;         // refractive index of the water (air 1)
    // Total mean-square slope s2 of an isotropic Cox-Munk surface (column/rough_surface.h); 0: flat.
    double surfaceMeanSquareSlope = 0;
    double sunZenith = 0;             // rad, in air
    double sunAzimuth = 0;            // rad, IR convention (counter-clockwise from east)
    double sunIrradiance = 0;         // on a plane normal to the beam, W m^-2 um^-1 (0: no sun)
    double skyRadiance = 0;           // uniform over the upper hemisphere, W m^-2 sr^-1 um^-1
    std::optional<double> bottomDepth;  // m; unset: infinitely deep
    double bottomReflectance = 0;       // Lambertian

    // Index of the layer holding `depth` (the deeper one on a boundary).
    int layerAt(double depth) const;
};

struct IrBottom {
    std::optional<double> depth;  // m below the water level; unset: none
    Spectrum reflectance = Spectrum::constant(0.0);
};

// Band `bandIndex` of the IR: water medium "water" (layers' z turned into depths below
// `waterLevel`), its refractive index, sun and sky, averaged over the band. InputError if the IR
// has no water medium or a spectrum does not cover the band.
ColumnBand columnBandFromIr(const ir::SceneIR& scene, double waterLevel, const IrBottom& bottom, int bandIndex);

}  // namespace littoral::column
