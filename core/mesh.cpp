#include "core/mesh.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/resource_limits.h"

namespace littoral {

BBox3 TriMesh::bounds() const {
    BBox3 b;
    for (const auto& p : positions) b.expand(p);
    return b;
}

Vec3 TriMesh::faceNormalArea(size_t f) const {
    const auto& t = triangles[f];
    return cross(positions[t[1]] - positions[t[0]], positions[t[2]] - positions[t[0]]);
}

double TriMesh::area() const {
    double a = 0;
    for (size_t f = 0; f < triangles.size(); ++f) a += 0.5 * length(faceNormalArea(f));
    return a;
}

double TriMesh::signedVolume() const {
    double v = 0;
    for (const auto& t : triangles) v += dot(positions[t[0]], cross(positions[t[1]], positions[t[2]]));
    return v / 6.0;
}

void TriMesh::append(const TriMesh& o) {
    const uint32_t base = static_cast<uint32_t>(positions.size());
    const size_t oldFaces = triangles.size();
    positions.insert(positions.end(), o.positions.begin(), o.positions.end());
    for (auto t : o.triangles) triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    if (!faceMaterial.empty() || !o.faceMaterial.empty()) {
        faceMaterial.resize(oldFaces, 0);
        for (size_t f = 0; f < o.triangles.size(); ++f) faceMaterial.push_back(o.materialOf(f));
    }
}

std::string plyBytes(const TriMesh& m) {
    const bool mat = !m.faceMaterial.empty();
    LITTORAL_CHECK(!mat || m.faceMaterial.size() == m.triangles.size());
    std::string out = "ply\nformat binary_little_endian 1.0\ncomment written by Littoral\n";
    out += fmt::format("element vertex {}\nproperty double x\nproperty double y\nproperty double z\n", m.positions.size());
    out += fmt::format("element face {}\nproperty list uchar uint vertex_indices\n", m.triangles.size());
    if (mat) out += "property ushort material\n";
    out += "end_header\n";
    static_assert(sizeof(double) == 8 && std::endian::native == std::endian::little);
    const size_t header = out.size();
    out.resize(header + 24 * m.positions.size() + (mat ? 15 : 13) * m.triangles.size());
    char* p = out.data() + header;
    for (const auto& v : m.positions) {
        const double xyz[3] = {v.x, v.y, v.z};
        std::memcpy(p, xyz, 24);
        p += 24;
    }
    for (size_t i = 0; i < m.triangles.size(); ++i) {
        *p++ = 3;
        std::memcpy(p, m.triangles[i].data(), 12);
        p += 12;
        if (mat) {
            std::memcpy(p, &m.faceMaterial[i], 2);
            p += 2;
        }
    }
    return out;
}

void writePly(const std::filesystem::path& path, const TriMesh& m) { writeFileAtomic(path, plyBytes(m)); }

namespace {

enum class PlyType { Char, UChar, Short, UShort, Int, UInt, Float, Double };

std::optional<PlyType> parseType(std::string_view s) {
    if (s == "char" || s == "int8") return PlyType::Char;
    if (s == "uchar" || s == "uint8") return PlyType::UChar;
    if (s == "short" || s == "int16") return PlyType::Short;
    if (s == "ushort" || s == "uint16") return PlyType::UShort;
    if (s == "int" || s == "int32") return PlyType::Int;
    if (s == "uint" || s == "uint32") return PlyType::UInt;
    if (s == "float" || s == "float32") return PlyType::Float;
    if (s == "double" || s == "float64") return PlyType::Double;
    return std::nullopt;
}

size_t typeSize(PlyType t) {
    switch (t) {
        case PlyType::Char: case PlyType::UChar: return 1;
        case PlyType::Short: case PlyType::UShort: return 2;
        case PlyType::Int: case PlyType::UInt: case PlyType::Float: return 4;
        case PlyType::Double: return 8;
    }
    return 0;
}

struct Property {
    std::string name;
    PlyType type = PlyType::Float;
    bool isList = false;
    PlyType countType = PlyType::UChar;
};
struct Element {
    std::string name;
    uint64_t count = 0;
    int line = 0;
    std::vector<Property> props;
};

enum class Encoding { Ascii, BinaryLE, BinaryBE };

// Reads the values of the body one at a time; every failure names the file, and for ASCII
// bodies the line and column.
class Reader {
public:
    Reader(std::string_view data, size_t pos, Encoding enc, const std::string& file, int firstLine)
        : d_(data), pos_(pos), enc_(enc), file_(file), bodyStart_(pos), firstLine_(firstLine) {}

