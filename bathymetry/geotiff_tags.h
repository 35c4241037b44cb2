#pragma once
// GeoTIFF georeferencing tags, read straight from the first TIFF directory.
//
// OpenImageIO 2.4 reads the pixels of a GeoTIFF but drops its georeferencing (it exposes no
// ModelPixelScale / ModelTiepoint / GeoKey attributes), so this small reader walks the first
// image file directory itself. Classic TIFF and BigTIFF, either byte order. Only the tags below
// are decoded; everything is bounds-checked, and a damaged directory is an InputError naming the
// file and what is wrong.
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace littoral::bathymetry {

struct GeoTiffInfo {
    bool isTiff = false;                         // the file starts with a TIFF header
    std::optional<std::array<double, 3>> pixelScale;  // tag 33550 (ScaleX, ScaleY, ScaleZ)
    std::vector<double> tiepoints;               // tag 33922, (I, J, K, X, Y, Z) per tie point
    std::optional<std::array<double, 16>> transformation;  // tag 34264, row-major 4x4
    int modelType = 0;   // GeoKey 1024 GTModelType: 1 projected, 2 geographic, 3 geocentric, 0 absent
    int rasterType = 1;  // GeoKey 1025 GTRasterType: 1 PixelIsArea (default), 2 PixelIsPoint
    int projectedCrs = 0;  // GeoKey 3072 ProjectedCSType (EPSG code), 0 absent
    std::optional<std::string> gdalNodata;  // tag 42113 GDAL_NODATA (ASCII)
    bool hasGeoreferencing() const { return transformation.has_value() || (pixelScale && tiepoints.size() >= 6); }
};

// Reads the header and first directory. A file that is not a TIFF gives isTiff = false (no error);
// a TIFF whose directory is damaged is an InputError.
GeoTiffInfo readGeoTiffInfo(const std::filesystem::path& path);
// The same for file contents in memory; `name` names them in messages.
GeoTiffInfo parseGeoTiffInfo(std::string_view data, const std::string& name);

}  // namespace littoral::bathymetry
