#include "scenegen/assemble.h"

#include <chrono>
#include <cmath>
#include <map>
#include <set>

#include <fmt/format.h>

#include "bathymetry/geo_frame.h"
#include "bathymetry/terrain.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/log.h"
#include "scenegen/assembly_sections.h"
#include "scenegen/mesh_validity.h"
#include "scenegen/objects.h"
#include "scenegen/scene_checks.h"
#include "scenegen/surface_section.h"
#include "scenegen/water_volume.h"
#include "surfaces/wave_surface.h"

namespace littoral::scenegen {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::unique_ptr<bathymetry::Terrain> makeTerrain(const BathymetrySpec& b, const bathymetry::Extent& extent,
                                                 const bathymetry::GeoFrame* frame) {
    try {
        switch (b.kind) {
            case BathymetrySpec::Kind::PlanarSlope: return bathymetry::makePlanarSlope(extent, b.planar);
            case BathymetrySpec::Kind::Dean: return bathymetry::makeDeanProfile(extent, b.dean);
            case BathymetrySpec::Kind::BarTrough: return bathymetry::makeBarTrough(extent, b.barTrough);
            case BathymetrySpec::Kind::Raster: return bathymetry::loadRaster(b.file, b.raster);
            case BathymetrySpec::Kind::Soundings:
                if (!frame) throw InputError(b.loc, "bathymetry from soundings needs scene.origin (latitude, longitude)");
                return bathymetry::fromSoundings(b.file, *frame, b.soundings);
        }
    } catch (const InputError& e) {
        // Keep a location that already names a data file; otherwise point at the section.
        if (!e.where().file.empty()) throw;
        throw InputError(b.loc, "bathymetry: " + e.message());
    }
    throw InternalError("unknown bathymetry kind");
}

// The smooth air-water interface; water.surface.roughness makes it the rough (Cox-Munk) one.
ir::Material interfaceMaterial() {
    ir::Material m;
    m.name = "air-water-interface";
    m.type = ir::Material::Type::Dielectric;  // smooth Fresnel interface between the water mesh's media
    // No explicit solver: the dirsig estimator gives interfaces the Fresnel solver (Table 10.4).
    return m;
}

// Vertical sides where the domain cuts the sea: an absorbing boundary, or with
// water.horizontal: periodic a wall that rays cross to re-enter from the opposite side, so the
// water is horizontally unbounded (see docs/scene-assembly.md).
ir::Material wallMaterial(bool periodic) {
    ir::Material m;
    m.name = periodic ? "periodic-wall" : "domain-wall";
    m.type = periodic ? ir::Material::Type::Periodic : ir::Material::Type::Black;
    return m;
}

// validity.json text. A file name from the command line need not be UTF-8; it is written with
// replacement characters rather than failing half-way through the outputs.
std::string validityText(const nlohmann::json& v) {
    return v.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

// water.surface omitted: a flat surface over the domain (docs/scene-format.md). A flat surface
// needs no resolution, so the grid is coarse (four cells across the shorter side) and kept whole.
surfaces::WaveParams defaultWaterSurface(const bathymetry::Extent& d) {
    surfaces::WaveParams p;
    p.model = surfaces::WaveModel::Flat;
    p.windSpeed = 0.0;
    p.sizeX = d.width();
    p.sizeY = d.height();
    p.centreX = 0.5 * (d.x0 + d.x1);
    p.centreY = 0.5 * (d.y0 + d.y1);
    p.spacing = 0.25 * std::min(d.width(), d.height());
    p.triangles = 0;
    return p;
}

// Drops the vertices no face uses (after faces moved to another mesh), keeping the order of the rest.
void compactVertices(TriMesh& m) {
    std::vector<uint32_t> remap(m.positions.size(), UINT32_MAX);
    std::vector<Point3> kept;
    for (auto& t : m.triangles)
        for (auto& v : t) {
            if (remap[v] == UINT32_MAX) remap[v] = 0;
        }
    for (size_t i = 0; i < m.positions.size(); ++i)
        if (remap[i] != UINT32_MAX) {
            remap[i] = static_cast<uint32_t>(kept.size());
            kept.push_back(m.positions[i]);
        }
    for (auto& t : m.triangles)
        for (auto& v : t) v = remap[v];
    m.positions = std::move(kept);
}

nlohmann::json meshSummary(const TriMesh& m) {
    nlohmann::json j;
    j["vertices"] = m.numVertices();
    j["faces"] = m.numTriangles();
    j["area_m2"] = m.area();
    return j;
}

}  // namespace

nlohmann::json StageSeconds::toJson() const {
    return {{"parse", parse},           {"surface", surface},           {"terrain", terrain},
            {"textures", textures},     {"objects", objects},           {"water_prism", waterPrism},
            {"water_terrain", waterTerrain}, {"water_boolean", waterBoolean}, {"water_solids", waterSolids},
            {"validity", validity},     {"write", write},               {"total", total()}};
}

AssembledScene assembleScene(const SceneSpec& spec, const AssembleOptions& opt) {
    AssembledScene out;
    ir::SceneIR& ir = out.ir;
    applyCommonSections(spec, &ir);
    const bathymetry::Extent domain{spec.scene.x0, spec.scene.y0, spec.scene.x1, spec.scene.y1};
    checkRenderMemory(spec, ir);  // before any geometry: refuse an impossible render at once

    // ---- parse the geometry sections ----
    auto t = Clock::now();
    if (!spec.bathymetry)
        throw InputError(SourceLoc{spec.file.string()}, "the scene has no 'bathymetry' section; a coastal scene needs "
                                                        "a seabed (e.g. bathymetry: {type: planar_slope, ...})");
    const BathymetrySpec bathy = parseBathymetry(*spec.bathymetry);
    const std::vector<ObjectSpec> objects = spec.objects ? parseObjects(*spec.objects) : std::vector<ObjectSpec>{};
    std::optional<TextureClassesSpec> classesSpec;
    if (spec.textureClasses) classesSpec = parseTextureClasses(*spec.textureClasses);
    out.seconds.parse = since(t);

    std::optional<bathymetry::GeoFrame> frame;
    if (spec.scene.origin) {
        const auto& o = *spec.scene.origin;
        frame = bathy.utmFrame ? bathymetry::GeoFrame::utm(o.latitude, o.longitude, o.altitude)
                               : bathymetry::GeoFrame::localCartesian(o.latitude, o.longitude, o.altitude);
        ir.metadata["geo_frame"] = frame->describe();
    }

    std::set<std::string> known;
    for (const auto& m : ir.materials) known.insert(m.name);
    // Dielectric materials of the materials section: each names the medium inside the objects that
    // use it (scene_file.cpp made both).
    std::set<std::string> dielectrics;
    for (const auto& m : spec.materials)
        if (m.type == "dielectric") dielectrics.insert(m.name);

    // ---- texture classes (terrain materials) ----
    t = Clock::now();
    std::vector<std::string> terrainMaterials;
    std::function<uint16_t(double, double)> materialAt;
    if (classesSpec) {
        out.textures = buildTextureClasses(*classesSpec, domain);
        for (const auto& m : out.textures->materials()) {
            if (known.count(m.name))
                throw InputError(classesSpec->loc, fmt::format("texture class '{}' has the name of a material already "
                                                               "defined under 'materials'",
                                                               m.name));
            ir.materials.push_back(m);
            known.insert(m.name);
        }
        // The ground's faces carry one classified material: the renderer looks the class up where
        // each ray lands, so class boundaries are as sharp as the map whatever the terrain grid.
        const ir::Material classified = out.textures->classifiedMaterial("texture-classes");
        if (known.count(classified.name))
            throw InputError(classesSpec->loc, fmt::format("'{}' is the name of the material Littoral makes for the "
                                                           "class map; rename the material or class that uses it",
                                                           classified.name));
        ir.materials.push_back(classified);
        known.insert(classified.name);
        terrainMaterials = {classified.name};
        if (!bathy.material.empty())
            throw InputError(bathy.loc, "bathymetry.material is not used when texture_classes assigns the ground "
                                        "materials; remove it");
    } else {
        if (bathy.material.empty())
            throw InputError(bathy.loc, "bathymetry: name the ground material with 'material' (one of 'materials') or "
                                        "add a texture_classes section");
        if (!known.count(bathy.material))
            throw InputError(bathy.loc, fmt::format("bathymetry.material '{}' is not defined under 'materials'",
                                                    bathy.material));
        if (dielectrics.count(bathy.material))
            throw InputError(bathy.loc, fmt::format("bathymetry.material '{}' is a dielectric; the ground must be "
                                                    "opaque (dielectrics are for objects)",
                                                    bathy.material));
        terrainMaterials.push_back(bathy.material);
    }
    out.seconds.textures = since(t);

    // ---- terrain ----
    t = Clock::now();
    const double margin = 3 * bathy.spacing + 1.0;
    const bathymetry::Extent grown{domain.x0 - margin, domain.y0 - margin, domain.x1 + margin, domain.y1 + margin};
    std::unique_ptr<bathymetry::Terrain> terrain = makeTerrain(bathy, grown, frame ? &*frame : nullptr);
    const bathymetry::Extent tex = terrain->extent();
    const bathymetry::Terrain* tp = terrain.get();
    // Outside its extent a terrain is clamped to the nearest point of the extent (rasters do this
    // themselves; a TIN would otherwise refuse the margin the booleans need around the domain).
    auto elevation = [tp, tex](double x, double y) {
        return tp->elevation(std::clamp(x, tex.x0, tex.x1), std::clamp(y, tex.y0, tex.y1));
    };
    ir.metadata["terrain"] = terrain->describe();
    out.seconds.terrain = since(t);

    // ---- objects ----
    t = Clock::now();
    std::vector<PlacedObject> placed;
    std::map<size_t, TriMesh> wholeSolids;  // transparent objects in water: the closed solid
    std::vector<std::string> objectMedium;  // per object: its dielectric's medium, or "" (opaque)
    for (const auto& o : objects) {
        std::string medium;
        for (const auto& m : o.materials) {
            if (!known.count(m))
                throw InputError(o.loc, fmt::format("object '{}': material '{}' is not defined under 'materials' or "
                                                    "texture_classes",
                                                    o.name, m));
            if (!dielectrics.count(m) || m == medium) continue;
            // A transparent object is filled with its dielectric: one per object.
            if (!medium.empty())
                throw InputError(o.loc, fmt::format("object '{}' uses two dielectrics, '{}' and '{}'; an object is "
                                                    "filled with one medium (split it into two objects)",
                                                    o.name, medium, m));
            medium = m;
        }
        objectMedium.push_back(medium);
        placed.push_back(loadObject(o, frame ? &*frame : nullptr, spec.waterLevel));
        placed.back().solid.keepDryPart = !medium.empty();
    }
    {
        std::vector<const TriMesh*> meshes;
        for (const auto& p : placed) meshes.push_back(&p.solid.mesh);
        checkObjectPlacement(objects, meshes, domain);
    }
    out.seconds.objects = since(t);

    // ---- water surface ----
    t = Clock::now();
    nlohmann::json validity;
    validity["scene"] = spec.file.filename().string();
    TriMesh land;
    bool valid = true;
    if (spec.hasWater) {
        surfaces::WaveParams wp;
        ir::Material interface = interfaceMaterial();
        if (spec.waterSurface) {
            wp = parseWaterSurface(*spec.waterSurface);
            checkSurfaceCoverage(wp, domain, spec.waterSurface->loc());
            if (auto rough = parseSurfaceRoughness(*spec.waterSurface, wp, interface.name)) interface = *rough;
        } else {
            wp = defaultWaterSurface(domain);
        }
        if (opt.surfaceTriangles) wp.triangles = *opt.surfaceTriangles;
        const surfaces::WaveSurface ws = surfaces::generateWaveSurface(wp);
        TriMesh surface = ws.mesh;
        for (auto& p : surface.positions) p.z += spec.waterLevel;
        ir.metadata["water.surface"] = ws.description;
        ir.metadata["water.surface.rms_height_m"] = fmt::format("{:.6g}", ws.actual.rmsHeight);
        out.seconds.surface = since(t);

        WaterVolumeInput in;
        in.domain = domain;
        in.surface = std::move(surface);
        in.elevation = elevation;
        in.terrainSpacing = bathy.spacing;
        in.terrainMaterials = terrainMaterials;
        in.terrainMaterialAt = materialAt;
        in.interfaceMaterial = interface.name;
        in.wallMaterial = wallMaterial(spec.periodic).name;
        for (const auto& p : placed) in.solids.push_back(p.solid);
        WaterVolumeResult wv = buildWaterVolume(in);
        out.seconds.waterPrism = wv.secondsPrism;
        out.seconds.waterTerrain = wv.secondsTerrain;
        out.seconds.waterBoolean = wv.secondsBoolean;
        out.seconds.waterSolids = wv.secondsSolids;
        for (const auto& m : {interface, wallMaterial(spec.periodic)})
            if (!known.count(m.name)) {
                ir.materials.push_back(m);
                known.insert(m.name);
            }

        t = Clock::now();
        CheckOptions co;
        co.testSelfIntersections = opt.checkSelfIntersections;
        const ValidityReport wr = checkMesh(wv.water, co);
        validity["water"] = wr.toJson();
        validity["water"]["materials"] = wv.waterMaterials;
        validity["water"]["faces_by_role"] = {{"interface", wv.interfaceFaces}, {"seabed", wv.seabedFaces},
                                              {"wall", wv.wallFaces}, {"object", wv.objectFaces}};
        validity["water"]["volume_before_objects_m3"] = wv.waterVolumeBeforeSolids;
        validity["water"]["prism_volume_m3"] = wv.prismVolume;
        valid = valid && wr.valid();
        out.seconds.validity += since(t);

        // The water's faces against a transparent object are the interface between the water and
        // the object's medium: they go to a mesh of their own, "water-<dielectric>", whose outside is
        // that medium (the object mesh keeps only its dry faces, below).
        std::map<std::string, TriMesh> contact;
        {
            TriMesh rest;
            rest.positions = wv.water.positions;
            std::vector<std::string> restMaterials;
            std::map<uint16_t, uint16_t> restSlot;
            for (size_t f = 0; f < wv.water.triangles.size(); ++f) {
                const uint16_t slot = wv.water.faceMaterial[f];
                const std::string& name = wv.waterMaterials[slot];
                if (dielectrics.count(name)) {
                    TriMesh& c = contact[name];
                    if (c.positions.empty()) c.positions = wv.water.positions;
                    c.triangles.push_back(wv.water.triangles[f]);
                    c.faceMaterial.push_back(0);
                    continue;
                }
                auto [it, inserted] = restSlot.try_emplace(slot, static_cast<uint16_t>(restMaterials.size()));
                if (inserted) restMaterials.push_back(name);
                rest.triangles.push_back(wv.water.triangles[f]);
                rest.faceMaterial.push_back(it->second);
            }
            if (!contact.empty()) {
                compactVertices(rest);
                for (auto& [name, c] : contact) compactVertices(c);
                wv.water = std::move(rest);
                wv.waterMaterials = std::move(restMaterials);
            }
        }

        ir::Mesh wm;
        wm.name = "water";
        wm.file = "meshes/water.ply";
        wm.materials = wv.waterMaterials;
        wm.inside = "water";
        wm.outside = "";
        wm.closed = wr.valid();  // the water body was checked whole, before its contact faces moved
        wm.data = std::move(wv.water);
        ir.meshes.push_back(std::move(wm));
        for (auto& [name, c] : contact) {
            ir::Mesh cm;
            cm.name = "water-" + name;
            cm.file = "meshes/water-" + name + ".ply";
            cm.materials = {name};
            cm.inside = "water";
            cm.outside = name;
            cm.closed = false;
            cm.data = std::move(c);
            ir.meshes.push_back(std::move(cm));
        }
        if (!wv.dryParts.empty())
            for (size_t i = 0; i < placed.size(); ++i)
                if (placed[i].solid.keepDryPart) {
                    wholeSolids[i] = placed[i].solid.mesh;  // for the geometric checks below
                    placed[i].solid.mesh = std::move(wv.dryParts[i]);
                }
        for (size_t i = 0; i < placed.size(); ++i) {
            validity["objects"][placed[i].solid.name]["displaced_water_m3"] = wv.displaced[i];
        }
        land = std::move(wv.land);
    } else {
        // No water: the whole terrain over the domain is land.
        land = bathymetry::terrainMesh(*terrain, domain, bathy.spacing);
        land.faceMaterial.assign(land.triangles.size(), 0);
        if (materialAt)
            for (size_t f = 0; f < land.triangles.size(); ++f) {
                const auto& tri = land.triangles[f];
                const Point3 c = (land.positions[tri[0]] + land.positions[tri[1]] + land.positions[tri[2]]) / 3.0;
                land.faceMaterial[f] = materialAt(c.x, c.y);
            }
        out.seconds.surface = since(t);
    }

    // ---- land and objects into the IR ----
    t = Clock::now();
    if (!land.triangles.empty()) {
        const ValidityReport lr = checkMesh(land, CheckOptions{false});
        validity["land"] = meshSummary(land);
        validity["land"]["manifold"] = lr.manifold;
        validity["land"]["boundary_edges"] = lr.boundaryEdges.size();
        validity["land"]["components"] = lr.components;
        ir::Mesh lm;
        lm.name = "land";
        lm.file = "meshes/land.ply";
        lm.materials = terrainMaterials;
        lm.closed = false;
        lm.data = std::move(land);
        ir.meshes.push_back(std::move(lm));
    }
    for (size_t i = 0; i < placed.size(); ++i) {
        auto& p = placed[i];
        auto& j = validity["objects"][p.solid.name];
        const auto disp = j.contains("displaced_water_m3") ? j["displaced_water_m3"] : nlohmann::json();
        j = p.validity.toJson();
        if (!disp.is_null()) j["displaced_water_m3"] = disp;
        valid = valid && p.validity.valid();
        ir::Mesh om;
        om.name = p.solid.name;
        om.file = "meshes/object_" + p.solid.name + ".ply";
        om.materials = p.solid.materials;
        // A transparent object is filled with its dielectric's medium; in water only its dry faces
        // remain here (its wet ones are the water's "water-<dielectric>" mesh).
        om.inside = objectMedium[i];
        om.closed = objectMedium[i].empty() || !spec.hasWater;
        om.data = std::move(p.solid.mesh);
        ir.meshes.push_back(std::move(om));
    }
    out.seconds.validity += since(t);
    if (out.textures) {
        auto cov = out.textures->coverage();
        for (size_t k = 0; k < out.textures->classes.size(); ++k) {
            const auto& s = out.textures->stats[k];
            validity["texture_classes"][out.textures->classes[k].name] = {
                {"coverage", cov[k]},         {"pixels", s.pixels},       {"mean_before", s.meanBefore},
                {"std_before", s.stdBefore},  {"mean_after", s.meanAfter}, {"std_after", s.stdAfter},
                {"clamped_to_zero", s.clampedToZero}};
        }
    }
    validity["valid"] = valid;
    validity["seconds"] = out.seconds.toJson();
    out.validity = std::move(validity);
    out.valid = valid;
    {
        // Sensors and probes against the ground, the objects (now in the IR) and the whole scene.
        std::vector<const TriMesh*> meshes;
        for (size_t i = 0; i < objects.size(); ++i)
            if (wholeSolids.count(i)) meshes.push_back(&wholeSolids.at(i));
            else if (const ir::Mesh* m = ir.findMesh(objects[i].name)) meshes.push_back(&m->data);
        if (meshes.size() == objects.size()) checkSensorsAndProbes(spec, ir, objects, meshes, elevation, domain);
    }
    ir.metadata["generator"] = "littoral build";
    return out;
}

void writeAssembledScene(const AssembledScene& scene, const std::filesystem::path& dir) {
    createOutputFolder(dir);
    if (scene.textures) scene.textures->writeTextures(dir);
    ir::writeIR(scene.ir, dir);
    writeTextFileAtomic(dir / "validity.json", validityText(scene.validity));
}

AssembledScene buildScene(const std::filesystem::path& sceneYaml, const std::filesystem::path& outDir,
                          const AssembleOptions& options) {
    auto t = Clock::now();
    const SceneSpec spec = loadSceneFile(sceneYaml);
    const double parse = since(t);
    AssembledScene s = assembleScene(spec, options);
    s.seconds.parse += parse;
    if (!s.valid) {
        if (!outDir.empty()) {
            createOutputFolder(outDir);
            writeTextFileAtomic(outDir / "validity.json", validityText(s.validity));
            publishStagedOutputs();  // the reasons stay readable although the command fails
        }
        std::string msg = "the assembled scene failed its validity checks";
        if (s.validity.contains("water") && !s.validity["water"]["valid"].get<bool>())
            for (const auto& r : s.validity["water"]["reasons"]) msg += "\n  water: " + r.get<std::string>();
        msg += outDir.empty() ? "" : "\n  details: " + (outDir / "validity.json").string();
        throw InputError(SourceLoc{sceneYaml.string()}, msg);
    }
    if (!outDir.empty()) {
        t = Clock::now();
        s.seconds.write = 0;
        writeAssembledScene(s, outDir);
        s.seconds.write = since(t);
        // Record the write time too (validity.json is rewritten with the final figures).
        s.validity["seconds"] = s.seconds.toJson();
        writeTextFileAtomic(outDir / "validity.json", validityText(s.validity));
    }
    return s;
}

}  // namespace littoral::scenegen
