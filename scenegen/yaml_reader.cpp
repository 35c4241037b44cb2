#include "scenegen/yaml_reader.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "core/suggest.h"

namespace littoral::scenegen {

namespace fs = std::filesystem;

namespace {
SourceLoc locOf(const std::string& file, const YAML::Mark& m) {
    // yaml-cpp marks are 0-based; -1 when unknown.
    if (m.line < 0) return SourceLoc{file};
    return SourceLoc{file, m.line + 1, m.column + 1};
}

std::string fmtNum(double v) { return fmt::format("{}", v); }

std::string rangeText(double min, double max, std::string_view unit) {
    std::string u = unit.empty() ? "" : " " + std::string(unit);
    if (std::isinf(max)) return fmt::format(">= {}{}", fmtNum(min), u);
    if (std::isinf(min)) return fmt::format("<= {}{}", fmtNum(max), u);
    return fmt::format("[{}, {}]{}", fmtNum(min), fmtNum(max), u);
}
}  // namespace

YamlNode::YamlNode(std::shared_ptr<const Doc> doc, YAML::Node node, std::string path, SourceLoc loc)
    : doc_(std::move(doc)), node_(std::move(node)), path_(std::move(path)), loc_(std::move(loc)) {}

YamlNode YamlNode::loadString(const std::string& text, const std::string& fileName) {
    auto doc = std::make_shared<Doc>();
    doc->file = fileName;
    doc->baseDir = fs::path(fileName).parent_path();
    YAML::Node root;
    try {
        root = YAML::Load(text);
    } catch (const YAML::Exception& e) {
        throw InputError(locOf(fileName, e.mark), "YAML syntax error: " + e.msg);
    }
    if (!root.IsDefined() || root.IsNull()) throw InputError(SourceLoc{fileName}, "the scene file is empty");
    return YamlNode(doc, root, "", locOf(fileName, root.Mark()));
}

YamlNode YamlNode::loadFile(const fs::path& file) {
    std::ifstream f(file, std::ios::binary);
    if (!f) throw InputError(SourceLoc{file.string()}, "cannot open the scene file");
    std::stringstream ss;
    ss << f.rdbuf();
    return loadString(ss.str(), file.string());
}

YamlNode YamlNode::child(const YAML::Node& n, std::string path) const {
    return YamlNode(doc_, n, std::move(path), locOf(doc_->file, n.Mark()));
}

void YamlNode::fail(const std::string& message) const {
    throw InputError(loc_, path_.empty() ? message : path_ + ": " + message);
}

std::string YamlNode::typeName() const {
    if (isNull()) return "nothing (null)";
    if (node_.IsMap()) return "a map";
    if (node_.IsSequence()) return "a list";
    return "'" + node_.Scalar() + "'";
}

void YamlNode::expectMap() const {
    if (!node_.IsMap()) fail("expected a map of keys, found " + typeName());
}

void YamlNode::expectKeys(std::initializer_list<std::string_view> allowed) const {
    std::vector<std::string> v;
    for (auto a : allowed) v.emplace_back(a);
    expectKeys(v);
}

void YamlNode::expectKeys(const std::vector<std::string>& allowed) const {
    expectMap();
    for (auto it = node_.begin(); it != node_.end(); ++it) {
        if (!it->first.IsScalar()) {
            throw InputError(locOf(doc_->file, it->first.Mark()), fmt::format("{}: keys must be plain names", path_));
        }
        const std::string key = it->first.Scalar();
        if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
        const std::string where = path_.empty() ? key : path_ + "." + key;
        std::string msg = fmt::format("{}: unknown key '{}'\n  allowed: {}", where, key, joinList(allowed));
        const std::string near = closestMatch(key, allowed);
        if (!near.empty()) msg += fmt::format(" (did you mean '{}'?)", near);
        throw InputError(locOf(doc_->file, it->first.Mark()), msg);
    }
}

bool YamlNode::has(std::string_view key) const {
    if (!node_.IsMap()) return false;
    return static_cast<bool>(node_[std::string(key)]);
}

std::vector<std::string> YamlNode::keys() const {
    expectMap();
    std::vector<std::string> k;
    for (auto it = node_.begin(); it != node_.end(); ++it) k.push_back(it->first.Scalar());
    return k;
}

YamlNode YamlNode::operator[](std::string_view key) const {
    expectMap();
    const std::string k(key);
    const YAML::Node n = node_[k];
    const std::string p = path_.empty() ? k : path_ + "." + k;
    if (!n) throw InputError(loc_, fmt::format("{}: missing required key '{}'", path_.empty() ? "scene" : path_, k));
    return child(n, p);
}

std::optional<YamlNode> YamlNode::optional(std::string_view key) const {
    expectMap();
    const std::string k(key);
    const YAML::Node n = node_[k];
    if (!n || n.IsNull()) return std::nullopt;
    return child(n, path_.empty() ? k : path_ + "." + k);
}

double YamlNode::asDouble() const {
    if (!node_.IsScalar()) fail("expected a number, found " + typeName());
    const std::string& s = node_.Scalar();
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v))
        fail("expected a number, found " + typeName());
    return v;
}

