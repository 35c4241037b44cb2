// Per-pixel georeferencing layers (NAME_geo.img, ENVI float64): for a nadir view of a scene with
// scene.origin, the centre pixel lies at the origin and a pixel 2 m east at the latitude and
// longitude that the WGS84 radii of curvature give (dlon = x / (N cos lat), N = a / sqrt(1 - e^2
// sin^2 lat), a = 6378137 m, e^2 = 0.00669437999014; second-order terms are below 1e-12 deg at
// 2 m); the view and sun angles follow from the geometry.
#include <cmath>
#include <cstring>
#include <string>

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include "core/atomic_file.h"
#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using namespace littoral::testing_support;

namespace {

std::string scene(bool origin) {
    return std::string("scene: {name: geo, ") +
           (origin ? "origin: {latitude: 36.1833, longitude: -75.75, altitude: 0}, " : "") +
           "domain: {x: [-5, 5], y: [-5, 5]}}\n"
           "sun: {zenith_deg: 30, azimuth_deg: 315, irradiance: 1000}\n"
           "sky: {radiance: 0}\n"
           "bathymetry: {type: planar_slope, z0_m: 0, material: floor}\n"
           "materials: [{name: floor, reflectance: 0.3}]\n"
           "sensors:\n"
           "  - {name: cam, type: frame, elevation_deg: 90, azimuth_deg: 0, range_m: 50, gsd_m: 1, width: 5, height: 5}\n"
           "render: {hemisphere_samples: 4}\n";
}

std::vector<double> readDoubles(const fs::path& p) {
    const std::string bytes = littoral::readTextFile(p);
    std::vector<double> v(bytes.size() / 8);
    std::memcpy(v.data(), bytes.data(), v.size() * 8);
    return v;
}

}  // namespace

TEST(GeoLayers, NadirPixelsLieWhereTheEllipsoidPutsThem) {
    const fs::path dir = scratchDir("geo_layers", "nadir");
    const fs::path file = writeTextFile(dir, "scene.yaml", scene(true));
    const auto r = runLittoral("-q run " + file.string() + " --out " + (dir / "out").string());
    ASSERT_EQ(r.status, 0) << r.output;
    const std::string hdr = littoral::readTextFile(dir / "out" / "cam_geo.hdr");
    EXPECT_NE(hdr.find("data type = 5"), std::string::npos) << hdr;
    EXPECT_NE(hdr.find("latitude_deg"), std::string::npos) << hdr;
    const std::vector<double> v = readDoubles(dir / "out" / "cam_geo.img");
    ASSERT_EQ(v.size(), 6u * 25u);
    auto at = [&](int layer, int x, int y) { return v[static_cast<size_t>(layer) * 25 + y * 5 + x]; };
    const double lat0 = 36.1833, lon0 = -75.75, a = 6378137.0, e2 = 0.00669437999014;
    const double s = std::sin(lat0 * M_PI / 180), n = a / std::sqrt(1 - e2 * s * s);
    const double m = a * (1 - e2) / std::pow(1 - e2 * s * s, 1.5);
    const double dLon = 2.0 / (n * std::cos(lat0 * M_PI / 180)) * 180 / M_PI, dLat = 2.0 / m * 180 / M_PI;
    EXPECT_NEAR(at(0, 2, 2), lat0, 1e-9);
    EXPECT_NEAR(at(1, 2, 2), lon0, 1e-9);
    EXPECT_NEAR(at(1, 4, 2), lon0 + dLon, 1e-9);  // the image's right is east
    EXPECT_NEAR(at(0, 4, 2), lat0, 1e-9);
    EXPECT_NEAR(at(0, 2, 0), lat0 + dLat, 1e-9);  // its top is north
    // View: straight down at the centre; 2 m east the sensor lies 2.29 deg off zenith, due west.
    EXPECT_NEAR(at(2, 2, 2), 0.0, 1e-6);
    EXPECT_NEAR(at(2, 4, 2), std::atan(2.0 / 50.0) * 180 / M_PI, 1e-6);
    // Due west of grid, plus the meridians' convergence on the tangent plane: true north 2 m east of
    // the tangent point is turned by dlon sin(lat) = 1.31e-5 deg.
    EXPECT_NEAR(at(3, 4, 2), 270.0 + dLon * s, 1e-7);
    EXPECT_NEAR(at(4, 0, 0), 30.0, 1e-9);
    EXPECT_NEAR(at(5, 0, 0), 315.0, 1e-4);  // true north at 3 m from the tangent point: 1e-6 deg off

    // GDAL reads the layers as written (six float64 bands, in order, the same values) and places
    // them where it places the radiance: the layers' header carries the radiance's map info.
    GDALAllRegister();
    GDALDataset* geo = static_cast<GDALDataset*>(GDALOpen((dir / "out" / "cam_geo.img").c_str(), GA_ReadOnly));
    GDALDataset* rad = static_cast<GDALDataset*>(GDALOpen((dir / "out" / "cam.img").c_str(), GA_ReadOnly));
    ASSERT_TRUE(geo && rad);
    ASSERT_EQ(geo->GetRasterCount(), 6);
    EXPECT_EQ(geo->GetRasterBand(1)->GetRasterDataType(), GDT_Float64);
    for (int b = 0; b < 6; ++b) {
        std::vector<double> band(25);
        ASSERT_EQ(geo->GetRasterBand(b + 1)->RasterIO(GF_Read, 0, 0, 5, 5, band.data(), 5, 5, GDT_Float64, 0, 0), CE_None);
        for (int k = 0; k < 25; ++k)
            if (!std::isnan(band[k])) {
                EXPECT_EQ(band[k], v[static_cast<size_t>(b) * 25 + k]) << "band " << b << " pixel " << k;
            }
    }
    double tg[6], tr[6];
    ASSERT_EQ(geo->GetGeoTransform(tg), CE_None);
    ASSERT_EQ(rad->GetGeoTransform(tr), CE_None);
    for (int k = 0; k < 6; ++k) EXPECT_DOUBLE_EQ(tg[k], tr[k]) << "geotransform term " << k;
    EXPECT_TRUE(geo->GetSpatialRef() && rad->GetSpatialRef() && geo->GetSpatialRef()->IsSame(rad->GetSpatialRef()));
    GDALClose(geo);
    GDALClose(rad);

    // Without scene.origin there is nothing to georeference.
    const fs::path dir2 = scratchDir("geo_layers", "no_origin");
    const auto r2 = runLittoral("-q run " + writeTextFile(dir2, "scene.yaml", scene(false)).string() + " --out " +
                                (dir2 / "out").string());
    ASSERT_EQ(r2.status, 0) << r2.output;
    EXPECT_FALSE(fs::exists(dir2 / "out" / "cam_geo.img"));
}
