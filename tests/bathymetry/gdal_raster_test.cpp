// Elevation rasters through GDAL: formats (GeoTIFF, BAG, NetCDF, ASCII with .prj), placement in
// the scene frame by the file's coordinate system (another UTM zone, geographic degrees, a local
// tangent plane), NODATA beyond the domain, vertical units, and hostile files.
//
// The expectations are independent of the reader's projection path: the files are filled with a
// field defined in the scene's local frame, f(x, y) = -4 + 0.1 x - 0.05 y, evaluated at each
// sample centre after converting the centre's file coordinates to latitude/longitude with
// GeographicLib (the reader uses PROJ, through GDAL, for that leg). f is linear, so bilinear
// interpolation of it is exact wherever the map from sample indices to the local frame is affine
// across a cell; its curvature over a 2 m cell moves a point by < 1e-9 m. What remains is the
// two projection libraries' disagreement, well under 1 mm; a placement error d shows as
// |grad f| d = 0.112 d, so the tolerance kTol = 1e-4 m holds positions to 0.9 mm.
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <GeographicLib/TransverseMercator.hpp>
#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <gtest/gtest.h>

#include "tests/support/test_support.h"

#include "bathymetry/geo_frame.h"
#include "bathymetry/terrain.h"
#include "core/error.h"
#include "core/resource_limits.h"

namespace lb = littoral::bathymetry;
namespace fs = std::filesystem;
using littoral::testing_support::inputErrorOf;

namespace {

constexpr double kLat = 36.18, kLon = -75.75;  // UTM zone 18 (central meridian 75 W)
constexpr double kTol = 1e-4;                  // m, see the header

double field(double x, double y) { return -4 + 0.1 * x - 0.05 * y; }

fs::path dir() {
    const fs::path d = fs::path(::testing::TempDir()) / "littoral_gdal_raster";
    fs::create_directories(d);
    return d;
}

struct RasterFile {
    std::string driver = "GTiff";
    int nx = 0, ny = 0;
    std::array<double, 6> gt{};
    std::string crs;  // "EPSG:..." or empty
    GDALDataType type = GDT_Float64;
    int bands = 1;
    // Value of band b at the sample centre (X, Y) in the file's coordinates.
    std::function<double(int b, double X, double Y)> value;
    double nodata = NAN;  // set if finite
    std::string unit;
    std::vector<std::string> options;  // creation options
};

fs::path write(const std::string& name, const RasterFile& r) {
    GDALAllRegister();
    GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
    GDALDataset* ds = mem->Create("", r.nx, r.ny, r.bands, r.type, nullptr);
    ds->SetGeoTransform(const_cast<double*>(r.gt.data()));
    if (!r.crs.empty()) {
        OGRSpatialReference s;
        s.SetFromUserInput(r.crs.c_str());
        ds->SetSpatialRef(&s);
    }
    for (int b = 1; b <= r.bands; ++b) {
        std::vector<double> v(size_t(r.nx) * size_t(r.ny));
        for (int j = 0; j < r.ny; ++j)
            for (int i = 0; i < r.nx; ++i) {
                const double X = r.gt[0] + (i + 0.5) * r.gt[1] + (j + 0.5) * r.gt[2];
                const double Y = r.gt[3] + (i + 0.5) * r.gt[4] + (j + 0.5) * r.gt[5];
                v[size_t(j) * size_t(r.nx) + size_t(i)] = r.value(b, X, Y);
            }
        GDALRasterBand* band = ds->GetRasterBand(b);
        EXPECT_EQ(band->RasterIO(GF_Write, 0, 0, r.nx, r.ny, v.data(), r.nx, r.ny, GDT_Float64, 0, 0), CE_None);
        if (std::isfinite(r.nodata)) band->SetNoDataValue(r.nodata);
        if (!r.unit.empty()) band->SetUnitType(r.unit.c_str());
    }
    std::vector<const char*> opts;
    for (const auto& o : r.options) opts.push_back(o.c_str());
    opts.push_back(nullptr);
    const fs::path path = dir() / name;
    fs::remove(path);
    GDALDriver* drv = GetGDALDriverManager()->GetDriverByName(r.driver.c_str());
    GDALDataset* out = drv->CreateCopy(path.string().c_str(), ds, FALSE, const_cast<char**>(opts.data()), nullptr, nullptr);
    EXPECT_NE(out, nullptr) << CPLGetLastErrorMsg();
    GDALClose(out);
    GDALClose(ds);
    for (const char* aux : {".aux.xml"}) fs::remove(path.string() + aux);
    return path;
}

// The field at a file's UTM sample centre: GeographicLib's inverse UTM, then the scene frame.
std::function<double(int, double, double)> utmField(int zone, const lb::GeoFrame& frame) {
    return [zone, &frame](int, double X, double Y) {
        const lb::Geodetic g = lb::fromUtm({zone, true, X, Y});
        const littoral::Point3 p = frame.toLocal(g.latDeg, g.lonDeg, 0);
        return field(p.x, p.y);
    };
}

// |terrain - f| over a grid of points inside `e`.
double maxError(const lb::Terrain& t, const lb::Extent& e) {
    double worst = 0;
    for (int a = 0; a <= 20; ++a)
        for (int b = 0; b <= 20; ++b) {
            const double x = e.x0 + e.width() * a / 20.0, y = e.y0 + e.height() * b / 20.0;
            worst = std::max(worst, std::abs(t.elevation(x, y) - field(x, y)));
        }
    return worst;
}

const lb::Extent kDomain{-50, -40, 50, 40};

// A 240 m x 200 m raster at 2 m around the site, in UTM zone `zone` (WGS 84).
RasterFile utmRaster(int zone, const lb::GeoFrame& frame) {
    const lb::UtmCoord c = lb::toUtm(kLat, kLon, zone);
    RasterFile r;
    r.nx = 120;
    r.ny = 100;
    r.gt = {std::round(c.easting) - 120, 2, 0, std::round(c.northing) + 100, 0, -2};
    r.crs = "EPSG:" + std::to_string(32600 + zone);
    r.value = utmField(zone, frame);
    return r;
}

}  // namespace

