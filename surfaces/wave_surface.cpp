#include "surfaces/wave_surface.h"

#include "core/resource_limits.h"

#include <chrono>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "core/log.h"
#include "core/progress.h"
#include "core/units.h"
#include "surfaces/cox_munk_surface.h"
#include "surfaces/facetize.h"
#include "surfaces/fft2d.h"
#include "surfaces/synthesis.h"
#include "surfaces/wave_kinds.h"
#include "surfaces/wave_spectra.h"

namespace littoral::surfaces {

namespace {
const double kNaN = std::numeric_limits<double>::quiet_NaN();

enum class Key { Model, Wind, Direction, Size, SizeY, Spacing, Seed, Triangles, Fetch, Gamma, Amplitude,
                 Wavelength, Phase, Time, Depth, MaxMemory, Sea };

std::string keyName(const WaveParams& p, Key k) {
    struct Names { const char* cli; const char* scene; };
    if (k == Key::Direction && p.model == WaveModel::Sinusoid) return p.sceneKeys ? "waves_from_deg" : "--waves-from";
    static const Names names[] = {
        {"--model", "model"}, {"--wind", "wind_speed"}, {"--wind-from", "wind_from_deg"},
        {"--size", "size"}, {"--size-y", "size_y"}, {"--spacing", "spacing"}, {"--seed", "seed"},
        {"--triangles", "triangles"}, {"--fetch", "fetch"}, {"--gamma", "gamma"},
        {"--amplitude", "amplitude"}, {"--wavelength", "wavelength"}, {"--phase", "phase"},
        {"--time", "time"}, {"--depth", "depth"}, {"--max-memory", "--max-memory"}, {"--sea", "sea"}};
    const Names& n = names[static_cast<int>(k)];
    return p.sceneKeys ? n.scene : n.cli;
}

[[noreturn]] void fail(const WaveParams& p, Key k, const std::string& msg) {
    throw InputError(p.where, fmt::format("{}: {}", keyName(p, k), msg));
}

void checkRange(const WaveParams& p, Key k, double v, double lo, double hi, const char* unit) {
    if (!std::isfinite(v) || v < lo || v > hi)
        fail(p, k, fmt::format("{} is out of range; allowed {} to {}{}", v, lo, hi, unit));
}

double seconds(std::chrono::steady_clock::time_point a) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
}

GridSpec gridSpecFor(const WaveParams& p) {
    const GridSize n = gridSizeFor(p);
    GridSpec g;
    g.nx = n.nx;
    g.ny = n.ny;
    g.sizeX = p.sizeX;
    g.sizeY = p.sizeY;
    g.x0 = p.centreX - 0.5 * p.sizeX;
    g.y0 = p.centreY - 0.5 * p.sizeY;
    return g;
}
}  // namespace

const std::vector<std::string>& waveModelNames() {
    static const std::vector<std::string> names = waveModelKinds().names();
    return names;
}

std::string waveModelName(WaveModel m) { return waveModelNames()[static_cast<int>(m)]; }

std::optional<WaveModel> parseWaveModel(const std::string& name) {
    const auto& n = waveModelNames();
    for (size_t i = 0; i < n.size(); ++i)
        if (n[i] == name) return static_cast<WaveModel>(i);
    return std::nullopt;
}

bool isWindDriven(WaveModel m) { return m != WaveModel::Sinusoid && m != WaveModel::Flat; }
bool isRandom(WaveModel m) { return isWindDriven(m); }

double directionFromCompass(double fromDeg) {
    // Toward = from + 180 degrees, clockwise from north; counter-clockwise from east that is
    // 90 - (from + 180) = -90 - from degrees. Reduced to (-180, 180].
    double d = std::remainder(-90.0 - fromDeg, 360.0);
    if (d <= -180.0) d += 360.0;
    return deg2rad(d);
}

double compassFromDirection(double direction) {
    double from = std::fmod(-90.0 - rad2deg(direction), 360.0);
    if (from < 0) from += 360.0;
    if (from >= 360.0) from -= 360.0;
    return from;
}

GridSize gridSizeFor(const WaveParams& p) {
    // The largest spacing <= the requested one that divides the size exactly, so the grid's
    // edges fall on the rectangle's edges. The 1e-9 guards against 300 / 0.25 = 1200.0000001.
    const double fx = std::ceil(p.sizeX / p.spacing - 1e-9), fy = std::ceil(p.sizeY / p.spacing - 1e-9);
    const double cap = 1.0e8;  // keeps the conversion defined; the memory check refuses far less
    return {static_cast<int>(std::min(fx, cap)), static_cast<int>(std::min(fy, cap))};
}

