// Elevation rasters: ESRI ASCII grids (own parser) and TIFF/GeoTIFF (pixels via OpenImageIO,
// georeferencing via geotiff_tags), interpolated bilinearly between sample centres.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include "bathymetry/geotiff_tags.h"
#include "bathymetry/param_check.h"
#include "bathymetry/terrain.h"
#include "core/atomic_file.h"
#include "core/resource_limits.h"
#include "core/stderr_capture.h"
#include "core/suggest.h"

namespace littoral::bathymetry {

namespace {

// A regular grid of samples; row 0 is the northernmost. Sample (i, j) sits at
// x = xc0 + i dx, y = yTop - j dy (sample centres).
struct Grid {
    long nx = 0, ny = 0;
    double xc0 = 0, yTop = 0, dx = 1, dy = 1;
    std::vector<double> z;  // row-major, metres after scale/offset
};

class RasterTerrain final : public Terrain {
public:
    RasterTerrain(Grid g, std::string name) : g_(std::move(g)), name_(std::move(name)) {}

    double elevation(double x, double y) const override {
        // Bilinear interpolation in the cell containing (x, y); outside the extent the point is
        // clamped to the nearest edge point first (documented in terrain.h).
        const double u = std::clamp((x - g_.xc0) / g_.dx, 0.0, double(g_.nx - 1));
        const double v = std::clamp((g_.yTop - y) / g_.dy, 0.0, double(g_.ny - 1));
        const long i = std::min(static_cast<long>(u), g_.nx - 2), j = std::min(static_cast<long>(v), g_.ny - 2);
        const double fu = u - double(i), fv = v - double(j);
        const double* r0 = &g_.z[size_t(j) * size_t(g_.nx) + size_t(i)];
        const double* r1 = r0 + g_.nx;
        return (1 - fv) * ((1 - fu) * r0[0] + fu * r0[1]) + fv * ((1 - fu) * r1[0] + fu * r1[1]);
    }
    Extent extent() const override {
        return {g_.xc0, g_.yTop - double(g_.ny - 1) * g_.dy, g_.xc0 + double(g_.nx - 1) * g_.dx, g_.yTop};
    }
    Extent footprint() const override {
        const Extent e = extent();
        return {e.x0 - 0.5 * g_.dx, e.y0 - 0.5 * g_.dy, e.x1 + 0.5 * g_.dx, e.y1 + 0.5 * g_.dy};
    }
    std::string describe() const override {
        return fmt::format("raster {} ({} x {} samples, {} x {} m spacing)", name_, g_.nx, g_.ny, g_.dx, g_.dy);
    }

private:
    Grid g_;
    std::string name_;
};

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

bool parseDouble(std::string_view tok, double* out) {
    const char* b = tok.data();
    const char* e = b + tok.size();
    if (b != e && *b == '+') ++b;
    const auto res = std::from_chars(b, e, *out);
    return res.ec == std::errc() && res.ptr == e;
}

// Whitespace-separated tokens of a line with their 1-based columns.
std::vector<std::pair<std::string_view, int>> tokens(std::string_view line) {
    std::vector<std::pair<std::string_view, int>> out;
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
        const size_t s = i;
        while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
        if (i > s) out.emplace_back(line.substr(s, i - s), int(s) + 1);
    }
    return out;
}

// The header of an ESRI ASCII grid: key -> (value, line).
using AsciiHeader = std::map<std::string, std::pair<double, int>>;

const std::vector<std::string>& asciiHeaderKeys() {
    static const std::vector<std::string> kKeys = {"ncols", "nrows", "xllcorner", "xllcenter", "yllcorner",
                                                   "yllcenter", "cellsize", "dx", "dy", "nodata_value"};
    return kKeys;
}

// One "key value" header line into `header`.
void parseHeaderLine(const std::vector<std::pair<std::string_view, int>>& tok, const std::string& line, int lineNo,
                     const std::string& file, AsciiHeader& header) {
    const auto& keys = asciiHeaderKeys();
    const std::string key = lower(std::string(tok[0].first));
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
        const std::string hint = closestMatch(key, keys);
        throw InputError(SourceLoc{file, lineNo, tok[0].second},
                         fmt::format("unknown ASCII grid header key '{}'{}; allowed: {}", tok[0].first,
                                     hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint), joinList(keys)));
    }
    if (tok.size() != 2)
        throw InputError(SourceLoc{file, lineNo, 1}, fmt::format("header line '{}' must be a key and one value", line));
    double v;
    if (!parseDouble(tok[1].first, &v) || !std::isfinite(v))
        throw InputError(SourceLoc{file, lineNo, tok[1].second},
                         fmt::format("'{}' value '{}' is not a finite number", key, tok[1].first));
    if (header.count(key))
        throw InputError(SourceLoc{file, lineNo, 1},
                         fmt::format("'{}' given twice (first on line {})", key, header[key].second));
    header[key] = {v, lineNo};
}

