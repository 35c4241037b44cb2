#pragma once
// The deterministic plane-parallel solver: light field of a ColumnBand (column/column_problem.h)
// at given depths, by discrete ordinates in azimuthal Fourier modes, delta-M scaling, the
// adding-doubling method and the Nakajima-Tanaka (1988) TMS single-scattering correction of the
// radiances. docs/column.md gives the equations and the reasons for each choice.
//
// Units: irradiances W m^-2 um^-1, radiances W m^-2 sr^-1 um^-1, depths m below the surface.
// Directions are directions of propagation: theta from the downward vertical for downwelling light,
// from the upward vertical for upwelling light; phi relative to the azimuth in which the refracted
// solar beam travels (0 = along it, 180 = against it; the field is symmetric in phi).
#include <vector>

#include "column/column_problem.h"
#include "column/streams.h"

namespace littoral::column {

struct SolverOptions {
    int streamsPerHalf = 8;   // Gauss nodes on each side of the Snell-window edge, per hemisphere
    int azimuths = 13;        // radiance table: phi = 0, 180/(azimuths-1), ..., 180 deg (>= 2)
    bool radiance = true;     // compute every Fourier mode (the radiance table); false: mode 0 only
    bool tms = true;          // the single-scattering correction of radiances
};

struct DepthResult {
    double depth = 0;
    double Ed = 0, Eu = 0, Eod = 0, Eou = 0, Lu = 0;  // Lu: nadir-viewing (upwelling, travelling up)
    double EdDirect = 0;                               // the unscattered (delta-M: scaled) solar beam
    double Kd = 0, Ku = 0;                             // -d ln E / dz, m^-1 (finite differences)
    // Radiance table: [direction][azimuth]; directions are the streams' downwelling ones (ascending
    // mu, the last straight down) then the upwelling ones (the last straight up = Lu's direction).
    std::vector<std::vector<double>> radiance;
};

struct ColumnResult {
    Band band;
    Streams streams;
    std::vector<double> azimuthsDeg;
    double sunZenithWater = 0;     // rad, refracted
    double EdAbove = 0;            // Ed(0+), W m^-2 um^-1
    double LwNadir = 0;            // water-leaving radiance toward zenith, just above the surface
    double Rrs = 0;                // LwNadir / EdAbove, sr^-1
    std::vector<DepthResult> depths;
};

// `depths`: strictly increasing, >= 0, within the bottom if there is one. InputError otherwise.
ColumnResult solveColumn(const ColumnBand& column, const std::vector<double>& depths, const SolverOptions& options = {});

// Fresnel reflectance of unpolarised light at a smooth interface, incidence cosine cosI on the side
// of index n1, the other side n2 (1 under total internal reflection).
double fresnelReflectance(double cosI, double n1, double n2);

}  // namespace littoral::column
