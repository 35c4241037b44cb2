#pragma once
// The public entry point for wind-driven (and simple) water surfaces: parameters in, a
// facetized height-field mesh plus predicted and measured statistics out. Used by
// `littoral waves` and by the scene assembler (scenegen, section water.surface).
//
// Frame: x, y horizontal (m), z up (m), z = 0 the mean water level. The mesh covers the
// rectangle [x0, x0 + sizeX] x [y0, y0 + sizeY] with x0 = centreX - sizeX/2, y0 = centreY - sizeY/2
// (by default centred on the origin). It is a height field (every triangle faces up,
// counter-clockwise seen from above) and its boundary vertices lie exactly on the rectangle's
// edges, with the four corners present, so it can be closed into a water volume with vertical
// walls. Wind direction (WaveParams::windDirection): radians counter-clockwise from +x, the
// direction the wind blows toward (and the waves travel); "upwind"/"crosswind" statistics are
// along/across that axis. Users give instead the compass direction the wind (or, for the
// sinusoid, the waves) comes FROM, degrees clockwise from north (scene keys wind_from_deg /
// waves_from_deg, options --wind-from / --waves-from); directionFromCompass converts.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/cox_munk_fit.h"
#include "core/error.h"
#include "core/mesh.h"
#include "core/resource_limits.h"
#include "surfaces/beaufort.h"
#include "surfaces/height_field.h"
#include "surfaces/surface_stats.h"

