#pragma once
// Plain, checked descriptions of the geometry sections of a scene file that scenegen assembles:
// bathymetry, objects, texture_classes. Filled by the section parsers in assembly_sections.h
// (which the top-level parser, scene_file.h, calls with the YAML nodes it kept) and consumed by
// assemble.h. Angles are already radians, paths already resolved against the scene file.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bathymetry/terrain.h"
#include "core/error.h"
#include "core/spectrum.h"
#include "core/vec.h"

namespace littoral::scenegen {

struct BathymetrySpec {
    enum class Kind { PlanarSlope, Dean, BarTrough, Raster, Soundings };
    Kind kind = Kind::PlanarSlope;
    bathymetry::PlanarSlope planar;
    bathymetry::DeanProfile dean;
    bathymetry::BarTrough barTrough;
    std::filesystem::path file;            // raster or soundings CSV
    bathymetry::RasterOptions raster;
    bool rasterOriginFromScene = false;    // raster `origin: scene`: originX/Y from the scene's UTM frame
    SourceLoc rasterOriginLoc;             // where `origin` was given
    // The key that places a raster (extent, origin, origin_x_m or file) and where it is, for the
    // error of a raster that does not cover the domain.
    std::string rasterPlacementKey;
    SourceLoc rasterPlacementLoc;
    bathymetry::SoundingsOptions soundings;
    bool utmFrame = false;                 // geo frame for soundings/objects: UTM instead of local tangent plane
    double spacing = 1.0;                  // m, terrain grid spacing of the water/land meshes
    std::string material;                  // single seabed/land material when there are no texture classes
    SourceLoc loc;
};

struct ObjectSpec {
    std::string name;
    std::filesystem::path mesh;            // OBJ / PLY / OFF / STL
    std::vector<std::string> materials;    // face material slot -> material name
    // Plan position of the object origin: local metres, or latitude/longitude (degrees) converted
    // through the scene's geo frame.
    std::optional<Vec2> positionLocal;
    std::optional<std::array<double, 2>> latLonDeg;
    double heading = 0;                    // radians clockwise from north (bow = local +y)
    // Vertical placement: draft (the mesh's lowest point at water level - draft) or absolute z of
    // the mesh origin.
    std::optional<double> draft;           // m
    std::optional<double> z;               // m
    double scale = 1.0;
    SourceLoc loc;
};

struct TextureClassSpec {
    int index = 0;                         // class value in the classification raster
    std::string name;                      // material name in the IR
    Spectrum reflectance = Spectrum::constant(0.0);
    std::optional<std::filesystem::path> texture;  // grey image; absent = uniform
    SourceLoc textureLoc;                  // where `texture` was given
    double mean = 1.0;                     // target mean of the texture multiplier
    double stddev = 0.0;                   // target standard deviation of the multiplier
    std::string solver;                    // classic | generic | surface-pm, or "" (not given)
    SourceLoc loc;
};

struct TextureClassesSpec {
    std::filesystem::path map;             // classification raster (PNG / TIFF), class index per pixel
    std::optional<bathymetry::Extent> extent;  // plan-view rectangle of the map; default: scene domain
    SourceLoc extentLoc;                   // where `extent` was given (for the coverage error)
    std::vector<TextureClassSpec> classes;
    SourceLoc loc;
};

}  // namespace littoral::scenegen
