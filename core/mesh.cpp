#include "core/mesh.h"

#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/error.h"

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

void writePly(const std::filesystem::path& path, const TriMesh& m) {
    const bool mat = !m.faceMaterial.empty();
    LITTORAL_CHECK(!mat || m.faceMaterial.size() == m.triangles.size());
    writeFileAtomic(path, [&](const std::filesystem::path& tmp) {
        std::ofstream f(tmp, std::ios::binary);
        f << "ply\nformat binary_little_endian 1.0\ncomment written by Littoral\n";
        f << "element vertex " << m.positions.size() << "\nproperty double x\nproperty double y\nproperty double z\n";
        f << "element face " << m.triangles.size() << "\nproperty list uchar uint vertex_indices\n";
        if (mat) f << "property ushort material\n";
        f << "end_header\n";
        static_assert(sizeof(double) == 8);
        for (const auto& p : m.positions) {
            const double xyz[3] = {p.x, p.y, p.z};
            f.write(reinterpret_cast<const char*>(xyz), sizeof(xyz));
        }
        for (size_t i = 0; i < m.triangles.size(); ++i) {
            const unsigned char n = 3;
            f.write(reinterpret_cast<const char*>(&n), 1);
            f.write(reinterpret_cast<const char*>(m.triangles[i].data()), 12);
            if (mat) f.write(reinterpret_cast<const char*>(&m.faceMaterial[i]), 2);
        }
        f.close();
        if (!f) throw InputError(SourceLoc{path.string()}, "cannot write PLY file");
    });
}

namespace {

enum class PlyType { Char, UChar, Short, UShort, Int, UInt, Float, Double };

PlyType parseType(const std::string& s, const std::string& file) {
    if (s == "char" || s == "int8") return PlyType::Char;
    if (s == "uchar" || s == "uint8") return PlyType::UChar;
    if (s == "short" || s == "int16") return PlyType::Short;
    if (s == "ushort" || s == "uint16") return PlyType::UShort;
    if (s == "int" || s == "int32") return PlyType::Int;
    if (s == "uint" || s == "uint32") return PlyType::UInt;
    if (s == "float" || s == "float32") return PlyType::Float;
    if (s == "double" || s == "float64") return PlyType::Double;
    throw InputError(SourceLoc{file}, "PLY header: unknown property type '" + s + "'");
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
    PlyType type;
    bool isList = false;
    PlyType countType = PlyType::UChar;
};
struct Element {
    std::string name;
    size_t count = 0;
    std::vector<Property> props;
};

class Reader {
public:
    Reader(const std::string& data, size_t pos, bool binary, std::string file)
        : d_(data), pos_(pos), binary_(binary), file_(std::move(file)) {}
    double read(PlyType t, const char* what) {
        if (!binary_) {
            skipSpace();
            if (pos_ >= d_.size()) fail(what);
            const char* start = d_.c_str() + pos_;
            char* end = nullptr;
            const double v = std::strtod(start, &end);
            if (end == start) fail(what);
            pos_ += static_cast<size_t>(end - start);
            return v;
        }
        const size_t n = typeSize(t);
        if (pos_ + n > d_.size()) fail(what);
        const char* p = d_.data() + pos_;
        pos_ += n;
        switch (t) {
            case PlyType::Char: return static_cast<int8_t>(*p);
            case PlyType::UChar: return static_cast<uint8_t>(*p);
            case PlyType::Short: { int16_t v; std::memcpy(&v, p, 2); return v; }
            case PlyType::UShort: { uint16_t v; std::memcpy(&v, p, 2); return v; }
            case PlyType::Int: { int32_t v; std::memcpy(&v, p, 4); return v; }
            case PlyType::UInt: { uint32_t v; std::memcpy(&v, p, 4); return v; }
            case PlyType::Float: { float v; std::memcpy(&v, p, 4); return v; }
            case PlyType::Double: { double v; std::memcpy(&v, p, 8); return v; }
        }
        return 0;
    }
    [[noreturn]] void fail(const char* what) {
        throw InputError(SourceLoc{file_}, fmt::format("PLY data ends early or is malformed while reading {}", what));
    }

private:
    void skipSpace() {
        while (pos_ < d_.size() && std::isspace(static_cast<unsigned char>(d_[pos_]))) ++pos_;
    }
    const std::string& d_;
    size_t pos_;
    bool binary_;
    std::string file_;
};

}  // namespace

