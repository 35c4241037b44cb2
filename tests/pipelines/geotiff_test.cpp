// Georeferenced rasters (pipelines/lib_geotiff.cpp), read back by GDAL: NAME.tif (GeoTIFF) and
// NAME.img with its ENVI map info put the image's corners where an independent computation from
// the scene origin puts them, within 0.01 pixel. The independent side: the corners of a nadir
// frame view on the plane z = 0 (the GSD times half the image, about the target), taken to WGS84
// with GeographicLib directly (LocalCartesian about the origin, or the UTM zone's transverse
// Mercator), against GDAL's own reading of each file: its geotransform (or control points) and
// CRS, transformed to WGS84 by GDAL/PROJ. Distances are compared in metres on the ellipsoid.
#include <cmath>
#include <fstream>
#include <string>

#include <GeographicLib/LocalCartesian.hpp>
#include <GeographicLib/UTMUPS.hpp>
#include <fmt/format.h>
#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <ogr_spatialref.h>

#include "core/atomic_file.h"
#include "render/camera.h"
#include "core/scene_ir.h"
#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using namespace littoral;
using namespace littoral::testing_support;

namespace {

constexpr double kLat0 = 36.1833, kLon0 = -75.75;
constexpr int kGeoW = 40, kGeoH = 30;
constexpr double kGsd = 0.1;

std::string scene(const std::string& origin, const std::string& sensor) {
    return "scene: {name: geotiff, " + origin + "domain: {x: [-10, 10], y: [-10, 10]}}\n"
           "sun: {zenith_deg: 30, irradiance: 1000}\n"
           "sky: {radiance: 10}\n"
           "bathymetry: {type: planar_slope, z0_m: 0, material: floor}\n"
           "materials: [{name: floor, reflectance: 0.3}]\n"
           "sensors:\n  - " + sensor + "\n"
           "render: {bands: [[0.5, 0.55], [0.6, 0.65]], hemisphere_samples: 2}\n";
}

std::string nadirSensor() {
    return fmt::format("{{name: cam, type: frame, elevation_deg: 90, azimuth_deg: 0, range_m: 100, gsd_m: {}, width: {}, "
                       "height: {}, target: [1.5, -2, 0]}}",
                       kGsd, kGeoW, kGeoH);
}

struct LatLon {
    double lat, lon;
};

// Metres between two nearby points on the WGS84 ellipsoid (radii of curvature at the first).
double metresApart(const LatLon& a, const LatLon& b) {
    const double A = 6378137.0, e2 = 0.00669437999014, s = std::sin(a.lat * M_PI / 180);
    const double n = A / std::sqrt(1 - e2 * s * s), m = A * (1 - e2) / std::pow(1 - e2 * s * s, 1.5);
    return std::hypot((b.lat - a.lat) * M_PI / 180 * m, (b.lon - a.lon) * M_PI / 180 * n * std::cos(a.lat * M_PI / 180));
}

// GDAL's reading of a georeferenced raster: pixel corner (col, row) -> WGS84.
class GdalReading {
public:
    explicit GdalReading(const fs::path& file) {
        GDALAllRegister();
        ds_ = static_cast<GDALDataset*>(GDALOpen(file.c_str(), GA_ReadOnly));
        if (!ds_) return;
        const OGRSpatialReference* srs = ds_->GetGCPCount() > 0 ? ds_->GetGCPSpatialRef() : ds_->GetSpatialRef();
        if (!srs) return;
        crs_ = *srs;
        crs_.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
        wgs84_.SetWellKnownGeogCS("WGS84");
        wgs84_.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
        ct_.reset(OGRCreateCoordinateTransformation(&crs_, &wgs84_));
        hasTransform_ = ds_->GetGeoTransform(t_) == CE_None;
    }
    ~GdalReading() {
        if (ds_) GDALClose(ds_);
    }
    bool ok() const { return ds_ && ct_; }
    bool hasTransform() const { return hasTransform_; }
    GDALDataset* dataset() const { return ds_; }
    LatLon crsToWgs84(double x, double y) const {
        ct_->Transform(1, &x, &y);
        return {y, x};
    }
    LatLon corner(double col, double row) const {
        return crsToWgs84(t_[0] + col * t_[1] + row * t_[2], t_[3] + col * t_[4] + row * t_[5]);
    }

private:
    GDALDataset* ds_ = nullptr;
    OGRSpatialReference crs_, wgs84_;
    std::unique_ptr<OGRCoordinateTransformation> ct_;
    double t_[6] = {0, 1, 0, 0, 0, 1};
    bool hasTransform_ = false;
};

// The four corners of the nadir view: target (1.5, -2) +- half the image in GSDs, north up.
std::vector<std::pair<std::array<double, 2>, std::array<double, 2>>> nadirCorners() {
    std::vector<std::pair<std::array<double, 2>, std::array<double, 2>>> c;
    for (int j : {0, 1})
        for (int i : {0, 1})
            c.push_back({{double(i * kGeoW), double(j * kGeoH)}, {1.5 + (i - 0.5) * kGeoW * kGsd, -2.0 - (j - 0.5) * kGeoH * kGsd}});
    return c;
}

void expectCorners(const GdalReading& g, const std::function<LatLon(double, double)>& independent, const std::string& what) {
    ASSERT_TRUE(g.ok()) << what;
    ASSERT_TRUE(g.hasTransform()) << what;
    double worst = 0;
    for (const auto& [pixel, xy] : nadirCorners()) {
        const LatLon got = g.corner(pixel[0], pixel[1]), want = independent(xy[0], xy[1]);
        const double d = metresApart(want, got);
        worst = std::max(worst, d);
        EXPECT_LT(d, 0.01 * kGsd) << what << " corner " << pixel[0] << "," << pixel[1];
    }
    std::printf("[ %s ] worst corner %.2e m (%.2e px)\n", what.c_str(), worst, worst / kGsd);
}

}  // namespace

