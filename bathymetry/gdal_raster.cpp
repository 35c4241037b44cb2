// Elevation rasters through GDAL: reading any format it opens (GeoTIFF, BAG, NetCDF, ...), the
// coordinate system of an ASCII grid's .prj, and resampling into the scene's frame.
#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <string_view>

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <fmt/format.h>

#include "bathymetry/geo_frame.h"
#include "bathymetry/raster_source.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/resource_limits.h"
#include "core/stderr_capture.h"

namespace littoral::bathymetry::detail {

namespace {

// The formats an elevation raster may come in. VRT and the network drivers are left out on
// purpose: a scene input names one file, which must not pull in others.
const char* const kDrivers[] = {"GTiff", "COG", "BAG", "netCDF", "HDF5", "HDF5Image", "XYZ", "ENVI", "EHdr",
                                "HFA",   "GSAG", "GSBG", "GS7BG", "PNG", "AAIGrid", nullptr};

void registerOnce() {
    static std::once_flag once;
    std::call_once(once, [] { GDALAllRegister(); });
}

// GDAL's failures during one read, collected instead of printed.
class GdalErrors {
public:
    GdalErrors() { CPLPushErrorHandlerEx(&GdalErrors::handler, this); }
    ~GdalErrors() { CPLPopErrorHandler(); }
    GdalErrors(const GdalErrors&) = delete;
    GdalErrors& operator=(const GdalErrors&) = delete;
    std::string message() const { return last_.empty() ? "GDAL gave no reason" : last_; }

private:
    static void CPL_STDCALL handler(CPLErr cls, CPLErrorNum, const char* msg) {
        auto* self = static_cast<GdalErrors*>(CPLGetErrorHandlerUserData());
        if (self && (cls == CE_Failure || cls == CE_Fatal) && msg) self->last_ = msg;
    }
    std::string last_;
};

struct DatasetCloser {
    void operator()(GDALDataset* d) const { GDALClose(d); }
};
using Dataset = std::unique_ptr<GDALDataset, DatasetCloser>;

Dataset openDataset(const std::string& name, const std::string& file, GdalErrors& errors) {
    // Read-only, and no .aux.xml written beside the input.
    CPLSetThreadLocalConfigOption("GDAL_PAM_ENABLED", "NO");
    Dataset ds(GDALDataset::Open(name.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, kDrivers, nullptr, nullptr));
    CPLSetThreadLocalConfigOption("GDAL_PAM_ENABLED", nullptr);
    if (!ds)
        throw InputError(SourceLoc{file}, "not a readable elevation raster (GeoTIFF, BAG, NetCDF, ESRI ASCII grid, or "
                                          "another raster format GDAL reads: ENVI, Erdas Imagine, Surfer, XYZ, PNG): " +
                                              errors.message());
    return ds;
}

// A NetCDF/HDF file with several variables opens as subdatasets: the one named by `variable`.
Dataset openVariable(Dataset ds, const std::string& file, const RasterOptions& opt, GdalErrors& errors) {
    char** sub = ds->GetMetadata("SUBDATASETS");
    std::vector<std::pair<std::string, std::string>> vars;  // (variable, GDAL name)
    for (int k = 1;; ++k) {
        const char* n = CSLFetchNameValue(sub, fmt::format("SUBDATASET_{}_NAME", k).c_str());
        if (!n) break;
        const std::string s = n;
        vars.emplace_back(s.substr(s.find_last_of(":/") + 1), s);
    }
    std::string names;
    for (const auto& v : vars) names += (names.empty() ? "" : ", ") + v.first;
    if (ds->GetRasterCount() > 0 && (opt.variable.empty() || vars.empty())) {
        const char* v = ds->GetRasterBand(1)->GetMetadataItem("NETCDF_VARNAME");
        if (!opt.variable.empty() && (!v || opt.variable != v))
            throw InputError(SourceLoc{file}, fmt::format("variable = '{}' but the file holds one raster{}", opt.variable,
                                                          v ? fmt::format(", variable '{}'", v) : std::string()));
        return ds;
    }
    if (vars.empty()) throw InputError(SourceLoc{file}, "the file holds no raster bands");
    if (opt.variable.empty())
        throw InputError(SourceLoc{file}, fmt::format("the file holds {} variables ({}); name the elevation with the "
                                                      "raster key 'variable'", vars.size(), names));
    for (const auto& v : vars)
        if (v.first == opt.variable) return openDataset(v.second, file, errors);
    throw InputError(SourceLoc{file},
                     fmt::format("variable = '{}' is not in the file; it holds: {}", opt.variable, names));
}

// Metres per unit of a band's unit type ("m", "ft", "US survey foot", ...); empty = metres.
double verticalUnit(const std::string& unitType, const std::string& file) {
    std::string u;
    for (char c : unitType) u += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (u.empty() || u == "m" || u == "metre" || u == "meter" || u == "metres" || u == "meters") return 1.0;
    if (u == "ft" || u == "foot" || u == "feet" || u == "international foot") return 0.3048;
    if (u == "us-ft" || u == "ftus" || u == "us survey foot" || u == "foot_us" || u == "us_survey_foot")
        return 1200.0 / 3937.0;
    throw InputError(SourceLoc{file}, fmt::format("the elevation band's unit is '{}', which is not a length unit "
                                                  "Littoral converts (m, ft, US survey foot)",
                                                  unitType));
}

std::vector<double> readBand(GDALRasterBand& band, long nx, long ny, const std::string& file, GdalErrors& errors) {
    std::vector<double> z(size_t(nx) * size_t(ny));
    if (band.RasterIO(GF_Read, 0, 0, int(nx), int(ny), z.data(), int(nx), int(ny), GDT_Float64, 0, 0, nullptr) !=
        CE_None)
        throw InputError(SourceLoc{file}, "cannot read the raster's samples: " + errors.message());
    return z;
}

// Values as stored -> band scale/offset and unit (metres); NODATA and non-finite samples marked.
void convertSamples(GDALRasterBand& band, const std::string& file, SourceRaster& src) {
    int has = 0;
    const double nd = band.GetNoDataValue(&has);
    if (has) src.nodata = nd;
    const double scale = band.GetScale(), offset = band.GetOffset();
    const double unit = verticalUnit(band.GetUnitType() ? band.GetUnitType() : "", file);
    src.missing.assign(src.z.size(), false);
    for (size_t k = 0; k < src.z.size(); ++k) {
        double& v = src.z[k];
        const bool isNodata = src.nodata && (std::isnan(*src.nodata) ? std::isnan(v) : v == *src.nodata);
        if (isNodata || !std::isfinite(v)) src.missing[k] = true;
        else v = (scale * v + offset) * unit;
    }
}

// What reading one band costs, refused before GDAL allocates any of it: the samples as double plus
// their missing-flags, and GDAL's own working set -- the band's blocks held in its block cache (at
// most GDAL_CACHEMAX of them), but never less than one whole block. A pixel-interleaved file
// (GeoTIFF PLANARCONFIG=CONTIG, ENVI BIP) decodes every band of a block to read one, so a file
// declaring 65 000 interleaved bands needs 65 000 times the block (found by fuzz_raster).
double decodingBytes(GDALDataset& ds, GDALRasterBand& band) {
    const double samples = double(ds.GetRasterXSize()) * double(ds.GetRasterYSize());
    int bx = 0, by = 0;
    band.GetBlockSize(&bx, &by);
    const char* il = ds.GetMetadataItem("INTERLEAVE", "IMAGE_STRUCTURE");
    const double bandsDecoded = il && std::string_view(il) == "PIXEL" ? std::max(1, ds.GetRasterCount()) : 1.0;
    const double sampleBytes = std::max(1, GDALGetDataTypeSizeBytes(band.GetRasterDataType())) * bandsDecoded;
    const double block = double(std::max(bx, 1)) * double(std::max(by, 1)) * sampleBytes;
    const double cached = std::min(samples * sampleBytes, double(GDALGetCacheMax64()));
    return 9.0 * samples + std::max(block, cached);
}

std::string formatName(GDALDataset& ds) {
    const std::string d = ds.GetDriver() ? ds.GetDriver()->GetDescription() : "";
    if (d == "GTiff" || d == "COG") return "GeoTIFF";
    return d.empty() ? "raster" : d;
}

void readCrs(GDALDataset& ds, SourceRaster& src) {
    const OGRSpatialReference* srs = ds.GetSpatialRef();
    // A system that is neither geographic nor projected (a GeoTIFF saying "projected" without
    // naming the projection, a local engineering system) cannot be related to the Earth: it
    // counts as undeclared, and places like one.
    if (!srs || srs->IsEmpty() || !(srs->IsGeographic() || srs->IsProjected())) return;
    char* wkt = nullptr;
    const char* opts[] = {"FORMAT=WKT2", nullptr};
    if (srs->exportToWkt(&wkt, opts) == OGRERR_NONE && wkt) src.wkt = wkt;
    CPLFree(wkt);
    src.crsName = srs->GetName() ? srs->GetName() : "";
}

OGRSpatialReference spatialRef(const SourceRaster& src) {
    OGRSpatialReference s;
    s.importFromWkt(src.wkt.c_str());
    s.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    return s;
}

}  // namespace

SourceRaster readGdalRaster(const std::string& gdalName, const std::string& file, const RasterOptions& opt) {
    registerOnce();
    // HDF5 and libpng print their own lines; the failure is the one reported below.
    return quietLibraryCall([&] {
        GdalErrors errors;
        Dataset ds = openVariable(openDataset(gdalName, file, errors), file, opt, errors);
        SourceRaster src;
        src.nx = ds->GetRasterXSize();
        src.ny = ds->GetRasterYSize();
        src.format = formatName(*ds);
        src.channel = opt.channel;
        if (src.nx < 2 || src.ny < 2)
            throw InputError(SourceLoc{file},
                             fmt::format("raster is {} x {}; need a 2D grid of at least 2 x 2", src.nx, src.ny));
        const int bands = ds->GetRasterCount();
        if (opt.channel < 0 || opt.channel >= bands)
            throw InputError(SourceLoc{file}, fmt::format("channel = {} but the raster has {} band(s) (0..{})",
                                                          opt.channel, bands, bands - 1));
        requireMemory(decodingBytes(*ds, *ds->GetRasterBand(opt.channel + 1)),
                      fmt::format("decoding an elevation raster of {} x {} samples ({} band(s)) would", src.nx, src.ny,
                                  bands),
                      SourceLoc{file});
        double gt[6];
        src.hasGeotransform = ds->GetGeoTransform(gt) == CE_None;
        if (src.hasGeotransform) std::copy(gt, gt + 6, src.gt.begin());
        readCrs(*ds, src);
        GDALRasterBand& band = *ds->GetRasterBand(opt.channel + 1);
        src.z = readBand(band, src.nx, src.ny, file, errors);
        convertSamples(band, file, src);
        return src;
    });
}

void readPrjSidecar(const std::filesystem::path& asciiPath, SourceRaster& src) {
    std::filesystem::path prj = asciiPath;
    prj.replace_extension(".prj");
    if (!std::filesystem::is_regular_file(prj)) return;
    noteInput(prj);
    const std::string text = readTextFile(prj);
    registerOnce();
    GdalErrors errors;
    OGRSpatialReference s;
    char** lines = CSLTokenizeString2(text.c_str(), "\r\n", 0);
    const OGRErr err = s.importFromESRI(lines);
    CSLDestroy(lines);
    if (err != OGRERR_NONE || s.IsEmpty())
        throw InputError(SourceLoc{prj.string()}, "not a coordinate system (ESRI WKT) GDAL can read: " + errors.message());
    char* wkt = nullptr;
    const char* opts[] = {"FORMAT=WKT2", nullptr};
    s.exportToWkt(&wkt, opts);
    src.wkt = wkt ? wkt : "";
    CPLFree(wkt);
    src.crsName = s.GetName() ? s.GetName() : "";
}

bool isProjectedMetres(const SourceRaster& src, std::string* why) {
    if (src.wkt.empty()) return true;
    const OGRSpatialReference s = spatialRef(src);
    if (s.IsGeographic()) {
        *why = fmt::format("its coordinate system ({}) is geographic (degrees)", src.crsName);
        return false;
    }
    if (s.IsGeocentric()) {
        *why = fmt::format("its coordinate system ({}) is geocentric", src.crsName);
        return false;
    }
    const char* unit = nullptr;
    const double m = s.GetLinearUnits(&unit);
    if (std::abs(m - 1.0) > 1e-12) {
        *why = fmt::format("its coordinate system ({}) counts in {} ({} m), not metres", src.crsName,
                           unit ? unit : "another unit", m);
        return false;
    }
    return true;
}

bool isFramesUtm(const SourceRaster& src, const GeoFrame& frame) {
    if (frame.kind() != GeoFrame::Kind::Utm) return false;
    if (src.wkt.empty()) return true;
    const OGRSpatialReference s = spatialRef(src);
    int north = 0;
    const int zone = s.IsProjected() ? s.GetUTMZone(&north) : 0;
    if (zone != frame.zone() || bool(north) != frame.originUtm().north) return false;
    // WGS 84 (a = 6378137, 1/f = 298.257223563) or GRS80 (NAD83, ETRS89; 1/f = 298.257222101): the
    // ellipsoids differ by 0.1 mm in the semi-minor axis. The datum shift between them (about 1 m)
    // is not applied, as PROJ does not apply it without a grid either.
    OGRErr e = OGRERR_NONE;
    const double a = s.GetSemiMajor(&e), invF = s.GetInvFlattening(&e);
    return std::abs(a - 6378137.0) < 1e-3 && std::abs(invF - 298.2572) < 1e-3 && std::abs(s.GetLinearUnits() - 1) < 1e-12;
}

namespace {

// The raster's sample-centre boundary in the scene frame, four edges of points (i, j) indices.
struct FrameEdges {
    std::array<std::vector<Point3>, 4> edge;  // j = 0 (first row), i = nx-1, j = ny-1, i = 0
};

class ToFrame {
public:
    ToFrame(const SourceRaster& src, const GeoFrame& frame, const std::string& file) : src_(src), frame_(frame) {
        OGRSpatialReference wgs84;
        wgs84.SetWellKnownGeogCS("WGS84");
        wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
        const OGRSpatialReference s = spatialRef(src);
        toFile_.reset(OGRCreateCoordinateTransformation(&wgs84, &s));
        fromFile_.reset(OGRCreateCoordinateTransformation(&s, &wgs84));
        if (!toFile_ || !fromFile_)
            throw InputError(SourceLoc{file}, fmt::format("no transformation from its coordinate system ({}) to WGS 84",
                                                          src.crsName));
        if (!GDALInvGeoTransform(const_cast<double*>(src.gt.data()), inv_.data()))
            throw InputError(SourceLoc{file}, "the raster's geotransform is singular");
    }
    // Sample-index coordinates (i, j) (centres at integers) -> local frame.
    Point3 local(double i, double j, const std::string& file) const {
        double x = src_.gt[0] + (i + 0.5) * src_.gt[1] + (j + 0.5) * src_.gt[2];
        double y = src_.gt[3] + (i + 0.5) * src_.gt[4] + (j + 0.5) * src_.gt[5];
        if (!fromFile_->Transform(1, &x, &y))
            throw InputError(SourceLoc{file}, fmt::format("sample ({}, {}) cannot be transformed to WGS 84", i + 1, j + 1));
        return frame_.toLocal(y, x, 0);
    }
    // Local points of one row of the frame -> sample-index coordinates (in place in u, v).
    bool indices(std::vector<double>& u, std::vector<double>& v) const {
        for (size_t k = 0; k < u.size(); ++k) {
            const Geodetic g = frame_.toGeodetic(u[k], v[k], 0);
            u[k] = g.lonDeg;
            v[k] = g.latDeg;
        }
        if (!toFile_->Transform(int(u.size()), u.data(), v.data())) return false;
        for (size_t k = 0; k < u.size(); ++k) {
            const double X = u[k], Y = v[k];
            u[k] = inv_[0] + X * inv_[1] + Y * inv_[2] - 0.5;
            v[k] = inv_[3] + X * inv_[4] + Y * inv_[5] - 0.5;
        }
        return true;
    }

private:
    struct CtDeleter {
        void operator()(OGRCoordinateTransformation* c) const { OGRCoordinateTransformation::DestroyCT(c); }
    };
    const SourceRaster& src_;
    const GeoFrame& frame_;
    std::unique_ptr<OGRCoordinateTransformation, CtDeleter> toFile_, fromFile_;
    std::array<double, 6> inv_{};
};

// The largest north-up rectangle inside the raster's sample-centre footprint, taken from the four
// edges mapped into the frame (each near a straight line: a raster turned by up to a few degrees,
// as another UTM zone or degrees of longitude and latitude are).
Extent inscribedRectangle(const SourceRaster& src, const ToFrame& to, const std::string& file) {
    constexpr int kPerEdge = 64;
    std::array<std::vector<Point3>, 4> e;
    const double I = double(src.nx - 1), J = double(src.ny - 1);
    for (int k = 0; k <= kPerEdge; ++k) {
        const double t = double(k) / kPerEdge;
        e[0].push_back(to.local(t * I, 0, file));
        e[1].push_back(to.local(I, t * J, file));
        e[2].push_back(to.local(t * I, J, file));
        e[3].push_back(to.local(0, t * J, file));
    }
    std::array<double, 4> mx{}, my{};
    for (int s = 0; s < 4; ++s) {
        for (const Point3& p : e[s]) mx[s] += p.x / e[s].size(), my[s] += p.y / e[s].size();
    }
    const int left = int(std::min_element(mx.begin(), mx.end()) - mx.begin());
    const int right = int(std::max_element(mx.begin(), mx.end()) - mx.begin());
    int bottom = -1, top = -1;
    for (int s = 0; s < 4; ++s) {
        if (s == left || s == right) continue;
        if (bottom < 0 || my[s] < my[bottom]) bottom = s;
    }
    for (int s = 0; s < 4; ++s)
        if (s != left && s != right && s != bottom) top = s;
    if (left == right || (left + 2) % 4 != right || top < 0 || my[top] <= my[bottom])
        throw InputError(SourceLoc{file}, "the raster's grid is turned by about 45 degrees or more against the scene "
                                          "frame's north; resample it north-up first");
    Extent r{-1e300, -1e300, 1e300, 1e300};
    for (const Point3& p : e[left]) r.x0 = std::max(r.x0, p.x);
    for (const Point3& p : e[right]) r.x1 = std::min(r.x1, p.x);
    for (const Point3& p : e[bottom]) r.y0 = std::max(r.y0, p.y);
    for (const Point3& p : e[top]) r.y1 = std::min(r.y1, p.y);
    if (!r.valid())
        throw InputError(SourceLoc{file}, "the raster's footprint in the scene frame holds no north-up rectangle");
    return r;
}

// The raster's spacing in the frame: the shorter step from its central sample to a neighbour.
double frameSpacing(const SourceRaster& src, const ToFrame& to, const std::string& file) {
    const double i = std::floor(0.5 * double(src.nx - 1)), j = std::floor(0.5 * double(src.ny - 1));
    const Point3 c = to.local(i, j, file), a = to.local(i + 1, j, file), b = to.local(i, j + 1, file);
    return std::min(std::hypot(a.x - c.x, a.y - c.y), std::hypot(b.x - c.x, b.y - c.y));
}

// Bilinear value at sample-index coordinates (u, v), from the samples with a non-zero weight.
double bilinearAt(const SourceRaster& src, double u, double v, const Point3& at, const std::string& file) {
    const long i = std::clamp(static_cast<long>(std::floor(u)), 0L, src.nx - 2);
    const long j = std::clamp(static_cast<long>(std::floor(v)), 0L, src.ny - 2);
    const double fu = std::clamp(u - double(i), 0.0, 1.0), fv = std::clamp(v - double(j), 0.0, 1.0);
    const double w[4] = {(1 - fu) * (1 - fv), fu * (1 - fv), (1 - fu) * fv, fu * fv};
    const long ii[4] = {i, i + 1, i, i + 1}, jj[4] = {j, j, j + 1, j + 1};
    double z = 0;
    for (int k = 0; k < 4; ++k) {
        if (w[k] == 0) continue;
        const size_t s = size_t(jj[k]) * size_t(src.nx) + size_t(ii[k]);
        if (!src.missing.empty() && src.missing[s])
            throw InputError(SourceLoc{file},
                             fmt::format("pixel (column {}, row {}; counted from 1, row 1 = the file's first), channel "
                                         "{} is NODATA or not finite, and the seabed at ({:.3f}, {:.3f}) m in the "
                                         "scene frame needs it: the terrain must be complete over the scene domain, "
                                         "fill holes before loading",
                                         ii[k] + 1, jj[k] + 1, src.channel, at.x, at.y));
        z += w[k] * src.z[s];
    }
    return z;
}

}  // namespace

Grid resampleIntoFrame(const SourceRaster& src, const GeoFrame& frame, const RasterOptions& opt,
                       const std::string& file) {
    if (!src.hasGeotransform)
        throw InputError(SourceLoc{file}, "the raster has no georeferencing (no geotransform); give its extent in the "
                                          "local frame");
    if (src.wkt.empty())
        throw InputError(SourceLoc{file},
                         "the raster declares no coordinate system (a GeoTIFF without GeoKeys, an ASCII grid without "
                         ".prj), so it cannot be placed in the scene's local tangent-plane frame; add one, or set "
                         "bathymetry.frame: utm (a raster without a system is then taken as in the scene's UTM zone)");
    const ToFrame to(src, frame, file);
    Extent r = inscribedRectangle(src, to, file);
    const double s = frameSpacing(src, to, file);
    if (opt.clip) {
        r = Extent{std::max(r.x0, opt.clip->x0 - 2 * s), std::max(r.y0, opt.clip->y0 - 2 * s),
                   std::min(r.x1, opt.clip->x1 + 2 * s), std::min(r.y1, opt.clip->y1 + 2 * s)};
        if (!r.valid()) r = inscribedRectangle(src, to, file);  // disjoint: the domain check reports it
    }
    // At the file's own spacing, from the rectangle's south-west corner (the last row and column
    // may stop short of its north and east edges by less than one step).
    Grid g;
    g.nx = static_cast<long>(std::floor(r.width() / s + 1e-9)) + 1;
    g.ny = static_cast<long>(std::floor(r.height() / s + 1e-9)) + 1;
    if (g.nx < 2 || g.ny < 2)
        throw InputError(SourceLoc{file}, fmt::format("the raster's footprint in the scene frame ({:.4g} x {:.4g} m) "
                                                      "holds less than two samples at its spacing {:.4g} m",
                                                      r.width(), r.height(), s));
    requireMemory(8.0 * double(g.nx) * double(g.ny) + 32.0 * double(g.nx),
                  fmt::format("the raster resampled into the scene frame ({} x {} samples at {:.4g} m) would", g.nx,
                              g.ny, s),
                  SourceLoc{file});
    g.dx = g.dy = s;
    g.xc0 = r.x0;
    g.yTop = r.y0 + double(g.ny - 1) * s;
    g.z.resize(size_t(g.nx) * size_t(g.ny));
    std::vector<double> u(size_t(g.nx)), v(size_t(g.nx));
    constexpr double kSlack = 1e-6;  // samples: the rectangle is inside the footprint up to rounding
    for (long j = 0; j < g.ny; ++j) {
        const double y = g.yTop - double(j) * g.dy;
        for (long i = 0; i < g.nx; ++i) u[size_t(i)] = g.xc0 + double(i) * g.dx, v[size_t(i)] = y;
        if (!to.indices(u, v))
            throw InputError(SourceLoc{file}, fmt::format("row {} of the scene-frame grid cannot be transformed into "
                                                          "the raster's coordinate system",
                                                          j + 1));
        for (long i = 0; i < g.nx; ++i) {
            const double ui = u[size_t(i)], vi = v[size_t(i)];
            const Point3 at{g.xc0 + double(i) * g.dx, y, 0};
            if (!(ui >= -kSlack && vi >= -kSlack && ui <= double(src.nx - 1) + kSlack &&
                  vi <= double(src.ny - 1) + kSlack))
                throw InputError(SourceLoc{file},
                                 fmt::format("the point ({:.3f}, {:.3f}) m of the scene frame falls outside the "
                                             "raster's samples (at column {:.2f}, row {:.2f}); its footprint is not a "
                                             "near-rectangle in the scene frame",
                                             at.x, at.y, ui + 1, vi + 1));
            g.z[size_t(j) * size_t(g.nx) + size_t(i)] = bilinearAt(src, ui, vi, at, file);
        }
    }
    return g;
}

}  // namespace littoral::bathymetry::detail