// A GeoTIFF in UTM zone 17N read into a scene whose frame is UTM zone 18N: resampled (the grids
// are turned 2.7 degrees against each other), at the file's spacing in the scene's grid metres:
// 2 m x k18 / k17 with the UTM point scale factors k = 0.9996 (1 + (dlon cos(lat))^2 / 2) to that
// order, 0.99966 and 1.00233 here, so 1.99466 m (the next term is below 1e-5 of it).
TEST(GdalRaster, AnotherUtmZoneIsResampledIntoTheScenesUtmFrame) {
    const lb::GeoFrame frame = lb::GeoFrame::utm(kLat, kLon);
    ASSERT_EQ(frame.zone(), 18);
    const fs::path path = write("utm17.tif", utmRaster(17, frame));
    lb::RasterOptions opt;
    opt.frame = &frame;
    opt.clip = kDomain;
    const auto t = lb::loadRaster(path, opt);
    const lb::Extent e = t->extent();
    EXPECT_LE(e.x0, kDomain.x0);
    EXPECT_GE(e.x1, kDomain.x1);
    EXPECT_LE(e.y0, kDomain.y0);
    EXPECT_GE(e.y1, kDomain.y1);
    EXPECT_LT(maxError(*t, kDomain), kTol);
    // Expected spacing: the file's 2 m in zone 17 metres is 2 k18/k17 scene metres, with k the
    // UTM point scale at the site, taken from GeographicLib's transverse Mercator (independent of
    // the PROJ transform the reader uses). The point scale changes by about 1.2e-8 per metre of
    // easting here, so over the 120 m between the site and the raster's centre the ratio moves
    // by under 3e-6 m: a 1e-5 m tolerance.
    const auto& tm = GeographicLib::TransverseMercator::UTM();
    double x = 0, y = 0, gamma = 0, k17 = 0, k18 = 0;
    tm.Forward(-81, kLat, kLon, x, y, gamma, k17);
    tm.Forward(-75, kLat, kLon, x, y, gamma, k18);
    const double expected = 2 * k18 / k17;
    // The grid is cut to the domain plus two cells; its spacing is read from the description.
    const std::string d = t->describe();
    const size_t at = d.find(" samples, ");
    ASSERT_NE(at, std::string::npos) << d;
    const double dx = std::stod(d.substr(at + 10));
    EXPECT_NEAR(dx, expected, 1e-5) << d;
    const lb::Extent f = t->footprint();
    EXPECT_LT(f.x1 - f.x0, kDomain.width() + 6 * expected);

    // Without the frame (placed by hand, in its own zone's metres) the file reads unresampled.
    lb::RasterOptions byHand;
    byHand.originX = lb::toUtm(kLat, kLon, 17).easting;
    byHand.originY = lb::toUtm(kLat, kLon, 17).northing;
    const auto own = lb::loadRaster(path, byHand);
    EXPECT_DOUBLE_EQ(own->extent().x1 - own->extent().x0, 2.0 * 119);
}