// The grid's size, spacing and origin from the header, complete once the first data line (at
// `lineNo`) is reached.
Grid gridFromHeader(AsciiHeader& header, int lineNo, const std::string& file) {
    Grid g;
    const auto need = [&](const char* key) {
        if (!header.count(key))
            throw InputError(SourceLoc{file, lineNo},
                             fmt::format("ASCII grid header lacks '{}' before the first data line", key));
        return header[key];
    };
    const auto count = [&](const char* key) {
        const auto [v, ln] = need(key);
        if (v != std::floor(v) || v < 2 || v > 1e6)
            throw InputError(SourceLoc{file, ln}, fmt::format("'{}' = {} must be a whole number in [2, 1000000]", key, v));
        return static_cast<long>(v);
    };
    g.nx = count("ncols");
    g.ny = count("nrows");
    if (header.count("cellsize")) {
        g.dx = g.dy = header["cellsize"].first;
        if (header.count("dx") || header.count("dy"))
            throw InputError(SourceLoc{file, header["cellsize"].second}, "give either cellsize or dx/dy, not both");
    } else if (header.count("dx") && header.count("dy")) {
        g.dx = header["dx"].first;
        g.dy = header["dy"].first;
    } else {
        throw InputError(SourceLoc{file, lineNo}, "ASCII grid header lacks 'cellsize' (or 'dx' and 'dy')");
    }
    if (!(g.dx > 0) || !(g.dy > 0))
        throw InputError(SourceLoc{file, header.count("cellsize") ? header["cellsize"].second : header["dx"].second},
                         fmt::format("cell size {} x {} must be > 0", g.dx, g.dy));
    const bool xc = header.count("xllcenter"), xk = header.count("xllcorner");
    const bool yc = header.count("yllcenter"), yk = header.count("yllcorner");
    if (xc == xk || yc == yk)
        throw InputError(SourceLoc{file, lineNo},
                         "ASCII grid header needs exactly one of xllcorner/xllcenter and one of "
                         "yllcorner/yllcenter");
    // Corner registration: the lower-left cell's centre is half a cell in from the corner.
    const double xll = xc ? header["xllcenter"].first : header["xllcorner"].first + 0.5 * g.dx;
    const double yll = yc ? header["yllcenter"].first : header["yllcorner"].first + 0.5 * g.dy;
    g.xc0 = xll;
    g.yTop = yll + double(g.ny - 1) * g.dy;
    return g;
}

// One data line, grid row `row` (0-based), appended to `raw`.
void parseDataRow(const std::vector<std::pair<std::string_view, int>>& tok, int lineNo, const std::string& file,
                  long row, const Grid& g, const std::optional<double>& nodata, std::vector<double>& raw) {
    if (row >= g.ny)
        throw InputError(SourceLoc{file, lineNo, tok[0].second},
                         fmt::format("extra data after the {} rows the header declares", g.ny));
    if (long(tok.size()) != g.nx)
        throw InputError(SourceLoc{file, lineNo},
                         fmt::format("row {} has {} values; ncols = {} (one grid row per line)", row + 1, tok.size(),
                                     g.nx));
    for (size_t c = 0; c < tok.size(); ++c) {
        double v;
        if (!parseDouble(tok[c].first, &v) || !std::isfinite(v))
            throw InputError(SourceLoc{file, lineNo, tok[c].second},
                             fmt::format("'{}' (row {}, column {}) is not a finite number", tok[c].first, row + 1,
                                         c + 1));
        if (nodata && v == *nodata)
            throw InputError(SourceLoc{file, lineNo, tok[c].second},
                             fmt::format("row {}, column {} is NODATA ({}); the terrain must be complete, fill "
                                         "holes before loading", row + 1, c + 1, v));
        raw.push_back(v);
    }
}

