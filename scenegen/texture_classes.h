#pragma once
// Texture classes: the classification map that assigns materials to the ground, and the per-class
// reflectance textures (dissertation Ch. 10, spec/seed-ch05-10.md §3.1).
//
// The classification raster (8- or 16-bit single-channel PNG or TIFF) holds one class index per
// pixel and is draped over the terrain in plan view across `extent` (pixel-is-area: the image's
// outer edges are the extent's edges; row 0 is the north edge y1, column 0 the west edge x0).
// Each class names a material with a spectral reflectance and, optionally, a grey texture image
// that modulates it. As in the dissertation, the texture is given the statistics wanted for the
// class by a linear remap over the class's own pixels:
//     t' = mu + (t - m) * (sigma / s)
// where m and s are the mean and standard deviation of the tiled texture over the class's pixels and
// mu, sigma the targets (the "statistical adjustment" of §3.1, which maps each class's mean and
// variance to a desired value). Values below zero after the remap are clamped to 0 and counted.
// The IR material is Textured: reflectance(lambda) * t'(x, y), so with mu = 1 the class's mean
// reflectance is its spectrum.
#include <filesystem>
#include <string>
#include <vector>

#include "bathymetry/terrain.h"
#include "core/scene_ir.h"
#include "scenegen/assembly_spec.h"

namespace littoral::scenegen {

// The classification raster in plan view.
struct ClassMap {
    int width = 0, height = 0;
    std::vector<uint16_t> value;  // row-major, row 0 = north
    bathymetry::Extent extent;
    // Class value of the pixel containing (x, y); points outside the extent take the nearest edge pixel.
    uint16_t at(double x, double y) const;
    // Plan centre of pixel (column i, row j).
    Vec2 pixelCentre(int i, int j) const;
};

// Reads an 8- or 16-bit integer image (channel 0). InputError naming the file for anything else.
ClassMap readClassMap(const std::filesystem::path& path, const bathymetry::Extent& extent);

struct RemapStats {
    size_t pixels = 0;            // pixels of the class in the map
    double meanBefore = 0, stdBefore = 0;
    double meanAfter = 0, stdAfter = 0;
    size_t clampedToZero = 0;
};

// t' = mu + (t - m)(sigma / s) over the pixels with mask != 0 (m, s: their mean and population
// standard deviation); pixels outside the mask are set to mu. InputError if sigma > 0 and the
// masked texture is constant (s = 0).
std::vector<float> remapMeanStd(const std::vector<float>& t, const std::vector<char>& mask, double mu, double sigma,
                                RemapStats* stats);

struct TextureClasses {
    ClassMap map;
    std::vector<TextureClassSpec> classes;
    std::vector<int> classOfValue;               // raster value -> position in `classes`
    std::vector<std::vector<float>> textures;    // per class: width x height multiplier, or empty (uniform)
    std::vector<RemapStats> stats;

    // Position in `classes` of the class at (x, y).
    uint16_t slotAt(double x, double y) const;
    // IR materials, one per class, in class order; textured ones reference "textures/<name>.tif".
    std::vector<ir::Material> materials() const;
    // The IR material `name` of type Classified that the ground's faces carry: the class map
    // ("textures/<kClassMapFile>", its extent) and, per raster value, the class material it names.
    // The renderer looks the class up where each ray lands.
    ir::Material classifiedMaterial(const std::string& name) const;
    static constexpr const char* kClassMapFile = "class-map.tif";
    // Writes the textures into dir/textures/ as single-channel float TIFF, and the class map as a
    // 16-bit TIFF (atomically).
    void writeTextures(const std::filesystem::path& irDir) const;
    // Fraction of map pixels per class.
    std::vector<double> coverage() const;
};

// Reads the map and the class textures, checks every raster value has a class and that the map covers
// the domain (the terrain the classes are draped on; InputError at `extent`), remaps textures.
TextureClasses buildTextureClasses(const TextureClassesSpec& spec, const bathymetry::Extent& domain);

}  // namespace littoral::scenegen