double estimateBytes(const WaveParams& p) {
    // Calibrated against peak resident memory of `littoral waves` (1201^2 vertices: 200 MB
    // decimated, 293 MB full grid; 2401^2 decimated: 400 MB), with a 20% margin.
    const GridSize n = gridSizeFor(p);
    const double V = (n.nx + 1.0) * (n.ny + 1.0);                          // grid vertices
    const double fft = 8.0 * n.nx * n.ny + 16.0 * (n.nx / 2 + 1.0) * n.ny;  // one r2c/c2r transform
    const double field = 8.0 * V;
    const bool decimate = p.triangles != 0 && p.triangles < 2.0 * n.nx * n.ny;
    // Final mesh: positions (24 B) and normals (24 B) per vertex, 12 B per triangle (~2 per vertex).
    const double meshVertices = decimate ? 0.5 * static_cast<double>(p.triangles) : V;
    const double mesh = 72.0 * meshVertices;
    // Decimation works on the presampled lattice (at most about 4 kPresampleFactor x target/2 vertices).
    const double lattice = decimate ? std::min(V, 4.0 * kPresampleFactor * 0.5 * static_cast<double>(p.triangles)) : 0.0;
    const double decimation = static_cast<double>(kFacetizeBytesPerVertex) * lattice;
    const double stats = 2.0 * fft + 8.0 * V + 9.0 * V;  // autocorrelation, mesh raster, coverage flags
    const double base = 64.0 * 1024 * 1024;               // program, libraries, FFTW plans
    return 1.2 * (base + field + mesh + std::max({fft, decimation, stats}));
}

size_t defaultTriangles(const WaveParams& p) {
    // Decimation smooths the facet slopes cox-munk is made for.
    if (p.model == WaveModel::CoxMunk) return 0;
    // A grid that cannot be measured (the checks refuse it) keeps the target.
    if (!(p.spacing > 0) || !std::isfinite(p.sizeX / p.spacing) || !std::isfinite(p.sizeY / p.spacing))
        return kDefaultTriangles;
    const GridSize g = gridSizeFor(p);
    return static_cast<double>(kDefaultTriangles) > 2.0 * g.nx * g.ny ? 0 : kDefaultTriangles;
}

