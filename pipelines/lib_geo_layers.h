#pragma once
// Per-pixel georeferencing layers (docs/outputs.md, "Georeferencing"): for each sensor of a scene
// with scene.origin, NAME_geo.img (+ .hdr: ENVI float64, band names) holds, for the surface each pixel's centre ray meets first,
// its latitude and longitude (WGS84, degrees), the view zenith and azimuth (the direction from
// that point toward the sensor) and the sun's zenith and azimuth there, in degrees; azimuths are
// compass bearings from true north (the UTM grid's convergence taken out). NaN where the ray
// meets nothing.
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bathymetry/geo_frame.h"
#include "core/scene_ir.h"
#include "render/render_job.h"

namespace littoral::pipelines {

// The scene frame of an IR geo reference (local-cartesian or utm; bathymetry/geo_frame.h).
bathymetry::GeoFrame geoFrameOf(const ir::GeoReference& g);

// Where a sensor's image lies in the scene's projected CRS (pipelines/lib_geotiff.cpp): UTM for a
// `utm` frame, the ellipsoidal orthographic projection about the origin (east and north in the
// tangent plane) for a `local-cartesian` one; pixels mapped onto the plane z = 0 of the scene.
struct ImageGeoreference {
    std::string wkt;      // the CRS, WKT1
    std::string crsName;
    bool affine = false;  // orthographic views and pinholes looking straight down: `transform` holds
    // The GDAL geotransform: CRS x = t0 + col t1 + row t2, y = t3 + col t4 + row t5, for pixel
    // corner coordinates (col, row) (0, 0 the top left corner of the image).
    std::array<double, 6> transform{};
    // Other views: ground control points, pixel coordinates -> CRS, where rays meet z = 0.
    struct Gcp {
        double col, row, x, y;
    };
    std::vector<Gcp> gcps;
};
// nullopt when the IR has no geo reference, or the view meets the plane z = 0 at fewer than four
// of its control points.
std::optional<ImageGeoreference> imageGeoreference(const ir::SceneIR& ir, const ir::Sensor& sensor);
// The ENVI header lines of a georeference, as GDAL's ENVI driver writes them: `map info` and
// `coordinate system string` of an affine one; otherwise `geo points` (pixel and line, 1-based,
// latitude and longitude WGS84, of every control point; ENVI's map info is affine only).
std::string enviGeoHeaderLines(const ImageGeoreference& g);
// The ENVI header lines for a sensor of this IR ("" without a geo reference):
// for RenderJobOptions::enviHeaderLines.
std::string enviGeoHeaderLines(const ir::SceneIR& ir, const ir::Sensor& sensor);
// A float32 GeoTIFF of the film (one band per film band, DEFLATE), with its CRS and transform or
// control points, written through GDAL and renamed into place atomically.
void writeGeoTiff(const std::filesystem::path& path, const render::Film& film, const ImageGeoreference& g,
                  const std::string& description);

// The layer names, in file order.
std::vector<std::string> geoLayerNames();

// Writes OUT/NAME_geo.img and .hdr and the radiance as OUT/NAME.tif (GeoTIFF) for every rendered
// sensor when the IR has a geo reference, and removes those an earlier run left when it has none.
// Returns the files written.
std::vector<std::filesystem::path> writeGeoLayers(const ir::SceneIR& ir, const render::RenderJobResult& res,
                                                  const std::filesystem::path& outDir);

}  // namespace littoral::pipelines