// ESRI ASCII grid (Arc/Info ASCII GRID): header lines "key value", then nrows lines of ncols values,
// north row first. Strict: every data line holds exactly ncols values.
Grid parseAsciiGrid(std::string_view text, const std::string& file) {
    std::istringstream in{std::string(text)};
    size_t consumed = 0;  // bytes of the text before the current line
    AsciiHeader header;
    std::string line;
    int lineNo = 0;
    Grid g;
    long row = 0;
    bool headerDone = false;
    std::optional<double> nodata;
    std::vector<double> raw;
    while (std::getline(in, line)) {
        ++lineNo;
        const size_t lineOffset = consumed;
        consumed += line.size() + 1;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        const auto tok = tokens(line);
        if (tok.empty()) continue;
        const bool isNumber = [&] { double d; return parseDouble(tok[0].first, &d); }();
        if (!headerDone && !isNumber) {
            parseHeaderLine(tok, line, lineNo, file, header);
            continue;
        }
        if (!headerDone) {
            headerDone = true;
            g = gridFromHeader(header, lineNo, file);
            if (header.count("nodata_value")) nodata = header["nodata_value"].first;
            // The header's counts against the memory budget, and against what the rest of the file
            // can hold (every value takes a digit and a separator) before reserving: a lying header
            // reserves nothing, and the rows are then read (and found missing) one by one.
            const double values = double(g.nx) * double(g.ny);
            requireMemory(8.0 * values, fmt::format("an elevation grid of {} x {} samples would", g.nx, g.ny),
                          SourceLoc{file, header["nrows"].second});
            const double left = double(text.size() - std::min(text.size(), lineOffset));
            if (2.0 * values - 1.0 <= left) raw.reserve(size_t(g.nx) * size_t(g.ny));
        }
        parseDataRow(tok, lineNo, file, row, g, nodata, raw);
        ++row;
    }
    if (!headerDone) throw InputError(SourceLoc{file}, "no grid data: the file is empty or holds only a header");
    if (row != g.ny)
        throw InputError(SourceLoc{file, lineNo},
                         fmt::format("the grid ends after {} rows; nrows = {}", row, g.ny));
    g.z = std::move(raw);
    return g;
}

// Native-typed pixel values of one channel, converted to double without OIIO's normalisation
// of integer types (an int16 DEM holds metres, not fractions of 32767).
std::vector<double> readChannel(OIIO::ImageInput& in, const std::filesystem::path& path, int channel) {
    const OIIO::ImageSpec& spec = in.spec();
    const size_t n = size_t(spec.width) * size_t(spec.height);
    OIIO::TypeDesc t = spec.format;
    std::vector<double> out(n);
    const auto readAs = [&](auto tag, OIIO::TypeDesc td) {
        using T = decltype(tag);
        std::vector<T> buf(n);
        if (!in.read_image(0, 0, channel, channel + 1, td, buf.data()))
            throw InputError(SourceLoc{path.string()}, "cannot read pixels: " + libraryMessage(in.geterror()));
        for (size_t k = 0; k < n; ++k) out[k] = static_cast<double>(buf[k]);
    };
    switch (t.basetype) {
        case OIIO::TypeDesc::UINT8: readAs(uint8_t{}, OIIO::TypeDesc::UINT8); break;
        case OIIO::TypeDesc::INT8: readAs(int8_t{}, OIIO::TypeDesc::INT8); break;
        case OIIO::TypeDesc::UINT16: readAs(uint16_t{}, OIIO::TypeDesc::UINT16); break;
        case OIIO::TypeDesc::INT16: readAs(int16_t{}, OIIO::TypeDesc::INT16); break;
        case OIIO::TypeDesc::UINT32: readAs(uint32_t{}, OIIO::TypeDesc::UINT32); break;
        case OIIO::TypeDesc::INT32: readAs(int32_t{}, OIIO::TypeDesc::INT32); break;
        default: readAs(double{}, OIIO::TypeDesc::DOUBLE); break;  // half, float, double
    }
    return out;
}

