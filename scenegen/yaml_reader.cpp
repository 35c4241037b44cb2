#include "scenegen/yaml_reader.h"

#include <cmath>
#include <cstring>
#include <map>
#include <sstream>

#include <fmt/format.h>
#include <yaml-cpp/anchor.h>
#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/parser.h>

#include "core/atomic_file.h"
#include "core/output_names.h"
#include "core/suggest.h"
#include "core/text_checks.h"

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

namespace {

// Limits on what a scene file may ask the parser to do. A real scene has a few hundred nodes;
// these are orders of magnitude above that and far below what would exhaust memory or stack.
constexpr uint64_t kMaxExpandedNodes = 1'000'000;  // nodes after expanding every alias
constexpr int kMaxNesting = 200;                    // block indentation steps / flow brackets

// Lexical checks before yaml-cpp sees the text (its parser recurses once per nesting level, so a
// file of ten thousand '[' would exhaust the stack): control characters and nesting depth. Depth
// is bounded by the flow-bracket depth plus the number of block indentation levels (plus compact
// "- - -" indicators) open at a line's first content.
void lexicalChecks(const std::string& text, const std::string& file) {
    std::vector<int> indents;  // open block indentation columns
    int flow = 0;
    size_t lineStart = 0;
    bool lineHasContent = false, inSingle = false, inDouble = false, inComment = false;
    for (size_t i = 0; i <= text.size(); ++i) {
        const char c = i < text.size() ? text[i] : '\n';
        const unsigned char u = static_cast<unsigned char>(c);
        if (u < 0x20 && c != '\n' && c != '\t' && c != '\r')
            throw InputError(locationOf(text, i, file),
                             fmt::format("control character 0x{:02x} is not allowed in a YAML file", u));
        if (u == 0x7f) throw InputError(locationOf(text, i, file), "control character 0x7f is not allowed in a YAML file");
        if (c == '\n') {
            lineStart = i + 1;
            lineHasContent = false;
            inComment = false;
            if (flow == 0) inSingle = inDouble = false;  // block scalars do not span lines unquoted
            continue;
        }
        if (inComment) continue;
        if (!lineHasContent && c != ' ' && c != '\t' && c != '\r') {
            lineHasContent = true;
            if (c == '#') {
                inComment = true;
                continue;
            }
            if (flow == 0 && !inSingle && !inDouble) {
                // Block structure: indentation levels that are still open at this column.
                const int col = static_cast<int>(i - lineStart);
                while (!indents.empty() && indents.back() >= col) indents.pop_back();
                indents.push_back(col);
                int compact = 0;  // "- - - x" opens one sequence per indicator
                for (size_t k = i; k + 1 < text.size() && (text[k] == '-' || text[k] == '?') && text[k + 1] == ' ';) {
                    ++compact;
                    k += 2;
                    while (k < text.size() && text[k] == ' ') ++k;
                }
                if (static_cast<int>(indents.size()) + compact + flow > kMaxNesting)
                    throw InputError(locationOf(text, i, file),
                                     fmt::format("YAML nesting deeper than {} levels is not supported", kMaxNesting));
            }
        }
        if (inSingle) {
            if (c == '\'') inSingle = false;
            continue;
        }
        if (inDouble) {
            if (c == '\\') ++i;
            else if (c == '"') inDouble = false;
            continue;
        }
        if (c == '#' && (i == 0 || text[i - 1] == ' ' || text[i - 1] == '\t')) {
            inComment = true;
        } else if (c == '\'' && (i == 0 || std::strchr(" \t[{,:", text[i - 1]))) {
            inSingle = true;
        } else if (c == '"' && (i == 0 || std::strchr(" \t[{,:", text[i - 1]))) {
            inDouble = true;
        } else if (c == '[' || c == '{') {
            if (++flow + static_cast<int>(indents.size()) > kMaxNesting)
                throw InputError(locationOf(text, i, file),
                                 fmt::format("YAML nesting deeper than {} levels is not supported", kMaxNesting));
        } else if ((c == ']' || c == '}') && flow > 0) {
            --flow;
        }
    }
}

// A pass over the parser's events before the document is built: one document only, no key twice
// in a map, and a cap on the size of the document with every alias expanded (a "billion laughs"
// file of a few kilobytes names 10^9 nodes through nested aliases; every consumer that walks the
// tree would walk all of them).
class Prescan final : public YAML::EventHandler {
public:
    explicit Prescan(const std::string& file) : file_(file) {}

    void OnDocumentStart(const YAML::Mark&) override {}
    void OnDocumentEnd() override {}
    void OnNull(const YAML::Mark& m, YAML::anchor_t a) override { leaf(m, a, nullptr); }
    void OnScalar(const YAML::Mark& m, const std::string&, YAML::anchor_t a, const std::string& v) override {
        leaf(m, a, &v);
    }
    void OnAlias(const YAML::Mark& m, YAML::anchor_t a) override {
        for (const Frame& f : stack_)
            if (f.anchor == a && a != 0)
                throw InputError(locOf(m), "this alias refers to a node that contains it (a recursive structure), "
                                           "which a scene file cannot use");
        const uint64_t n = a < anchorSize_.size() ? anchorSize_[a] : 1;
        keyOrValue(m, nullptr);
        add(m, n);
    }
    void OnSequenceStart(const YAML::Mark& m, const std::string&, YAML::anchor_t a, YAML::EmitterStyle::value) override {
        open(m, a, false);
    }
    void OnSequenceEnd() override { close(); }
    void OnMapStart(const YAML::Mark& m, const std::string&, YAML::anchor_t a, YAML::EmitterStyle::value) override {
        open(m, a, true);
    }
    void OnMapEnd() override { close(); }

private:
    struct Frame {
        bool map = false;
        bool expectKey = true;
        YAML::anchor_t anchor = 0;
        uint64_t size = 1;
        YAML::Mark mark;
        std::map<std::string, YAML::Mark> keys;
    };

