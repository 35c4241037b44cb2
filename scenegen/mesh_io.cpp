#include "scenegen/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include "core/atomic_file.h"

namespace littoral::scenegen {
namespace {

namespace OM = OpenMesh;

std::string lowerExt(const std::filesystem::path& p) {
    std::string e = p.extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return e;
}

// An OpenMesh importer that records vertices and faces verbatim, without building topology, so
// that defects survive loading. Everything except positions and faces is ignored.
class SoupImporter final : public OM::IO::BaseImporter {
public:
    std::vector<Point3> points;
    std::vector<std::vector<int>> faces;

    OM::VertexHandle add_vertex(const OM::Vec3f& p) override { return push(p[0], p[1], p[2]); }
    OM::VertexHandle add_vertex(const OM::Vec3d& p) override { return push(p[0], p[1], p[2]); }
    OM::VertexHandle add_vertex() override { return push(0, 0, 0); }
    OM::HalfedgeHandle add_edge(OM::VertexHandle, OM::VertexHandle) override { return OM::HalfedgeHandle(); }
    OM::FaceHandle add_face(const VHandles& idx) override {
        std::vector<int> f;
        f.reserve(idx.size());
        for (const auto& v : idx) f.push_back(v.idx());
        faces.push_back(std::move(f));
        return OM::FaceHandle(static_cast<int>(faces.size()) - 1);
    }
    OM::FaceHandle add_face(OM::HalfedgeHandle) override { return OM::FaceHandle(); }
    void add_face_texcoords(OM::FaceHandle, OM::VertexHandle, const std::vector<OM::Vec2f>&) override {}
    void add_face_texcoords(OM::FaceHandle, OM::VertexHandle, const std::vector<OM::Vec3f>&) override {}
    void set_face_texindex(OM::FaceHandle, int) override {}
    void set_point(OM::VertexHandle v, const OM::Vec3f& p) override {
        if (v.idx() >= 0 && static_cast<size_t>(v.idx()) < points.size()) points[v.idx()] = {p[0], p[1], p[2]};
    }
    void set_halfedge(OM::VertexHandle, OM::HalfedgeHandle) override {}
    void set_normal(OM::VertexHandle, const OM::Vec3f&) override {}
    void set_normal(OM::VertexHandle, const OM::Vec3d&) override {}
    void set_color(OM::VertexHandle, const OM::Vec3uc&) override {}
    void set_color(OM::VertexHandle, const OM::Vec4uc&) override {}
    void set_color(OM::VertexHandle, const OM::Vec3f&) override {}
    void set_color(OM::VertexHandle, const OM::Vec4f&) override {}
    void set_texcoord(OM::VertexHandle, const OM::Vec2f&) override {}
    void set_status(OM::VertexHandle, const OM::Attributes::StatusInfo&) override {}
    void set_next(OM::HalfedgeHandle, OM::HalfedgeHandle) override {}
    void set_face(OM::HalfedgeHandle, OM::FaceHandle) override {}
    void request_face_texcoords2D() override {}
    void set_texcoord(OM::HalfedgeHandle, const OM::Vec2f&) override {}
    void set_texcoord(OM::VertexHandle, const OM::Vec3f&) override {}
    void set_texcoord(OM::HalfedgeHandle, const OM::Vec3f&) override {}
    void set_status(OM::HalfedgeHandle, const OM::Attributes::StatusInfo&) override {}
    void set_color(OM::EdgeHandle, const OM::Vec3uc&) override {}
    void set_color(OM::EdgeHandle, const OM::Vec4uc&) override {}
    void set_color(OM::EdgeHandle, const OM::Vec3f&) override {}
    void set_color(OM::EdgeHandle, const OM::Vec4f&) override {}
    void set_status(OM::EdgeHandle, const OM::Attributes::StatusInfo&) override {}
    void set_normal(OM::FaceHandle, const OM::Vec3f&) override {}
    void set_normal(OM::FaceHandle, const OM::Vec3d&) override {}
    void set_color(OM::FaceHandle, const OM::Vec3uc&) override {}
    void set_color(OM::FaceHandle, const OM::Vec4uc&) override {}
    void set_color(OM::FaceHandle, const OM::Vec3f&) override {}
    void set_color(OM::FaceHandle, const OM::Vec4f&) override {}
    void set_status(OM::FaceHandle, const OM::Attributes::StatusInfo&) override {}
    void add_texture_information(int, std::string) override {}
    size_t n_vertices() const override { return points.size(); }
    size_t n_faces() const override { return faces.size(); }
    size_t n_edges() const override { return 0; }

private:
    OM::VertexHandle push(double x, double y, double z) {
        points.push_back({x, y, z});
        return OM::VertexHandle(static_cast<int>(points.size()) - 1);
    }
};

// Element counts a text or PLY header declares (OFF: first line after the magic; PLY: "element
// vertex N", "element face M"), so a truncated file is not mistaken for a smaller mesh. -1 = unknown.
std::pair<long long, long long> declaredCounts(const std::filesystem::path& path, const std::string& ext) {
    std::ifstream f(path, std::ios::binary);
    std::string line;
    if (ext == ".off") {
        while (std::getline(f, line)) {
            const auto c = line.find('#');
            if (c != std::string::npos) line.resize(c);
            std::istringstream ls(line);
            std::string first;
            if (!(ls >> first)) continue;
            if (first.find("OFF") != std::string::npos) {
                long long nv, nf;
                if (ls >> nv >> nf) return {nv, nf};
                continue;
            }
            long long nv = std::stoll(first), nf;
            if (ls >> nf) return {nv, nf};
            return {-1, -1};
        }
    } else if (ext == ".ply") {
        long long nv = -1, nf = -1;
        for (int n = 0; n < 200 && std::getline(f, line); ++n) {
            if (line.rfind("end_header", 0) == 0) break;
            std::istringstream ls(line);
            std::string kw, name;
            long long count;
            if (ls >> kw >> name >> count && kw == "element") {
                if (name == "vertex") nv = count;
                if (name == "face") nf = count;
            }
        }
        return {nv, nf};
    }
    return {-1, -1};
}

// True if a PLY header declares the face "material" property written by core writePly.
bool plyHasMaterial(const std::filesystem::path& path) {
    std::ifstream f(path, std::ios::binary);
    std::string line;
    bool inFace = false;
    for (int n = 0; n < 200 && std::getline(f, line); ++n) {
        if (line.rfind("end_header", 0) == 0) return false;
        if (line.rfind("element", 0) == 0) inFace = line.find(" face ") != std::string::npos;
        if (inFace && line.rfind("property", 0) == 0 && line.find(" material") != std::string::npos) return true;
    }
    return false;
}

}  // namespace

bool isSupportedMeshExtension(const std::filesystem::path& path) {
    const std::string e = lowerExt(path);
    return e == ".obj" || e == ".ply" || e == ".off" || e == ".stl";
}

TriMesh readMeshFile(const std::filesystem::path& path) {
    const SourceLoc where{path.string()};
    std::error_code ec;
    if (!std::filesystem::exists(path, ec))
        throw MeshReadError(where, "mesh file does not exist");
    if (std::filesystem::is_directory(path, ec))
        throw MeshReadError(where, "is a directory, not a mesh file");
    if (!isSupportedMeshExtension(path))
        throw MeshReadError(where, fmt::format("unsupported mesh extension '{}'; allowed: .obj, .ply, .off, .stl",
                                               path.extension().string()));
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) throw MeshReadError(where, "cannot read file size: " + ec.message());
    if (size == 0) throw MeshReadError(where, "file is empty (0 bytes)");
    {
        std::ifstream probe(path, std::ios::binary);
        if (!probe) throw MeshReadError(where, "cannot open file for reading");
    }

