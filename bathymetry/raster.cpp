// Elevation rasters: ESRI ASCII grids (own parser) and everything GDAL reads (gdal_raster.cpp),
// placed in the local frame and interpolated bilinearly between sample centres.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include <fmt/format.h>

#include "bathymetry/geo_frame.h"
#include "bathymetry/param_check.h"
#include "bathymetry/raster_source.h"
#include "bathymetry/terrain.h"
#include "core/atomic_file.h"
#include "core/resource_limits.h"
#include "core/suggest.h"

namespace littoral::bathymetry {

namespace {

using detail::Grid;
using detail::SourceRaster;

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

// An ESRI ASCII grid as a source raster in its file's coordinates, with the .prj's system if any.
SourceRaster asciiSource(Grid g, const std::filesystem::path& path) {
    SourceRaster src;
    src.nx = g.nx;
    src.ny = g.ny;
    src.gt = {g.xc0 - 0.5 * g.dx, g.dx, 0, g.yTop + 0.5 * g.dy, 0, -g.dy};
    src.hasGeotransform = true;
    src.z = std::move(g.z);
    src.format = "ESRI ASCII grid";
    detail::readPrjSidecar(path, src);
    return src;
}

// Every sample of a raster placed sample for sample must be a finite elevation.
void checkComplete(const SourceRaster& src, const std::string& file) {
    for (size_t k = 0; k < src.missing.size(); ++k) {
        if (!src.missing[k]) continue;
        const double v = src.z[k];
        const bool isNodata = src.nodata && (std::isnan(*src.nodata) ? std::isnan(v) : v == *src.nodata);
        throw InputError(SourceLoc{file},
                         fmt::format("pixel (column {}, row {}; counted from 1, row 1 = north), channel {} is {} ({}); "
                                     "every sample must be a finite elevation: the terrain must be complete, fill "
                                     "holes before loading",
                                     k % size_t(src.nx) + 1, k / size_t(src.nx) + 1, src.channel,
                                     isNodata ? "NODATA" : "not finite", v));
    }
}

// The caller's extent: the rectangle spanned by the sample centres.
Grid byExtent(SourceRaster src, const Extent& e, const std::string& file) {
    checkComplete(src, file);
    Grid g;
    g.nx = src.nx;
    g.ny = src.ny;
    g.dx = e.width() / double(g.nx - 1);
    g.dy = e.height() / double(g.ny - 1);
    g.xc0 = e.x0;
    g.yTop = e.y1;
    g.z = std::move(src.z);
    return g;
}

// A raster stored south row first (positive y step, as NetCDF often is) turned north-up.
void flipToNorthUp(SourceRaster& src) {
    if (src.gt[5] <= 0 || src.gt[2] != 0 || src.gt[4] != 0) return;
    const size_t w = size_t(src.nx);
    for (long j = 0; j < src.ny / 2; ++j) {
        const size_t a = size_t(j) * w, b = size_t(src.ny - 1 - j) * w;
        std::swap_ranges(src.z.begin() + long(a), src.z.begin() + long(a + w), src.z.begin() + long(b));
        if (!src.missing.empty())
            for (size_t i = 0; i < w; ++i) {
                const bool t = src.missing[a + i];
                src.missing[a + i] = src.missing[b + i];
                src.missing[b + i] = t;
            }
    }
    src.gt[3] += double(src.ny) * src.gt[5];
    src.gt[5] = -src.gt[5];
}

// The samples of a north-up grid whose cells reach `clip` grown by two cells: the rest is
// dropped (with any NODATA it holds). A clip the grid misses keeps the grid whole, for the
// domain check to report.
void cropTo(const Extent& clip, Grid& g, SourceRaster& src) {
    const auto lo = [](double v) { return static_cast<long>(std::floor(v)); };
    const long i0 = std::max(0L, lo((clip.x0 - g.xc0) / g.dx) - 2);
    const long i1 = std::min(g.nx - 1, lo((clip.x1 - g.xc0) / g.dx) + 3);
    const long j0 = std::max(0L, lo((g.yTop - clip.y1) / g.dy) - 2);
    const long j1 = std::min(g.ny - 1, lo((g.yTop - clip.y0) / g.dy) + 3);
    if (i1 - i0 < 1 || j1 - j0 < 1 || (i0 == 0 && j0 == 0 && i1 == g.nx - 1 && j1 == g.ny - 1)) return;
    std::vector<double> z;
    std::vector<bool> missing;
    z.reserve(size_t(i1 - i0 + 1) * size_t(j1 - j0 + 1));
    for (long j = j0; j <= j1; ++j)
        for (long i = i0; i <= i1; ++i) {
            const size_t k = size_t(j) * size_t(g.nx) + size_t(i);
            z.push_back(src.z[k]);
            if (!src.missing.empty()) missing.push_back(src.missing[k]);
        }
    src.z = std::move(z);
    src.missing = std::move(missing);
    g.xc0 += double(i0) * g.dx;
    g.yTop -= double(j0) * g.dy;
    g.nx = src.nx = i1 - i0 + 1;
    g.ny = src.ny = j1 - j0 + 1;
}

// The file's north-up grid in a projected system in metres, less the local origin (ox, oy); cut
// to opt.clip if given.
Grid byOffset(SourceRaster src, double ox, double oy, const RasterOptions& opt, const std::string& file) {
    if (!src.hasGeotransform)
        throw InputError(SourceLoc{file}, fmt::format("the {} has no georeferencing (no GeoTIFF ModelPixelScale/"
                                                      "ModelTiepoint or ModelTransformation, no geotransform); give "
                                                      "its extent in the local frame",
                                                      src.format));
    std::string why;
    if (!detail::isProjectedMetres(src, &why))
        throw InputError(SourceLoc{file}, fmt::format("the {} cannot be placed by shifting its coordinates: {}; give "
                                                      "origin: scene (with scene.origin), which reprojects it into "
                                                      "the scene frame, or an extent in the local frame",
                                                      src.format, why));
    if (src.gt[2] != 0 || src.gt[4] != 0)
        throw InputError(SourceLoc{file}, fmt::format("the {} grid is rotated (its geotransform has shear terms); give "
                                                      "origin: scene, which resamples it north-up into the scene "
                                                      "frame",
                                                      src.format));
    flipToNorthUp(src);
    if (!(src.gt[1] > 0) || !(src.gt[5] < 0))
        throw InputError(SourceLoc{file}, fmt::format("{} pixel size ({}, {}) must be positive in x and negative in y "
                                                      "(north-up)",
                                                      src.format, src.gt[1], src.gt[5]));
    Grid g;
    g.nx = src.nx;
    g.ny = src.ny;
    g.dx = src.gt[1];
    g.dy = -src.gt[5];
    g.xc0 = src.gt[0] + 0.5 * src.gt[1] - ox;
    g.yTop = src.gt[3] + 0.5 * src.gt[5] - oy;
    if (opt.clip) cropTo(*opt.clip, g, src);
    checkComplete(src, file);
    g.z = std::move(src.z);
    return g;
}

// Placement rules 1–3 of terrain.h.
Grid place(SourceRaster src, const RasterOptions& opt, const std::string& file) {
    if (opt.extent) return byExtent(std::move(src), *opt.extent, file);
    if (!opt.frame) return byOffset(std::move(src), opt.originX, opt.originY, opt, file);
    if (detail::isFramesUtm(src, *opt.frame))
        return byOffset(std::move(src), opt.frame->originUtm().easting, opt.frame->originUtm().northing, opt,
                        file);
    return detail::resampleIntoFrame(src, *opt.frame, opt, file);
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
    const std::string file = path.string();
    SourceRaster src = looksLikeAsciiGrid(path) ? asciiSource(parseAsciiGrid(readTextFile(path), file), path)
                                                : detail::readGdalRaster(file, file, opt);
    Grid g = place(std::move(src), opt, file);
    scaleElevations(g, opt, path.string());
    return std::make_unique<RasterTerrain>(std::move(g), path.filename().string());
}

}  // namespace littoral::bathymetry