    // A scalar in key position of a map is checked against the keys seen before.
    void keyOrValue(const YAML::Mark& m, const std::string* scalar) {
        if (stack_.empty() || !stack_.back().map) return;
        Frame& f = stack_.back();
        if (f.expectKey && scalar) {
            auto [it, inserted] = f.keys.emplace(*scalar, m);
            if (!inserted)
                throw InputError(locOf(m), fmt::format("duplicate key '{}' (first given at line {}, column {}); each "
                                                       "key may appear once in a map",
                                                       *scalar, it->second.line + 1, it->second.column + 1));
        }
        f.expectKey = !f.expectKey;
    }
    void leaf(const YAML::Mark& m, YAML::anchor_t a, const std::string* scalar) {
        keyOrValue(m, scalar);
        setAnchor(a, 1);
        add(m, 1);
    }
    void open(const YAML::Mark& m, YAML::anchor_t a, bool map) {
        keyOrValue(m, nullptr);
        Frame f;
        f.map = map;
        f.anchor = a;
        f.mark = m;
        stack_.push_back(std::move(f));
    }
    void close() {
        const Frame f = std::move(stack_.back());
        stack_.pop_back();
        setAnchor(f.anchor, f.size);
        add(f.mark, f.size);
    }
    void setAnchor(YAML::anchor_t a, uint64_t n) {
        if (a == 0) return;
        if (a >= anchorSize_.size()) anchorSize_.resize(a + 1, 1);
        anchorSize_[a] = n;
    }
    // Adds a finished node of `n` expanded nodes to its parent and to the total.
    void add(const YAML::Mark& m, uint64_t n) {
        total_ += n;
        if (!stack_.empty()) stack_.back().size += n;
        if (total_ > kMaxExpandedNodes)
            throw InputError(locOf(m), fmt::format("the document expands to more than {} nodes (through aliases of "
                                                   "anchored nodes); a scene file is far smaller, so this is refused",
                                                   kMaxExpandedNodes));
    }
    SourceLoc locOf(const YAML::Mark& m) const {
        return m.line < 0 ? SourceLoc{file_} : SourceLoc{file_, m.line + 1, m.column + 1};
    }

    const std::string& file_;
    std::vector<Frame> stack_;
    std::vector<uint64_t> anchorSize_;
    uint64_t total_ = 0;
};

// Document start marks: yaml-cpp reports them only through the parser's tokens, so the second
// document is located by its first event.
class FirstMark final : public YAML::EventHandler {
public:
    std::optional<YAML::Mark> mark;
    void OnDocumentStart(const YAML::Mark& m) override { if (!mark) mark = m; }
    void OnDocumentEnd() override {}
    void OnNull(const YAML::Mark& m, YAML::anchor_t) override { note(m); }
    void OnAlias(const YAML::Mark& m, YAML::anchor_t) override { note(m); }
    void OnScalar(const YAML::Mark& m, const std::string&, YAML::anchor_t, const std::string&) override { note(m); }
    void OnSequenceStart(const YAML::Mark& m, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override { note(m); }
    void OnSequenceEnd() override {}
    void OnMapStart(const YAML::Mark& m, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override { note(m); }
    void OnMapEnd() override {}

private:
    void note(const YAML::Mark& m) { if (!mark) mark = m; }
};

void prescan(const std::string& text, const std::string& file) {
    requireUtf8(text, file);
    lexicalChecks(text, file);
    std::istringstream in(text);
    YAML::Parser parser(in);
    Prescan events(file);
    parser.HandleNextDocument(events);
    FirstMark second;
    if (parser.HandleNextDocument(second)) {
        const SourceLoc where = second.mark && second.mark->line >= 0
                                    ? SourceLoc{file, second.mark->line + 1, second.mark->column + 1}
                                    : SourceLoc{file};
        throw InputError(where, "a second YAML document starts here; a scene file holds exactly one document "
                                "(remove the '---' separator or split the file)");
    }
}

}  // namespace

YamlNode YamlNode::loadString(const std::string& text, const std::string& fileName) {
    auto doc = std::make_shared<Doc>();
    doc->file = fileName;
    doc->baseDir = fs::path(fileName).parent_path();
    YAML::Node root;
    try {
        prescan(text, fileName);
        root = YAML::Load(text);
    } catch (const YAML::Exception& e) {
        std::string msg = e.msg;
        if (!msg.empty()) msg[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(msg[0])));
        throw InputError(locOf(fileName, e.mark), "YAML syntax error: " + msg);
    }
    if (!root.IsDefined() || root.IsNull())
        throw InputError(SourceLoc{fileName}, "the scene file holds no settings (it is empty or only comments)");
    if (!root.IsMap())
        throw InputError(locOf(fileName, root.Mark()), "the scene file must be a map of sections (scene:, sun:, ...), "
                                                       "found " + std::string(root.IsSequence() ? "a list" : "a single value"));
    return YamlNode(doc, root, "", locOf(fileName, root.Mark()));
}

YamlNode YamlNode::loadFile(const fs::path& file) {
    requireRegularInputFile(file, "scene file");
    return loadString(readTextFile(file), file.string());
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

std::string YamlNode::asOutputName(std::string_view what) const {
    const std::string v = asString();
    const std::string problem = outputNameProblem(v);
    if (!problem.empty()) fail(fmt::format("{} name '{}' {}", what, printableName(v), problem));
    return v;
}

fs::path YamlNode::asPath() const {
    const fs::path p(asString());
    doc_->pathNodes.push_back(node_);
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