// The samples of the raster's channel `opt.channel`, row-major from the north; sets the grid's size.
std::vector<double> readImageSamples(const std::filesystem::path& path, const RasterOptions& opt, Grid& g) {
    // libpng prints its own lines before the failure reported below (core/stderr_capture.h).
    return quietLibraryCall([&] {
        const std::string file = path.string();
        noteInput(file);  // no output may replace it
        auto in = OIIO::ImageInput::open(file);
        if (!in)
            throw InputError(SourceLoc{file}, "not a readable elevation raster (TIFF/GeoTIFF, ESRI ASCII grid, or another "
                                              "image format OpenImageIO reads): " + libraryMessage(OIIO::geterror()));
        const OIIO::ImageSpec& spec = in->spec();
        if (spec.width < 2 || spec.height < 2 || spec.depth > 1)
            throw InputError(SourceLoc{file}, fmt::format("raster is {} x {} x {}; need a 2D grid of at least 2 x 2",
                                                          spec.width, spec.height, spec.depth));
        if (opt.channel < 0 || opt.channel >= spec.nchannels)
            throw InputError(SourceLoc{file}, fmt::format("channel = {} but the raster has {} channel(s) (0..{})",
                                                          opt.channel, spec.nchannels, spec.nchannels - 1));
        // Decoding holds the samples twice (the file's type, then double): refuse before allocating.
        requireMemory(16.0 * double(spec.width) * double(spec.height),
                      fmt::format("an elevation raster of {} x {} samples would", spec.width, spec.height), SourceLoc{file});
        g.nx = spec.width;
        g.ny = spec.height;
        std::vector<double> raw = readChannel(*in, path, opt.channel);
        in->close();
        return raw;
    });
}

// With opt.utmZone set (the raster is placed by the scene's UTM frame), the projected system the
// GeoTIFF declares, if any, must be UTM in that zone and hemisphere.
void checkUtmZone(const GeoTiffInfo& geo, const RasterOptions& opt, const std::string& file) {
    if (opt.utmZone == 0 || geo.projectedCrs == 0) return;
    const int c = geo.projectedCrs;
    int zone = 0;
    bool north = true;
    std::string datum = "WGS 84";
    if (c >= 32601 && c <= 32660) zone = c - 32600;
    else if (c >= 32701 && c <= 32760) zone = c - 32700, north = false;
    else if (c >= 26901 && c <= 26923) zone = c - 26900, datum = "NAD83";
    const std::string scene = fmt::format("UTM zone {}{}", opt.utmZone, opt.utmNorth ? 'N' : 'S');
    if (zone == 0)
        throw InputError(SourceLoc{file}, fmt::format("the GeoTIFF declares the projected system EPSG:{}, which is not "
                                                      "UTM; origin: scene places a raster in the scene's frame ({}): "
                                                      "reproject it to {}, or give origin_x_m and origin_y_m in its "
                                                      "own system",
                                                      c, scene, scene));
    if (zone != opt.utmZone || north != opt.utmNorth)
        throw InputError(SourceLoc{file}, fmt::format("the GeoTIFF is in {} / UTM zone {}{} (EPSG:{}), but the scene's "
                                                      "frame is {} (from scene.origin); reproject the raster to {}",
                                                      datum, zone, north ? 'N' : 'S', c, scene, scene));
}