    double read(PlyType t, const std::string& what) {
        if (enc_ == Encoding::Ascii) {
            while (pos_ < d_.size() && std::isspace(static_cast<unsigned char>(d_[pos_]))) ++pos_;
            if (pos_ >= d_.size()) fail(fmt::format("the data ends while reading {}", what));
            size_t end = pos_;
            while (end < d_.size() && !std::isspace(static_cast<unsigned char>(d_[end]))) ++end;
            const std::string tok(d_.substr(pos_, end - pos_));
            char* stop = nullptr;
            const double v = std::strtod(tok.c_str(), &stop);
            if (stop != tok.c_str() + tok.size()) fail(fmt::format("'{}' is not a number (reading {})", tok, what));
            pos_ = end;
            return v;
        }
        const size_t n = typeSize(t);
        if (d_.size() - pos_ < n) fail(fmt::format("the data ends while reading {}", what));
        unsigned char b[8];
        std::memcpy(b, d_.data() + pos_, n);
        if (enc_ == Encoding::BinaryBE) std::reverse(b, b + n);
        pos_ += n;
        switch (t) {
            case PlyType::Char: return static_cast<int8_t>(b[0]);
            case PlyType::UChar: return b[0];
            case PlyType::Short: { int16_t v; std::memcpy(&v, b, 2); return v; }
            case PlyType::UShort: { uint16_t v; std::memcpy(&v, b, 2); return v; }
            case PlyType::Int: { int32_t v; std::memcpy(&v, b, 4); return v; }
            case PlyType::UInt: { uint32_t v; std::memcpy(&v, b, 4); return v; }
            case PlyType::Float: { float v; std::memcpy(&v, b, 4); return v; }
            case PlyType::Double: { double v; std::memcpy(&v, b, 8); return v; }
        }
        return 0;
    }
    // A list length or an index: a whole number in [0, limit].
    uint64_t readCount(PlyType t, uint64_t limit, const std::string& what) {
        const size_t at = pos_;
        const double v = read(t, what);
        if (!(v >= 0) || v > static_cast<double>(limit) || v != std::floor(v)) {
            pos_ = at;
            fail(fmt::format("{} is {}; expected a whole number from 0 to {}", what, v, limit));
        }
        return static_cast<uint64_t>(v);
    }
    [[noreturn]] void fail(const std::string& msg) const {
        SourceLoc where{file_};
        if (enc_ == Encoding::Ascii) {
            // Line and column of the current position (counted only when reporting).
            where.line = firstLine_;
            size_t lineStart = bodyStart_;
            for (size_t i = bodyStart_; i < pos_ && i < d_.size(); ++i)
                if (d_[i] == '\n') {
                    ++where.line;
                    lineStart = i + 1;
                }
            where.column = static_cast<int>(std::min<size_t>(pos_ - lineStart, 1u << 30)) + 1;
        }
        throw InputError(where, "PLY data: " + msg);
    }
    size_t remaining() const { return d_.size() - pos_; }

private:
    std::string_view d_;
    size_t pos_;
    Encoding enc_;
    const std::string& file_;
    size_t bodyStart_;
    int firstLine_;
};

bool parseCount(std::string_view s, uint64_t* out) {
    const auto r = std::from_chars(s.data(), s.data() + s.size(), *out);
    return !s.empty() && r.ec == std::errc() && r.ptr == s.data() + s.size();
}

std::vector<std::string_view> words(std::string_view line) {
    std::vector<std::string_view> w;
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
        size_t j = i;
        while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
        if (j > i) w.push_back(line.substr(i, j - i));
        i = j;
    }
    return w;
}

// What the header declares, and where the body starts.
struct PlyHeader {
    std::vector<Element> elements;
    std::optional<Encoding> encoding;
    size_t bodyStart = 0;  // byte offset of the body
    int lines = 0;         // header lines, end_header included
};

Encoding parseFormatLine(const std::vector<std::string_view>& w, const SourceLoc& here) {
    if (w.size() != 3 || w[2] != "1.0")
        throw InputError(here, "PLY header: expected 'format <ascii|binary_little_endian|binary_big_endian> 1.0'");
    if (w[1] == "ascii") return Encoding::Ascii;
    if (w[1] == "binary_little_endian") return Encoding::BinaryLE;
    if (w[1] == "binary_big_endian") return Encoding::BinaryBE;
    throw InputError(here, fmt::format("PLY format '{}' is not one of ascii, binary_little_endian, "
                                       "binary_big_endian", w[1]));
}

Element parseElementLine(const std::vector<std::string_view>& w, const SourceLoc& here,
                         const std::vector<Element>& elements) {
    Element e;
    if (w.size() != 3 || !parseCount(w[2], &e.count))
        throw InputError(here, "PLY header: expected 'element <name> <count>' with a whole-number count");
    e.name = std::string(w[1]);
    e.line = here.line;
    for (const auto& o : elements)
        if (o.name == e.name) throw InputError(here, fmt::format("PLY header: element '{}' declared twice", e.name));
    return e;
}

Property parsePropertyLine(const std::vector<std::string_view>& w, const SourceLoc& here, const Element& element) {
    Property p;
    if (w.size() == 5 && w[1] == "list") {
        const auto ct = parseType(w[2]), it = parseType(w[3]);
        if (!ct || !it || *ct == PlyType::Float || *ct == PlyType::Double)
            throw InputError(here, fmt::format("PLY header: list types '{} {}' are not valid (an integer "
                                               "count type, then any type)", w[2], w[3]));
        p.isList = true;
        p.countType = *ct;
        p.type = *it;
        p.name = std::string(w[4]);
    } else if (w.size() == 3) {
        const auto t = parseType(w[1]);
        if (!t) throw InputError(here, fmt::format("PLY header: unknown property type '{}'", w[1]));
        p.type = *t;
        p.name = std::string(w[2]);
    } else {
        throw InputError(here, "PLY header: expected 'property <type> <name>' or 'property list <count type> "
                               "<item type> <name>'");
    }
    for (const auto& o : element.props)
        if (o.name == p.name) throw InputError(here, fmt::format("PLY header: property '{}' declared twice", p.name));
    return p;
}

// The header: one keyword per line up to end_header.
PlyHeader parseHeader(std::string_view data, const std::string& file) {
    PlyHeader h;
    size_t pos = 0;
    bool ended = false;
    while (pos < data.size()) {
        const size_t nl = data.find('\n', pos);
        if (nl == std::string_view::npos) break;
        const std::string_view line = data.substr(pos, nl - pos);
        pos = nl + 1;
        ++h.lines;
        if (h.lines == 1) continue;  // "ply"
        const auto w = words(line);
        const SourceLoc here{file, h.lines, 1};
        if (w.empty()) continue;
        if (w[0] == "end_header") {
            ended = true;
            break;
        }
        if (w[0] == "comment" || w[0] == "obj_info") continue;
        if (w[0] == "format") {
            if (h.encoding) throw InputError(here, "PLY header: 'format' given twice");
            h.encoding = parseFormatLine(w, here);
        } else if (w[0] == "element") {
            h.elements.push_back(parseElementLine(w, here, h.elements));
        } else if (w[0] == "property") {
            if (h.elements.empty()) throw InputError(here, "PLY header: 'property' before any 'element'");
            h.elements.back().props.push_back(parsePropertyLine(w, here, h.elements.back()));
        } else {
            throw InputError(here, fmt::format("PLY header: unknown keyword '{}'", w[0]));
        }
    }
    if (!ended) throw InputError(SourceLoc{file}, "PLY header has no end_header line (truncated or not a PLY file)");
    if (!h.encoding) throw InputError(SourceLoc{file}, "PLY header has no 'format' line");
    h.bodyStart = pos;
    return h;
}

// Every declared count must fit in what the file holds, before anything is allocated.
void checkDeclaredSizes(const PlyHeader& h, std::string_view data, const std::string& file) {
    const bool ascii = *h.encoding == Encoding::Ascii;
    double minBytes = 0;
    for (const auto& e : h.elements) {
        double each = 0;
        for (const auto& p : e.props)
            each += ascii ? 2.0 : static_cast<double>(typeSize(p.isList ? p.countType : p.type));
        minBytes += each * static_cast<double>(e.count);
    }
    // ASCII: one character and one separator per value, except that the last needs no separator.
    const double payload = static_cast<double>(data.size() - h.bodyStart) + (ascii ? 1.0 : 0.0);
    if (minBytes > payload) {
        std::string what;
        for (const auto& e : h.elements) what += fmt::format("{}{} {}", what.empty() ? "" : ", ", e.count, e.name);
        throw InputError(SourceLoc{file}, fmt::format("PLY header declares {} elements, needing at least {:.0f} bytes "
                                                      "of {} data, but the file holds only {} bytes after the "
                                                      "header: truncated or corrupt",
                                                      what, minBytes, ascii ? "ascii" : "binary",
                                                      data.size() - h.bodyStart));
    }
}

void readVertices(const Element& e, Reader& r, const std::string& file, const PlyReadOptions& options, TriMesh& m) {
    int ix = -1, iy = -1, iz = -1;
    for (size_t k = 0; k < e.props.size(); ++k) {
        if (e.props[k].isList) continue;
        if (e.props[k].name == "x") ix = static_cast<int>(k);
        if (e.props[k].name == "y") iy = static_cast<int>(k);
        if (e.props[k].name == "z") iz = static_cast<int>(k);
    }
    if (ix < 0 || iy < 0 || iz < 0)
        throw InputError(SourceLoc{file, e.line, 1}, "PLY vertex element lacks a scalar x, y or z property");
    if (e.count > std::numeric_limits<uint32_t>::max())
        throw InputError(SourceLoc{file, e.line, 1}, fmt::format("{} vertices: at most 2^32 - 1 supported", e.count));
    m.positions.resize(e.count);
    for (uint64_t i = 0; i < e.count; ++i) {
        for (size_t k = 0; k < e.props.size(); ++k) {
            const auto& p = e.props[k];
            if (p.isList) {
                const uint64_t n = r.readCount(p.countType, r.remaining(), "a vertex list length");
                for (uint64_t j = 0; j < n; ++j) r.read(p.type, "a vertex list");
                continue;
            }
            const double v = r.read(p.type, fmt::format("vertex {}", i));
            if (static_cast<int>(k) == ix) m.positions[i].x = v;
            else if (static_cast<int>(k) == iy) m.positions[i].y = v;
            else if (static_cast<int>(k) == iz) m.positions[i].z = v;
        }
        if (!options.allowNonFinite && !isFinite(m.positions[i]))
            throw InputError(SourceLoc{file}, fmt::format("PLY vertex {} has a non-finite coordinate ({}, {}, {})", i,
                                                          m.positions[i].x, m.positions[i].y, m.positions[i].z));
    }
}

bool isIndexList(const Property& p) { return p.name == "vertex_indices" || p.name == "vertex_index"; }

// Faces, fanned into triangles; sets *sawMaterial if the faces carry a material.
void readFaces(const Element& e, Reader& r, const std::string& file, TriMesh& m, bool* sawMaterial) {
    bool hasIndices = false;
    for (const auto& p : e.props) hasIndices = hasIndices || (p.isList && isIndexList(p));
    if (!hasIndices) throw InputError(SourceLoc{file, e.line, 1}, "PLY face element lacks a 'vertex_indices' list property");
    for (uint64_t i = 0; i < e.count; ++i) {
        std::vector<uint32_t> idx;
        uint16_t mat = 0;
        for (const auto& p : e.props) {
            const bool indices = isIndexList(p);
            if (p.isList) {
                const uint64_t n = r.readCount(p.countType, indices ? 1000 : r.remaining(),
                                               fmt::format("the corner count of face {}", i));
                for (uint64_t j = 0; j < n; ++j) {
                    if (!indices) {
                        r.read(p.type, fmt::format("face {}", i));
                        continue;
                    }
                    idx.push_back(static_cast<uint32_t>(r.readCount(p.type, std::numeric_limits<uint32_t>::max(),
                                                                    fmt::format("a vertex index of face {}", i))));
                }
            } else if (p.name == "material") {
                mat = static_cast<uint16_t>(r.readCount(p.type, 65535, fmt::format("the material of face {}", i)));
                *sawMaterial = true;
            } else {
                r.read(p.type, fmt::format("face {}", i));
            }
        }
        if (idx.size() < 3)
            throw InputError(SourceLoc{file}, fmt::format("PLY face {} has {} corners; at least 3 needed", i, idx.size()));
        for (size_t j = 1; j + 1 < idx.size(); ++j) {
            m.triangles.push_back({idx[0], idx[j], idx[j + 1]});
            m.faceMaterial.push_back(mat);
        }
    }
}

// An element Littoral does not use: its values are read (and so checked) and dropped.
void skipElement(const Element& e, Reader& r) {
    for (uint64_t i = 0; i < e.count; ++i)
        for (const auto& p : e.props) {
            if (p.isList) {
                const uint64_t n = r.readCount(p.countType, r.remaining(), "a list length of element " + e.name);
                for (uint64_t j = 0; j < n; ++j) r.read(p.type, "element " + e.name);
            } else {
                r.read(p.type, "element " + e.name);
            }
        }
}

}  // namespace

