#include "scenegen/objects.h"

#include <cmath>

#include <fmt/format.h>

#include "core/error.h"
#include "scenegen/mesh_io.h"

namespace littoral::scenegen {

TriMesh placeMesh(const TriMesh& local, const Pose& pose, double waterLevel) {
    if (pose.draft.has_value() == pose.z.has_value())
        throw InputError("object placement needs exactly one of 'draft_m' and 'z_m'");
    if (!(pose.scale > 0)) throw InputError(fmt::format("object scale {} must be positive", pose.scale));
    TriMesh m = local;
    const double c = std::cos(pose.heading), s = std::sin(pose.heading);
    for (auto& p : m.positions) {
        const Vec3 q = p * pose.scale;
        // Rotation by -heading about z (clockwise heading from north, bow = +y).
        p = {c * q.x + s * q.y, -s * q.x + c * q.y, q.z};
    }
    double dz = 0;
    if (pose.draft) {
        double zMin = std::numeric_limits<double>::infinity();
        for (const auto& p : m.positions) zMin = std::min(zMin, p.z);
        dz = (waterLevel - *pose.draft) - zMin;
    } else {
        dz = *pose.z;
    }
    for (auto& p : m.positions) p += Vec3{pose.position.x, pose.position.y, dz};
    return m;
}

namespace {

// "slot 0 'hull' (line 4) -> fiberglass, slot 1 'deck' (line 9) -> teak, slot 2 'rail' (line 20)"
std::string slotList(const std::vector<MaterialSlotName>& names, const std::vector<std::string>& materials) {
    std::string out;
    for (size_t k = 0; k < names.size() && k < 8; ++k) {
        out += fmt::format("{}slot {} {}", k ? ", " : "", k,
                           names[k].line ? fmt::format("'{}' (line {})", names[k].name, names[k].line)
                                         : std::string("(the faces before any usemtl)"));
        if (k < materials.size()) out += " -> " + materials[k];
    }
    if (names.size() > 8) out += fmt::format(", ... ({} slots)", names.size());
    return out;
}

}  // namespace

void checkMaterialSlots(const ObjectSpec& spec, const TriMesh& mesh, const std::vector<MaterialSlotName>& slotNames) {
    // Material slots used by the faces must all be named.
    uint16_t maxSlot = 0;
    size_t firstFace = 0;
    for (size_t f = 0; f < mesh.triangles.size(); ++f)
        if (mesh.materialOf(f) > maxSlot) maxSlot = mesh.materialOf(f), firstFace = f;
    if (spec.materials.size() > maxSlot) return;
    const std::string who = fmt::format("object '{}'", spec.name);
    if (spec.materials.size() < slotNames.size()) {
        // An OBJ: name the usemtl line that starts the first slot without a material.
        const MaterialSlotName& first = slotNames[spec.materials.size()];
        throw InputError(spec.loc, fmt::format("{}: {}:{}: usemtl '{}' starts face material slot {}, but 'materials' "
                                               "lists {} ({}); list one material per distinct usemtl name, in the "
                                               "order the names first appear on faces",
                                               who, spec.mesh.string(), first.line, first.name,
                                               spec.materials.size(), spec.materials.size(),
                                               slotList(slotNames, spec.materials)));
    }
    throw InputError(spec.loc, fmt::format("{}: mesh {} uses material slots 0..{}, but 'materials' names only {} "
                                           "(face {} is the first of slot {})",
                                           who, spec.mesh.filename().string(), maxSlot, spec.materials.size(),
                                           firstFace, maxSlot));
}

PlacedObject loadObject(const ObjectSpec& spec, const bathymetry::GeoFrame* frame, double waterLevel) {
    const std::string who = fmt::format("object '{}'", spec.name);
    TriMesh local;
    std::vector<MaterialSlotName> slotNames;
    try {
        local = readMeshFile(spec.mesh, &slotNames);
    } catch (const MeshReadError& e) {
        throw InputError(spec.loc, fmt::format("{}: cannot read mesh {}: {}", who, spec.mesh.string(), e.what()));
    }
    checkMaterialSlots(spec, local, slotNames);

    PlacedObject out;
    Pose& pose = out.pose;
    if (spec.latLonDeg) {
        if (!frame)
            throw InputError(spec.loc, who + ": a latitude/longitude position needs scene.origin (the geo frame)");
        const Point3 p = frame->toLocal((*spec.latLonDeg)[0], (*spec.latLonDeg)[1], 0.0);
        pose.position = {p.x, p.y};
    } else if (spec.positionLocal) {
        pose.position = *spec.positionLocal;
    }
    pose.heading = spec.heading;
    pose.draft = spec.draft;
    pose.z = spec.z;
    pose.scale = spec.scale;
    try {
        out.solid.mesh = placeMesh(local, pose, waterLevel);
    } catch (const InputError& e) {
        throw InputError(spec.loc, who + ": " + e.message());
    }
    out.solid.name = spec.name;
    out.solid.materials = spec.materials;
    out.validity = checkMesh(out.solid.mesh);
    if (!out.validity.valid()) {
        std::string msg = fmt::format("{}: mesh {} is not a valid closed volume:", who, spec.mesh.string());
        for (const auto& r : out.validity.reasons(5)) msg += "\n  " + r;
        msg += "\n  (inspect it with `littoral check-mesh`; `--repair OUT` can stitch and orient it)";
        throw InputError(spec.loc, msg);
    }
    return out;
}

}  // namespace littoral::scenegen