// A local-cartesian origin: the GeoTIFF and the ENVI header in the orthographic CRS about it.
TEST(GeoTiff, NadirCornersLieWhereTheOriginPutsThem) {
    const fs::path dir = scratchDir("geotiff", "local");
    const fs::path file = writeTextFile(
        dir, "scene.yaml", scene(fmt::format("origin: {{latitude: {}, longitude: {}, altitude: 12}}, ", kLat0, kLon0), nadirSensor()));
    const auto r = runLittoral("-q run " + file.string() + " --out " + (dir / "out").string());
    ASSERT_EQ(r.status, 0) << r.output;
    const GeographicLib::LocalCartesian lc(kLat0, kLon0, 12.0);
    auto independent = [&](double x, double y) {
        double lat, lon, h;
        lc.Reverse(x, y, 0.0, lat, lon, h);
        return LatLon{lat, lon};
    };
    const GdalReading tif(dir / "out" / "cam.tif");
    expectCorners(tif, independent, "GeoTIFF, local tangent plane");
    ASSERT_TRUE(tif.ok());
    EXPECT_EQ(tif.dataset()->GetRasterCount(), 2);
    EXPECT_EQ(tif.dataset()->GetRasterXSize(), kGeoW);
    EXPECT_STREQ(tif.dataset()->GetRasterBand(1)->GetMetadataItem("wavelength_um"), "0.525");
    // The GeoTIFF holds the radiance image itself.
    float v = 0;
    ASSERT_EQ(tif.dataset()->GetRasterBand(2)->RasterIO(GF_Read, 3, 4, 1, 1, &v, 1, 1, GDT_Float32, 0, 0), CE_None);
    const GdalReading envi(dir / "out" / "cam.img");
    expectCorners(envi, independent, "ENVI map info, local tangent plane");
    float e = 0;
    ASSERT_EQ(envi.dataset()->GetRasterBand(2)->RasterIO(GF_Read, 3, 4, 1, 1, &e, 1, 1, GDT_Float32, 0, 0), CE_None);
    EXPECT_EQ(v, e);
    const std::string hdr = littoral::readTextFile(dir / "out" / "cam.hdr");
    EXPECT_NE(hdr.find("map info = {"), std::string::npos) << hdr;
    EXPECT_NE(hdr.find("coordinate system string = {"), std::string::npos) << hdr;
    EXPECT_NE(hdr.find("wavelength = {0.525, 0.625}"), std::string::npos) << hdr;
}

