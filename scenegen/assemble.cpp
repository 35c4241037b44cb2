#include "scenegen/assemble.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>

#include <fmt/format.h>

#include "bathymetry/geo_frame.h"
#include "bathymetry/terrain.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/suggest.h"
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

// A raster's options: the domain it must cover (the samples beyond are dropped) and, for `origin:
// scene`, the scene's frame, into which the raster is placed by its coordinate system.
bathymetry::RasterOptions rasterOptions(const BathymetrySpec& b, const bathymetry::GeoFrame* frame,
                                        const bathymetry::Extent& domain) {
    bathymetry::RasterOptions o = b.raster;
    o.clip = domain;
    if (!b.rasterOriginFromScene) return o;
    if (!frame)
        throw InputError(b.rasterOriginLoc, "bathymetry.origin: 'scene' takes the raster's offset from scene.origin, "
                                            "which this scene does not give (latitude, longitude)");
    o.frame = frame;
    return o;
}

// A raster must cover the domain: outside its cells it repeats its edge values, so a raster that
// misses the domain (a georeferenced one without its origin, say) would silently give a flat seabed.
void checkRasterCoversDomain(const BathymetrySpec& b, const bathymetry::Terrain& t, const bathymetry::Extent& d) {
    const bathymetry::Extent e = t.footprint();
    const double tol = 1e-9 * std::max({1.0, d.width(), d.height(), std::abs(e.x0), std::abs(e.y0)});
    if (e.x0 <= d.x0 + tol && e.x1 >= d.x1 - tol && e.y0 <= d.y0 + tol && e.y1 >= d.y1 - tol) return;
    const std::string both = fmt::format("the raster {} covers x [{:.10g}, {:.10g}], y [{:.10g}, {:.10g}] m in the "
                                         "local frame (its cells), and the scene domain is x [{:.10g}, {:.10g}], "
                                         "y [{:.10g}, {:.10g}] m",
                                         b.file.filename().string(), e.x0, e.x1, e.y0, e.y1, d.x0, d.x1, d.y0, d.y1);
    const double gapX = std::max({0.0, e.x0 - d.x1, d.x0 - e.x1}), gapY = std::max({0.0, e.y0 - d.y1, d.y0 - e.y1});
    const double gap = std::hypot(gapX, gapY);
    std::string msg;
    if (gapX > 0 || gapY > 0) {
        msg = fmt::format("bathymetry.{}: {}: the raster lies {} from the domain, entirely outside it",
                          b.rasterPlacementKey, both,
                          gap >= 1000 ? fmt::format("{:.4g} km", gap / 1000) : fmt::format("{:.4g} m", gap));
        msg += b.raster.extent ? "; give an extent that contains the domain"
                               : "; a georeferenced raster needs the projected coordinates of the local origin: "
                                 "origin: scene (reprojected from its coordinate system through scene.origin) or "
                                 "origin_x_m and origin_y_m";
    } else {
        msg = fmt::format("bathymetry.{}: {}, which it covers only in part; beyond the raster the seabed would repeat "
                          "the raster's edge values: use a raster that covers the domain, or a smaller scene.domain",
                          b.rasterPlacementKey, both);
    }
    throw InputError(b.rasterPlacementLoc, msg);
}

