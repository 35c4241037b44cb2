#pragma once
// Terrain: the ground elevation z(x, y) of a coastal scene, seabed and land in one field.
//
// Frame: local, x east (grid east for a UTM frame), y north, z up, metres. The still-water
// level is z = 0, so the seabed has z < 0 and beach, berm and dune have z > 0.
//
// Sources (each returns a Terrain):
//   makePlanarSlope  – z = z0 + sx x + sy y
//   makeDeanProfile  – Dean equilibrium profile h = A d^(2/3) offshore, beach face and berm onshore
//   makeBarTrough    – Dean profile plus a Gaussian sandbar and a Gaussian trough
//   loadRaster       – GeoTIFF, BAG, NetCDF, ... (GDAL) or ESRI ASCII grid, bilinear
//   fromSoundings    – CSV latitude,longitude,depth -> GeoFrame -> CGAL Delaunay TIN
// Parameters are plain structs so the scene-file parser can fill them key by key; every
// factory validates its parameters and raises InputError naming the field and the allowed range.
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/mesh.h"
#include "core/vec.h"

namespace littoral::bathymetry {

class GeoFrame;  // bathymetry/geo_frame.h

// Plan-view rectangle [x0, x1] x [y0, y1], metres, local frame.
struct Extent {
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    double width() const { return x1 - x0; }
    double height() const { return y1 - y0; }
    bool valid() const { return x1 > x0 && y1 > y0; }
    // Inside the closed rectangle grown by tol (metres) on every side.
    bool contains(double x, double y, double tol = 0) const {
        return x >= x0 - tol && x <= x1 + tol && y >= y0 - tol && y <= y1 + tol;
    }
};

// A terrain: ground elevation z(x, y) in the local frame (see the top of this file). Land and
// seabed are one terrain. elevation() is defined over extent(); analytic terrains are defined
// everywhere, rasters clamp to their edge outside the extent, TINs follow their OutsideHull policy.
// Implementations are immutable after construction, so elevation() may be called from many threads.
class Terrain {
public:
    virtual ~Terrain() = default;
    virtual double elevation(double x, double y) const = 0;  // metres, z up
    virtual Extent extent() const = 0;
    // The plan area the terrain's data stand for: extent() but for rasters, whose samples each
    // stand for their cell, so the rectangle of sample centres grown by half a cell on every side.
    // Outside it a raster repeats its edge values.
    virtual Extent footprint() const { return extent(); }
    // One line for logs and validity reports, e.g. "Dean profile A=0.1 m^(1/3), shoreline x=30 m".
    virtual std::string describe() const = 0;
};

// Regular-grid triangle mesh of the terrain over `extent` at (at most) `spacing` metres: the cell
// counts are nx = ceil(width / spacing), ny = ceil(height / spacing) and the actual spacing is
// width / nx, height / ny, so the boundary vertices lie exactly on the extent edges. Two triangles
// per cell, counter-clockwise seen from above (normals point up, +z). Vertex (i, j) has index
// j * (nx + 1) + i. Throws InputError for an invalid extent, spacing <= 0 or more than 50 million
// vertices, and for a non-finite elevation.
TriMesh terrainMesh(const Terrain& t, const Extent& extent, double spacing);

// Volume (m^3) between the horizontal plane z = level and a height-field mesh below it:
//   V = Int max(0, level - z(x, y)) dA
// over the mesh's plan-view footprint, exact for the piecewise-linear surface (triangles that
// cross the plane are clipped). For terrainMesh output and level = 0 this is the water volume
// above the seabed. Triangles seen from below (clockwise from above) count negatively.
double volumeBelow(const TriMesh& heightField, double level = 0.0);

// ---------------------------------------------------------------- analytic profiles

// Planar slope z = z0 + slopeX * x + slopeY * y (slopes dimensionless, dz/dx, dz/dy).
struct PlanarSlope {
    double z0 = 0;      // m, elevation at x = y = 0
    double slopeX = 0;  // dz/dx
    double slopeY = 0;  // dz/dy
};
std::unique_ptr<Terrain> makePlanarSlope(const Extent& extent, const PlanarSlope& p);
std::unique_ptr<Terrain> makePlanarSlope(const Extent& extent, double z0, double slopeX, double slopeY);

// Dean (1977, 1991) equilibrium beach profile. The profile varies across shore only (along x);
// the shoreline (z = 0) is the line x = shorelineX. With d the distance offshore of the
// shoreline (d = x - shorelineX if offshoreTowardPositiveX, else shorelineX - x):
//   d >= 0 (sea):  z = -min(A d^(2/3), maxDepth)                    Dean (1991) eq. 1, h = A x^(2/3)
//   d <  0 (land): z = min(beachSlope * (-d), bermHeight)            planar beach face up to the berm
// then, if duneHeight > bermHeight, a dune rising from the berm crest as a smooth cosine ramp of
// width duneWidth, starting duneOffset metres landward of the berm crest.
struct DeanProfile {
    double A = 0.1;                    // m^(1/3), profile scale; see deanScaleFromGrainSize
    double shorelineX = 0;             // m, x of the still-water shoreline
    bool offshoreTowardPositiveX = true;
    double beachSlope = 0.1;           // dimensionless beach-face slope above the waterline (> 0)
    double bermHeight = 1.5;           // m above still water (>= 0); the flat berm top
    double maxDepth = std::numeric_limits<double>::infinity();  // m (> 0): flat bottom beyond this
    double duneHeight = 0;             // m; <= bermHeight means no dune
    double duneOffset = 10;            // m landward of the berm crest where the dune starts (>= 0)
    double duneWidth = 10;             // m, horizontal width of the dune's seaward face (> 0)
};
// Dean (1987) fit to Moore's (1982) data: A = 0.21 D^0.48, D = median grain size in mm,
// A in m^(1/3). Valid for sand, roughly 0.1 mm <= D <= 1 mm; InputError outside 0.05–5 mm.
double deanScaleFromGrainSize(double grainSizeMm);
std::unique_ptr<Terrain> makeDeanProfile(const Extent& extent, const DeanProfile& p);
// Shorthand of the above: offshore toward +x, berm at `berm` metres, other fields default.
std::unique_ptr<Terrain> makeDeanProfile(const Extent& extent, double A, double shorelineX, double berm,
                                         double beachSlope = 0.1);

// Dean profile with a longshore sandbar and the trough landward of it (both Gaussian in the
// cross-shore distance d, metres offshore of the shoreline):
//   z = z_Dean(d) + barHeight   exp(-(d - barCrest(y))^2   / (2 barWidth^2))
//                 - troughDepth exp(-(d - troughCentre(y))^2 / (2 troughWidth^2))
// Offshore only: the Gaussians are multiplied by the smoothstep ramp 3t^2 - 2t^3,
// t = clamp(d / (troughDistance / 2), 0, 1), so land is untouched and the shoreline stays at d = 0. For a crescentic bar the crest and trough positions meander:
//   barCrest(y) = barCrestDistance + crescentAmplitude sin(2 pi (y - y0) / crescentWavelength),
// troughCentre likewise. The result must stay below the water (checked on a dense sampling of
// the extent: InputError if the bar breaches the surface, since a bar island is not a bar).
struct BarTrough {
    DeanProfile dean;
    double barCrestDistance = 60;  // m offshore of the shoreline (> 0)
    double barHeight = 0.8;        // m above the Dean profile (> 0)
    double barWidth = 10;          // m, Gaussian standard deviation (> 0)
    double troughDistance = 40;    // m offshore (> 0, < barCrestDistance)
    double troughDepth = 0.4;      // m below the Dean profile (>= 0)
    double troughWidth = 8;        // m, Gaussian standard deviation (> 0)
    double crescentAmplitude = 0;  // m (>= 0); 0 = straight longshore bar
    double crescentWavelength = 200;  // m (> 0)
};
std::unique_ptr<Terrain> makeBarTrough(const Extent& extent, const BarTrough& p);

// ---------------------------------------------------------------- rasters

// Elevation raster: any raster GDAL reads (GeoTIFF in any coordinate system, BAG, NetCDF, ENVI,
// Erdas Imagine, Surfer grids, XYZ, 16-bit PNG), or an ESRI ASCII grid (.asc, .grd; own parser
// with line/column errors; coordinate system from a .prj sidecar), chosen by content (an ASCII
// grid starts with "ncols"/"nrows"). Values are metres after z = zScale * (band scale * value +
// band offset) * unit + zOffset: a band in feet or US survey feet is converted; zScale = -1 reads
// a depth-positive-down raster.
// Placement in the local frame, first that applies:
//   1. options.extent: the rectangle spanned by the sample centres (first column at x0, last at
//      x1; first row at y1 = north, last at y0); the file's georeferencing is ignored.
//   2. options.frame (scene file `origin: scene`): the file's coordinate system into the scene
//      frame. A raster in the frame's own UTM zone (WGS 84 or GRS80, metres; or declaring no
//      system while the frame is UTM) is shifted by the origin's easting/northing, sample for
//      sample. Any other system (another zone, geographic degrees, a state plane in feet, a
//      rotated grid, a local tangent-plane frame) is resampled bilinearly onto a north-up grid in
//      the frame at the raster's own spacing, over its footprint within options.clip.
//   3. otherwise the file's north-up geotransform less (originX, originY), for a raster in a
//      projected system in metres (or none); geographic degrees, other units or a rotated grid
//      are refused (use `origin: scene`). A raster with no georeferencing needs an extent.
// NODATA (the band's value, NaN, infinity) in a sample kept (all of them, without clip), or in a
// sample the resampled grid uses, is an InputError naming the pixel (and the file line for ASCII
// grids): fill holes before loading.
// Interpolation: bilinear between sample centres; extent() is the rectangle of sample centres and
// queries outside it clamp to the nearest edge point.
struct RasterOptions {
    std::optional<Extent> extent;  // overrides file georeferencing
    double originX = 0;            // projected coordinate of the local origin (file units, metres)
    double originY = 0;
    double zScale = 1;             // elevation = zScale * value + zOffset
    double zOffset = 0;            // m, e.g. datum to still-water level shift
    int channel = 0;               // band holding elevation (0 = the first)
    std::string variable;          // NetCDF/HDF variable (subdataset) holding elevation, if several
    // The scene's frame (scene file `origin: scene`): the raster is placed by its coordinate
    // system (see 2. above). Not owned; must outlive the call.
    const GeoFrame* frame = nullptr;
    // The part of the local frame the terrain must cover (the scene domain), if known: a raster
    // placed by its georeferencing (rules 2 and 3) keeps only the samples whose cells reach it
    // (plus two cells), so NODATA far away does not matter and a large survey costs little.
    std::optional<Extent> clip;
};
std::unique_ptr<Terrain> loadRaster(const std::filesystem::path& path, const RasterOptions& options = {});
// An ESRI ASCII grid already in memory, georeferenced by its own header; `file` names it in
// messages. The header's ncols x nrows is checked against the text's length and the memory
// budget before anything is allocated.
std::unique_ptr<Terrain> parseAsciiGridTerrain(std::string_view text, const std::string& file);

// ---------------------------------------------------------------- soundings

// One sounding as read from CSV: geodetic latitude/longitude (degrees, WGS84) and depth below the
// still-water level (metres, positive down; negative = above water, e.g. a surveyed beach point).
struct Sounding {
    double latDeg = 0, lonDeg = 0, depth = 0;
    int line = 0;  // 1-based source line, 0 if not from a file
};
// Reads a CSV whose header names the columns latitude, longitude, depth (any order, case-
// insensitive, extra columns ignored; "lat"/"lon" accepted). Blank lines and lines starting with
// '#' are skipped. A malformed number, a missing field or an out-of-range latitude/longitude is an
// InputError naming file:line and the column.
// The file must be a regular file (core readTextFile). parseSoundingsCsv reads text already in
// memory, `file` naming it in messages.
std::vector<Sounding> readSoundingsCsv(const std::filesystem::path& path);
std::vector<Sounding> parseSoundingsCsv(std::string_view text, const std::string& file);

// What a TIN does at a point outside the convex hull of its vertices.
enum class OutsideHull {
    Error,            // InputError naming the point (default: no silent extrapolation)
    NearestHullPoint  // elevation of the nearest point on the hull boundary (continuous)
};

struct SoundingsOptions {
    // Shoreline (or other break-line) constraints as polylines of geodetic points, degrees; their
    // vertices are inserted with elevation `constraintZ` and their segments become constrained
    // edges that no triangle crosses (CGAL Constrained_Delaunay_triangulation_2).
    struct LatLon { double latDeg = 0, lonDeg = 0; };
    std::vector<std::vector<LatLon>> shorelines;
    double constraintZ = 0;                       // m, elevation of constraint vertices
    OutsideHull outside = OutsideHull::Error;
    // Soundings closer than this in plan (metres) are merged into one vertex at their mean depth.
    double mergeDistance = 1e-3;
};
// Soundings -> local frame with `frame` (elevation = -depth; the frame's height origin is ignored
// for z so that z = 0 stays the still-water level) -> constrained Delaunay TIN. At least three
// non-collinear soundings are required. extent() is the bounding box of the vertices.
std::unique_ptr<Terrain> fromSoundings(const std::vector<Sounding>& soundings, const GeoFrame& frame,
                                       const SoundingsOptions& options = {}, const std::string& sourceName = "");
std::unique_ptr<Terrain> fromSoundings(const std::filesystem::path& csv, const GeoFrame& frame,
                                       const SoundingsOptions& options = {});
// The same TIN from points already in the local frame (x, y, z metres) and local constraint polylines.
// Points closer than mergeDistance in plan merge as for soundings. Constraint polylines may not
// cross one another (InputError naming the polylines); they may share vertices.
std::unique_ptr<Terrain> fromLocalPoints(const std::vector<Point3>& points,
                                         const std::vector<std::vector<Point3>>& constraints = {},
                                         OutsideHull outside = OutsideHull::Error,
                                         const std::string& sourceName = "", double mergeDistance = 1e-3);

}  // namespace littoral::bathymetry