// A UTM frame (the IR's geo.frame, as a raster bathymetry in UTM sets it; here edited into the IR
// and rendered with `render`): EPSG 326xx and the zone's transverse Mercator.
TEST(GeoTiff, UtmFrameUsesTheZonesCrs) {
    const fs::path dir = scratchDir("geotiff", "utm");
    const fs::path file = writeTextFile(
        dir, "scene.yaml", scene(fmt::format("origin: {{latitude: {}, longitude: {}}}, ", kLat0, kLon0), nadirSensor()));
    auto r = runLittoral("-q build " + file.string() + " --out " + (dir / "ir").string());
    ASSERT_EQ(r.status, 0) << r.output;
    auto j = nlohmann::json::parse(littoral::readTextFile(dir / "ir" / "scene.json"));
    ASSERT_TRUE(j.contains("geo")) << j.dump();
    j["geo"]["frame"] = "utm";
    j["geo"]["utm_zone"] = 18;
    std::ofstream(dir / "ir" / "scene.json") << j.dump(2);
    r = runLittoral("-q render " + (dir / "ir").string() + " --out " + (dir / "out").string());
    ASSERT_EQ(r.status, 0) << r.output;
    // Independent: the origin's UTM coordinates plus the scene's metres, back to WGS84.
    int zone;
    bool north;
    double e0, n0, gamma, k;
    GeographicLib::UTMUPS::Forward(kLat0, kLon0, zone, north, e0, n0, gamma, k, 18);
    auto independent = [&](double x, double y) {
        double lat, lon;
        GeographicLib::UTMUPS::Reverse(zone, north, e0 + x, n0 + y, lat, lon, gamma, k);
        return LatLon{lat, lon};
    };
    const GdalReading tif(dir / "out" / "cam.tif");
    expectCorners(tif, independent, "GeoTIFF, UTM 18N");
    ASSERT_TRUE(tif.ok());
    EXPECT_NE(std::string(tif.dataset()->GetProjectionRef()).find("UTM zone 18N"), std::string::npos)
        << tif.dataset()->GetProjectionRef();
    expectCorners(GdalReading(dir / "out" / "cam.img"), independent, "ENVI map info, UTM 18N");
    EXPECT_NE(littoral::readTextFile(dir / "out" / "cam.hdr").find("map info = {UTM"), std::string::npos);
}

// An oblique view is not affine: ground control points where rays meet z = 0, each at the
// position GeographicLib gives for the ray's own intersection (the camera model of render/, the
// georeferencing code not involved). The ENVI header has no map info then.
TEST(GeoTiff, ObliqueViewsCarryGroundControlPoints) {
    const fs::path dir = scratchDir("geotiff", "oblique");
    const std::string sensor =
        "{name: cam, type: frame, elevation_deg: 50, azimuth_deg: 200, range_m: 60, gsd_m: 0.1, width: 40, height: 30}";
    const fs::path file = writeTextFile(
        dir, "scene.yaml", scene(fmt::format("origin: {{latitude: {}, longitude: {}}}, ", kLat0, kLon0), sensor));
    const auto r = runLittoral("-q run " + file.string() + " --out " + (dir / "out").string());
    ASSERT_EQ(r.status, 0) << r.output;
    const GdalReading tif(dir / "out" / "cam.tif");
    ASSERT_TRUE(tif.ok());
    EXPECT_FALSE(tif.hasTransform());
    const int n = tif.dataset()->GetGCPCount();
    EXPECT_EQ(n, 81);
    const ir::SceneIR ir = ir::readIR(dir / "out" / "ir");
    const render::Camera cam(ir.sensors[0]);
    const GeographicLib::LocalCartesian lc(kLat0, kLon0, 0.0);
    // Where the ray through pixel corner (col, row) meets z = 0, by GeographicLib.
    auto onTheGround = [&](double col, double row) {
        const Ray ray = cam.generateRay(col, row);
        const double t = -ray.o.z / ray.d.z;
        LatLon p{};
        double h;
        lc.Reverse(ray.o.x + t * ray.d.x, ray.o.y + t * ray.d.y, 0.0, p.lat, p.lon, h);
        return p;
    };
    double worst = 0;
    for (int k = 0; k < n; ++k) {
        const GDAL_GCP& g = tif.dataset()->GetGCPs()[k];
        const double d = metresApart(onTheGround(g.dfGCPPixel, g.dfGCPLine), tif.crsToWgs84(g.dfGCPX, g.dfGCPY));
        worst = std::max(worst, d);
        EXPECT_LT(d, 0.01 * 0.1) << "control point " << k;
    }
    std::printf("[ oblique GCPs ] %d points, worst %.2e m\n", n, worst);
    // The ENVI header has no map info (ENVI's is affine only) but the same points as geo points
    // (latitude and longitude), which GDAL reads back as WGS84 control points.
    EXPECT_EQ(littoral::readTextFile(dir / "out" / "cam.hdr").find("map info"), std::string::npos);
    for (const char* file : {"cam.img"}) {
        GDALDataset* img = static_cast<GDALDataset*>(GDALOpen((dir / "out" / file).c_str(), GA_ReadOnly));
        ASSERT_TRUE(img) << file;
        ASSERT_EQ(img->GetGCPCount(), n) << file;
        double worstEnvi = 0;
        for (int k = 0; k < n; ++k) {
            // GDAL gives ENVI's geo points as x = longitude, y = latitude, in 0-based pixel corners.
            const GDAL_GCP& g = img->GetGCPs()[k];
            const double d = metresApart(onTheGround(g.dfGCPPixel, g.dfGCPLine), {g.dfGCPY, g.dfGCPX});
            worstEnvi = std::max(worstEnvi, d);
            EXPECT_LT(d, 0.01 * 0.1) << file << " control point " << k;
        }
        std::printf("[ oblique ENVI geo points ] %s: %d points, worst %.2e m\n", file, n, worstEnvi);
        GDALClose(img);
    }
}

