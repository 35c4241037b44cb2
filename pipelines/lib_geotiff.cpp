// Georeferenced rasters through GDAL (docs/outputs.md, "Georeferencing"): where each sensor's image
// lies in the scene's projected CRS, the ENVI header lines that say so, and the GeoTIFF.
//
// The CRS is the scene frame's own: UTM (EPSG 326zz / 327zz) for a `utm` frame; for a
// `local-cartesian` frame the ellipsoidal orthographic projection about the origin, which maps a
// point on the ellipsoid to its east and north coordinates in the tangent frame there (EPSG method
// 9840; PROJ's ellipsoidal `ortho`). Pixels are mapped onto the plane z = 0 of the scene: corner
// points of the pixel grid are intersected with it, taken to WGS84 through the scene's GeoFrame
// (GeographicLib) and projected into the CRS by GDAL/PROJ. Orthographic views and pinholes looking
// straight down project that plane affinely (a 6-term geotransform, from three corners); other
// views get a grid of ground control points (GeoTIFF tie points) instead.
#include <array>
#include <cmath>
#include <memory>
#include <optional>

#include <cpl_conv.h>
#include <cpl_vsi.h>
#include <fmt/format.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include "bathymetry/geo_frame.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "pipelines/lib_geo_layers.h"
#include "render/camera.h"
#include "render/image_output.h"