std::unique_ptr<bathymetry::Terrain> makeTerrain(const BathymetrySpec& b, const bathymetry::Extent& extent,
                                                 const bathymetry::GeoFrame* frame) {
    try {
        switch (b.kind) {
            case BathymetrySpec::Kind::PlanarSlope: return bathymetry::makePlanarSlope(extent, b.planar);
            case BathymetrySpec::Kind::Dean: return bathymetry::makeDeanProfile(extent, b.dean);
            case BathymetrySpec::Kind::BarTrough: return bathymetry::makeBarTrough(extent, b.barTrough);
            case BathymetrySpec::Kind::Raster: return bathymetry::loadRaster(b.file, rasterOptions(b, frame, extent));
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
    m.name = kInterfaceMaterialName;
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

// water.surface omitted: a flat surface over the domain (docs/scene-format.md), on flatSpacing's
// coarse grid, kept whole.
surfaces::WaveParams defaultWaterSurface(const bathymetry::Extent& d) {
    surfaces::WaveParams p;
    p.model = surfaces::WaveModel::Flat;
    p.windSpeed = 0.0;
    p.sizeX = d.width();
    p.sizeY = d.height();
    p.centreX = 0.5 * (d.x0 + d.x1);
    p.centreY = 0.5 * (d.y0 + d.y1);
    p.spacing = flatSpacing(p);
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

// The geometry sections of the scene file (applyCommonSections parses the others).
struct GeometrySpecs {
    BathymetrySpec bathy;
    std::vector<ObjectSpec> objects;
    std::optional<TextureClassesSpec> classes;
};

GeometrySpecs parseGeometrySections(const SceneSpec& spec) {
    if (!spec.bathymetry)
        throw InputError(SourceLoc{spec.file.string()}, "the scene has no 'bathymetry' section; a coastal scene needs "
                                                        "a seabed (e.g. bathymetry: {type: planar_slope, ...})");
    GeometrySpecs g{parseBathymetry(*spec.bathymetry),
                    spec.objects ? parseObjects(*spec.objects) : std::vector<ObjectSpec>{}, std::nullopt};
    if (spec.textureClasses) g.classes = parseTextureClasses(*spec.textureClasses);
    return g;
}

// The names of the IR's materials, and those of the materials section's dielectrics: each names
// the medium inside the objects that use it (scene_file.cpp made both).
struct MaterialNames {
    std::set<std::string> known;
    std::set<std::string> dielectrics;

    void add(const ir::Material& m, ir::SceneIR* ir) {
        ir->materials.push_back(m);
        known.insert(m.name);
    }
    // "; did you mean 'sand'?" for a misspelt name, "" when nothing is close.
    std::string suggest(const std::string& name) const {
        const std::string near = closestMatch(name, std::vector<std::string>(known.begin(), known.end()));
        return near.empty() ? "" : fmt::format("; did you mean '{}'?", near);
    }
};

MaterialNames materialNames(const SceneSpec& spec, const ir::SceneIR& ir) {
    MaterialNames names;
    for (const auto& m : ir.materials) names.known.insert(m.name);
    for (const auto& m : spec.materials)
        if (m.type == "dielectric") names.dielectrics.insert(m.name);
    return names;
}

// The dielectric an object is filled with, or "" for an opaque object. Every material it names
// must exist, and a transparent object is filled with one dielectric only.
std::string objectMedium(const ObjectSpec& o, const MaterialNames& names) {
    std::string medium;
    for (const auto& m : o.materials) {
        if (!names.known.count(m))
            throw InputError(o.loc, fmt::format("object '{}': material '{}' is not defined under 'materials' or "
                                                "texture_classes{}",
                                                o.name, m, names.suggest(m)));
        if (!names.dielectrics.count(m) || m == medium) continue;
        if (!medium.empty())
            throw InputError(o.loc, fmt::format("object '{}' uses two dielectrics, '{}' and '{}'; an object is "
                                                "filled with one medium (split it into two objects)",
                                                o.name, medium, m));
        medium = m;
    }
    return medium;
}

// The water's faces against a transparent object are the interface between the water and the
// object's medium: they move from `wv.water` to a mesh of their own per dielectric, returned by
// the dielectric's name (the object mesh keeps only its dry faces).
std::map<std::string, TriMesh> splitContactFaces(WaterVolumeResult& wv, const std::set<std::string>& dielectrics) {
    std::map<std::string, TriMesh> contact;
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
    return contact;
}

// The IR meshes of the water: "water" (closed when the whole body passed its checks) and one
// "water-<dielectric>" per transparent object's medium it touches, whose outside is that medium.
void addWaterMeshes(TriMesh water, const std::vector<std::string>& materials, std::map<std::string, TriMesh> contact,
                    bool closed, ir::SceneIR* ir) {
    ir::Mesh wm;
    wm.name = "water";
    wm.file = "meshes/water.ply";
    wm.materials = materials;
    wm.inside = "water";
    wm.outside = "";
    wm.closed = closed;
    wm.data = std::move(water);
    ir->meshes.push_back(std::move(wm));
    for (auto& [name, c] : contact) {
        ir::Mesh cm;
        cm.name = "water-" + name;
        cm.file = "meshes/water-" + name + ".ply";
        cm.materials = {name};
        cm.inside = "water";
        cm.outside = name;
        cm.closed = false;
        cm.data = std::move(c);
        ir->meshes.push_back(std::move(cm));
    }
}

// One scene being assembled: the stages of assembleScene, in order, each using what the stages
// before it made.
class Assembly {
public:
    Assembly(const SceneSpec& spec, const AssembleOptions& opt)
        : spec_(spec), opt_(opt), domain_{spec.scene.x0, spec.scene.y0, spec.scene.x1, spec.scene.y1} {}

    AssembledScene run();

private:
    void addGeoFrame();
    std::vector<std::string> terrainMaterials();
    std::string addTextureClassMaterials();
    void buildTerrain();
    void placeObjects();
    TriMesh waterSurface(ir::Material* interface);
    void buildWater();
    bool checkWater(const WaterVolumeResult& wv);
    void keepDryParts(std::vector<TriMesh>& dryParts);
    void buildLandWithoutWater();
    void addLandMesh();
    void addObjectMeshes();
    void addTextureClassStatistics();
    void checkSensors() const;

    const SceneSpec& spec_;
    const AssembleOptions& opt_;
    const bathymetry::Extent domain_;
    AssembledScene out_;
    ir::SceneIR& ir_ = out_.ir;
    GeometrySpecs geometry_;
    std::optional<bathymetry::GeoFrame> frame_;
    MaterialNames names_;
    std::vector<std::string> terrainMaterials_;
    std::unique_ptr<bathymetry::Terrain> terrain_;
    std::function<double(double, double)> elevation_;
    std::vector<PlacedObject> placed_;
    std::vector<std::string> objectMedium_;  // per object: its dielectric's medium, or "" (opaque)
    std::map<size_t, TriMesh> wholeSolids_;  // transparent objects in water: the closed solid
    nlohmann::json validity_;
    TriMesh land_;
    bool valid_ = true;
};

AssembledScene Assembly::run() {
    applyCommonSections(spec_, &ir_);
    checkRenderMemory(spec_, ir_);  // before any geometry: refuse an impossible render at once

    auto t = Clock::now();
    geometry_ = parseGeometrySections(spec_);
    out_.seconds.parse = since(t);
    addGeoFrame();
    names_ = materialNames(spec_, ir_);

    t = Clock::now();
    terrainMaterials_ = terrainMaterials();
    out_.seconds.textures = since(t);

    t = Clock::now();
    buildTerrain();
    out_.seconds.terrain = since(t);

    t = Clock::now();
    placeObjects();
    out_.seconds.objects = since(t);

    validity_["scene"] = spec_.file.filename().string();
    if (spec_.hasWater) buildWater();
    else buildLandWithoutWater();

    t = Clock::now();
    addLandMesh();
    addObjectMeshes();
    out_.seconds.validity += since(t);
    addTextureClassStatistics();
    validity_["valid"] = valid_;
    validity_["seconds"] = out_.seconds.toJson();
    out_.validity = std::move(validity_);
    out_.valid = valid_;
    checkSensors();
    ir_.metadata["generator"] = "littoral build";
    return std::move(out_);
}

void Assembly::addGeoFrame() {
    if (!spec_.scene.origin) return;
    const auto& o = *spec_.scene.origin;
    frame_ = geometry_.bathy.utmFrame ? bathymetry::GeoFrame::utm(o.latitude, o.longitude, o.altitude)
                                      : bathymetry::GeoFrame::localCartesian(o.latitude, o.longitude, o.altitude);
    ir_.metadata["geo_frame"] = frame_->describe();
    const bool utm = frame_->kind() == bathymetry::GeoFrame::Kind::Utm;
    ir_.geo = ir::GeoReference{utm ? "utm" : "local-cartesian", o.latitude, o.longitude, o.altitude, utm ? frame_->zone() : 0};
}

// The ground's material slots: the classified material of texture_classes, or bathymetry.material.
std::vector<std::string> Assembly::terrainMaterials() {
    const BathymetrySpec& bathy = geometry_.bathy;
    if (geometry_.classes) {
        const std::string classified = addTextureClassMaterials();
        if (!bathy.material.empty())
            throw InputError(bathy.loc, "bathymetry.material is not used when texture_classes assigns the ground "
                                        "materials; remove it");
        return {classified};
    }
    if (bathy.material.empty())
        throw InputError(bathy.loc, "bathymetry: name the ground material with 'material' (one of 'materials') or "
                                    "add a texture_classes section");
    if (!names_.known.count(bathy.material))
        throw InputError(bathy.loc, fmt::format("bathymetry.material '{}' is not defined under 'materials'{}",
                                                bathy.material, names_.suggest(bathy.material)));
    if (names_.dielectrics.count(bathy.material))
        throw InputError(bathy.loc, fmt::format("bathymetry.material '{}' is a dielectric; the ground must be "
                                                "opaque (dielectrics are for objects)",
                                                bathy.material));
    return {bathy.material};
}

// Builds the texture classes, adds a material per class and the classified material of the
// ground's faces, and returns the latter's name.
std::string Assembly::addTextureClassMaterials() {
    const TextureClassesSpec& classes = *geometry_.classes;
    out_.textures = buildTextureClasses(classes, domain_);
    for (const auto& m : out_.textures->materials()) {
        if (names_.known.count(m.name))
            throw InputError(classes.loc, fmt::format("texture class '{}' has the name of a material already "
                                                      "defined under 'materials'",
                                                      m.name));
        names_.add(m, &ir_);
    }
    // The ground's faces carry one classified material: the renderer looks the class up where
    // each ray lands, so class boundaries are as sharp as the map whatever the terrain grid.
    const ir::Material classified = out_.textures->classifiedMaterial("texture-classes");
    if (names_.known.count(classified.name))
        throw InputError(classes.loc, fmt::format("'{}' is the name of the material Littoral makes for the "
                                                  "class map; rename the material or class that uses it",
                                                  classified.name));
    names_.add(classified, &ir_);
    return classified.name;
}

void Assembly::buildTerrain() {
    const BathymetrySpec& bathy = geometry_.bathy;
    const double margin = 3 * bathy.spacing + 1.0;
    const bathymetry::Extent grown{domain_.x0 - margin, domain_.y0 - margin, domain_.x1 + margin,
                                   domain_.y1 + margin};
    terrain_ = makeTerrain(bathy, grown, frame_ ? &*frame_ : nullptr);
    if (bathy.kind == BathymetrySpec::Kind::Raster) checkRasterCoversDomain(bathy, *terrain_, domain_);
    const bathymetry::Extent tex = terrain_->extent();
    const bathymetry::Terrain* tp = terrain_.get();
    // Outside its extent a terrain is clamped to the nearest point of the extent (rasters do this
    // themselves; a TIN would otherwise refuse the margin the booleans need around the domain).
    elevation_ = [tp, tex](double x, double y) {
        return tp->elevation(std::clamp(x, tex.x0, tex.x1), std::clamp(y, tex.y0, tex.y1));
    };
    ir_.metadata["terrain"] = terrain_->describe();
}

void Assembly::placeObjects() {
    for (const auto& o : geometry_.objects) {
        const std::string medium = objectMedium(o, names_);
        objectMedium_.push_back(medium);
        placed_.push_back(loadObject(o, frame_ ? &*frame_ : nullptr, spec_.waterLevel));
        placed_.back().solid.keepDryPart = !medium.empty();
    }
    std::vector<const TriMesh*> meshes;
    for (const auto& p : placed_) meshes.push_back(&p.solid.mesh);
    checkObjectPlacement(geometry_.objects, meshes, domain_);
}

// The air-water interface at the water level, from water.surface (flat without it). With
// water.surface.roughness, `interface` becomes the rough interface.
TriMesh Assembly::waterSurface(ir::Material* interface) {
    surfaces::WaveParams wp;
    if (spec_.waterSurface) {
        wp = parseWaterSurface(*spec_.waterSurface);
        checkSurfaceCoverage(wp, domain_, spec_.waterSurface->loc());
        if (auto rough = parseSurfaceRoughness(*spec_.waterSurface, wp, interface->name)) *interface = *rough;
    } else {
        wp = defaultWaterSurface(domain_);
    }
    if (opt_.surfaceTriangles) wp.triangles = *opt_.surfaceTriangles;
    const surfaces::WaveSurface ws = surfaces::generateWaveSurface(wp);
    TriMesh surface = ws.mesh;
    for (auto& p : surface.positions) p.z += spec_.waterLevel;
    ir_.metadata["water.surface"] = ws.description;
    ir_.metadata["water.surface.rms_height_m"] = fmt::format("{:.6g}", ws.actual.rmsHeight);
    return surface;
}

// The closed water body with the objects subtracted, checked, into the IR; the land is what of
// the terrain lies above the water.
void Assembly::buildWater() {
    auto t = Clock::now();
    ir::Material interface = interfaceMaterial();
    WaterVolumeInput in;
    in.surface = waterSurface(&interface);
    out_.seconds.surface = since(t);

    in.domain = domain_;
    in.elevation = elevation_;
    in.terrainSpacing = geometry_.bathy.spacing;
    in.terrainMaterials = terrainMaterials_;
    in.interfaceMaterial = interface.name;
    in.wallMaterial = wallMaterial(spec_.periodic).name;
    for (const auto& p : placed_) in.solids.push_back(p.solid);
    WaterVolumeResult wv = buildWaterVolume(in);
    out_.seconds.waterPrism = wv.secondsPrism;
    out_.seconds.waterTerrain = wv.secondsTerrain;
    out_.seconds.waterBoolean = wv.secondsBoolean;
    out_.seconds.waterSolids = wv.secondsSolids;
    for (const auto& m : {interface, wallMaterial(spec_.periodic)})
        if (!names_.known.count(m.name)) names_.add(m, &ir_);

    t = Clock::now();
    const bool closed = checkWater(wv);  // the whole body, before its contact faces move
    out_.seconds.validity += since(t);

    std::map<std::string, TriMesh> contact = splitContactFaces(wv, names_.dielectrics);
    addWaterMeshes(std::move(wv.water), wv.waterMaterials, std::move(contact), closed, &ir_);
    keepDryParts(wv.dryParts);
    for (size_t i = 0; i < placed_.size(); ++i) {
        validity_["objects"][placed_[i].solid.name]["displaced_water_m3"] = wv.displaced[i];
    }
    land_ = std::move(wv.land);
}

// Checks the water body and records the report in validity.json; true if it passed.
bool Assembly::checkWater(const WaterVolumeResult& wv) {
    CheckOptions co;
    co.testSelfIntersections = opt_.checkSelfIntersections;
    const ValidityReport wr = checkMesh(wv.water, co);
    validity_["water"] = wr.toJson();
    validity_["water"]["materials"] = wv.waterMaterials;
    validity_["water"]["faces_by_role"] = {{"interface", wv.interfaceFaces}, {"seabed", wv.seabedFaces},
                                           {"wall", wv.wallFaces}, {"object", wv.objectFaces}};
    validity_["water"]["volume_before_objects_m3"] = wv.waterVolumeBeforeSolids;
    validity_["water"]["prism_volume_m3"] = wv.prismVolume;
    valid_ = valid_ && wr.valid();
    return wr.valid();
}

// A transparent object in water keeps only its dry faces (its wet ones are the water's
// "water-<dielectric>" mesh); its whole solid stays for the geometric checks of checkSensors.
void Assembly::keepDryParts(std::vector<TriMesh>& dryParts) {
    if (dryParts.empty()) return;
    for (size_t i = 0; i < placed_.size(); ++i)
        if (placed_[i].solid.keepDryPart) {
            wholeSolids_[i] = placed_[i].solid.mesh;
            placed_[i].solid.mesh = std::move(dryParts[i]);
        }
}

// No water: the whole terrain over the domain is land.
void Assembly::buildLandWithoutWater() {
    const auto t = Clock::now();
    land_ = bathymetry::terrainMesh(*terrain_, domain_, geometry_.bathy.spacing);
    land_.faceMaterial.assign(land_.triangles.size(), 0);
    out_.seconds.surface = since(t);
}

void Assembly::addLandMesh() {
    if (land_.triangles.empty()) return;
    const ValidityReport lr = checkMesh(land_, CheckOptions{false});
    validity_["land"] = meshSummary(land_);
    validity_["land"]["manifold"] = lr.manifold;
    validity_["land"]["boundary_edges"] = lr.boundaryEdges.size();
    validity_["land"]["components"] = lr.components;
    ir::Mesh lm;
    lm.name = "land";
    lm.file = "meshes/land.ply";
    lm.materials = terrainMaterials_;
    lm.closed = false;
    lm.data = std::move(land_);
    ir_.meshes.push_back(std::move(lm));
}

void Assembly::addObjectMeshes() {
    for (size_t i = 0; i < placed_.size(); ++i) {
        auto& p = placed_[i];
        auto& j = validity_["objects"][p.solid.name];
        const auto disp = j.contains("displaced_water_m3") ? j["displaced_water_m3"] : nlohmann::json();
        j = p.validity.toJson();
        if (!disp.is_null()) j["displaced_water_m3"] = disp;
        valid_ = valid_ && p.validity.valid();
        ir::Mesh om;
        om.name = p.solid.name;
        om.file = "meshes/object_" + p.solid.name + ".ply";
        om.materials = p.solid.materials;
        // A transparent object is filled with its dielectric's medium; in water only its dry faces
        // remain here (its wet ones are the water's "water-<dielectric>" mesh).
        om.inside = objectMedium_[i];
        om.closed = objectMedium_[i].empty() || !spec_.hasWater;
        om.data = std::move(p.solid.mesh);
        ir_.meshes.push_back(std::move(om));
    }
}

void Assembly::addTextureClassStatistics() {
    if (!out_.textures) return;
    auto cov = out_.textures->coverage();
    for (size_t k = 0; k < out_.textures->classes.size(); ++k) {
        const auto& s = out_.textures->stats[k];
        validity_["texture_classes"][out_.textures->classes[k].name] = {
            {"coverage", cov[k]},         {"pixels", s.pixels},       {"mean_before", s.meanBefore},
            {"std_before", s.stdBefore},  {"mean_after", s.meanAfter}, {"std_after", s.stdAfter},
            {"clamped_to_zero", s.clampedToZero}};
    }
}

// Sensors and probes against the ground, the objects (now in the IR) and the whole scene.
void Assembly::checkSensors() const {
    const std::vector<ObjectSpec>& objects = geometry_.objects;
    std::vector<const TriMesh*> meshes;
    for (size_t i = 0; i < objects.size(); ++i)
        if (wholeSolids_.count(i)) meshes.push_back(&wholeSolids_.at(i));
        else if (const ir::Mesh* m = ir_.findMesh(objects[i].name)) meshes.push_back(&m->data);
    if (meshes.size() == objects.size()) checkSensorsAndProbes(spec_, ir_, objects, meshes, elevation_, domain_);
}

}  // namespace

nlohmann::json StageSeconds::toJson() const {
    return {{"parse", parse},           {"surface", surface},           {"terrain", terrain},
            {"textures", textures},     {"objects", objects},           {"water_prism", waterPrism},
            {"water_terrain", waterTerrain}, {"water_boolean", waterBoolean}, {"water_solids", waterSolids},
            {"validity", validity},     {"write", write},               {"total", total()}};
}

AssembledScene assembleScene(const SceneSpec& spec, const AssembleOptions& opt) { return Assembly(spec, opt).run(); }

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
    if (options.beforeWrite) options.beforeWrite(spec, s);
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