// A raster in the frame's own zone is shifted, sample for sample: its values at the sample
// centres are the stored ones (exactly, for Float64).
TEST(GdalRaster, TheFramesOwnZoneIsShiftedNotResampled) {
    const lb::GeoFrame frame = lb::GeoFrame::utm(kLat, kLon);
    RasterFile r = utmRaster(18, frame);
    const fs::path path = write("utm18.tif", r);
    lb::RasterOptions opt;
    opt.frame = &frame;
    const auto t = lb::loadRaster(path, opt);
    const lb::Extent e = t->extent();
    EXPECT_DOUBLE_EQ(e.x0, r.gt[0] + 1 - frame.originUtm().easting);
    EXPECT_DOUBLE_EQ(e.y1, r.gt[3] - 1 - frame.originUtm().northing);
    EXPECT_DOUBLE_EQ(e.x1 - e.x0, 238);
    EXPECT_LT(maxError(*t, kDomain), kTol);
}

// Geographic degrees (EPSG:4326) into the local tangent-plane frame, as GeoTIFF and as NetCDF
// (CF, written bottom-up by GDAL): 1e-5 degree pixels (0.90 m east, 1.11 m north).
TEST(GdalRaster, GeographicDegreesIntoTheTangentPlaneAsGeoTiffAndNetcdf) {
    const lb::GeoFrame frame = lb::GeoFrame::localCartesian(kLat, kLon);
    RasterFile r;
    r.nx = 200;
    r.ny = 150;
    r.gt = {kLon - 100e-5, 1e-5, 0, kLat + 75e-5, 0, -1e-5};
    r.crs = "EPSG:4326";
    r.value = [&](int, double lon, double lat) {
        const littoral::Point3 p = frame.toLocal(lat, lon, 0);
        return field(p.x, p.y);
    };
    for (const char* driver : {"GTiff", "netCDF"}) {
        r.driver = driver;
        const fs::path path = write(std::string("geographic.") + (r.driver == "GTiff" ? "tif" : "nc"), r);
        lb::RasterOptions opt;
        opt.frame = &frame;
        opt.clip = kDomain;
        const auto t = lb::loadRaster(path, opt);
        EXPECT_LT(maxError(*t, kDomain), kTol) << driver;
        EXPECT_NE(t->describe().find(path.filename().string()), std::string::npos);
        // Shifting degrees as if they were metres is refused.
        const std::string m = inputErrorOf([&] { lb::loadRaster(path); });
        EXPECT_NE(m.find("is geographic (degrees)"), std::string::npos) << m;
        EXPECT_NE(m.find("origin: scene"), std::string::npos) << m;
    }
}

// BAG (NOAA's Bathymetry Attributed Grid: HDF5, elevation and uncertainty bands, NODATA 1e6)
// whose NODATA lies away from the domain: the samples kept are complete, so it loads; a hole
// under the domain is named by its pixel.
TEST(GdalRaster, BagWithNodataAwayFromTheDomain) {
    const lb::GeoFrame frame = lb::GeoFrame::utm(kLat, kLon);
    RasterFile r = utmRaster(18, frame);
    r.driver = "BAG";
    r.type = GDT_Float32;
    r.nodata = 1e6;
    r.options = {"VAR_DATE=2026-12-02"};  // the metadata template's date
    const auto inner = r.value;
    const double e0 = r.gt[0], n0 = r.gt[3];
    r.value = [=](int b, double X, double Y) {
        if (X < e0 + 20) return 1e6;  // a 20 m strip of NODATA along the west edge
        return inner(b, X, Y);
    };
    const fs::path path = write("survey.bag", r);
    lb::RasterOptions opt;
    opt.frame = &frame;
    opt.clip = kDomain;
    const auto t = lb::loadRaster(path, opt);
    // float32 storage: |f| < 10 m is held to 1e-6 m.
    EXPECT_LT(maxError(*t, kDomain), kTol);
    opt.clip = lb::Extent{e0 - frame.originUtm().easting, -40, e0 - frame.originUtm().easting + 60, 40};
    const std::string m = inputErrorOf([&] { lb::loadRaster(path, opt); });
    EXPECT_NE(m.find("survey.bag"), std::string::npos) << m;
    EXPECT_NE(m.find("channel 0 is NODATA (1000000)"), std::string::npos) << m;
    (void)n0;
}