TriMesh parsePly(std::string_view data, const std::string& file, const PlyReadOptions& options) {
    if (data.empty()) throw InputError(SourceLoc{file}, "PLY file is empty (0 bytes)");
    if (data.substr(0, 4) != "ply\n" && data.substr(0, 5) != "ply\r\n")
        throw InputError(SourceLoc{file, 1, 1}, "not a PLY file (the first line must be 'ply')");
    const PlyHeader h = parseHeader(data, file);
    checkDeclaredSizes(h, data, file);

    TriMesh m;
    Reader r(data, h.bodyStart, *h.encoding, file, h.lines + 1);
    bool sawMaterial = false, sawVertex = false;
    for (const auto& e : h.elements) {
        if (e.props.empty()) continue;  // nothing stored per element
        if (e.name == "vertex") {
            sawVertex = true;
            readVertices(e, r, file, options, m);
        } else if (e.name == "face") {
            readFaces(e, r, file, m, &sawMaterial);
        } else {
            skipElement(e, r);
        }
    }
    if (!sawVertex && !m.triangles.empty()) throw InputError(SourceLoc{file}, "PLY file has faces but no vertex element");
    if (!sawMaterial) m.faceMaterial.clear();
    for (size_t f = 0; f < m.triangles.size(); ++f)
        for (uint32_t v : m.triangles[f])
            if (v >= m.positions.size())
                throw InputError(SourceLoc{file}, fmt::format("PLY face {} refers to vertex {}, but there are only {} "
                                                              "vertices (numbered from 0)",
                                                              f, v, m.positions.size()));
    return m;
}

TriMesh readPly(const std::filesystem::path& path, const PlyReadOptions& options) {
    return parsePly(readTextFile(path), path.string(), options);
}

}  // namespace littoral
