#pragma once
// Strict YAML reading for scene files. Every node remembers the file, line and column it came
// from and its dotted key path ("water.surface.wind_speed", "objects[2].mesh"), so that every
// mistake is reported as
//     coast.yaml:14:5: error: water.surface.wind_speed: 95 is out of range; allowed [0, 50] m/s
// Maps are closed: expectKeys() lists every key a map may hold and rejects any other with a
// "did you mean" suggestion.
#include <filesystem>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "core/error.h"

namespace littoral::scenegen {

class YamlNode {
public:
    static YamlNode loadFile(const std::filesystem::path& file);
    static YamlNode loadString(const std::string& text, const std::string& fileName);

    const SourceLoc& loc() const { return loc_; }
    const std::string& path() const { return path_; }
    // Folder of the scene file; relative paths in the file resolve against it.
    const std::filesystem::path& baseDir() const { return doc_->baseDir; }

    bool isMap() const { return node_.IsMap(); }
    bool isSequence() const { return node_.IsSequence(); }
    bool isScalar() const { return node_.IsScalar(); }
    bool isNull() const { return !node_.IsDefined() || node_.IsNull(); }

    // ---- maps ----
    void expectMap() const;
    void expectKeys(std::initializer_list<std::string_view> allowed) const;
    void expectKeys(const std::vector<std::string>& allowed) const;
    bool has(std::string_view key) const;
    YamlNode operator[](std::string_view key) const;  // required key
    std::optional<YamlNode> optional(std::string_view key) const;
    std::vector<std::string> keys() const;

    // ---- scalars ----
    double asDouble() const;
    double asDouble(double min, double max, std::string_view unit = "") const;
    long long asInt() const;
    long long asInt(long long min, long long max) const;
    bool asBool() const;
    std::string asString() const;
    std::string asEnum(const std::vector<std::string>& allowed) const;
    // A name that becomes a file name or appears in output tables (core/output_names.h): portable
    // characters only, no separators, no leading '.' or '-'. `what` names it ("sensor").
    std::string asOutputName(std::string_view what) const;
    std::filesystem::path asPath() const;          // resolved against baseDir(); not checked
    std::filesystem::path asExistingPath() const;  // ... and must exist as a regular file

    double getDouble(std::string_view key, double def, double min, double max, std::string_view unit = "") const;
    long long getInt(std::string_view key, long long def, long long min, long long max) const;
    bool getBool(std::string_view key, bool def) const;
    std::string getString(std::string_view key, const std::string& def) const;
    std::string getEnum(std::string_view key, const std::string& def, const std::vector<std::string>& allowed) const;

    // ---- sequences ----
    size_t size() const;
    YamlNode at(size_t i) const;
    std::vector<YamlNode> items() const;  // a sequence's items (error if not a sequence)
    std::vector<double> asDoubleList() const;
    std::vector<double> asDoubleList(double min, double max, std::string_view unit = "") const;

    [[noreturn]] void fail(const std::string& message) const;

    // The yaml-cpp node itself. yaml-cpp nodes are handles: assigning through the returned node
    // changes this document (`littoral sweep` sets the values it varies this way, then parses).
    YAML::Node yaml() const { return node_; }
    // Every scalar of this document that a parser has read as a file path (asPath, asExistingPath),
    // in reading order, for rewriting them as absolute paths (a sweep's self-contained scene files).
    std::vector<YAML::Node> pathNodes() const { return doc_->pathNodes; }

private:
    struct Doc {
        std::string file;
        std::filesystem::path baseDir;
        mutable std::vector<YAML::Node> pathNodes;
    };
    YamlNode(std::shared_ptr<const Doc> doc, YAML::Node node, std::string path, SourceLoc loc);
    YamlNode child(const YAML::Node& n, std::string path) const;
    std::string typeName() const;

    std::shared_ptr<const Doc> doc_;
    YAML::Node node_;
    std::string path_;
    SourceLoc loc_;
};

}  // namespace littoral::scenegen