// A NetCDF with two variables opens as subdatasets: `variable` picks one; without it the error
// lists them; a name not in the file is refused.
TEST(GdalRaster, NetcdfVariableIsChosenByName) {
    const lb::GeoFrame frame = lb::GeoFrame::utm(kLat, kLon);
    RasterFile r = utmRaster(18, frame);
    r.driver = "netCDF";
    r.bands = 2;
    const auto inner = r.value;
    r.value = [=](int b, double X, double Y) { return b == 2 ? inner(b, X, Y) : 99.0; };
    const fs::path path = write("two_vars.nc", r);
    lb::RasterOptions opt;
    opt.frame = &frame;
    std::string m = inputErrorOf([&] { lb::loadRaster(path, opt); });
    EXPECT_NE(m.find("holds 2 variables (Band1, Band2); name the elevation with the raster key 'variable'"),
              std::string::npos)
        << m;
    opt.variable = "Band2";
    const auto t = lb::loadRaster(path, opt);
    EXPECT_LT(maxError(*t, kDomain), kTol);
    opt.variable = "depth";
    m = inputErrorOf([&] { lb::loadRaster(path, opt); });
    EXPECT_NE(m.find("variable = 'depth' is not in the file; it holds: Band1, Band2"), std::string::npos) << m;
}

// An ESRI ASCII grid takes its coordinate system from its .prj (ESRI WKT): zone 17 into a zone 18
// frame is resampled; without the .prj it is taken as in the frame's zone (as before GDAL).
TEST(GdalRaster, AsciiGridWithPrjSidecar) {
    const lb::GeoFrame frame = lb::GeoFrame::utm(kLat, kLon);
    const RasterFile r = utmRaster(17, frame);
    std::string text = "ncols " + std::to_string(r.nx) + "\nnrows " + std::to_string(r.ny) + "\nxllcorner " +
                       std::to_string(r.gt[0]) + "\nyllcorner " + std::to_string(r.gt[3] + r.ny * r.gt[5]) +
                       "\ncellsize 2\n";
    char buf[64];
    for (int j = 0; j < r.ny; ++j) {
        for (int i = 0; i < r.nx; ++i) {
            std::snprintf(buf, sizeof buf, "%.17g ", r.value(1, r.gt[0] + (i + 0.5) * 2, r.gt[3] - (j + 0.5) * 2));
            text += buf;
        }
        text += "\n";
    }
    const fs::path asc = littoral::testing_support::writeTextFile(dir(), "zone17.asc", text);
    OGRSpatialReference s;
    s.importFromEPSG(32617);
    s.morphToESRI();
    char* wkt = nullptr;
    s.exportToWkt(&wkt);
    littoral::testing_support::writeTextFile(dir(), "zone17.prj", wkt);
    CPLFree(wkt);
    lb::RasterOptions opt;
    opt.frame = &frame;
    opt.clip = kDomain;
    EXPECT_LT(maxError(*lb::loadRaster(asc, opt), kDomain), kTol);
    // A .prj that is not a coordinate system is named.
    littoral::testing_support::writeTextFile(dir(), "zone17.prj", "PROJCS[garbage\n");
    const std::string m = inputErrorOf([&] { lb::loadRaster(asc, opt); });
    EXPECT_NE(m.find("zone17.prj"), std::string::npos) << m;
    EXPECT_NE(m.find("not a coordinate system"), std::string::npos) << m;
    fs::remove(dir() / "zone17.prj");
    // Without it, in the local tangent-plane frame, there is no way to place it.
    const lb::GeoFrame tangent = lb::GeoFrame::localCartesian(kLat, kLon);
    opt.frame = &tangent;
    const std::string n = inputErrorOf([&] { lb::loadRaster(asc, opt); });
    EXPECT_NE(n.find("declares no coordinate system"), std::string::npos) << n;
}

