#include "surfaces/wave_kinds.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <variant>

#include <fmt/format.h>

#include "core/cox_munk_fit.h"
#include "core/error.h"
#include "core/names.h"
#include "core/suggest.h"
#include "core/units.h"
#include "surfaces/beaufort.h"
#include "surfaces/cox_munk_surface.h"

namespace littoral::surfaces {

namespace {
const double kNaN = std::numeric_limits<double>::quiet_NaN();
const char* const kFamily = "wave model";

// ---- the parameters several models share --------------------------------------------------------
// Defaults are WaveParams' own; ranges are WaveLimits'.

ParamSpec real(std::string name, std::optional<double> def, double lo, double hi, std::string unit, std::string doc) {
    return {std::move(name), "", ParamType::Real, def, lo, hi, std::move(unit), std::move(doc)};
}

// Wind speed at the model's reference height: (0, 40] m/s.
ParamSpec windSpeedParam(const char* height) {
    ParamSpec p = real("wind_speed", std::nullopt, 0.0, WaveLimits::kMaxWind, "m/s",
                       fmt::format("wind speed at {} m", height));
    p.loOpen = true;
    return p;
}
ParamSpec compassParam(const char* key, const char* what) {
    return real(key, 270.0, 0.0, 360.0, "degrees",
                fmt::format("compass direction the {} comes from, clockwise from north (270: from the west)", what));
}
ParamSpec seedParam() {
    // 2^62, as `littoral waves --seed`; a double holds it exactly.
    return {"seed", "", ParamType::Integer, static_cast<double>(WaveParams{}.seed), 0.0, 4611686018427387904.0, "",
            "random seed of the realisation"};
}
ParamSpec timeParam() {
    return real("time", WaveParams{}.time, 0.0, WaveLimits::kMaxTime, "s",
                "advances each wave component by its dispersion relation");
}
ParamSpec depthParam() {
    return real("depth", WaveParams{}.depth, 0.0, WaveLimits::kMaxDepth, "m",
                "water depth for the dispersion relation; 0 = deep water");
}
ParamSpec fetchParam() {
    return real("fetch", WaveParams{}.fetch, 0.0, WaveLimits::kMaxFetch, "m", "fetch; 0 = fully developed");
}

int64_t integer(const ParamValues& v, std::string_view key) {
    const ParamValue* x = v.find(key);
    if (!x || !std::holds_alternative<int64_t>(*x)) throw InternalError(fmt::format("wave parameter '{}' is not an integer", key));
    return std::get<int64_t>(*x);
}

// The wind and the seed of the wind-driven models.
void applyWind(const ParamValues& v, WaveParams& p) {
    p.windSpeed = v.number("wind_speed");
    p.windDirection = directionFromCompass(v.number("wind_from_deg"));
    p.seed = static_cast<uint64_t>(integer(v, "seed"));
}
void applyDispersion(const ParamValues& v, WaveParams& p) {
    p.time = v.number("time");
    p.depth = v.number("depth");
}

// ---- beaufort ---------------------------------------------------------------------------------

std::optional<ModePower> synthesizeBeaufort(const WaveParams& p, const GridSpec& g, WaveSurface& out) {
    PredictedStats& pr = out.predicted;
    const BeaufortPrediction b = beaufortPrediction(p.windSpeed);
    pr.rmsHeight = b.rmsHeight;
    pr.rmsSlope = b.rmsSlope;
    pr.correlationLength = b.correlationLength;
    out.field = synthesizeGaussian(g, b.rmsHeight, b.correlationLength, p.seed);
    std::optional<ModePower> power = gaussianModePower(g, b.rmsHeight, b.correlationLength);
    out.description = fmt::format("beaufort/RMS Gaussian field, U12.5 = {} m/s: h = {:.4g} m, s = {:.4g}, L = {:.4g} m",
                                  p.windSpeed, b.rmsHeight, b.rmsSlope, b.correlationLength);
    return power;
}

WaveKind beaufortKind() {
    return {{kFamily, "beaufort", "isotropic Gaussian field with the Beaufort/RMS height, slope and correlation length",
             {windSpeedParam("12.5"), compassParam("wind_from_deg", "wind"), seedParam()}},
            WaveModel::Beaufort,
            {},
            [](const ParamValues& v, const std::vector<std::string>&, WaveParams& p) { applyWind(v, p); },
            {},
            synthesizeBeaufort};
}

// ---- the spectra: pierson-moskowitz, jonswap, elfouhaily ----------------------------------------

std::optional<ModePower> synthesizeFromSpectrum(const WaveParams& p, const GridSpec& g, WaveSurface& out) {
    PredictedStats& pr = out.predicted;
    const WaveSpectrum s(spectrumParamsFor(p));
    out.field = synthesizeSpectral(g, s, p.windDirection, p.seed, p.time, p.depth);
    std::optional<ModePower> power = spectralModePower(g, s, p.windDirection);
    // Full-spectrum moments up to 1e4 rad/m (beyond the capillary range of Elfouhaily's
    // spectrum); the PM/JONSWAP k^-3 tail makes their full mss grow without bound, so only
    // the resolved values are reported for them.
    const auto m = s.moments(1.0e4);
    pr.rmsHeight = std::sqrt(m.m0);
    if (p.model == WaveModel::Elfouhaily) {
        pr.mssUpwind = m.mssUpwind;
        pr.mssCrosswind = m.mssCrosswind;
    }
    pr.peakWavelength = 2 * kPi / s.peakWavenumber();
    out.description = s.describe();
    return power;
}

WaveKind piersonMoskowitzKind() {
    return {{kFamily, "pierson-moskowitz", "Pierson and Moskowitz (1964): the fully developed sea of a wind",
             {windSpeedParam("19.5"), compassParam("wind_from_deg", "wind"), seedParam(), timeParam(), depthParam()}},
            WaveModel::PiersonMoskowitz,
            {},
            [](const ParamValues& v, const std::vector<std::string>&, WaveParams& p) {
                applyWind(v, p);
                applyDispersion(v, p);
            },
            {},
            synthesizeFromSpectrum};
}

WaveKind jonswapKind() {
    return {{kFamily, "jonswap", "JONSWAP (Hasselmann et al. 1973): a fetch-limited sea with an enhanced peak",
             {windSpeedParam("10"), compassParam("wind_from_deg", "wind"), seedParam(), fetchParam(),
              real("gamma", WaveParams{}.gamma, WaveLimits::kMinGamma, WaveLimits::kMaxGamma, "",
                   "peak enhancement factor"),
              timeParam(), depthParam()}},
            WaveModel::Jonswap,
            {},
            [](const ParamValues& v, const std::vector<std::string>&, WaveParams& p) {
                applyWind(v, p);
                p.fetch = v.number("fetch");
                p.gamma = v.number("gamma");
                applyDispersion(v, p);
            },
            {},
            synthesizeFromSpectrum};
}

WaveKind elfouhailyKind() {
    return {{kFamily, "elfouhaily", "Elfouhaily et al. (1997): long waves and the capillary range in one spectrum",
             {windSpeedParam("10"), compassParam("wind_from_deg", "wind"), seedParam(), fetchParam(), timeParam(), depthParam()}},
            WaveModel::Elfouhaily,
            {},
            [](const ParamValues& v, const std::vector<std::string>&, WaveParams& p) {
                applyWind(v, p);
                p.fetch = v.number("fetch");
                applyDispersion(v, p);
            },
            {},
            synthesizeFromSpectrum};
}

// ---- cox-munk ---------------------------------------------------------------------------------

std::optional<ModePower> synthesizeCoxMunk(const WaveParams& p, const GridSpec& g, WaveSurface& out) {
    PredictedStats& pr = out.predicted;
    const CoxMunkSurfaceDesign d = designCoxMunkSurface(g, p.windSpeed, p.sea, p.windDirection);
    std::optional<ModePower> power =
        anisotropicGaussianModePower(g, d.rmsHeight, d.lengthUpwind, d.lengthCrosswind, p.windDirection);
    out.field = synthesizeFromModePower(*power, p.seed);
    pr.rmsHeight = d.rmsHeight;
    pr.mssUpwind = d.target.upwind;
    pr.mssCrosswind = d.target.crosswind;
    pr.rmsSlope = std::sqrt(0.5 * d.target.total());
    out.description = fmt::format("cox-munk Gaussian field ({} sea), U12.5 = {} m/s: h = {:.4g} m, mss upwind {:.4g} "
                                  "/ crosswind {:.4g}, L = {:.4g} / {:.4g} m",
                                  nameOf(p.sea), p.windSpeed, d.rmsHeight, d.target.upwind, d.target.crosswind,
                                  d.lengthUpwind, d.lengthCrosswind);
    return power;
}

WaveKind coxMunkKind() {
    return {{kFamily, "cox-munk", "Gaussian field whose facet slopes follow Cox and Munk's (1954) fit at the wind",
             {real("wind_speed", std::nullopt, CoxMunkLimits::kMinWind, CoxMunkLimits::kMaxWind, "m/s",
                   "wind speed at 12.5 m, in Cox and Munk's range"),
              compassParam("wind_from_deg", "wind"), seedParam()}},
            WaveModel::CoxMunk,
            {WaveChoice{"sea", allNames<CoxMunkSea>(), std::string(nameOf(CoxMunkSea::Clean)),
                        "which Cox-Munk fit the slopes follow"}},
            [](const ParamValues& v, const std::vector<std::string>& c, WaveParams& p) {
                applyWind(v, p);
                p.sea = *parseName<CoxMunkSea>(c.at(0));
            },
            std::vector<std::string>{"wind_speed"},
            synthesizeCoxMunk};
}

// ---- sinusoid and flat --------------------------------------------------------------------------

std::optional<ModePower> synthesizeSinusoid(const WaveParams& p, const GridSpec& g, WaveSurface& out) {
    PredictedStats& pr = out.predicted;
    out.field = sinusoidField(g, p.amplitude, p.wavelength, p.phase, p.windDirection, p.time, p.depth);
    const double ak = p.amplitude * 2 * kPi / p.wavelength;
    pr.rmsHeight = p.amplitude / std::sqrt(2.0);
    pr.rmsSlope = ak / 2.0;  // per axis: mss along the wave (ak)^2/2, across 0
    pr.mssUpwindResolved = 0.5 * ak * ak;
    pr.mssCrosswindResolved = 0.0;
    pr.correlationLength = std::acos(std::exp(-1.0)) / (2 * kPi / p.wavelength);  // along the wave
    pr.peakWavelength = p.wavelength;
    out.description = fmt::format("sinusoid: amplitude {} m, wavelength {} m, first trough at {} m", p.amplitude,
                                  p.wavelength, p.phase);
    return std::nullopt;
}

WaveKind sinusoidKind() {
    const WaveParams d;
    return {{kFamily, "sinusoid", "one long-crested sine wave",
             {compassParam("waves_from_deg", "waves"),
              real("amplitude", d.amplitude, 0.0, WaveLimits::kMaxAmplitude, "m", "amplitude (half the crest-to-trough height)"),
              real("wavelength", d.wavelength, WaveLimits::kMinSpacing, WaveLimits::kMaxSize, "m",
                   "wavelength; at least 2 x the grid spacing"),
              real("phase", d.phase, -WaveLimits::kMaxSize, WaveLimits::kMaxSize, "m",
                   "position of the first trough along the direction of travel"),
              timeParam(), depthParam()}},
            WaveModel::Sinusoid,
            {},
            [](const ParamValues& v, const std::vector<std::string>&, WaveParams& p) {
                p.windSpeed = 0.0;
                p.windDirection = directionFromCompass(v.number("waves_from_deg"));
                p.amplitude = v.number("amplitude");
                p.wavelength = v.number("wavelength");
                p.phase = v.number("phase");
                applyDispersion(v, p);
            },
            {},
            synthesizeSinusoid};
}

std::optional<ModePower> synthesizeFlat(const WaveParams&, const GridSpec& g, WaveSurface& out) {
    out.field = flatField(g);
    out.predicted.correlationLength = kNaN;
    out.description = "flat surface at z = 0";
    return std::nullopt;
}

WaveKind flatKind() {
    return {{kFamily, "flat", "the still-water plane z = 0", {}},
            WaveModel::Flat,
            {},
            [](const ParamValues&, const std::vector<std::string>&, WaveParams& p) {
                p.windSpeed = 0.0;
                p.windDirection = directionFromCompass(270.0);  // no wind: the default direction
            },
            {},
            synthesizeFlat};
}

}  // namespace

SpectrumParams spectrumParamsFor(const WaveParams& p) {
    SpectrumParams s;
    s.model = p.model == WaveModel::PiersonMoskowitz ? SpectrumModel::PiersonMoskowitz
            : p.model == WaveModel::Jonswap          ? SpectrumModel::Jonswap
                                                     : SpectrumModel::Elfouhaily;
    s.windSpeed = p.windSpeed;
    s.fetch = p.fetch;
    s.gamma = p.gamma;
    return s;
}

const WaveChoice* WaveKind::choice(std::string_view key) const {
    for (const WaveChoice& c : choices)
        if (c.key == key) return &c;
    return nullptr;
}

// ---- the wave-model kinds: one registration line per kind, in the order of the enum --------------

const KindRegistry<WaveKind>& waveModelKinds() {
    static const KindRegistry<WaveKind> registry = [] {
        KindRegistry<WaveKind> r(kFamily);
        r.add(beaufortKind());
        r.add(piersonMoskowitzKind());
        r.add(jonswapKind());
        r.add(elfouhailyKind());
        r.add(coxMunkKind());
        r.add(sinusoidKind());
        r.add(flatKind());
        for (size_t i = 0; i < r.kinds().size(); ++i)
            if (static_cast<size_t>(r.kinds()[i].model) != i)
                kindRegistrationError(kFamily, r.kinds()[i].info.name, "is registered out of the enum's order");
        return r;
    }();
    return registry;
}

const WaveKind& waveKind(WaveModel m) { return waveModelKinds().kinds().at(static_cast<size_t>(m)); }

std::vector<std::string> waveModelKeys() {
    std::vector<std::string> keys = waveModelKinds().allParamNames();
    for (const WaveKind& k : waveModelKinds().kinds())
        for (const WaveChoice& c : k.choices)
            if (std::find(keys.begin(), keys.end(), c.key) == keys.end()) keys.push_back(c.key);
    return keys;
}

std::string waveModelsTaking(std::string_view key) {
    std::vector<std::string> names;
    for (const WaveKind& k : waveModelKinds().kinds())
        if (k.takes(key)) names.push_back(k.info.name);
    return joinList(names);
}

}  // namespace littoral::surfaces