// Sample spacing and origin from the GeoTIFF tags (north-up, projected in metres), in the local
// frame of opt.originX/Y.
void georeference(const GeoTiffInfo& geo, const RasterOptions& opt, const std::string& file, Grid& g) {
    if (geo.modelType == 2)
        throw InputError(SourceLoc{file}, "the GeoTIFF is in geographic coordinates (degrees, GTModelType 2); "
                                          "reproject it to a projected system in metres (e.g. UTM) or give an "
                                          "extent in the local frame");
    if (geo.modelType == 3)
        throw InputError(SourceLoc{file}, "the GeoTIFF is geocentric (GTModelType 3); a projected system in metres "
                                          "is required");
    // Raster (I, J) -> model (X, Y): X = a I + b J + d, Y = e I + f J + h (GeoTIFF 1.1, 7.3).
    double a, b, d, e, f, h;
    if (geo.transformation) {
        const auto& m = *geo.transformation;
        a = m[0]; b = m[1]; d = m[3]; e = m[4]; f = m[5]; h = m[7];
    } else {
        const auto& s = *geo.pixelScale;
        const auto& tp = geo.tiepoints;  // first tie point anchors the grid
        a = s[0]; b = 0; e = 0; f = -s[1];
        d = tp[3] - tp[0] * s[0];
        h = tp[4] + tp[1] * s[1];
    }
    if (b != 0 || e != 0)
        throw InputError(SourceLoc{file}, "the GeoTIFF grid is rotated (ModelTransformation has shear terms); "
                                          "only north-up rasters are supported");
    if (!(a > 0) || !(f < 0))
        throw InputError(SourceLoc{file}, fmt::format("GeoTIFF pixel size ({}, {}) must be positive in x and "
                                                      "negative in y (north-up)", a, f));
    checkUtmZone(geo, opt, file);
    const double c = geo.rasterType == 2 ? 0.0 : 0.5;  // PixelIsPoint vs PixelIsArea centres
    g.dx = a;
    g.dy = -f;
    g.xc0 = a * c + d - opt.originX;
    g.yTop = f * c + h - opt.originY;
}

// Every sample must be finite and not the GDAL NODATA value.
void checkComplete(const std::vector<double>& raw, const GeoTiffInfo& geo, const Grid& g, const std::string& file,
                   int channel) {
    std::optional<double> nodata;
    if (geo.gdalNodata) {
        double v;
        if (lower(*geo.gdalNodata) == "nan") nodata = std::numeric_limits<double>::quiet_NaN();
        else if (parseDouble(*geo.gdalNodata, &v)) nodata = v;
    }
    for (long j = 0; j < g.ny; ++j)
        for (long i = 0; i < g.nx; ++i) {
            const double v = raw[size_t(j) * size_t(g.nx) + size_t(i)];
            const bool isNodata = nodata && (std::isnan(*nodata) ? std::isnan(v) : v == *nodata);
            if (isNodata || !std::isfinite(v))
                throw InputError(SourceLoc{file},
                                 fmt::format("pixel (column {}, row {}; counted from 1, row 1 = north), channel {} is "
                                             "{} ({}); every sample must be a finite elevation: the terrain must be "
                                             "complete, fill holes before loading",
                                             i + 1, j + 1, channel, isNodata ? "NODATA" : "not finite", v));
        }
}

Grid readImage(const std::filesystem::path& path, const RasterOptions& opt) {
    const std::string file = path.string();
    const GeoTiffInfo geo = readGeoTiffInfo(path);  // also reports a missing file clearly
    Grid g;
    std::vector<double> raw = readImageSamples(path, opt, g);
    if (opt.extent) {
        // Caller's extent: the rectangle spanned by the sample centres.
        g.dx = opt.extent->width() / double(g.nx - 1);
        g.dy = opt.extent->height() / double(g.ny - 1);
        g.xc0 = opt.extent->x0;
        g.yTop = opt.extent->y1;
    } else if (geo.hasGeoreferencing()) {
        georeference(geo, opt, file, g);
    } else {
        throw InputError(SourceLoc{file}, "raster has no georeferencing (no GeoTIFF ModelPixelScale/ModelTiepoint or "
                                          "ModelTransformation); give its extent in the local frame");
    }
    checkComplete(raw, geo, g, file, opt.channel);
    g.z = std::move(raw);
    return g;
}

