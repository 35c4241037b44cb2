#include "scenegen/surface_section.h"

#include <climits>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/suggest.h"
#include "core/units.h"

namespace littoral::scenegen {

namespace {
using surfaces::WaveLimits;
using surfaces::WaveModel;

// Keys that only some models use; giving one to another model is a mistake worth reporting.
struct ModelKey {
    const char* key;
    std::vector<WaveModel> models;
};
const std::vector<ModelKey>& modelKeys() {
    static const std::vector<WaveModel> wind{WaveModel::Beaufort, WaveModel::PiersonMoskowitz, WaveModel::Jonswap,
                                             WaveModel::Elfouhaily, WaveModel::CoxMunk};
    static const std::vector<ModelKey> keys{
        {"wind_speed", wind},
        {"wind_from_deg", wind},
        {"waves_from_deg", {WaveModel::Sinusoid}},
        {"seed", wind},
        {"sea", {WaveModel::CoxMunk}},
        {"fetch", {WaveModel::Jonswap, WaveModel::Elfouhaily}},
        {"gamma", {WaveModel::Jonswap}},
        {"amplitude", {WaveModel::Sinusoid}},
        {"wavelength", {WaveModel::Sinusoid}},
        {"phase", {WaveModel::Sinusoid}},
        {"time", {WaveModel::PiersonMoskowitz, WaveModel::Jonswap, WaveModel::Elfouhaily, WaveModel::Sinusoid}},
        {"depth", {WaveModel::PiersonMoskowitz, WaveModel::Jonswap, WaveModel::Elfouhaily, WaveModel::Sinusoid}},
    };
    return keys;
}

std::string modelList(const std::vector<WaveModel>& ms) {
    std::vector<std::string> names;
    for (WaveModel m : ms) names.push_back(surfaces::waveModelName(m));
    return joinList(names);
}

// A 2-vector given as [x, y].
std::pair<double, double> pairOf(const YamlNode& n, double lo, double hi, const char* unit) {
    if (!n.isSequence() || n.size() != 2) n.fail("expected a list of two numbers [x, y]");
    const auto v = n.asDoubleList(lo, hi, unit);
    return {v[0], v[1]};
}
}  // namespace

namespace {

// The key of the old convention is refused with the conversion, never reinterpreted.
void refuseOldDirectionKey(const YamlNode& n) {
    auto old = n.optional("wind_direction_deg");
    if (!old) return;
    const bool sinusoid = n.has("model") && n["model"].isScalar() && n["model"].asString() == "sinusoid";
    const char* key = sinusoid ? "waves_from_deg" : "wind_from_deg";
    std::string example;
    if (old->isScalar()) {
        try {
            example = fmt::format("; your {} would be {}: {:g}", old->asDouble(), key,
                                  surfaces::compassFromDirection(deg2rad(old->asDouble())));
        } catch (const InputError&) {
            // not a number: the message without the conversion
        }
    }
    old->fail(fmt::format("this key was removed: it gave the direction the {} TOWARD, in degrees counter-clockwise "
                          "from east. Give {} instead: the compass direction the {} FROM, in degrees clockwise "
                          "from north, like every other azimuth in a scene file{}",
                          sinusoid ? "waves travel" : "wind blows", key, sinusoid ? "waves come" : "wind comes",
                          example));
}

// A key that only other models use is a mistake worth reporting.
void refuseKeysOfOtherModels(const YamlNode& n, WaveModel model) {
    for (const ModelKey& mk : modelKeys())
        if (auto k = n.optional(mk.key)) {
            bool ok = false;
            for (WaveModel m : mk.models) ok = ok || m == model;
            if (!ok)
                k->fail(fmt::format("does not apply to model {}; it is used by: {}", surfaces::waveModelName(model),
                                    modelList(mk.models)));
        }
}

// The wind, and its compass direction (sinusoid: the waves'); sea for cox-munk.
void parseWind(const YamlNode& n, surfaces::WaveParams& p) {
    if (surfaces::isWindDriven(p.model)) {
        const YamlNode w = n["wind_speed"];  // required: the model is driven by it
        // cox-munk has its own, narrower range: validateWaveParams reports it at this key.
        p.windSpeed = p.model == WaveModel::CoxMunk ? w.asDouble() : w.asDouble(0.0, WaveLimits::kMaxWind, "m/s");
        if (p.windSpeed <= 0 && p.model != WaveModel::CoxMunk)
            w.fail(fmt::format("{} m/s is not allowed for model {}; allowed > 0 and <= {} m/s", p.windSpeed,
                               surfaces::waveModelName(p.model), WaveLimits::kMaxWind));
    } else {
        p.windSpeed = 0.0;
    }
    // Compass direction the wind (sinusoid: the waves) comes from; default 270 (from the west, i.e.
    // travelling toward +x, east).
    const char* dirKey = p.model == WaveModel::Sinusoid ? "waves_from_deg" : "wind_from_deg";
    p.windDirection = surfaces::directionFromCompass(n.getDouble(dirKey, 270.0, 0.0, 360.0, "degrees"));
    if (p.model == WaveModel::CoxMunk)
        p.sea = *parseName<CoxMunkSea>(n.getEnum("sea", "clean", allNames<CoxMunkSea>()));
}

// The surface rectangle, the grid and the models' other parameters.
void parseGridAndShape(const YamlNode& n, surfaces::WaveParams& p) {
    if (auto s = n.optional("size")) {
        if (s->isSequence()) {
            const auto [sx, sy] = pairOf(*s, WaveLimits::kMinSize, WaveLimits::kMaxSize, "m");
            p.sizeX = sx;
            p.sizeY = sy;
        } else {
            p.sizeX = p.sizeY = s->asDouble(WaveLimits::kMinSize, WaveLimits::kMaxSize, "m");
        }
    }
    if (auto c = n.optional("centre")) {
        const auto [cx, cy] = pairOf(*c, -1.0e7, 1.0e7, "m");
        p.centreX = cx;
        p.centreY = cy;
    }
    p.spacing = n.getDouble("spacing", p.spacing, WaveLimits::kMinSpacing, WaveLimits::kMaxSize, "m");
    p.seed = static_cast<uint64_t>(n.getInt("seed", static_cast<long long>(p.seed), 0, LLONG_MAX));
    p.triangles = static_cast<size_t>(n.getInt("triangles", static_cast<long long>(p.triangles), 0, 2'000'000'000LL));
    p.fetch = n.getDouble("fetch", p.fetch, 0.0, WaveLimits::kMaxFetch, "m");
    p.gamma = n.getDouble("gamma", p.gamma, WaveLimits::kMinGamma, WaveLimits::kMaxGamma);
    p.amplitude = n.getDouble("amplitude", p.amplitude, 0.0, WaveLimits::kMaxAmplitude, "m");
    p.wavelength = n.getDouble("wavelength", p.wavelength, WaveLimits::kMinSpacing, WaveLimits::kMaxSize, "m");
    p.phase = n.getDouble("phase", p.phase, -WaveLimits::kMaxSize, WaveLimits::kMaxSize, "m");
    p.time = n.getDouble("time", p.time, 0.0, WaveLimits::kMaxTime, "s");
    p.depth = n.getDouble("depth", p.depth, 0.0, WaveLimits::kMaxDepth, "m");
}

// Checks on the combination (memory, triangle target, resolution). Report them at the key they
// name when that key is in the file, else at the section.
void validateAtKey(const YamlNode& n, const surfaces::WaveParams& p) {
    try {
        surfaces::validateWaveParams(p);
    } catch (const InputError& e) {
        const std::string& msg = e.message();
        const std::string key = msg.substr(0, msg.find(':'));
        const auto k = n.optional(key);
        const std::string where = n.path().empty() ? "" : n.path() + ".";
        throw InputError(k ? k->loc() : n.loc(), where + msg);
    }
}

}  // namespace

surfaces::WaveParams parseWaterSurface(const YamlNode& n) {
    n.expectMap();
    refuseOldDirectionKey(n);
    n.expectKeys({"model", "wind_speed", "wind_from_deg", "waves_from_deg", "sea", "size", "centre", "spacing", "seed",
                  "triangles", "fetch", "gamma", "amplitude", "wavelength", "phase", "time", "depth", "roughness"});
    surfaces::WaveParams p;
    p.sceneKeys = true;
    p.where = n.loc();
    p.model = *surfaces::parseWaveModel(n.getEnum("model", "beaufort", surfaces::waveModelNames()));
    refuseKeysOfOtherModels(n, p.model);
    parseWind(n, p);
    parseGridAndShape(n, p);
    // Without `triangles`: the default target, or the full grid where that target would be refused
    // or would smooth cox-munk's facets (surfaces::defaultTriangles).
    if (!n.has("triangles")) p.triangles = surfaces::defaultTriangles(p);
    validateAtKey(n, p);
    return p;
}

std::optional<ir::Material> parseSurfaceRoughness(const YamlNode& n, const surfaces::WaveParams& waves,
                                                  const std::string& name) {
    const auto r = n.optional("roughness");
    if (!r) return std::nullopt;
    r->expectKeys({"model", "wind_speed", "wind_from_deg", "sea", "gram_charlier", "shadowing"});
    r->getEnum("model", "cox-munk", {"cox-munk"});
    ir::Material m;
    m.name = name;
    m.type = ir::Material::Type::RoughDielectric;
    m.origin = r->loc();
    const bool windModel = surfaces::isWindDriven(waves.model);
    // The wind: the roughness's own, or the surface's for a wind-driven model (then a wind outside
    // Cox and Munk's range is reported at the surface's key, naming the roughness that took it).
    if (auto w = r->optional("wind_speed")) {
        m.windSpeed = w->asDouble();
        checkCoxMunkWind(m.windSpeed, w->loc(), r->path() + ".wind_speed");
    } else if (windModel) {
        m.windSpeed = waves.windSpeed;
        checkCoxMunkWind(m.windSpeed, n["wind_speed"].loc(),
                         n.path() + ".wind_speed (taken by " + r->path() + ", which has no wind_speed of its own)");
    } else {
        r->fail(fmt::format("missing required key 'wind_speed' (m/s at 12.5 m, {} to {}): the {} surface has no wind "
                            "to take it from",
                            CoxMunkLimits::kMinWind, CoxMunkLimits::kMaxWind, surfaces::waveModelName(waves.model)));
    }
    // Compass direction the wind comes FROM (like every azimuth in a scene file); the IR holds the
    // direction it blows toward, counter-clockwise from east.
    if (auto d = r->optional("wind_from_deg"))
        m.windAzimuth = surfaces::directionFromCompass(d->asDouble(0.0, 360.0, "degrees"));
    else
        m.windAzimuth = windModel ? waves.windDirection : surfaces::directionFromCompass(270.0);
    m.sea = *parseName<CoxMunkSea>(r->getEnum("sea", "clean", allNames<CoxMunkSea>()));
    m.gramCharlier = r->getBool("gram_charlier", false);
    if (m.gramCharlier && m.sea != CoxMunkSea::Clean)
        (*r)["gram_charlier"].fail(fmt::format("Cox and Munk published Gram-Charlier coefficients for the clean sea "
                                               "only; this roughness has sea: {}",
                                               nameOf(m.sea)));
    m.shadowing = *parseName<MicrofacetShadowing>(r->getEnum("shadowing", "none", allNames<MicrofacetShadowing>()));
    return m;
}

}  // namespace littoral::scenegen