namespace {

// The checks of validateWaveParams.

// Each parameter on its own.
void checkEachParam(const WaveParams& p) {
    if (p.model == WaveModel::CoxMunk) {
        checkCoxMunkWind(p.windSpeed, p.where, keyName(p, Key::Wind));
    } else if (isWindDriven(p.model)) {
        if (!std::isfinite(p.windSpeed) || p.windSpeed <= 0 || p.windSpeed > WaveLimits::kMaxWind)
            fail(p, Key::Wind, fmt::format("{} m/s is not allowed for model {}; allowed: > 0 and <= {} m/s",
                                           p.windSpeed, waveModelName(p.model), WaveLimits::kMaxWind));
    } else {
        checkRange(p, Key::Wind, p.windSpeed, 0.0, WaveLimits::kMaxWind, " m/s");
    }
    if (!std::isfinite(p.windDirection)) fail(p, Key::Direction, "must be a finite angle in degrees");
    checkRange(p, Key::Size, p.sizeX, WaveLimits::kMinSize, WaveLimits::kMaxSize, " m");
    checkRange(p, Key::SizeY, p.sizeY, WaveLimits::kMinSize, WaveLimits::kMaxSize, " m");
    if (!std::isfinite(p.centreX) || !std::isfinite(p.centreY)) fail(p, Key::Size, "the centre must be finite");
    if (!std::isfinite(p.spacing) || p.spacing <= 0)
        fail(p, Key::Spacing, fmt::format("{} m is not allowed; the grid spacing must be > 0 (at least {} m)",
                                          p.spacing, WaveLimits::kMinSpacing));
    if (p.spacing < WaveLimits::kMinSpacing || p.spacing > 0.5 * std::min(p.sizeX, p.sizeY))
        fail(p, Key::Spacing, fmt::format("{} m is out of range; allowed {} m to half the size ({} m)", p.spacing,
                                          WaveLimits::kMinSpacing, 0.5 * std::min(p.sizeX, p.sizeY)));
    checkRange(p, Key::Fetch, p.fetch, 0.0, WaveLimits::kMaxFetch, " m (0 = fully developed)");
    checkRange(p, Key::Gamma, p.gamma, WaveLimits::kMinGamma, WaveLimits::kMaxGamma, "");
    checkRange(p, Key::Amplitude, p.amplitude, 0.0, WaveLimits::kMaxAmplitude, " m");
    if (!std::isfinite(p.phase)) fail(p, Key::Phase, "must be finite (metres along the wave direction)");
    checkRange(p, Key::Time, p.time, 0.0, WaveLimits::kMaxTime, " s");
    checkRange(p, Key::Depth, p.depth, 0.0, WaveLimits::kMaxDepth, " m (0 = deep water)");
    if (p.time != 0 && (p.model == WaveModel::Beaufort || p.model == WaveModel::CoxMunk || p.model == WaveModel::Flat))
        fail(p, Key::Time, fmt::format("model {} is static; time applies to pierson-moskowitz, jonswap, "
                                       "elfouhaily and sinusoid", waveModelName(p.model)));
    if (!(p.maxMemoryBytes > 0)) fail(p, Key::MaxMemory, "must be > 0");
    if (p.sea != CoxMunkSea::Clean && p.model != WaveModel::CoxMunk)
        fail(p, Key::Sea, fmt::format("applies to model cox-munk only (model {} has its own slopes)", waveModelName(p.model)));
}

// Memory, before anything is allocated; and the triangle target against the grid.
void checkGridBudget(const WaveParams& p, const GridSize& n) {
    const double bytes = estimateBytes(p);
    if (bytes > p.maxMemoryBytes)
        fail(p, Key::Spacing, fmt::format("a {} x {} grid ({:.1f} M vertices) needs about {} of memory, more than the "
                                          "memory budget of {}; increase the spacing, reduce the size, or raise {}",
                                          n.nx, n.ny, (n.nx + 1.0) * (n.ny + 1.0) / 1e6, formatBytes(bytes),
                                          formatBytes(p.maxMemoryBytes), keyName(p, Key::MaxMemory)));
    const double gridTris = 2.0 * n.nx * n.ny;
    if (p.triangles != 0 && (p.triangles < kMinTriangles || static_cast<double>(p.triangles) > gridTris))
        fail(p, Key::Triangles, fmt::format("{} is not possible: the {} x {} grid has {:.0f} triangles; allowed "
                                            "{} to {:.0f}, or 0 to keep the full grid", p.triangles, n.nx, n.ny,
                                            gridTris, kMinTriangles, gridTris));
}

// The advice for a grid that does not resolve a length: the spacing that would (`needed`, m), or,
// when even the smallest allowed spacing would not, the wind that would.
std::string spacingAdvice(double needed) {
    if (needed >= WaveLimits::kMinSpacing) return fmt::format("use a spacing <= {:.4g} m", needed);
    return fmt::format("that needs a spacing <= {:.4g} m, below the smallest allowed ({} m): give a stronger wind", needed,
                       WaveLimits::kMinSpacing);
}

// Resolution of the beaufort model at grid spacing `dmax` (m).
void checkBeaufortResolution(const WaveParams& p, double dmax) {
    const double L = beaufortPrediction(p.windSpeed).correlationLength;
    // Forward-difference slopes lose (1 - exp(-d^2/L^2)) L^2/d^2 of the slope variance: 12% at d = L/2.
    if (dmax > 0.5 * L)
        fail(p, Key::Spacing, fmt::format("{} m does not resolve the correlation length {:.4g} m of the beaufort "
                                          "model at {} m/s; {}", dmax, L, p.windSpeed, spacingAdvice(0.5 * L)));
    if (std::min(p.sizeX, p.sizeY) < 5 * L)
        log::warnOnce("waves: size {} m is less than 5 correlation lengths ({:.1f} m): expect large scatter "
                  "of the measured statistics", std::min(p.sizeX, p.sizeY), L);
}

void checkCoxMunkResolution(const WaveParams& p, double dmax) {
    const SlopeVariances v = coxMunkSlopeVariances(p.windSpeed, p.sea);
    const double h = coxMunkSurfaceRmsHeight(p.windSpeed);
    const double L = std::sqrt(2.0) * h / std::sqrt(std::max(v.upwind, v.crosswind));  // the shorter length
    // As for beaufort: at spacing L/2 forward differences already see 12% less slope variance
    // (the design compensates, but only while the grid resolves the correlation).
    if (dmax > 0.5 * L)
        fail(p, Key::Spacing, fmt::format("{} m does not resolve the correlation length {:.4g} m of the cox-munk "
                                          "surface at {} m/s (h = {:.4g} m, RMS slope {:.4g}); {}",
                                          dmax, L, p.windSpeed, h, std::sqrt(std::max(v.upwind, v.crosswind)),
                                          spacingAdvice(0.5 * L)));
    // One realisation's slope variance along the wind has relative standard deviation
    // sqrt(3 pi Lu Lc / (4 A)) (docs/waves.md); warn when it exceeds 5%.
    const double Lu = std::sqrt(2.0) * h / std::sqrt(v.upwind), Lc = std::sqrt(2.0) * h / std::sqrt(v.crosswind);
    const double rel = std::sqrt(3.0 * kPi * Lu * Lc / (4.0 * p.sizeX * p.sizeY));
    if (rel > 0.05)
        log::warnOnce("waves: a {} x {} m cox-munk surface holds few correlation lengths ({:.3g} x {:.3g} m): its "
                      "measured slope variances scatter by about {:.0f}% about Cox-Munk's",
                      p.sizeX, p.sizeY, Lu, Lc, 100 * rel);
}

// The spectral models (pierson-moskowitz, jonswap, elfouhaily): the grid must resolve the peak.
void checkSpectralResolution(const WaveParams& p, double dmax) {
    const WaveSpectrum s(spectrumParamsFor(p));
    const double lp = 2 * kPi / s.peakWavenumber();
    if (dmax > 0.5 * lp)
        fail(p, Key::Spacing, fmt::format("{} m does not resolve the spectral peak (wavelength {:.4g} m); {}", dmax, lp,
                                          spacingAdvice(0.5 * lp)));
    if (std::min(p.sizeX, p.sizeY) < lp)
        log::warnOnce("waves: size {} m is smaller than the peak wavelength {:.1f} m: most of the wave energy is "
                  "not represented", std::min(p.sizeX, p.sizeY), lp);
}

}  // namespace

