#include "scenegen/assembly_sections.h"

#include "core/material_kinds.h"
#include "scenegen/scene_file.h"

#include <set>

#include <fmt/format.h>

#include "core/output_names.h"
#include "core/units.h"

namespace littoral::scenegen {
namespace {

bathymetry::Extent parseExtent(const YamlNode& n) {
    n.expectKeys({"x", "y"});
    const auto x = n["x"].asDoubleList(-1e7, 1e7, "m");
    const auto y = n["y"].asDoubleList(-1e7, 1e7, "m");
    if (x.size() != 2 || !(x[1] > x[0])) n["x"].fail("expected [x0, x1] with x1 > x0 (metres)");
    if (y.size() != 2 || !(y[1] > y[0])) n["y"].fail("expected [y0, y1] with y1 > y0 (metres)");
    return {x[0], y[0], x[1], y[1]};
}

void parseDean(const YamlNode& n, bathymetry::DeanProfile* d) {
    if (n.has("A") && n.has("grain_size_mm")) n["A"].fail("give either 'A' or 'grain_size_mm', not both");
    if (auto g = n.optional("grain_size_mm")) {
        try {
            d->A = bathymetry::deanScaleFromGrainSize(g->asDouble(0.05, 5.0, "mm"));
        } catch (const InputError& e) {
            g->fail(e.message());
        }
    } else {
        d->A = n.getDouble("A", d->A, 0.01, 1.0, "m^(1/3)");
    }
    d->shorelineX = n.getDouble("shoreline_x_m", d->shorelineX, -1e6, 1e6, "m");
    d->offshoreTowardPositiveX = n.getEnum("offshore", "+x", {"+x", "-x"}) == "+x";
    d->beachSlope = n.getDouble("beach_slope", d->beachSlope, 1e-4, 10, "");
    d->bermHeight = n.getDouble("berm_height_m", d->bermHeight, 0, 100, "m");
    if (n.has("max_depth_m")) d->maxDepth = n.getDouble("max_depth_m", 10, 0.01, 12000, "m");
    d->duneHeight = n.getDouble("dune_height_m", d->duneHeight, 0, 200, "m");
    d->duneOffset = n.getDouble("dune_offset_m", d->duneOffset, 0, 1e5, "m");
    d->duneWidth = n.getDouble("dune_width_m", d->duneWidth, 0.01, 1e5, "m");
}

const std::vector<std::string> kDeanKeys = {"A", "grain_size_mm", "shoreline_x_m", "offshore", "beach_slope",
                                            "berm_height_m", "max_depth_m", "dune_height_m", "dune_offset_m",
                                            "dune_width_m"};
const std::vector<std::string> kBarKeys = {"bar_crest_m", "bar_height_m", "bar_width_m", "trough_m",
                                           "trough_depth_m", "trough_width_m", "crescent_amplitude_m",
                                           "crescent_wavelength_m"};

// Where a bathymetry raster sits: its file, and `extent` (the grid placed by hand), or the file's
// georeferencing less the local origin (origin_x_m/origin_y_m, or `origin: scene`).
void parseRasterPlacement(const YamlNode& n, BathymetrySpec* b) {
    b->file = n["file"].asExistingPath();
    b->rasterPlacementKey = "file";
    b->rasterPlacementLoc = n["file"].loc();
    const bool byHand = n.has("origin_x_m") || n.has("origin_y_m");
    if (auto e = n.optional("extent")) {
        b->raster.extent = parseExtent(*e);
        b->rasterPlacementKey = "extent";
        b->rasterPlacementLoc = e->loc();
        for (const char* k : {"origin", "origin_x_m", "origin_y_m"})
            if (n.has(k))
                n[k].fail(fmt::format("'extent' places the raster in the local frame itself, so '{}' (which shifts "
                                      "the file's own georeferencing) would be ignored; remove one of them", k));
    }
    if (auto o = n.optional("origin")) {
        o->asEnum({"scene"});
        if (byHand)
            o->fail("give either 'origin: scene' or origin_x_m/origin_y_m (the projected coordinates of the local "
                    "origin), not both");
        b->rasterOriginFromScene = true;
        b->rasterOriginLoc = o->loc();
        b->rasterPlacementKey = "origin";
        b->rasterPlacementLoc = o->loc();
    } else if (byHand) {
        const char* k = n.has("origin_x_m") ? "origin_x_m" : "origin_y_m";
        b->rasterPlacementKey = k;
        b->rasterPlacementLoc = n[k].loc();
    }
    b->raster.originX = n.getDouble("origin_x_m", 0, -1e8, 1e8, "m");
    b->raster.originY = n.getDouble("origin_y_m", 0, -1e8, 1e8, "m");
}

}  // namespace

BathymetrySpec parseBathymetry(const YamlNode& n) {
    BathymetrySpec b;
    b.loc = n.loc();
    n.expectMap();
    const std::string type = n["type"].asEnum({"planar_slope", "dean", "bar_trough", "raster", "soundings"});
    std::vector<std::string> keys = {"type", "spacing_m", "material", "frame"};
    if (type == "planar_slope") {
        keys.insert(keys.end(), {"z0_m", "slope_x", "slope_y"});
    } else if (type == "dean") {
        keys.insert(keys.end(), kDeanKeys.begin(), kDeanKeys.end());
    } else if (type == "bar_trough") {
        keys.insert(keys.end(), kDeanKeys.begin(), kDeanKeys.end());
        keys.insert(keys.end(), kBarKeys.begin(), kBarKeys.end());
    } else if (type == "raster") {
        keys.insert(keys.end(),
                    {"file", "extent", "origin", "origin_x_m", "origin_y_m", "z_scale", "z_offset_m", "channel",
                     "variable"});
    } else {
        keys.insert(keys.end(), {"file", "outside_hull", "merge_distance_m", "constraint_z_m"});
    }
    n.expectKeys(keys);
    b.spacing = n.getDouble("spacing_m", 1.0, 0.05, 100.0, "m");
    b.material = n.getString("material", "");
    b.utmFrame = n.getEnum("frame", "local", {"local", "utm"}) == "utm";
    if (type == "planar_slope") {
        b.kind = BathymetrySpec::Kind::PlanarSlope;
        b.planar.z0 = n.getDouble("z0_m", 0.0, -12000, 9000, "m");
        b.planar.slopeX = n.getDouble("slope_x", 0.0, -10, 10, "(dz/dx)");
        b.planar.slopeY = n.getDouble("slope_y", 0.0, -10, 10, "(dz/dy)");
    } else if (type == "dean" || type == "bar_trough") {
        b.kind = type == "dean" ? BathymetrySpec::Kind::Dean : BathymetrySpec::Kind::BarTrough;
        parseDean(n, &b.dean);
        if (type == "bar_trough") {
            auto& p = b.barTrough;
            p.dean = b.dean;
            p.barCrestDistance = n.getDouble("bar_crest_m", p.barCrestDistance, 0.01, 1e5, "m");
            p.barHeight = n.getDouble("bar_height_m", p.barHeight, 0.001, 100, "m");
            p.barWidth = n.getDouble("bar_width_m", p.barWidth, 0.01, 1e4, "m");
            p.troughDistance = n.getDouble("trough_m", p.troughDistance, 0.01, 1e5, "m");
            p.troughDepth = n.getDouble("trough_depth_m", p.troughDepth, 0, 100, "m");
            p.troughWidth = n.getDouble("trough_width_m", p.troughWidth, 0.01, 1e4, "m");
            p.crescentAmplitude = n.getDouble("crescent_amplitude_m", p.crescentAmplitude, 0, 1e4, "m");
            p.crescentWavelength = n.getDouble("crescent_wavelength_m", p.crescentWavelength, 0.01, 1e6, "m");
            if (!(p.troughDistance < p.barCrestDistance))
                n["trough_m"].fail(fmt::format("the trough ({} m offshore) must lie landward of the bar crest ({} m)",
                                               p.troughDistance, p.barCrestDistance));
        }
    } else if (type == "raster") {
        b.kind = BathymetrySpec::Kind::Raster;
        parseRasterPlacement(n, &b);
        b.raster.zScale = n.getDouble("z_scale", 1, -1e3, 1e3, "");
        if (b.raster.zScale == 0) n["z_scale"].fail("z_scale must not be 0");
        b.raster.zOffset = n.getDouble("z_offset_m", 0, -1e4, 1e4, "m");
        b.raster.channel = static_cast<int>(n.getInt("channel", 0, 0, 64));
        b.raster.variable = n.getString("variable", "");
    } else {
        b.kind = BathymetrySpec::Kind::Soundings;
        b.file = n["file"].asExistingPath();
        b.soundings.outside = n.getEnum("outside_hull", "error", {"error", "nearest"}) == "nearest"
                                  ? bathymetry::OutsideHull::NearestHullPoint
                                  : bathymetry::OutsideHull::Error;
        b.soundings.mergeDistance = n.getDouble("merge_distance_m", 1e-3, 0, 100, "m");
        b.soundings.constraintZ = n.getDouble("constraint_z_m", 0, -1e4, 1e4, "m");
    }
    return b;
}

std::vector<ObjectSpec> parseObjects(const YamlNode& n) {
    std::vector<ObjectSpec> out;
    std::set<std::string> names;
    for (const auto& o : n.items()) {
        o.expectKeys({"name", "mesh", "materials", "position_m", "latlon_deg", "heading_deg", "draft_m", "z_m", "scale"});
        ObjectSpec s;
        s.loc = o.loc();
        // The name becomes a file name (meshes/object_<name>.ply) and an IR mesh name beside "water"
        // and "land".
        s.name = o["name"].asOutputName("object");
        if (s.name == "water" || s.name == "land")
            o["name"].fail(fmt::format("'{}' is the name of a mesh Littoral builds itself; choose another", s.name));
        if (!names.insert(s.name).second) o["name"].fail(fmt::format("duplicate object name '{}'", s.name));
        s.mesh = o["mesh"].asExistingPath();
        const auto mats = o["materials"];
        if (mats.isScalar()) s.materials.push_back(mats.asString());
        else
            for (const auto& m : mats.items()) s.materials.push_back(m.asString());
        if (s.materials.empty()) mats.fail("list at least one material (face slot 0)");
        if (o.has("position_m") == o.has("latlon_deg"))
            o.fail("give exactly one of 'position_m' ([x, y] metres) and 'latlon_deg' ([latitude, longitude])");
        if (auto p = o.optional("position_m")) {
            const auto v = p->asDoubleList(-1e7, 1e7, "m");
            if (v.size() != 2) p->fail("expected [x, y] in metres");
            s.positionLocal = Vec2{v[0], v[1]};
        }
        if (auto p = o.optional("latlon_deg")) {
            if (p->size() != 2) p->fail("expected [latitude, longitude] in degrees");
            s.latLonDeg = std::array<double, 2>{p->at(0).asDouble(-90, 90, "degrees"), p->at(1).asDouble(-180, 180, "degrees")};
        }
        s.heading = deg2rad(o.getDouble("heading_deg", 0.0, -360, 360, "degrees clockwise from north"));
        if (o.has("draft_m") == o.has("z_m"))
            o.fail("give exactly one of 'draft_m' (depth of the lowest point below the water level) and 'z_m' "
                   "(elevation of the mesh origin)");
        if (o.has("draft_m")) s.draft = o.getDouble("draft_m", 0, -1e3, 1e4, "m");
        if (o.has("z_m")) s.z = o.getDouble("z_m", 0, -12000, 9000, "m");
        s.scale = o.getDouble("scale", 1.0, 1e-6, 1e6, "");
        out.push_back(std::move(s));
    }
    return out;
}

TextureClassesSpec parseTextureClasses(const YamlNode& n) {
    TextureClassesSpec t;
    t.loc = n.loc();
    n.expectKeys({"map", "extent", "classes"});
    t.map = n["map"].asExistingPath();
    if (auto e = n.optional("extent")) {
        t.extent = parseExtent(*e);
        t.extentLoc = e->loc();
    }
    std::set<int> indices;
    std::set<std::string> names;
    for (const auto& c : n["classes"].items()) {
        c.expectKeys({"index", "name", "reflectance", "texture", "mean", "stddev", "solver"});
        TextureClassSpec s;
        s.loc = c.loc();
        s.index = static_cast<int>(c["index"].asInt(0, 65535));
        if (!indices.insert(s.index).second) c["index"].fail(fmt::format("class index {} is defined twice", s.index));
        s.name = c["name"].asOutputName("texture class");  // it names textures/<name>.tif
        if (!names.insert(s.name).second) c["name"].fail(fmt::format("duplicate class name '{}'", s.name));
        s.reflectance = parseSpectrum(c["reflectance"], 0, 1, "(reflectance)");
        if (auto tx = c.optional("texture")) {
            s.texture = tx->asExistingPath();
            s.textureLoc = tx->loc();
        }
        s.mean = c.getDouble("mean", 1.0, 0, 100, "");
        s.stddev = c.getDouble("stddev", 0.0, 0, 100, "");
        if (s.stddev > 0 && !s.texture) c["stddev"].fail("a standard deviation needs a 'texture' image to shape");
        // Optional: only a solver written in the file is set (the dirsig estimator defaults to
        // classic; other estimators refuse per-material solvers).
        // A class becomes a lambertian or textured material: the solvers those types take.
        if (auto sv = c.optional("solver")) s.solver = sv->asEnum(materialKind(ir::Material::Type::Textured).solverNames());
        t.classes.push_back(std::move(s));
    }
    if (t.classes.empty()) n["classes"].fail("define at least one class");
    return t;
}

}  // namespace littoral::scenegen