// A band in feet is converted (0.3048 m per foot); a south-up grid (positive y step) is turned
// north-up; a unit that is not a length is refused.
TEST(GdalRaster, FeetAndSouthUpGrids) {
    const lb::GeoFrame frame = lb::GeoFrame::utm(kLat, kLon);
    RasterFile r = utmRaster(18, frame);
    const auto inner = r.value;
    r.value = [=](int b, double X, double Y) { return inner(b, X, Y) / 0.3048; };
    r.unit = "ft";
    lb::RasterOptions opt;
    opt.frame = &frame;
    EXPECT_LT(maxError(*lb::loadRaster(write("feet.tif", r), opt), kDomain), kTol);
    r.unit = "kelvin";
    std::string m = inputErrorOf([&] { lb::loadRaster(write("kelvin.tif", r), opt); });
    EXPECT_NE(m.find("the elevation band's unit is 'kelvin'"), std::string::npos) << m;
    r.unit.clear();
    r.value = inner;
    r.gt[3] -= 200;  // the south edge
    r.gt[5] = 2;     // rows run north
    const auto t = lb::loadRaster(write("south_up.tif", r), opt);
    EXPECT_LT(maxError(*t, kDomain), kTol);
}

// Files GDAL cannot read, or that lie about themselves, are InputErrors naming the file; every
// truncation of a NetCDF is read or refused, never a crash.
TEST(GdalRaster, CorruptFilesAreNamed) {
    for (const char* name : {"garbage.bag", "garbage.nc", "garbage.tif"}) {
        const fs::path p = littoral::testing_support::writeTextFile(dir(), name, "this is not a raster\n");
        const std::string m = inputErrorOf([&] { lb::loadRaster(p); });
        EXPECT_NE(m.find(name), std::string::npos) << m;
        EXPECT_NE(m.find("not a readable elevation raster"), std::string::npos) << m;
    }
    const lb::GeoFrame frame = lb::GeoFrame::utm(kLat, kLon);
    RasterFile r = utmRaster(18, frame);
    r.nx = 8;
    r.ny = 6;
    r.driver = "netCDF";
    const fs::path full = write("small.nc", r);
    std::ifstream in(full, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    int refused = 0;
    for (size_t n = 1; n < bytes.size(); n += 7) {
        const fs::path cut = littoral::testing_support::writeTextFile(dir(), "cut.nc", bytes.substr(0, n));
        try {
            lb::loadRaster(cut);
        } catch (const littoral::InputError& e) {
            ++refused;
            EXPECT_NE(std::string(e.what()).find("cut.nc"), std::string::npos) << e.what();
        }
    }
    EXPECT_GT(refused, 0);
}

// A pixel-interleaved file decodes every band of a block to read one (fuzz_raster found a
// 64771 x 2 GeoTIFF declaring 65281 interleaved bands, whose one block is 16.9 GB). The budget
// check counts them: 64 x 64 Float32 samples in 100 interleaved bands need 9 B/sample for the
// read plus 4 B x 100 bands of GDAL's block cache, 1.67 MB, refused under a 1 MB budget; the same
// grid in one band needs 53 kB and is read.
TEST(GdalRaster, InterleavedBandsCountAgainstTheMemoryBudget) {
    const lb::GeoFrame frame = lb::GeoFrame::utm(kLat, kLon);
    RasterFile r = utmRaster(18, frame);
    r.nx = r.ny = 64;
    r.type = GDT_Float32;
    r.bands = 100;
    r.options = {"INTERLEAVE=PIXEL"};
    const fs::path many = write("interleaved.tif", r);
    r.bands = 1;
    const fs::path one = write("one_band.tif", r);
    const uint64_t before = littoral::memoryBudget();
    littoral::setMemoryBudget(1u << 20);
    const std::string m = inputErrorOf([&] { lb::loadRaster(many); });
    EXPECT_NO_THROW(lb::loadRaster(one));
    littoral::setMemoryBudget(before);
    EXPECT_NE(m.find("interleaved.tif"), std::string::npos) << m;
    EXPECT_NE(m.find("100 band(s)"), std::string::npos) << m;
    EXPECT_NE(m.find("memory budget"), std::string::npos) << m;
}
