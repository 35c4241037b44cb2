// `littoral check-mesh FILE [--json] [--repair OUT]`: is this mesh a valid closed volume?
// Exit status: 0 valid closed volume, 1 invalid (reasons on stderr, element by element),
// 2 the file cannot be read as a mesh.
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "pipelines/command_registry.h"
#include "scenegen/mesh_io.h"
#include "scenegen/mesh_validity.h"

namespace {

struct CheckMeshOptions {
    std::string file;
    bool json = false;
    std::string repairOut;
    size_t maxListed = 10;
};

int runCheckMesh(const CheckMeshOptions& o) {
    using namespace littoral;
    using namespace littoral::scenegen;
    TriMesh mesh;
    try {
        mesh = readMeshFile(o.file);
    } catch (const MeshReadError& e) {
        std::fprintf(stderr, "%s\n", e.what());
        if (o.json)
            std::cout << nlohmann::json{{"file", o.file}, {"readable", false}, {"error", e.message()}}.dump(
                             2, ' ', false, nlohmann::json::error_handler_t::replace)
                      << "\n";
        return 2;
    }
    ValidityReport rep = checkMesh(mesh);
    nlohmann::json j = rep.toJson(o.json ? 100 : o.maxListed);
    j["file"] = o.file;
    j["readable"] = true;
    if (!o.repairOut.empty()) {
        TriMesh fixed = mesh;
        const RepairReport rr = repairMesh(fixed);
        writeMeshFile(o.repairOut, fixed);
        const ValidityReport after = checkMesh(fixed);
        j["repair"] = rr.toJson();
        j["repair"]["output"] = o.repairOut;
        j["repair"]["valid_after"] = after.valid();
        for (const auto& c : rr.changes()) std::fprintf(stderr, "repair: %s\n", c.c_str());
        std::fprintf(stderr, "repair: wrote %s (%s)\n", o.repairOut.c_str(),
                     after.valid() ? "valid closed volume" : "still invalid");
        for (const auto& r : after.reasons(o.maxListed)) std::fprintf(stderr, "repair: remaining: %s\n", r.c_str());
    }
    if (o.json) {
        std::cout << j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
    } else {
        std::cout << fmt::format("{}: {} vertices, {} faces, {} component(s)\n", o.file, rep.vertices, rep.faces,
                                 rep.components);
        std::cout << fmt::format("  closed {}  manifold {}  self-intersections {}  bounds volume {}  outward {}\n",
                                 rep.closed ? "yes" : "no", rep.manifold ? "yes" : "no", rep.selfIntersections.size(),
                                 rep.boundsVolume ? "yes" : "no", rep.outward ? "yes" : "no");
        const std::string volume = rep.boundsVolume ? fmt::format("{:.9g} m^3", rep.volume)
                                                    : std::string("n/a (the mesh does not bound a volume)");
        std::cout << fmt::format("  volume {}, area {:.9g} m^2, boundary edges {}\n", volume, rep.area,
                                 rep.boundaryEdges.size());
        std::cout << (rep.valid() ? "  valid closed volume\n" : "  INVALID\n");
    }
    for (const auto& r : rep.reasons(o.maxListed)) std::fprintf(stderr, "%s: %s\n", o.file.c_str(), r.c_str());
    return rep.valid() ? 0 : 1;
}

littoral::CommandRegistrar registerCheckMesh{"check-mesh", [](CLI::App& app) {
    auto* cmd = app.add_subcommand("check-mesh",
                                   "Check that a mesh (OBJ/PLY/OFF/STL) is a closed, manifold, non-self-intersecting, "
                                   "outward-oriented volume. Exit 0 valid, 1 invalid, 2 unreadable");
    auto o = std::make_shared<CheckMeshOptions>();
    cmd->add_option("file", o->file, "Mesh file (.obj, .ply, .off, .stl)")->required();
    cmd->add_flag("--json", o->json, "Print the full report as JSON on stdout");
    cmd->add_option("--repair", o->repairOut,
                    "Merge coincident vertices, drop degenerate faces, make orientation consistent, stitch borders, "
                    "orient outward, and write the result here (the exit status still describes the input)");
    cmd->add_option("--max-listed", o->maxListed, "Elements listed per reason")->check(CLI::Range(1, 1000000));
    cmd->callback([o] { littoral::setExitCode(runCheckMesh(*o)); });
}};

}  // namespace