void validateWaveParams(const WaveParams& p) {
    checkEachParam(p);
    const GridSize n = gridSizeFor(p);
    checkGridBudget(p, n);

    // Resolution checks per model.
    const double dmax = std::max(p.sizeX / n.nx, p.sizeY / n.ny);
    if (p.model == WaveModel::Beaufort) {
        checkBeaufortResolution(p, dmax);
    } else if (p.model == WaveModel::CoxMunk) {
        checkCoxMunkResolution(p, dmax);
    } else if (isWindDriven(p.model)) {
        checkSpectralResolution(p, dmax);
    } else if (p.model == WaveModel::Sinusoid) {
        if (!std::isfinite(p.wavelength) || p.wavelength < 2 * dmax || p.wavelength > WaveLimits::kMaxSize)
            fail(p, Key::Wavelength, fmt::format("{} m is out of range; allowed 2 x spacing ({} m) to {} m",
                                                 p.wavelength, 2 * dmax, WaveLimits::kMaxSize));
    }
}

namespace {

// The stages of generateWaveSurface.

// Beaufort force and the Cox-Munk slope statistics for the wind (NaN without wind); the other
// predictions start as unknown.
void predictWindStatistics(const WaveParams& p, WaveSurface& out) {
    PredictedStats& pr = out.predicted;
    pr.mssUpwind = pr.mssCrosswind = kNaN;
    pr.peakWavelength = kNaN;
    if (!isWindDriven(p.model)) {
        pr.coxMunkUpwind = pr.coxMunkCrosswind = pr.coxMunkTotal = kNaN;
        return;
    }
    out.beaufort = beaufortForce(p.windSpeed);
    pr.coxMunkSea = p.model == WaveModel::CoxMunk ? p.sea : CoxMunkSea::Clean;
    const SlopeVariances cm = coxMunkSlopeVariances(p.windSpeed, pr.coxMunkSea);
    pr.coxMunkUpwind = cm.upwind;
    pr.coxMunkCrosswind = cm.crosswind;
    // The clean sea's total is Cox and Munk's own fit to it (0.003 + 5.12e-3 U, what beaufort uses);
    // the other fits publish components only.
    pr.coxMunkTotal = pr.coxMunkSea == CoxMunkSea::Clean ? coxMunkCleanTotalMss(p.windSpeed) : cm.total();
}

// The statistics the grid's modes carry (`power`; without it, the model's own predictions).
void predictResolvedStatistics(const WaveParams& p, const GridSpec& g, const std::optional<ModePower>& power,
                               PredictedStats& pr) {
    if (!power) {
        pr.expectedRmsHeight = pr.rmsHeight;
        pr.expectedRmsSlope = pr.rmsSlope;
        pr.expectedCorrelationLength = pr.correlationLength;
        return;
    }
    // Resolved mean-square slopes: Sum over the grid's modes of (k . u)^2 E|h_k|^2.
    const double cu = std::cos(p.windDirection), su = std::sin(p.windDirection);
    double mu = 0, mc = 0;
    for (int n = 0; n < g.ny; ++n)
        for (int mm = 0; mm < power->halfX(); ++mm) {
            const double P = power->power[static_cast<size_t>(n) * power->halfX() + mm] * power->weight(mm);
            const double kx = power->kx(mm), ky = power->ky(n);
            mu += P * sqr(kx * cu + ky * su);
            mc += P * sqr(-kx * su + ky * cu);
        }
    pr.mssUpwindResolved = mu;
    pr.mssCrosswindResolved = mc;
    const ExpectedStats e = expectedStatistics(*power, p.windDirection);
    pr.expectedRmsHeight = std::sqrt(e.variance);
    pr.expectedRmsSlope = std::sqrt(0.5 * (e.mssX + e.mssY));
    pr.expectedCorrelationLength = e.correlationLength;
    if (p.model != WaveModel::Beaufort) pr.correlationLength = e.correlationLength;
    if (p.model != WaveModel::Beaufort && p.model != WaveModel::CoxMunk) pr.rmsSlope = std::sqrt(0.5 * (mu + mc));
}

// A decimated mesh has larger, smoother facets than the grid whose slopes were designed.
void warnIfCoxMunkFacetsSmoothed(const WaveSurface& out) {
    const PredictedStats& pr = out.predicted;
    const double ru = out.actual.mssUpwind / pr.mssUpwind, rc = out.actual.mssCrosswind / pr.mssCrosswind;
    if (std::abs(ru - 1.0) > 0.1 || std::abs(rc - 1.0) > 0.1)
        log::warnOnce("waves: the {} facets of the cox-munk mesh have mean-square slopes {:.4g} upwind and {:.4g} "
                      "crosswind, {:.0f}% and {:.0f}% of Cox-Munk's; keep the full grid (triangles 0) for glint",
                      out.mesh.numTriangles(), out.actual.mssUpwind, out.actual.mssCrosswind, 100 * ru, 100 * rc);
}

}  // namespace

