#include "scenegen/mesh_io.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <vector>

#include <fmt/format.h>

#include "core/atomic_file.h"

namespace littoral::scenegen {
namespace {

std::string lowerExt(const std::filesystem::path& p) {
    std::string e = p.extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return e;
}

// One whitespace-separated word of a text line and its 1-based column.
struct Token {
    std::string_view text;
    int column = 0;
};

// Lines of a text file with their numbers; '#' starts a comment (OBJ, OFF).
class TextLines {
public:
    TextLines(std::string_view data, const std::string& file, bool comments)
        : d_(data), file_(file), comments_(comments) {}

    // The next line that holds at least one token; false at the end of the data.
    bool next(std::vector<Token>* tokens) {
        while (pos_ < d_.size()) {
            const size_t nl = d_.find('\n', pos_);
            const size_t end = nl == std::string_view::npos ? d_.size() : nl;
            std::string_view line = d_.substr(pos_, end - pos_);
            pos_ = end + 1;
            ++line_;
            if (comments_) {
                const size_t c = line.find('#');
                if (c != std::string_view::npos) line = line.substr(0, c);
            }
            tokens->clear();
            size_t i = 0;
            while (i < line.size()) {
                while (i < line.size() && isBlank(line[i])) ++i;
                size_t j = i;
                while (j < line.size() && !isBlank(line[j])) ++j;
                if (j > i) tokens->push_back({line.substr(i, j - i), static_cast<int>(std::min<size_t>(i, 1u << 30)) + 1});
                i = j;
            }
            if (!tokens->empty()) return true;
        }
        return false;
    }
    int line() const { return line_; }
    size_t remainingBytes() const { return pos_ < d_.size() ? d_.size() - pos_ : 0; }
    [[noreturn]] void fail(int column, const std::string& msg) const {
        throw MeshReadError(SourceLoc{file_, line_, column}, msg);
    }
    // A decimal number filling the whole token. NaN, infinities and values beyond the double range
    // (which strtod returns as +-HUGE_VAL = infinity) are numbers here: the caller decides.
    double number(const Token& t, const char* what) const {
        const std::string s(t.text);
        char* end = nullptr;
        const double v = std::strtod(s.c_str(), &end);
        if (s.empty() || end != s.c_str() + s.size())
            fail(t.column, fmt::format("'{}' is not a number ({})", printable(t.text), what));
        return v;
    }
    // A whole number filling the token, in [lo, hi].
    long long integer(const Token& t, long long lo, long long hi, const char* what) const {
        const std::string s(t.text);
        char* end = nullptr;
        errno = 0;
        const long long v = std::strtoll(s.c_str(), &end, 10);
        if (s.empty() || end != s.c_str() + s.size() || errno == ERANGE)
            fail(t.column, fmt::format("'{}' is not a whole number ({})", printable(t.text), what));
        if (v < lo || v > hi) fail(t.column, fmt::format("{} is {}; allowed {} to {}", what, v, lo, hi));
        return v;
    }
    static std::string printable(std::string_view s) {
        std::string out;
        for (size_t i = 0; i < s.size() && i < 40; ++i) {
            const unsigned char c = static_cast<unsigned char>(s[i]);
            out += (c >= 0x20 && c < 0x7f) ? std::string(1, static_cast<char>(c)) : fmt::format("\\x{:02x}", c);
        }
        if (s.size() > 40) out += "...";
        return out;
    }

private:
    static bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
    std::string_view d_;
    const std::string& file_;
    bool comments_;
    size_t pos_ = 0;
    int line_ = 0;
};

void addPolygon(TriMesh& m, const std::vector<uint32_t>& f) {
    for (size_t k = 1; k + 1 < f.size(); ++k) m.triangles.push_back({f[0], f[k], f[k + 1]});
}

constexpr long long kMaxVertices = std::numeric_limits<uint32_t>::max();
constexpr size_t kMaxCorners = 1000;  // corners of one polygon

// ---------------------------------------------------------------------------------------- OBJ
// Wavefront OBJ (geometry statements of the 3.0 specification). v and f build the mesh and usemtl
// gives the faces after it their material slot; the other statements of the specification are
// accepted and ignored; anything else is an error.

bool objIgnored(std::string_view k) {
    static const char* kIgnored[] = {"vt", "vn", "vp", "g", "o", "s", "mtllib", "l", "p", "cstype", "deg",
                                     "bmat", "step", "curv", "curv2", "surf", "parm", "trim", "hole", "scrv", "sp",
                                     "end", "con", "mg", "bevel", "c_interp", "d_interp", "lod", "usemap", "maplib",
                                     "shadow_obj", "trace_obj", "ctech", "stech", "call", "csh"};
    for (const char* s : kIgnored)
        if (k == s) return true;
    return false;
}

// OBJ face material slots: each distinct usemtl name takes the next slot when its first face comes
// (slot 0 for faces before any usemtl), so slots follow the order in which the names first appear
// on faces; a name no face follows takes none.
class ObjSlots {
public:
    void use(const std::vector<Token>& t, const TextLines& in) {
        if (t.size() < 2) in.fail(t[0].column, "usemtl needs a material name");
        current_.clear();
        for (size_t k = 1; k < t.size(); ++k) current_ += (k > 1 ? " " : "") + std::string(t[k].text);
        line_ = in.line();
        named_ = true;
        slot_.reset();
    }
    // The slot of a face read now (assigned at the first face after a usemtl).
    uint16_t slotOfFace(const TextLines& in) {
        if (slot_) return *slot_;
        const std::string key = named_ ? "n" + current_ : std::string("-");  // "-": before any usemtl
        auto it = index_.find(key);
        if (it == index_.end()) {
            if (names_.size() > 65535) in.fail(1, "more than 65536 distinct usemtl names (material slots)");
            it = index_.emplace(key, static_cast<uint16_t>(names_.size())).first;
            names_.push_back({named_ ? current_ : std::string(), named_ ? line_ : 0});
        }
        slot_ = it->second;
        return *slot_;
    }
    const std::vector<MaterialSlotName>& names() const { return names_; }

private:
    std::string current_;
    int line_ = 0;
    bool named_ = false;
    std::optional<uint16_t> slot_;
    std::map<std::string, uint16_t> index_;
    std::vector<MaterialSlotName> names_;
};

TriMesh parseObj(std::string_view data, const std::string& file, std::vector<MaterialSlotName>* slotNames) {
    TriMesh m;
    TextLines in(data, file, true);
    std::vector<Token> t;
    std::vector<uint32_t> face;
    std::vector<uint16_t> material;  // per triangle
    ObjSlots slots;
    struct PendingIndex { int line, column; long long index; };
    std::vector<std::pair<size_t, PendingIndex>> absolute;  // triangle corner -> index to check at the end
    while (in.next(&t)) {
        const std::string_view key = t[0].text;
        if (key == "v") {
            // x y z, optionally w or a vertex colour (r g b): 3, 4, 6 or 7 numbers.
            const size_t n = t.size() - 1;
            if (n != 3 && n != 4 && n != 6 && n != 7)
                in.fail(t[0].column, fmt::format("a vertex needs x y z (optionally w, or r g b); found {} value(s)", n));
            for (size_t k = 4; k < t.size(); ++k) in.number(t[k], "vertex");
            if (static_cast<long long>(m.positions.size()) >= kMaxVertices) in.fail(1, "more than 2^32 - 1 vertices");
            m.positions.push_back({in.number(t[1], "vertex x"), in.number(t[2], "vertex y"), in.number(t[3], "vertex z")});
        } else if (key == "f" || key == "fo") {
            if (t.size() < 4) in.fail(t[0].column, fmt::format("a face needs at least 3 corners; found {}", t.size() - 1));
            if (t.size() - 1 > kMaxCorners) in.fail(t[0].column, fmt::format("a face has more than {} corners", kMaxCorners));
            face.clear();
            std::vector<PendingIndex> pending;
            for (size_t k = 1; k < t.size(); ++k) {
                // v, v/vt, v//vn or v/vt/vn: the vertex index is the part before the first '/'.
                const std::string_view corner = t[k].text;
                const Token vtok{corner.substr(0, corner.find('/')), t[k].column};
                const long long idx = in.integer(vtok, -kMaxVertices, kMaxVertices, "a face's vertex index");
                if (idx == 0) in.fail(t[k].column, "vertex index 0: OBJ numbers vertices from 1 (negative = relative)");
                long long v;
                if (idx < 0) {
                    // Relative: -1 is the most recent vertex.
                    v = static_cast<long long>(m.positions.size()) + idx;
                    if (v < 0)
                        in.fail(t[k].column, fmt::format("relative vertex index {} reaches before the first vertex "
                                                         "(only {} defined so far)",
                                                         idx, m.positions.size()));
                } else {
                    v = idx - 1;
                    pending.push_back({in.line(), t[k].column, idx});
                }
                face.push_back(static_cast<uint32_t>(v));
            }
            const size_t first = m.triangles.size();
            addPolygon(m, face);
            material.resize(m.triangles.size(), slots.slotOfFace(in));
            // Absolute indices may name vertices defined later in the file; check them at the end.
            for (const auto& p : pending) absolute.push_back({first, p});
        } else if (key == "usemtl") {
            slots.use(t, in);
        } else if (!objIgnored(key)) {
            in.fail(t[0].column, fmt::format("'{}' is not an OBJ statement (expected v, f, vt, vn, g, o, usemtl, ...): "
                                             "not an OBJ file, or a damaged one",
                                             TextLines::printable(key)));
        }
    }
    for (const auto& [tri, p] : absolute)
        if (p.index > static_cast<long long>(m.positions.size()))
            throw MeshReadError(SourceLoc{file, p.line, p.column},
                                fmt::format("face refers to vertex {}, but the file defines only {} vertices", p.index,
                                            m.positions.size()));
    // One slot in all: no per-face materials (every face is slot 0), as for a file without usemtl.
    if (slots.names().size() > 1) m.faceMaterial = std::move(material);
    if (slotNames) *slotNames = slots.names();
    return m;
}

// ---------------------------------------------------------------------------------------- OFF
// Object File Format: optional "OFF" keyword (with the ST / C / N prefixes: texture coordinates,
// colours and normals after each vertex's x y z, ignored here), then "nv nf ne", nv vertex lines,
// nf face lines "n i1 ... in [colour]". 4OFF / nOFF (other dimensions) and binary OFF are refused.

TriMesh parseOff(std::string_view data, const std::string& file) {
    TextLines in(data, file, true);
    std::vector<Token> t;
    if (!in.next(&t)) throw MeshReadError(SourceLoc{file}, "OFF file holds no header (only blank lines or comments)");
    const std::string_view kw = t[0].text;
    if (kw.size() >= 3 && kw.substr(kw.size() - 3) == "OFF") {
        std::string_view prefix = kw.substr(0, kw.size() - 3);
        for (const char* p : {"ST", "C", "N"})
            if (prefix.substr(0, std::strlen(p)) == p) prefix.remove_prefix(std::strlen(p));
        if (!prefix.empty())
            in.fail(t[0].column, fmt::format("'{}' files are not supported (only 3-D OFF with ST, C or N prefixes)",
                                             TextLines::printable(kw)));
        if (t.size() > 1 && t[1].text == "BINARY") in.fail(t[1].column, "binary OFF is not supported; use ascii OFF");
        if (t.size() > 1) t.erase(t.begin());  // counts on the keyword's line
        else if (!in.next(&t)) throw MeshReadError(SourceLoc{file}, "OFF file ends after its keyword");
    }
    if (t.size() < 2 || t.size() > 3)
        in.fail(t[0].column, "expected the counts line 'vertices faces [edges]'");
    const long long nv = in.integer(t[0], 0, kMaxVertices, "the vertex count");
    const long long nf = in.integer(t[1], 0, std::numeric_limits<int32_t>::max(), "the face count");
    if (t.size() == 3) in.integer(t[2], 0, std::numeric_limits<int64_t>::max(), "the edge count");
    // A vertex line holds at least "x y z\n" (6 bytes), a face line "3 a b c\n" (8 bytes).
    // (The last line may lack its newline, hence one byte of slack.)
    const double needed = double(nv) * 6.0 + double(nf) * 8.0;
    if (needed > double(in.remainingBytes()) + 1.0)
        in.fail(t[0].column, fmt::format("the header declares {} vertices and {} faces, which need at least {:.0f} bytes "
                                         "of lines, but only {} bytes follow: truncated or corrupt",
                                         nv, nf, needed, in.remainingBytes()));
    TriMesh m;
    m.positions.reserve(static_cast<size_t>(nv));
    for (long long i = 0; i < nv; ++i) {
        if (!in.next(&t))
            throw MeshReadError(SourceLoc{file, in.line(), 0},
                                fmt::format("the file ends after {} of the {} vertices its header declares (truncated)", i, nv));
        if (t.size() < 3) in.fail(t[0].column, fmt::format("vertex {} needs x y z; found {} value(s)", i, t.size()));
        for (size_t k = 3; k < t.size(); ++k) in.number(t[k], "vertex attribute");
        m.positions.push_back({in.number(t[0], "vertex x"), in.number(t[1], "vertex y"), in.number(t[2], "vertex z")});
    }
    std::vector<uint32_t> face;
    for (long long i = 0; i < nf; ++i) {
        if (!in.next(&t))
            throw MeshReadError(SourceLoc{file, in.line(), 0},
                                fmt::format("the file ends after {} of the {} faces its header declares (truncated)", i, nf));
        const long long n = in.integer(t[0], 3, static_cast<long long>(kMaxCorners), "a face's corner count");
        if (static_cast<long long>(t.size()) - 1 < n)
            in.fail(t[0].column, fmt::format("face {} declares {} corners but lists {}", i, n, t.size() - 1));
        face.clear();
        for (long long k = 1; k <= n; ++k) {
            const long long v = in.integer(t[k], 0, kMaxVertices, "a vertex index");
            if (v >= nv)
                in.fail(t[k].column, fmt::format("face {} refers to vertex {}, but there are {} vertices (numbered from 0)",
                                                 i, v, nv));
            face.push_back(static_cast<uint32_t>(v));
        }
        for (size_t k = static_cast<size_t>(n) + 1; k < t.size(); ++k) in.number(t[k], "face colour");
        addPolygon(m, face);
    }
    if (in.next(&t))
        in.fail(t[0].column, fmt::format("data after the {} vertices and {} faces the header declares (wrong counts?)",
                                         nv, nf));
    return m;
}

// ---------------------------------------------------------------------------------------- STL
// Binary: 80-byte header, uint32 triangle count n, then n records of 50 bytes (normal, three
// vertices as float32, a 16-bit attribute); the file size must be exactly 84 + 50 n. ASCII:
// solid / facet normal / outer loop / 3 x vertex / endloop / endfacet ... endsolid.

// Coincident corners become one vertex (bit-exact equality; each NaN corner stays its own vertex).
struct VertexMerger {
    TriMesh& m;
    std::map<std::array<double, 3>, uint32_t> index;
    uint32_t add(double x, double y, double z) {
        if (std::isnan(x) || std::isnan(y) || std::isnan(z)) {
            m.positions.push_back({x, y, z});
            return static_cast<uint32_t>(m.positions.size() - 1);
        }
        auto [it, inserted] = index.try_emplace({x, y, z}, static_cast<uint32_t>(m.positions.size()));
        if (inserted) m.positions.push_back({x, y, z});
        return it->second;
    }
};

TriMesh parseStlBinary(std::string_view data, const std::string& file) {
    uint32_t n = 0;
    std::memcpy(&n, data.data() + 80, 4);
    const double expected = 84.0 + 50.0 * n;
    if (static_cast<double>(data.size()) != expected)
        throw MeshReadError(SourceLoc{file}, fmt::format("binary STL header declares {} triangles, which take {:.0f} "
                                                         "bytes, but the file has {} bytes: truncated or corrupt",
                                                         n, expected, data.size()));
    TriMesh m;
    VertexMerger merge{m, {}};
    const char* p = data.data() + 84;
    for (uint32_t i = 0; i < n; ++i, p += 50) {
        float v[12];
        std::memcpy(v, p, 48);
        std::array<uint32_t, 3> tri{};
        for (int k = 0; k < 3; ++k) tri[k] = merge.add(v[3 + 3 * k], v[4 + 3 * k], v[5 + 3 * k]);
        m.triangles.push_back(tri);
    }
    return m;
}

TriMesh parseStlAscii(std::string_view data, const std::string& file) {
    TextLines in(data, file, false);
    std::vector<Token> t;
    TriMesh m;
    VertexMerger merge{m, {}};
    auto expect = [&](std::initializer_list<const char*> words, const char* what) {
        if (!in.next(&t)) throw MeshReadError(SourceLoc{file, in.line(), 0}, fmt::format("the file ends where {} was expected (truncated)", what));
        size_t k = 0;
        for (const char* w : words) {
            if (k >= t.size() || t[k].text != w)
                in.fail(k < t.size() ? t[k].column : 1, fmt::format("expected {}", what));
            ++k;
        }
    };
    bool inSolid = false;
    while (in.next(&t)) {
        const std::string_view k = t[0].text;
        if (k == "solid") {
            if (inSolid) in.fail(t[0].column, "'solid' inside a solid (missing 'endsolid')");
            inSolid = true;
        } else if (k == "endsolid") {
            if (!inSolid) in.fail(t[0].column, "'endsolid' without 'solid'");
            inSolid = false;
        } else if (k == "facet") {
            if (!inSolid) in.fail(t[0].column, "'facet' outside 'solid ... endsolid'");
            if (t.size() != 5 || t[1].text != "normal") in.fail(t[0].column, "expected 'facet normal nx ny nz'");
            for (int c = 2; c < 5; ++c) in.number(t[c], "facet normal");
            expect({"outer", "loop"}, "'outer loop'");
            std::array<uint32_t, 3> tri{};
            for (int c = 0; c < 3; ++c) {
                expect({"vertex"}, "'vertex x y z' (a facet has exactly 3 vertices)");
                if (t.size() != 4) in.fail(t[0].column, "expected 'vertex x y z'");
                tri[c] = merge.add(in.number(t[1], "vertex x"), in.number(t[2], "vertex y"), in.number(t[3], "vertex z"));
            }
            expect({"endloop"}, "'endloop' (a facet has exactly 3 vertices)");
            expect({"endfacet"}, "'endfacet'");
            m.triangles.push_back(tri);
        } else {
            in.fail(t[0].column, fmt::format("'{}' is not an STL keyword (expected solid, facet or endsolid): not an "
                                             "STL file, or a damaged one",
                                             TextLines::printable(k)));
        }
    }
    if (inSolid) throw MeshReadError(SourceLoc{file, in.line(), 0}, "the file ends inside a solid (no 'endsolid'; truncated)");
    return m;
}

TriMesh parseStl(std::string_view data, const std::string& file) {
    // A binary file whose size matches its count is binary even if its header begins with "solid"
    // (many exporters write that); otherwise text starting with "solid" is ascii.
    if (data.size() >= 84) {
        uint32_t n = 0;
        std::memcpy(&n, data.data() + 80, 4);
        if (static_cast<double>(data.size()) == 84.0 + 50.0 * n) return parseStlBinary(data, file);
    }
    size_t i = 0;
    while (i < data.size() && std::isspace(static_cast<unsigned char>(data[i]))) ++i;
    if (data.substr(i, 5) == "solid") return parseStlAscii(data, file);
    if (data.size() >= 84) return parseStlBinary(data, file);  // reports the size mismatch
    throw MeshReadError(SourceLoc{file}, fmt::format("not an STL file: {} bytes, neither ascii ('solid ...') nor a binary "
                                                     "STL (at least 84 bytes)",
                                                     data.size()));
}

}  // namespace

bool isSupportedMeshExtension(const std::filesystem::path& path) {
    const std::string e = lowerExt(path);
    return e == ".obj" || e == ".ply" || e == ".off" || e == ".stl";
}

TriMesh parseMeshData(std::string_view data, MeshFormat format, const std::string& file,
                      std::vector<MaterialSlotName>* slotNames) {
    if (slotNames) slotNames->clear();
    if (data.empty()) throw MeshReadError(SourceLoc{file}, "file is empty (0 bytes)");
    switch (format) {
        case MeshFormat::Obj: return parseObj(data, file, slotNames);
        case MeshFormat::Off: return parseOff(data, file);
        case MeshFormat::Stl: return parseStl(data, file);
        case MeshFormat::Ply:
            try {
                PlyReadOptions po;
                po.allowNonFinite = true;
                return parsePly(data, file, po);
            } catch (const MeshReadError&) {
                throw;
            } catch (const InputError& e) {
                throw MeshReadError(e.where(), e.message());
            }
    }
    throw InternalError("unknown mesh format");
}

TriMesh readMeshFile(const std::filesystem::path& path, std::vector<MaterialSlotName>* slotNames) {
    if (slotNames) slotNames->clear();
    const SourceLoc where{path.string()};
    std::string data;
    try {
        requireRegularInputFile(path, "mesh file");
        if (!isSupportedMeshExtension(path))
            throw InputError(where, fmt::format("unsupported mesh extension '{}'; allowed: .obj, .ply, .off, .stl",
                                                path.extension().string()));
        data = readTextFile(path);
    } catch (const MeshReadError&) {
        throw;
    } catch (const InputError& e) {
        throw MeshReadError(e.where(), e.message());
    }
    const std::string e = lowerExt(path);
    const MeshFormat f = e == ".obj" ? MeshFormat::Obj : e == ".ply" ? MeshFormat::Ply : e == ".off" ? MeshFormat::Off
                                                                                                   : MeshFormat::Stl;
    return parseMeshData(data, f, path.string(), slotNames);
}

void writeMeshFile(const std::filesystem::path& path, const TriMesh& mesh) {
    const std::string e = lowerExt(path);
    if (e == ".ply") {
        writePly(path, mesh);
        return;
    }
    std::ostringstream os;
    os.precision(17);
    if (e == ".obj") {
        os << "# written by littoral\n";
        for (const auto& p : mesh.positions) os << "v " << p.x << ' ' << p.y << ' ' << p.z << '\n';
        for (const auto& t : mesh.triangles) os << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
    } else if (e == ".off") {
        os << "OFF\n" << mesh.positions.size() << ' ' << mesh.triangles.size() << " 0\n";
        for (const auto& p : mesh.positions) os << p.x << ' ' << p.y << ' ' << p.z << '\n';
        for (const auto& t : mesh.triangles) os << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
    } else if (e == ".stl") {
        os << "solid littoral\n";
        for (size_t f = 0; f < mesh.triangles.size(); ++f) {
            Vec3 n = mesh.faceNormalArea(f);
            const double l = length(n);
            if (l > 0) n = n / l;
            os << " facet normal " << n.x << ' ' << n.y << ' ' << n.z << "\n  outer loop\n";
            for (uint32_t v : mesh.triangles[f]) {
                const auto& p = mesh.positions[v];
                os << "   vertex " << p.x << ' ' << p.y << ' ' << p.z << '\n';
            }
            os << "  endloop\n endfacet\n";
        }
        os << "endsolid littoral\n";
    } else {
        throw InputError(SourceLoc{path.string()}, fmt::format("unsupported mesh extension '{}'; allowed: .obj, .ply, .off, .stl",
                                                               path.extension().string()));
    }
    writeTextFileAtomic(path, os.str());
}

}  // namespace littoral::scenegen
