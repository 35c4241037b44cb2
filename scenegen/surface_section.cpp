#include "scenegen/surface_section.h"

#include <algorithm>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/units.h"
#include "surfaces/wave_kinds.h"

namespace littoral::scenegen {

namespace {
using surfaces::WaveKind;
using surfaces::WaveLimits;
using surfaces::WaveModel;

// The keys every model takes; the others belong to the models' descriptors (surfaces/wave_kinds.h).
const std::vector<std::string> kCommonKeys{"model", "size", "centre", "spacing", "triangles", "roughness"};

// A 2-vector given as [x, y].
std::pair<double, double> pairOf(const YamlNode& n, double lo, double hi, const char* unit) {
    if (!n.isSequence() || n.size() != 2) n.fail("expected a list of two numbers [x, y]");
    const auto v = n.asDoubleList(lo, hi, unit);
    return {v[0], v[1]};
}

// The model the section names (located, with a did-you-mean), or nullptr when that is not a name.
const WaveKind* namedKind(const YamlNode& n) {
    if (!n.has("model") || !n["model"].isScalar()) return nullptr;
    const auto m = surfaces::parseWaveModel(n["model"].asString());
    return m ? &surfaces::waveKind(*m) : nullptr;
}

// The key of the old convention is refused with the conversion, never reinterpreted.
void refuseOldDirectionKey(const YamlNode& n) {
    auto old = n.optional("wind_direction_deg");
    if (!old) return;
    const WaveKind* kind = namedKind(n);
    const bool waves = kind && kind->takes("waves_from_deg");
    const char* key = waves ? "waves_from_deg" : "wind_from_deg";
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
                          waves ? "waves travel" : "wind blows", key, waves ? "waves come" : "wind comes", example));
}

// A key that only other models take is a mistake worth reporting.
void refuseKeysOfOtherModels(const YamlNode& n, const WaveKind& kind) {
    for (const std::string& key : surfaces::waveModelKeys())
        if (auto k = n.optional(key); k && !kind.takes(key))
            k->fail(fmt::format("does not apply to model {}; it is used by: {}", kind.info.name,
                                surfaces::waveModelsTaking(key)));
}

// The value of one of the model's parameters, range-checked at its key (unless the model's
// validation words that range itself).
ParamValue parseWaveParam(const YamlNode& v, const ParamSpec& spec, const WaveKind& kind) {
    if (spec.type == ParamType::Integer)
        return static_cast<int64_t>(v.asInt(static_cast<long long>(spec.lo), static_cast<long long>(spec.hi)));
    const double x = v.asDouble();
    const auto& own = kind.rangeCheckedByValidation;
    if (!spec.inRange(x) && std::find(own.begin(), own.end(), spec.name) == own.end())
        v.fail(fmt::format("{} is out of range; allowed {}", x, spec.rangeText()));
    return x;
}

// The model's own keys, as its descriptor gives them: values (defaults filled in) and choices.
void parseModelKeys(const YamlNode& n, const WaveKind& kind, surfaces::WaveParams& p) {
    ParamValues values;
    for (const ParamSpec& spec : kind.info.params) {
        if (!n.has(spec.name) && spec.defaultValue) values.set(spec.name, spec.defaultParamValue());
        else values.set(spec.name, parseWaveParam(n[spec.name], spec, kind));  // n[...]: missing required key
    }
    std::vector<std::string> choices;
    for (const surfaces::WaveChoice& c : kind.choices) choices.push_back(n.getEnum(c.key, c.defaultValue, c.allowed));
    kind.apply(values, choices, p);
}

// The surface rectangle and the grid: the keys every model takes.
void parseGrid(const YamlNode& n, surfaces::WaveParams& p) {
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
    // Without `triangles`: the default target, or the full grid where that target would be refused
    // or would smooth cox-munk's facets (surfaces::defaultTriangles).
    if (n.has("triangles"))
        p.triangles = static_cast<size_t>(n["triangles"].asInt(0, 2'000'000'000LL));
    else
        p.triangles = surfaces::defaultTriangles(p);
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

surfaces::WaveParams readWaterSurfaceKeys(const YamlNode& n) {
    n.expectMap();
    refuseOldDirectionKey(n);
    std::vector<std::string> keys = kCommonKeys;
    for (const std::string& k : surfaces::waveModelKeys()) keys.push_back(k);
    n.expectKeys(keys);
    surfaces::WaveParams p;
    p.sceneKeys = true;
    p.where = n.loc();
    const auto& kinds = surfaces::waveModelKinds();
    const WaveKind& kind = *kinds.find(n.getEnum("model", "beaufort", kinds.names()));
    p.model = kind.model;
    refuseKeysOfOtherModels(n, kind);
    parseModelKeys(n, kind, p);
    parseGrid(n, p);
    // flatSpacing's grid rather than 1.44 M samples of z = 0 decimated to 30 000 triangles, which
    // took about 1.3 CPU-s of every run of a flat sea.
    if (p.model == surfaces::WaveModel::Flat) {
        if (!n.has("spacing")) p.spacing = flatSpacing(p);
        if (!n.has("triangles")) p.triangles = 0;
    }
    return p;
}

surfaces::WaveParams parseWaterSurface(const YamlNode& n) {
    const surfaces::WaveParams p = readWaterSurfaceKeys(n);
    validateAtKey(n, p);
    return p;
}

std::optional<ir::Material> parseSurfaceRoughness(const YamlNode& n, const surfaces::WaveParams& waves,
                                                  const std::string& name) {
    const auto r = n.optional("roughness");
    if (!r) return std::nullopt;
    r->expectKeys({"model", "wind_speed", "wind_from_deg", "sea", "slopes", "gram_charlier", "shadowing"});
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
    m.slopes = *parseName<CoxMunkSlopes>(r->getEnum("slopes", "anisotropic", allNames<CoxMunkSlopes>()));
    if (const std::string why = coxMunkSlopesProblem(m.slopes, m.sea, m.gramCharlier); !why.empty()) (*r)["slopes"].fail(why);
    m.shadowing = *parseName<MicrofacetShadowing>(r->getEnum("shadowing", "smith-light", allNames<MicrofacetShadowing>()));
    return m;
}

}  // namespace littoral::scenegen