double YamlNode::asDouble(double min, double max, std::string_view unit) const {
    const double v = asDouble();
    if (v < min || v > max) fail(fmt::format("{} is out of range; allowed {}", fmtNum(v), rangeText(min, max, unit)));
    return v;
}

long long YamlNode::asInt() const {
    if (!node_.IsScalar()) fail("expected an integer, found " + typeName());
    const std::string& s = node_.Scalar();
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(s.c_str(), &end, 10);
    if (s.empty() || end != s.c_str() + s.size() || errno == ERANGE) fail("expected an integer, found " + typeName());
    return v;
}

long long YamlNode::asInt(long long min, long long max) const {
    const long long v = asInt();
    if (v < min || v > max) fail(fmt::format("{} is out of range; allowed [{}, {}]", v, min, max));
    return v;
}

bool YamlNode::asBool() const {
    if (node_.IsScalar()) {
        const std::string& s = node_.Scalar();
        if (s == "true" || s == "yes" || s == "on") return true;
        if (s == "false" || s == "no" || s == "off") return false;
    }
    fail("expected true or false, found " + typeName());
}

std::string YamlNode::asString() const {
    if (!node_.IsScalar()) fail("expected a text value, found " + typeName());
    return node_.Scalar();
}

std::string YamlNode::asEnum(const std::vector<std::string>& allowed) const {
    const std::string v = asString();
    if (std::find(allowed.begin(), allowed.end(), v) != allowed.end()) return v;
    std::string msg = fmt::format("unknown value '{}'\n  allowed: {}", v, joinList(allowed));
    const std::string near = closestMatch(v, allowed);
    if (!near.empty()) msg += fmt::format(" (did you mean '{}'?)", near);
    fail(msg);
}

fs::path YamlNode::asPath() const {
    const fs::path p(asString());
    return p.is_absolute() ? p : doc_->baseDir / p;
}

fs::path YamlNode::asExistingPath() const {
    const fs::path p = asPath();
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) fail(fmt::format("file '{}' does not exist or is not a regular file", p.string()));
    return p;
}

double YamlNode::getDouble(std::string_view key, double def, double min, double max, std::string_view unit) const {
    auto n = optional(key);
    return n ? n->asDouble(min, max, unit) : def;
}
long long YamlNode::getInt(std::string_view key, long long def, long long min, long long max) const {
    auto n = optional(key);
    return n ? n->asInt(min, max) : def;
}
bool YamlNode::getBool(std::string_view key, bool def) const {
    auto n = optional(key);
    return n ? n->asBool() : def;
}
std::string YamlNode::getString(std::string_view key, const std::string& def) const {
    auto n = optional(key);
    return n ? n->asString() : def;
}
std::string YamlNode::getEnum(std::string_view key, const std::string& def, const std::vector<std::string>& allowed) const {
    auto n = optional(key);
    return n ? n->asEnum(allowed) : def;
}

size_t YamlNode::size() const {
    if (!node_.IsSequence()) fail("expected a list, found " + typeName());
    return node_.size();
}

YamlNode YamlNode::at(size_t i) const {
    if (!node_.IsSequence()) fail("expected a list, found " + typeName());
    if (i >= node_.size()) fail(fmt::format("list has {} items; item {} requested", node_.size(), i));
    return child(node_[i], fmt::format("{}[{}]", path_, i));
}

std::vector<YamlNode> YamlNode::items() const {
    const size_t n = size();
    std::vector<YamlNode> out;
    out.reserve(n);
    for (size_t i = 0; i < n; ++i) out.push_back(at(i));
    return out;
}

std::vector<double> YamlNode::asDoubleList() const {
    std::vector<double> v;
    for (const auto& it : items()) v.push_back(it.asDouble());
    return v;
}

std::vector<double> YamlNode::asDoubleList(double min, double max, std::string_view unit) const {
    std::vector<double> v;
    for (const auto& it : items()) v.push_back(it.asDouble(min, max, unit));
    return v;
}

}  // namespace littoral::scenegen
