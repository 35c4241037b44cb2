#include "pipelines/lib_waves.h"

#include <cmath>

#include <fmt/format.h>

#include "core/cox_munk_fit.h"
#include "core/error.h"
#include "core/names.h"
#include "core/suggest.h"
#include "surfaces/facetize.h"

namespace littoral::pipelines {

namespace surf = littoral::surfaces;

surf::WaveParams toParams(const WavesOptions& o) {
    surf::WaveParams p;
    const auto model = surf::parseWaveModel(o.model);
    if (!model) {
        const std::string close = littoral::closestMatch(o.model, surf::waveModelNames());
        throw InputError(fmt::format("--model: unknown model '{}'; allowed: {}{}", o.model,
                                     littoral::joinList(surf::waveModelNames()),
                                     close.empty() ? "" : fmt::format(" (did you mean '{}'?)", close)));
    }
    p.model = *model;
    if (surf::isWindDriven(p.model) && !o.wind)
        throw InputError(fmt::format("--wind: required for model {} (wind speed in m/s, > 0 and <= {})", o.model,
                                     surf::WaveLimits::kMaxWind));
    p.windSpeed = o.wind.value_or(0.0);
    if (o.removedDirection)
        throw InputError(fmt::format(
            "--direction: this option was removed: it gave the direction the wind blew TOWARD, in degrees "
            "counter-clockwise from east. Give {} instead: the compass direction the {} FROM, in degrees clockwise "
            "from north, as in scene files (--direction D is {} (270 - D) mod 360)",
            p.model == surf::WaveModel::Sinusoid ? "--waves-from" : "--wind-from",
            p.model == surf::WaveModel::Sinusoid ? "waves come" : "wind comes",
            p.model == surf::WaveModel::Sinusoid ? "--waves-from" : "--wind-from"));
    if (p.model == surf::WaveModel::Sinusoid && o.windFromDeg)
        throw InputError("--wind-from: the sinusoid has no wind; give the direction its waves come from with --waves-from");
    if (p.model != surf::WaveModel::Sinusoid && o.wavesFromDeg)
        throw InputError(fmt::format("--waves-from: applies to model sinusoid only; model {} takes --wind-from", o.model));
    const double fromDeg = (p.model == surf::WaveModel::Sinusoid ? o.wavesFromDeg : o.windFromDeg).value_or(270.0);
    if (!std::isfinite(fromDeg) || fromDeg < 0.0 || fromDeg > 360.0)
        throw InputError(fmt::format("{}: {} is out of range; allowed 0 to 360 degrees (compass, clockwise from north)",
                                     p.model == surf::WaveModel::Sinusoid ? "--waves-from" : "--wind-from", fromDeg));
    p.windDirection = surf::directionFromCompass(fromDeg);
    if (o.sea) {
        if (p.model != surf::WaveModel::CoxMunk)
            throw InputError(fmt::format("--sea: applies to model cox-munk only (model {} has its own slopes)", o.model));
        const auto sea = littoral::parseName<littoral::CoxMunkSea>(*o.sea);
        if (!sea) {
            const auto names = littoral::allNames<littoral::CoxMunkSea>();
            const std::string close = littoral::closestMatch(*o.sea, names);
            throw InputError(fmt::format("--sea: unknown Cox-Munk surface '{}'; allowed: {}{}", *o.sea,
                                         littoral::joinList(names),
                                         close.empty() ? "" : fmt::format(" (did you mean '{}'?)", close)));
        }
        p.sea = *sea;
    }
    p.sizeX = o.size;
    p.sizeY = o.sizeY.value_or(o.size);
    p.spacing = o.spacing;
    p.seed = o.seed;
    if (o.triangles && *o.triangles < 0)
        throw InputError(fmt::format("--triangles: {} is negative; give a target >= {} or 0 for the full grid",
                                     *o.triangles, surf::kMinTriangles));
    // Without --triangles: the default target, or the full grid for cox-munk and for a grid smaller
    // than the target (as in a scene file).
    p.triangles = o.triangles ? static_cast<size_t>(*o.triangles) : surf::defaultTriangles(p);
    p.fetch = o.fetch;
    p.gamma = o.gamma;
    p.amplitude = o.amplitude;
    p.wavelength = o.wavelength;
    p.phase = o.phase;
    p.time = o.time;
    p.depth = o.depth;
    return p;
}

}  // namespace littoral::pipelines