    if (lowerExt(path) == ".ply" && plyHasMaterial(path)) {
        try {
            return readPly(path);
        } catch (const InputError& e) {
            throw MeshReadError(e.where(), e.message());
        }
    }

    SoupImporter soup;
    OM::IO::Options opt;
    // OpenMesh writes its diagnostics to omerr/omlog; keep stderr for our own messages.
    omerr().disable();
    omlog().disable();
    const bool ok = OM::IO::IOManager().read(path.string(), soup, opt);
    omerr().enable();
    omlog().enable();
    if (!ok) throw MeshReadError(where, "OpenMesh could not parse the file as " + lowerExt(path).substr(1) + " mesh data");

    try {
        const auto [nv, nf] = declaredCounts(path, lowerExt(path));
        if ((nv >= 0 && static_cast<size_t>(nv) != soup.points.size()) ||
            (nf >= 0 && static_cast<size_t>(nf) != soup.faces.size()))
            throw MeshReadError(where, fmt::format("the header declares {} vertices and {} faces but the file holds {} "
                                                   "and {} (truncated or malformed)",
                                                   nv, nf, soup.points.size(), soup.faces.size()));
    } catch (const std::invalid_argument&) {
        throw MeshReadError(where, "malformed OFF header");
    } catch (const std::out_of_range&) {
        throw MeshReadError(where, "malformed OFF header");
    }
    TriMesh m;
    m.positions = std::move(soup.points);
    const auto nv = static_cast<int>(m.positions.size());
    for (size_t fi = 0; fi < soup.faces.size(); ++fi) {
        const auto& f = soup.faces[fi];
        if (f.size() < 3) throw MeshReadError(where, fmt::format("face {} has {} vertices; at least 3 needed", fi, f.size()));
        for (int v : f)
            if (v < 0 || v >= nv)
                throw MeshReadError(where, fmt::format("face {} refers to vertex {}, but there are {} vertices", fi, v, nv));
        // Fan triangulation of polygons (exact for the convex quads and n-gons exporters write).
        for (size_t k = 1; k + 1 < f.size(); ++k)
            m.triangles.push_back({static_cast<uint32_t>(f[0]), static_cast<uint32_t>(f[k]), static_cast<uint32_t>(f[k + 1])});
    }
    return m;
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