TriMesh readPly(const std::filesystem::path& path) {
    const std::string file = path.string();
    const std::string data = readTextFile(path);
    if (data.empty()) throw InputError(SourceLoc{file}, "PLY file is empty");
    if (data.compare(0, 3, "ply") != 0) throw InputError(SourceLoc{file, 1, 1}, "not a PLY file (no 'ply' magic)");
    const size_t headerEnd = data.find("end_header");
    if (headerEnd == std::string::npos) throw InputError(SourceLoc{file}, "PLY header has no end_header");
    size_t bodyStart = data.find('\n', headerEnd);
    if (bodyStart == std::string::npos) throw InputError(SourceLoc{file}, "PLY header has no end_header line");
    ++bodyStart;

    std::istringstream header(data.substr(0, headerEnd));
    std::string line;
    std::vector<Element> elements;
    bool binary = false;
    int lineNo = 0;
    while (std::getline(header, line)) {
        ++lineNo;
        std::istringstream ls(line);
        std::string kw;
        ls >> kw;
        if (kw == "format") {
            std::string fmtName;
            ls >> fmtName;
            if (fmtName == "ascii") binary = false;
            else if (fmtName == "binary_little_endian") binary = true;
            else throw InputError(SourceLoc{file, lineNo, 1}, "PLY format '" + fmtName + "' is not supported (ascii, binary_little_endian)");
        } else if (kw == "element") {
            Element e;
            long long count = -1;
            ls >> e.name >> count;
            if (count < 0) throw InputError(SourceLoc{file, lineNo, 1}, "PLY element '" + e.name + "' has no valid count");
            e.count = static_cast<size_t>(count);
            elements.push_back(e);
        } else if (kw == "property") {
            if (elements.empty()) throw InputError(SourceLoc{file, lineNo, 1}, "PLY property before any element");
            Property p;
            std::string t;
            ls >> t;
            if (t == "list") {
                std::string ct, it;
                ls >> ct >> it >> p.name;
                p.isList = true;
                p.countType = parseType(ct, file);
                p.type = parseType(it, file);
            } else {
                p.type = parseType(t, file);
                ls >> p.name;
            }
            elements.back().props.push_back(p);
        }
    }

    TriMesh m;
    Reader r(data, bodyStart, binary, file);
    bool sawMaterial = false;
    for (const auto& e : elements) {
        if (e.name == "vertex") {
            int ix = -1, iy = -1, iz = -1;
            for (size_t k = 0; k < e.props.size(); ++k) {
                if (e.props[k].name == "x") ix = static_cast<int>(k);
                if (e.props[k].name == "y") iy = static_cast<int>(k);
                if (e.props[k].name == "z") iz = static_cast<int>(k);
            }
            if (ix < 0 || iy < 0 || iz < 0) throw InputError(SourceLoc{file}, "PLY vertex element lacks x, y or z");
            m.positions.resize(e.count);
            for (size_t i = 0; i < e.count; ++i) {
                for (size_t k = 0; k < e.props.size(); ++k) {
                    const auto& p = e.props[k];
                    if (p.isList) {
                        const size_t n = static_cast<size_t>(r.read(p.countType, "a vertex list"));
                        for (size_t j = 0; j < n; ++j) r.read(p.type, "a vertex list");
                        continue;
                    }
                    const double v = r.read(p.type, "vertices");
                    if (static_cast<int>(k) == ix) m.positions[i].x = v;
                    else if (static_cast<int>(k) == iy) m.positions[i].y = v;
                    else if (static_cast<int>(k) == iz) m.positions[i].z = v;
                }
                if (!isFinite(m.positions[i]))
                    throw InputError(SourceLoc{file}, fmt::format("vertex {} has a non-finite coordinate", i));
            }
        } else if (e.name == "face") {
            for (size_t i = 0; i < e.count; ++i) {
                std::vector<uint32_t> idx;
                uint16_t mat = 0;
                for (const auto& p : e.props) {
                    if (p.isList) {
                        const double n = r.read(p.countType, "faces");
                        if (n < 0 || n > 1000) r.fail("faces");
                        for (int j = 0; j < static_cast<int>(n); ++j) {
                            const double v = r.read(p.type, "faces");
                            if (p.name == "vertex_indices" || p.name == "vertex_index") idx.push_back(static_cast<uint32_t>(v));
                        }
                    } else {
                        const double v = r.read(p.type, "faces");
                        if (p.name == "material") { mat = static_cast<uint16_t>(v); sawMaterial = true; }
                    }
                }
                if (idx.size() < 3)
                    throw InputError(SourceLoc{file}, fmt::format("face {} has {} vertices; at least 3 needed", i, idx.size()));
                for (size_t j = 1; j + 1 < idx.size(); ++j) {
                    m.triangles.push_back({idx[0], idx[j], idx[j + 1]});
                    m.faceMaterial.push_back(mat);
                }
            }
        } else {
            for (size_t i = 0; i < e.count; ++i)
                for (const auto& p : e.props) {
                    if (p.isList) {
                        const size_t n = static_cast<size_t>(r.read(p.countType, e.name.c_str()));
                        for (size_t j = 0; j < n; ++j) r.read(p.type, e.name.c_str());
                    } else {
                        r.read(p.type, e.name.c_str());
                    }
                }
        }
    }
    if (!sawMaterial) m.faceMaterial.clear();
    for (size_t f = 0; f < m.triangles.size(); ++f)
        for (uint32_t v : m.triangles[f])
            if (v >= m.positions.size())
                throw InputError(SourceLoc{file}, fmt::format("face {} refers to vertex {}, but there are only {} vertices",
                                                              f, v, m.positions.size()));
    return m;
}

}  // namespace littoral
