#pragma once
// Kind descriptors: one description per kind (a phase function, an estimator, ...), read by the
// scene-file parser, the Scene IR writer and reader, the error messages and the factories.
//
// A kind has a family ("phase function"), a name ("henyey-greenstein"), a one-line doc and typed
// parameters, each with a default (or none: required), one range (inclusive, or open at its lower
// end: "(0, 40]"), a unit and a doc line. A family's kinds sit in one KindRegistry, built by an explicit list of registrations
// (one line per kind, in one place per family) inside a function-local static, so nothing
// depends on static initialisers that the linker may drop from a static library.
//
//   const KindRegistry<PhaseKind>& reg = phaseFunctionKinds();
//   const PhaseKind& k = reg.get("henyey-greenstein", where);   // InputError with did-you-mean
//   for (const ParamSpec& p : k.info.params) ...
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace littoral {

enum class ParamType { Real, Integer, Boolean };

// A parameter value as written in a file: an integer, a real number or a boolean. Values parsed
// against a descriptor have the descriptor's type; values read from a Scene IR keep their JSON
// type (so a hand-edited `1` stays `1` and an IR round-trips byte-identically).
using ParamValue = std::variant<int64_t, double, bool>;

// The value as a number (booleans as 0 / 1).
double numberOf(const ParamValue& v);
// "12", "0.5", "true".
std::string formatValue(const ParamValue& v);

struct ParamSpec {
    std::string name;      // key in the Scene IR, and in a scene file unless sceneKey is given
    std::string sceneKey;  // key path under the kind's section of a scene file ("photons.surface"); "" = name
    ParamType type = ParamType::Real;
    std::optional<double> defaultValue;  // unset: required (booleans: 0 or 1)
    double lo = 0, hi = 0;               // inclusive range (not used for booleans)
    std::string unit;                    // "m", "sr^-1", "" ...
    std::string doc;                     // one line
    bool loOpen = false;                 // the range excludes lo: (lo, hi] (a wind speed > 0)

    const std::string& sceneName() const { return sceneKey.empty() ? name : sceneKey; }
    bool inRange(double v) const {
        return type == ParamType::Boolean || ((loOpen ? v > lo : v >= lo) && v <= hi);
    }
    // "[-0.999, 0.999]", "[1, 10000000000]", "[0.0001, 100] m", "(0, 40] m/s", "true or false".
    std::string rangeText() const;
    std::string typeName() const;  // "real", "integer", "boolean"
    ParamValue defaultParamValue() const;
};

// Parameter values by key, in the order they were first set (which is the order the Scene IR
// writes them in).
class ParamValues {
public:
    ParamValues() = default;
    ParamValues(std::initializer_list<std::pair<std::string, ParamValue>> items);

    bool empty() const { return items_.empty(); }
    size_t size() const { return items_.size(); }
    bool has(std::string_view key) const { return find(key) != nullptr; }
    const ParamValue* find(std::string_view key) const;
    // Sets (or replaces, keeping its place) the value of `key`. Integral arguments are stored as
    // integers, floating-point ones as reals, bool as a boolean.
    void set(std::string key, ParamValue v);
    template <class T>
        requires(std::is_arithmetic_v<T> && !std::is_same_v<T, bool>)
    void set(std::string key, T v) {
        if constexpr (std::is_integral_v<T>) set(std::move(key), ParamValue(static_cast<int64_t>(v)));
        else set(std::move(key), ParamValue(static_cast<double>(v)));
    }
    void set(std::string key, bool v) { set(std::move(key), ParamValue(v)); }
    void erase(std::string_view key);
    // The number stored under `key` (InternalError when it is missing).
    double number(std::string_view key) const;

    auto begin() const { return items_.begin(); }
    auto end() const { return items_.end(); }
    bool operator==(const ParamValues&) const = default;

private:
    std::vector<std::pair<std::string, ParamValue>> items_;
};

struct KindInfo {
    std::string family;  // "phase function", "estimator", ...
    std::string name;    // as written in scene files and the IR
    std::string doc;     // one line
    std::vector<ParamSpec> params;

    const ParamSpec* param(std::string_view key) const;
    const ParamSpec* paramBySceneKey(std::string_view sceneKey) const;
};

inline const KindInfo& kindInfo(const KindInfo& k) { return k; }

// "unknown phase function 'hg' (allowed: isotropic, henyey-greenstein, ...); did you mean ...?"
std::string unknownKindMessage(std::string_view family, std::string_view name, const std::vector<std::string>& allowed);

// Checks `given` against the kind: every key is a parameter, every value has the parameter's type
// and lies in its range; fills in defaults. Returns the complete values in parameter order, or
// throws InputError "{who}: ..." (who = "" gives no prefix).
ParamValues resolveParams(const KindInfo& kind, const ParamValues& given, const std::string& who);

// The kinds of one family.
template <class K> class KindRegistry {
public:
    explicit KindRegistry(std::string family) : family_(std::move(family)) {}
    const std::string& family() const { return family_; }

    void add(K kind);  // InternalError on a repeated name or a kind of another family
    const K* find(std::string_view name) const {
        for (const K& k : kinds_)
            if (kindInfo(k).name == name) return &k;
        return nullptr;
    }
    // The kind called `name`, or InputError "{who}: unknown ... (allowed ...); did you mean ...".
    const K& get(std::string_view name, const std::string& who) const;
    std::vector<std::string> names() const {
        std::vector<std::string> v;
        for (const K& k : kinds_) v.push_back(kindInfo(k).name);
        return v;
    }
    // Parameter names over all kinds, each once, in registration order.
    std::vector<std::string> allParamNames() const;
    // The kinds that have a parameter `key` ("henyey-greenstein", or "a or b").
    std::string kindsWithParam(std::string_view key) const;
    const std::vector<K>& kinds() const { return kinds_; }
    bool empty() const { return kinds_.empty(); }

private:
    std::string family_;
    std::vector<K> kinds_;
};

// Helpers behind the template (kinds.cpp).
[[noreturn]] void kindRegistrationError(const std::string& family, const std::string& name, const char* why);
[[noreturn]] void unknownKind(const std::string& family, std::string_view name, const std::vector<std::string>& allowed,
                              const std::string& who);

template <class K> void KindRegistry<K>::add(K kind) {
    const KindInfo& info = kindInfo(kind);
    if (info.family != family_) kindRegistrationError(family_, info.name, "belongs to another family");
    if (find(info.name)) kindRegistrationError(family_, info.name, "is registered twice");
    kinds_.push_back(std::move(kind));
}

template <class K> const K& KindRegistry<K>::get(std::string_view name, const std::string& who) const {
    if (const K* k = find(name)) return *k;
    unknownKind(family_, name, names(), who);
}

template <class K> std::vector<std::string> KindRegistry<K>::allParamNames() const {
    std::vector<std::string> v;
    for (const K& k : kinds_)
        for (const ParamSpec& p : kindInfo(k).params) {
            bool seen = false;
            for (const auto& s : v) seen = seen || s == p.name;
            if (!seen) v.push_back(p.name);
        }
    return v;
}

template <class K> std::string KindRegistry<K>::kindsWithParam(std::string_view key) const {
    std::string s;
    for (const K& k : kinds_)
        if (kindInfo(k).param(key)) s += (s.empty() ? "" : " or ") + kindInfo(k).name;
    return s;
}

// ---- estimators -------------------------------------------------------------------------------
// The render settings each estimator reads (name = key in the IR's `render` object, sceneKey = key
// path under `render:` in a scene file). The descriptors live beside the estimators in render/,
// which registers them here (render::registerEstimatorKinds()) so that the scene-file parser in
// scenegen/, which may not use render/, reads the settings from the same descriptors.
KindRegistry<KindInfo>& estimatorKindsForRegistration();
const KindRegistry<KindInfo>& estimatorKinds();
// Every declared render setting once (first declaration wins), in registration order.
std::vector<const ParamSpec*> allRenderSettings();

}  // namespace littoral