// z = zScale * value + zOffset for every sample, which must then be an elevation on Earth: a sample
// far outside (3.4e38 is a common undeclared NODATA value of float rasters) would make a seabed
// thousands of kilometres deep, or an infinite one after scaling.
void scaleElevations(Grid& g, const RasterOptions& opt, const std::string& file) {
    constexpr double kLowest = -12000, kHighest = 9000;  // m: below the deepest trench, above the highest peak
    for (size_t k = 0; k < g.z.size(); ++k) {
        const double raw = g.z[k], z = opt.zScale * raw + opt.zOffset;
        if (!(z >= kLowest && z <= kHighest))
            throw InputError(SourceLoc{file},
                             fmt::format("sample (column {}, row {}; counted from 1, row 1 = north) holds {:.7g}, which "
                                         "is an elevation of {:.7g} m after z_scale {} and z_offset_m {}; allowed {} "
                                         "to {} m "
                                         "(a NODATA value the file does not declare? fill such holes before "
                                         "loading)",
                                         k % size_t(g.nx) + 1, k / size_t(g.nx) + 1, raw, z, opt.zScale, opt.zOffset,
                                         kLowest, kHighest));
        g.z[k] = z;
    }
}

bool looksLikeAsciiGrid(const std::filesystem::path& path) {
    noteInput(path);  // no output may replace it
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(SourceLoc{path.string()}, "cannot open file (missing or unreadable)");
    std::string head(64, '\0');
    in.read(head.data(), 64);
    head.resize(static_cast<size_t>(in.gcount()));
    size_t i = 0;
    while (i < head.size() && std::isspace(static_cast<unsigned char>(head[i]))) ++i;
    const std::string w = lower(head.substr(i, 5));
    return w == "ncols" || w == "nrows";
}

}  // namespace

std::unique_ptr<Terrain> parseAsciiGridTerrain(std::string_view text, const std::string& file) {
    Grid g = parseAsciiGrid(text, file);
    return std::make_unique<RasterTerrain>(std::move(g), file);
}

std::unique_ptr<Terrain> loadRaster(const std::filesystem::path& path, const RasterOptions& opt) {
    using detail::requireFinite;
    requireFinite("raster", "origin_x_m", opt.originX);
    requireFinite("raster", "origin_y_m", opt.originY);
    detail::require(std::isfinite(opt.zScale) && opt.zScale != 0, "raster", "z_scale", opt.zScale,
                    "a finite, non-zero number");
    requireFinite("raster", "z_offset_m", opt.zOffset);
    if (opt.extent) {
        for (double v : {opt.extent->x0, opt.extent->y0, opt.extent->x1, opt.extent->y1})
            requireFinite("raster", "extent", v);
        if (!opt.extent->valid())
            throw InputError(fmt::format("raster.extent = [{}, {}] x [{}, {}] m: must have x0 < x1 and y0 < y1",
                                         opt.extent->x0, opt.extent->x1, opt.extent->y0, opt.extent->y1));
    }
    if (!std::filesystem::exists(path))
        throw InputError(SourceLoc{path.string()}, "elevation raster not found");
    if (!std::filesystem::is_regular_file(path))
        throw InputError(SourceLoc{path.string()}, "elevation raster is not a regular file");
    Grid g;
    if (looksLikeAsciiGrid(path)) {
        g = parseAsciiGrid(readTextFile(path), path.string());
        if (opt.extent) {
            // An explicit extent overrides the header's georeferencing (sample-centre rectangle).
            g.dx = opt.extent->width() / double(g.nx - 1);
            g.dy = opt.extent->height() / double(g.ny - 1);
            g.xc0 = opt.extent->x0;
            g.yTop = opt.extent->y1;
        } else {
            g.xc0 -= opt.originX;
            g.yTop -= opt.originY;
        }
    } else {
        g = readImage(path, opt);
    }
    scaleElevations(g, opt, path.string());
    return std::make_unique<RasterTerrain>(std::move(g), path.filename().string());
}

}  // namespace littoral::bathymetry
