#pragma once
// Internal to bathymetry/: an elevation raster as read from its file, before it is placed in the
// scene's local frame (raster.cpp places it; gdal_raster.cpp reads it and, where the file's
// coordinate system is not the scene's, resamples it into the scene frame).
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bathymetry/terrain.h"

namespace littoral::bathymetry {

class GeoFrame;

namespace detail {

// A regular grid of samples in the local frame; row 0 is the northernmost. Sample (i, j) sits at
// x = xc0 + i dx, y = yTop - j dy (sample centres).
struct Grid {
    long nx = 0, ny = 0;
    double xc0 = 0, yTop = 0, dx = 1, dy = 1;
    std::vector<double> z;  // row-major, metres after scale/offset
};

// A raster in its file's own coordinates. The affine geotransform maps pixel-edge coordinates
// (col, row) to the file's system: X = gt[0] + col gt[1] + row gt[2], Y = gt[3] + col gt[4] + row
// gt[5] (GDAL's convention: sample (i, j) has its centre at col = i + 0.5, row = j + 0.5).
struct SourceRaster {
    long nx = 0, ny = 0;
    std::array<double, 6> gt{0, 1, 0, 0, 0, -1};
    bool hasGeotransform = false;
    std::vector<double> z;         // row-major from the file's first row, values as stored x band scale + offset
    std::optional<double> nodata;  // in stored units (compared before the band scale/offset)
    std::vector<bool> missing;     // per sample: NODATA or not finite (empty: none)
    std::string wkt;               // the file's coordinate system (WKT2), empty if it declares none
    std::string crsName;           // its name, for messages
    std::string format;            // "GeoTIFF", "BAG", "netCDF", "ESRI ASCII grid", ...
    int channel = 0;
};

// Reads any raster GDAL opens (GeoTIFF, BAG, NetCDF, ...) at `gdalName` (a path or a /vsimem/
// name); `file` names it in messages. Limits are checked before the samples are allocated.
SourceRaster readGdalRaster(const std::string& gdalName, const std::string& file, const RasterOptions& opt);
// The coordinate system of an ESRI ASCII grid from its .prj sidecar (ESRI WKT), if one exists.
void readPrjSidecar(const std::filesystem::path& asciiPath, SourceRaster& src);

// The raster resampled (bilinearly, between its sample centres) onto a north-up grid in the
// scene's frame, covering the part of the raster's footprint inside opt.clip (if given). The
// samples used must be present (not NODATA); values are then z_scale / z_offset_m applied.
Grid resampleIntoFrame(const SourceRaster& src, const GeoFrame& frame, const RasterOptions& opt,
                       const std::string& file);
// True when the file's coordinate system is the scene frame's own UTM zone on the WGS 84 or GRS80
// ellipsoid in metres (so placing it is a shift, no resampling), or when it declares none and
// the frame is UTM.
bool isFramesUtm(const SourceRaster& src, const GeoFrame& frame);
// Projected in metres (true), or no declared system (true); geographic or other units: false,
// with `why` set.
bool isProjectedMetres(const SourceRaster& src, std::string* why);

}  // namespace detail
}  // namespace littoral::bathymetry