// The water-leaving products and the standard-error image carry the radiance's georeferencing: GDAL
// reads the same geotransform and CRS from each of their headers as from NAME.img's (whose corners
// the tests above check against GeographicLib).
TEST(GeoTiff, ProductsAndErrorsAreGeoreferencedLikeTheRadiance) {
    const fs::path dir = scratchDir("geotiff", "products");
    std::string text = scene(fmt::format("origin: {{latitude: {}, longitude: {}}}, ", kLat0, kLon0),
                             nadirSensor().substr(0, nadirSensor().size() - 1) + ", water_products: true, samples_per_pixel: 2}");
    text = replacedOnce(text, "bathymetry: {type: planar_slope, z0_m: 0", "water: {level_m: 0}\nbathymetry: {type: planar_slope, z0_m: -2");
    const fs::path file = writeTextFile(dir, "scene.yaml", text);
    const auto r = runLittoral("-q run " + file.string() + " --out " + (dir / "out").string());
    ASSERT_EQ(r.status, 0) << r.output;
    const GdalReading radiance(dir / "out" / "cam.img");
    ASSERT_TRUE(radiance.ok() && radiance.hasTransform());
    double want[6];
    ASSERT_EQ(radiance.dataset()->GetGeoTransform(want), CE_None);
    for (const char* name : {"water_leaving", "sky_reflected", "glint", "other", "ed0", "rrs", "stderr"}) {
        const fs::path img = dir / "out" / fmt::format("cam_{}.img", name);
        const GdalReading g(img);
        ASSERT_TRUE(g.ok() && g.hasTransform()) << img;
        double got[6];
        ASSERT_EQ(g.dataset()->GetGeoTransform(got), CE_None);
        for (int k = 0; k < 6; ++k) EXPECT_EQ(got[k], want[k]) << img << " term " << k;
        EXPECT_TRUE(g.dataset()->GetSpatialRef()->IsSame(radiance.dataset()->GetSpatialRef())) << img;
    }
}

// Without scene.origin there is no GeoTIFF, and one left by an earlier run into the folder is
// removed (it would describe another scene).
TEST(GeoTiff, NoOriginNoGeoTiff) {
    const fs::path dir = scratchDir("geotiff", "none");
    const fs::path with = writeTextFile(
        dir, "with.yaml", scene(fmt::format("origin: {{latitude: {}, longitude: {}}}, ", kLat0, kLon0), nadirSensor()));
    auto r = runLittoral("-q run " + with.string() + " --out " + (dir / "out").string());
    ASSERT_EQ(r.status, 0) << r.output;
    ASSERT_TRUE(fs::exists(dir / "out" / "cam.tif"));
    const fs::path without = writeTextFile(dir, "without.yaml", scene("", nadirSensor()));
    r = runLittoral("run " + without.string() + " --out " + (dir / "out").string());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_FALSE(fs::exists(dir / "out" / "cam.tif"));
    EXPECT_EQ(littoral::readTextFile(dir / "out" / "cam.hdr").find("map info"), std::string::npos);
}