namespace littoral::surfaces {

enum class WaveModel { Beaufort, PiersonMoskowitz, Jonswap, Elfouhaily, CoxMunk, Sinusoid, Flat };

// "beaufort", "pierson-moskowitz", "jonswap", "elfouhaily", "cox-munk", "sinusoid", "flat".
const std::vector<std::string>& waveModelNames();
std::string waveModelName(WaveModel m);
std::optional<WaveModel> parseWaveModel(const std::string& name);
bool isWindDriven(WaveModel m);  // beaufort, the three spectra and cox-munk
bool isRandom(WaveModel m);      // synthesised from random numbers (seed matters)

// The compass direction something comes FROM (degrees clockwise from north, as meteorologists give
// the wind) as the direction it goes TOWARD in radians counter-clockwise from +x (east), and back
// (result in [0, 360)). A wind from 270 (west) blows toward +x: direction 0.
double directionFromCompass(double fromDeg);
double compassFromDirection(double direction);

// Accepted ranges, shared by the command line and the scene file so both say the same thing.
struct WaveLimits {
    static constexpr double kMaxWind = 40.0;          // m/s; beyond hurricane force 12 (32.7 m/s)
    static constexpr double kMinSize = 1.0;           // m
    static constexpr double kMaxSize = 100000.0;      // m
    static constexpr double kMinSpacing = 0.001;      // m
    static constexpr double kMaxFetch = 1.0e7;        // m
    static constexpr double kMinGamma = 1.0, kMaxGamma = 10.0;
    static constexpr double kMaxAmplitude = 50.0;     // m
    static constexpr double kMaxDepth = 12000.0;      // m
    static constexpr double kMaxTime = 1.0e6;         // s
};

// The dissertation's triangle target after decimation (its Tables 9.5 and 10.2).
inline constexpr size_t kDefaultTriangles = 30000;

struct WaveParams {
    WaveModel model = WaveModel::Beaufort;
    // Wind speed, m/s, at the model's reference height: 12.5 m for beaufort and cox-munk (Cox and
    // Munk 1954), 19.5 m for pierson-moskowitz, 10 m for jonswap and elfouhaily. Not used by
    // sinusoid and flat.
    double windSpeed = 6.0;
    double windDirection = 0.0;       // radians, ccw from +x, direction the wind blows toward
    CoxMunkSea sea = CoxMunkSea::Clean;  // cox-munk: which Cox-Munk fit the slopes follow
    double sizeX = 300.0, sizeY = 300.0;  // m (dissertation: 1200 x 1200 samples at 0.25 m)
    double centreX = 0.0, centreY = 0.0;  // m
    double spacing = 0.25;            // m; the grid uses the largest spacing <= this that divides the size
    uint64_t seed = 500;              // dissertation's seed
    size_t triangles = kDefaultTriangles;  // target after decimation; 0 = keep the full grid
    // Model-specific
    double fetch = 0.0;               // m, jonswap/elfouhaily; 0 = fully developed
    double gamma = 3.3;               // jonswap peak enhancement
    double amplitude = 0.5;           // m, sinusoid
    double wavelength = 2.0;          // m, sinusoid
    double phase = 0.0;               // m, sinusoid: position of the first trough along the direction
    double time = 0.0;                // s, spectral models and sinusoid (dispersion relation)
    double depth = 0.0;               // m, water depth for the dispersion relation; 0 = deep
    // Refuse grids estimated to need more memory than this: the process-wide budget
    // (`littoral --max-memory`, core/resource_limits.h) when the parameters are made.
    double maxMemoryBytes = static_cast<double>(memoryBudget());
    // Names used in error messages: command-line options by default; the scene parser sets
    // sceneKeys so messages name its keys (and `where`, the section's location).
    bool sceneKeys = false;
    SourceLoc where;
};

// Predicted (model) statistics. For beaufort: h, s, L of the Beaufort/RMS model. For the
// spectra: from the spectrum, both in full and restricted to the wavenumbers the grid resolves.
struct PredictedStats {
    double rmsHeight = 0, rmsSlope = 0, correlationLength = 0;
    double significantWaveHeight = 0;           // 4 rms height, m
    double mssUpwind = 0, mssCrosswind = 0;     // full spectrum (spectral models), the Cox-Munk target
                                                // (cox-munk), else NaN
    double mssUpwindResolved = 0, mssCrosswindResolved = 0;  // modes on the grid
    double peakWavelength = 0;                  // m (spectral models, sinusoid)
    // Cox and Munk (1954) values at the same wind speed (wind-driven models): the clean-sea fit,
    // or for cox-munk the fit its slopes follow (coxMunkSea).
    double coxMunkUpwind = 0, coxMunkCrosswind = 0, coxMunkTotal = 0;
    CoxMunkSea coxMunkSea = CoxMunkSea::Clean;
    // Ensemble means of the measured grid statistics for this finite periodic grid (random
    // models): what `actual` scatters about, from the discrete mode powers.
    double expectedRmsHeight = 0, expectedRmsSlope = 0, expectedCorrelationLength = 0;
};

struct WaveSurface {
    WaveParams params;
    HeightField field;                 // the realised full-resolution height field
    TriMesh mesh;                      // final (decimated) mesh
    std::vector<Normal3> vertexNormals;
    std::optional<BeaufortForce> beaufort;  // wind-driven models
    PredictedStats predicted;
    SurfaceStats grid;                 // measured on the full-resolution grid
    SurfaceStats actual;               // measured on the final mesh
    double meshMaxDeviation = 0;       // max |mesh - grid| at the grid's vertices, m
    double spacingX = 0, spacingY = 0; // grid spacing actually used, m
    std::string description;           // one line: model and parameters
    struct Timing { double synthesis = 0, facetization = 0, statistics = 0; } seconds;

    // Height of the realised surface at (x, y), bilinear in the grid (clamped to the rectangle).
    double heightAt(double x, double y) const { return field.sample(x, y); }
};

// Grid cells along x and y for the params (ceil(size / spacing)).
struct GridSize { int nx = 0, ny = 0; };
GridSize gridSizeFor(const WaveParams& p);
// Estimated peak memory of generateWaveSurface, bytes (checked before anything is allocated).
double estimateBytes(const WaveParams& p);

// The triangle target when none is given (the other fields set): kDefaultTriangles, or 0 (the full
// grid) for cox-munk, whose facet slopes decimation would smooth, and for a grid with fewer
// triangles than that, rather than refusing a target nobody asked for.
size_t defaultTriangles(const WaveParams& p);

// Checks every parameter and the combinations (grid size vs memory and triangle target,
// spacing vs correlation length); throws InputError naming the option or key and what is allowed.
void validateWaveParams(const WaveParams& p);

// Validates, synthesises, facetizes, measures. Throws InputError for bad parameters.
WaveSurface generateWaveSurface(const WaveParams& p);

}  // namespace littoral::surfaces
