#include "core/kinds.h"

#include <fmt/format.h>

#include "core/error.h"
#include "core/probe_quantities.h"
#include "core/suggest.h"

namespace littoral {

double numberOf(const ParamValue& v) {
    if (const auto* i = std::get_if<int64_t>(&v)) return static_cast<double>(*i);
    if (const auto* d = std::get_if<double>(&v)) return *d;
    return std::get<bool>(v) ? 1.0 : 0.0;
}

std::string formatValue(const ParamValue& v) {
    if (const auto* i = std::get_if<int64_t>(&v)) return fmt::format("{}", *i);
    if (const auto* d = std::get_if<double>(&v)) return fmt::format("{}", *d);
    return std::get<bool>(v) ? "true" : "false";
}

std::string ParamSpec::rangeText() const {
    switch (type) {
        case ParamType::Boolean: return "true or false";
        case ParamType::Integer:
            return fmt::format("{}{}, {}]{}{}", loOpen ? "(" : "[", static_cast<long long>(lo), static_cast<long long>(hi),
                               unit.empty() ? "" : " ", unit);
        case ParamType::Real: break;
    }
    return fmt::format("{}{}, {}]{}{}", loOpen ? "(" : "[", lo, hi, unit.empty() ? "" : " ", unit);
}

std::string ParamSpec::typeName() const {
    switch (type) {
        case ParamType::Boolean: return "boolean";
        case ParamType::Integer: return "integer";
        case ParamType::Real: break;
    }
    return "real";
}

ParamValue ParamSpec::defaultParamValue() const {
    const double d = defaultValue.value_or(0.0);
    switch (type) {
        case ParamType::Boolean: return ParamValue(d != 0.0);
        case ParamType::Integer: return ParamValue(static_cast<int64_t>(d));
        case ParamType::Real: break;
    }
    return ParamValue(d);
}

ParamValues::ParamValues(std::initializer_list<std::pair<std::string, ParamValue>> items) {
    for (const auto& [k, v] : items) set(k, v);
}

const ParamValue* ParamValues::find(std::string_view key) const {
    for (const auto& [k, v] : items_)
        if (k == key) return &v;
    return nullptr;
}

void ParamValues::set(std::string key, ParamValue v) {
    for (auto& [k, old] : items_)
        if (k == key) {
            old = v;
            return;
        }
    items_.emplace_back(std::move(key), v);
}

void ParamValues::erase(std::string_view key) {
    for (auto it = items_.begin(); it != items_.end(); ++it)
        if (it->first == key) {
            items_.erase(it);
            return;
        }
}

double ParamValues::number(std::string_view key) const {
    const ParamValue* v = find(key);
    if (!v) throw InternalError(fmt::format("parameter '{}' has no value", key));
    return numberOf(*v);
}

const ParamSpec* KindInfo::param(std::string_view key) const {
    for (const ParamSpec& p : params)
        if (p.name == key) return &p;
    return nullptr;
}

const ParamSpec* KindInfo::paramBySceneKey(std::string_view sceneKey) const {
    for (const ParamSpec& p : params)
        if (p.sceneName() == sceneKey) return &p;
    return nullptr;
}

std::string unknownKindMessage(std::string_view family, std::string_view name, const std::vector<std::string>& allowed) {
    std::string m = fmt::format("unknown {} '{}' (allowed: {})", family, name, joinList(allowed));
    const std::string near = closestMatch(name, allowed);
    if (!near.empty()) m += fmt::format("; did you mean '{}'?", near);
    return m;
}

void kindRegistrationError(const std::string& family, const std::string& name, const char* why) {
    throw InternalError(fmt::format("{} '{}' {}", family, name, why));
}

void unknownKind(const std::string& family, std::string_view name, const std::vector<std::string>& allowed,
                 const std::string& who) {
    const std::string m = unknownKindMessage(family, name, allowed);
    throw InputError(who.empty() ? m : who + ": " + m);
}

ParamValues resolveParams(const KindInfo& kind, const ParamValues& given, const std::string& who) {
    const std::string prefix = who.empty() ? "" : who + ": ";
    for (const auto& [key, value] : given)
        if (!kind.param(key)) {
            std::vector<std::string> names;
            for (const ParamSpec& p : kind.params) names.push_back(p.name);
            std::string m = fmt::format("{}the {} {} has no parameter '{}'", prefix, kind.name, kind.family, key);
            m += names.empty() ? " (it has none)" : fmt::format(" (it has: {})", joinList(names));
            throw InputError(m);
        }
    ParamValues out;
    for (const ParamSpec& p : kind.params) {
        const ParamValue* v = given.find(p.name);
        if (!v) {
            if (!p.defaultValue) throw InputError(fmt::format("{}{} needs '{}'", prefix, kind.name, p.name));
            out.set(p.name, p.defaultParamValue());
            continue;
        }
        const bool typeOk = p.type == ParamType::Boolean  ? std::holds_alternative<bool>(*v)
                            : p.type == ParamType::Integer ? std::holds_alternative<int64_t>(*v)
                                                           : !std::holds_alternative<bool>(*v);
        if (!typeOk)
            throw InputError(fmt::format("{}{} {} = {} is not a {} value", prefix, kind.name, p.name, formatValue(*v),
                                         p.typeName()));
        if (!p.inRange(numberOf(*v)))
            throw InputError(fmt::format("{}{} {} = {} is out of range; allowed {}", prefix, kind.name, p.name,
                                         formatValue(*v), p.rangeText()));
        // Reals are stored as reals even when the file wrote an integer.
        if (p.type == ParamType::Real) out.set(p.name, numberOf(*v));
        else out.set(p.name, *v);
    }
    return out;
}

KindRegistry<KindInfo>& estimatorKindsForRegistration() {
    static KindRegistry<KindInfo> registry("estimator");
    return registry;
}

const KindRegistry<KindInfo>& estimatorKinds() { return estimatorKindsForRegistration(); }

KindRegistry<KindInfo>& probeQuantityKindsForRegistration() {
    static KindRegistry<KindInfo> registry("probe quantity");
    return registry;
}

const KindRegistry<KindInfo>& probeQuantityKinds() { return probeQuantityKindsForRegistration(); }

std::vector<const ParamSpec*> allRenderSettings() {
    std::vector<const ParamSpec*> v;
    for (const KindInfo& k : estimatorKinds().kinds())
        for (const ParamSpec& p : k.params) {
            bool seen = false;
            for (const ParamSpec* s : v) seen = seen || s->name == p.name;
            if (!seen) v.push_back(&p);
        }
    return v;
}

}  // namespace littoral