WaveSurface generateWaveSurface(const WaveParams& p) {
    validateWaveParams(p);
    WaveSurface out;
    out.params = p;
    const GridSpec g = gridSpecFor(p);
    out.spacingX = g.dx();
    out.spacingY = g.dy();
    const double statsDirection = p.windDirection;
    predictWindStatistics(p, out);
    Progress progress("waves", 3, "stages");
    auto t0 = std::chrono::steady_clock::now();
    const std::optional<ModePower> power = waveKind(p.model).synthesize(p, g, out);
    predictResolvedStatistics(p, g, power, out.predicted);
    out.predicted.significantWaveHeight = 4.0 * out.predicted.rmsHeight;
    out.seconds.synthesis = seconds(t0);
    progress.advance();

    t0 = std::chrono::steady_clock::now();
    Facets f = facetize(out.field, p.triangles == 0 ? gridTriangles(out.field) : p.triangles);
    out.mesh = std::move(f.mesh);
    out.vertexNormals = std::move(f.vertexNormals);
    out.seconds.facetization = seconds(t0);
    progress.advance();

    t0 = std::chrono::steady_clock::now();
    out.grid = measureHeightField(out.field, statsDirection);
    out.actual = measureMesh(out.mesh, out.field, statsDirection, &out.meshMaxDeviation);
    out.seconds.statistics = seconds(t0);
    if (p.model == WaveModel::CoxMunk) warnIfCoxMunkFacetsSmoothed(out);
    progress.advance();
    progress.finish();
    return out;
}

}  // namespace littoral::surfaces