namespace littoral::pipelines {
namespace {

constexpr int kGcpGrid = 9;  // ground control points per image side for oblique views

OGRSpatialReference crsOf(const ir::GeoReference& g, const bathymetry::GeoFrame& frame) {
    OGRSpatialReference srs;
    srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    if (g.frame == "utm") {
        const bathymetry::UtmCoord o = frame.originUtm();
        if (srs.importFromEPSG((o.north ? 32600 : 32700) + o.zone) != OGRERR_NONE)
            throw InternalError(fmt::format("GDAL: no CRS for UTM zone {}{}", o.zone, o.north ? "N" : "S"));
    } else {
        srs.SetProjCS(fmt::format("Littoral local tangent plane about {:.9f} {:.9f}", g.latitudeDeg, g.longitudeDeg).c_str());
        srs.SetWellKnownGeogCS("WGS84");
        srs.SetOrthographic(g.latitudeDeg, g.longitudeDeg, 0.0, 0.0);
        srs.SetLinearUnits(SRS_UL_METER, 1.0);
    }
    return srs;
}

// From the scene frame's plane z = 0 to the CRS: through WGS84, point by point.
class PlaneToCrs {
public:
    PlaneToCrs(const ir::GeoReference& g) : frame_(geoFrameOf(g)), crs_(crsOf(g, frame_)) {
        wgs84_.SetWellKnownGeogCS("WGS84");
        wgs84_.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
        ct_.reset(OGRCreateCoordinateTransformation(&wgs84_, &crs_));
        if (!ct_) throw InternalError("GDAL: no transformation from WGS84 to the scene's CRS");
    }
    std::array<double, 2> operator()(double x, double y) const {
        const bathymetry::Geodetic p = frame_.toGeodetic(x, y, 0.0);
        double cx = p.lonDeg, cy = p.latDeg;
        if (!ct_->Transform(1, &cx, &cy)) throw InternalError("GDAL: a point of the scene does not project into its CRS");
        return {cx, cy};
    }
    const OGRSpatialReference& crs() const { return crs_; }
    std::string describe() const { return frame_.describe(); }

private:
    bathymetry::GeoFrame frame_;
    OGRSpatialReference crs_, wgs84_;
    std::unique_ptr<OGRCoordinateTransformation> ct_;
};

// Where the ray through pixel coordinates (u, v) (corner (0, 0) top left) meets z = 0, if it does.
std::optional<std::array<double, 2>> onPlane(const render::Camera& cam, double u, double v) {
    const Ray r = cam.generateRay(u, v);
    if (!(r.d.z < -1e-9) || !(r.o.z > 0)) return std::nullopt;
    const double t = -r.o.z / r.d.z;
    return std::array<double, 2>{r.o.x + t * r.d.x, r.o.y + t * r.d.y};
}

std::string wktOf(const OGRSpatialReference& srs) {
    char* w = nullptr;
    const char* opts[] = {"FORMAT=WKT1", nullptr};
    srs.exportToWkt(&w, opts);
    std::string s = w ? w : "";
    CPLFree(w);
    return s;
}

}  // namespace

std::optional<ImageGeoreference> imageGeoreference(const ir::SceneIR& ir, const ir::Sensor& sensor) {
    if (!ir.geo) return std::nullopt;
    GDALAllRegister();
    const PlaneToCrs toCrs(*ir.geo);
    const render::Camera cam(sensor);
    ImageGeoreference g;
    g.wkt = wktOf(toCrs.crs());
    g.crsName = toCrs.crs().GetName() ? toCrs.crs().GetName() : "";
    const int W = cam.width(), H = cam.height();
    const bool straightDown = cam.forward().z < -(1.0 - 1e-12);
    if (sensor.type == ir::Sensor::Type::Orthographic || straightDown) {
        const auto p00 = onPlane(cam, 0, 0), pW0 = onPlane(cam, W, 0), p0H = onPlane(cam, 0, H);
        if (p00 && pW0 && p0H) {
            const auto a = toCrs((*p00)[0], (*p00)[1]), b = toCrs((*pW0)[0], (*pW0)[1]), c = toCrs((*p0H)[0], (*p0H)[1]);
            g.affine = true;
            g.transform = {a[0], (b[0] - a[0]) / W, (c[0] - a[0]) / H, a[1], (b[1] - a[1]) / W, (c[1] - a[1]) / H};
            return g;
        }
    }
    for (int j = 0; j < kGcpGrid; ++j)
        for (int i = 0; i < kGcpGrid; ++i) {
            const double u = W * (i + 0.5) / kGcpGrid, v = H * (j + 0.5) / kGcpGrid;
            if (const auto p = onPlane(cam, u, v)) {
                const auto q = toCrs((*p)[0], (*p)[1]);
                g.gcps.push_back({u, v, q[0], q[1]});
            }
        }
    if (g.gcps.size() < 4) return std::nullopt;  // the view hardly meets the plane: nothing to tie
    return g;
}

// The control points in GDAL's form; `ids` holds their names while the points are used.
std::vector<GDAL_GCP> gdalGcps(const ImageGeoreference& g, std::vector<std::string>& ids) {
    std::vector<GDAL_GCP> gcps(g.gcps.size());
    ids.clear();
    for (size_t k = 0; k < g.gcps.size(); ++k) ids.push_back(std::to_string(k + 1));
    for (size_t k = 0; k < g.gcps.size(); ++k) {
        gcps[k].pszId = const_cast<char*>(ids[k].c_str());
        gcps[k].pszInfo = const_cast<char*>("");
        gcps[k].dfGCPPixel = g.gcps[k].col;
        gcps[k].dfGCPLine = g.gcps[k].row;
        gcps[k].dfGCPX = g.gcps[k].x;
        gcps[k].dfGCPY = g.gcps[k].y;
        gcps[k].dfGCPZ = 0;
    }
    return gcps;
}

// ENVI's `geo points` for the control points of an oblique view: pixel and line (1-based, so the
// image's top left corner is 1, 1), latitude and longitude (ENVI's geo points are geographic): the
// points taken from the CRS to WGS84. Written here, since GDAL's ENVI driver keeps only four.
std::string enviGeoPoints(const ImageGeoreference& g) {
    OGRSpatialReference crs, wgs84;
    crs.importFromWkt(g.wkt.c_str());
    crs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    wgs84.SetWellKnownGeogCS("WGS84");
    wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    std::unique_ptr<OGRCoordinateTransformation> ct(OGRCreateCoordinateTransformation(&crs, &wgs84));
    if (!ct) throw InternalError("GDAL: no transformation from the scene's CRS to WGS84");
    std::string lines = "geo points = {\n";
    for (size_t k = 0; k < g.gcps.size(); ++k) {
        double lon = g.gcps[k].x, lat = g.gcps[k].y;
        if (!ct->Transform(1, &lon, &lat)) throw InternalError("GDAL: a control point did not reach WGS84");
        // 1e-10 deg: 0.01 mm on the ground
        lines += fmt::format(" {:.6f}, {:.6f}, {:.10f}, {:.10f}{}\n", g.gcps[k].col + 1, g.gcps[k].row + 1, lat, lon,
                             k + 1 < g.gcps.size() ? "," : "}");
    }
    return lines;
}

std::string enviGeoHeaderLines(const ImageGeoreference& g) {
    if (!g.affine) return enviGeoPoints(g);
    // GDAL's ENVI driver writes the header lines for this transform and CRS (map info with its
    // rotation convention, coordinate system string); they are taken from a 1-band dataset in memory.
    GDALAllRegister();
    GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("ENVI");
    if (!drv) throw InternalError("GDAL has no ENVI driver");
    const std::string path = fmt::format("/vsimem/littoral_envi_{}.img", static_cast<const void*>(&g));
    {
        GDALDataset* ds = drv->Create(path.c_str(), 1, 1, 1, GDT_Float32, nullptr);
        if (!ds) throw InternalError("GDAL: cannot create an ENVI dataset in memory");
        std::array<double, 6> t = g.transform;
        ds->SetGeoTransform(t.data());
        ds->SetProjection(g.wkt.c_str());
        GDALClose(ds);
    }
    const std::string hdr = fmt::format("/vsimem/littoral_envi_{}.hdr", static_cast<const void*>(&g));
    vsi_l_offset size = 0;
    GByte* buf = VSIGetMemFileBuffer(hdr.c_str(), &size, FALSE);
    const std::string text = buf ? std::string(reinterpret_cast<const char*>(buf), size) : std::string();
    VSIUnlink(path.c_str());
    VSIUnlink(hdr.c_str());
    std::string lines;
    size_t pos = 0;
    while (pos < text.size()) {
        size_t end = text.find('\n', pos);
        if (end == std::string::npos) end = text.size();
        // A field may run over several lines until its closing brace.
        std::string field = text.substr(pos, end - pos);
        while (field.find('{') != std::string::npos && field.find('}') == std::string::npos && end < text.size()) {
            const size_t next = text.find('\n', end + 1);
            field += "\n" + text.substr(end + 1, (next == std::string::npos ? text.size() : next) - end - 1);
            end = next == std::string::npos ? text.size() : next;
        }
        for (const char* key : {"map info", "coordinate system string", "projection info"})
            if (field.rfind(key, 0) == 0) lines += field + "\n";
        pos = end + 1;
    }
    if (lines.find("map info") == std::string::npos) throw InternalError("GDAL wrote no ENVI map info");
    return lines;
}

std::string enviGeoHeaderLines(const ir::SceneIR& ir, const ir::Sensor& sensor) {
    const auto g = imageGeoreference(ir, sensor);
    return g ? enviGeoHeaderLines(*g) : "";
}

void writeGeoTiff(const std::filesystem::path& path, const render::Film& film, const ImageGeoreference& g,
                  const std::string& description) {
    GDALAllRegister();
    GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("GTiff");
    if (!drv) throw InternalError("GDAL has no GTiff driver");
    const std::string mem = fmt::format("/vsimem/littoral_{}.tif", static_cast<const void*>(&film));
    const char* opts[] = {"COMPRESS=DEFLATE", "PREDICTOR=3", "INTERLEAVE=BAND", nullptr};
    GDALDataset* ds = drv->Create(mem.c_str(), film.width, film.height, film.bandCount(), GDT_Float32,
                                  const_cast<char**>(opts));
    if (!ds) throw InternalError("GDAL: cannot create a GeoTIFF in memory");
    OGRSpatialReference srs;
    srs.importFromWkt(g.wkt.c_str());
    if (g.affine) {
        std::array<double, 6> t = g.transform;
        ds->SetGeoTransform(t.data());
        ds->SetSpatialRef(&srs);
    } else {
        std::vector<std::string> ids;
        const std::vector<GDAL_GCP> gcps = gdalGcps(g, ids);
        ds->SetGCPs(static_cast<int>(gcps.size()), gcps.data(), &srs);
    }
    ds->SetMetadataItem("TIFFTAG_IMAGEDESCRIPTION", description.c_str());
    ds->SetMetadataItem("LITTORAL_UNITS", "W m^-2 sr^-1 um^-1");
    for (int b = 0; b < film.bandCount(); ++b) {
        GDALRasterBand* band = ds->GetRasterBand(b + 1);
        band->SetDescription(fmt::format("{:g}-{:g} um", film.bands[b].lo, film.bands[b].hi).c_str());
        band->SetMetadataItem("wavelength_um", fmt::format("{:g}", film.bands[b].center()).c_str());
        band->SetMetadataItem("fwhm_um", fmt::format("{:g}", film.bands[b].width()).c_str());
        band->SetUnitType("W m^-2 sr^-1 um^-1");
        const std::vector<float> plane = film.bandPlane(b);
        if (band->RasterIO(GF_Write, 0, 0, film.width, film.height, const_cast<float*>(plane.data()), film.width,
                           film.height, GDT_Float32, 0, 0) != CE_None) {
            GDALClose(ds);
            VSIUnlink(mem.c_str());
            throw InternalError("GDAL: writing a GeoTIFF band failed");
        }
    }
    GDALClose(ds);
    vsi_l_offset size = 0;
    GByte* buf = VSIGetMemFileBuffer(mem.c_str(), &size, FALSE);
    const std::string bytes = buf ? std::string(reinterpret_cast<const char*>(buf), size) : std::string();
    VSIUnlink(mem.c_str());
    if (bytes.empty()) throw InternalError("GDAL wrote an empty GeoTIFF");
    writeFileAtomic(path, bytes);
}

}  // namespace littoral::pipelines
