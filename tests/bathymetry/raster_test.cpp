// Elevation rasters: ESRI ASCII grids and (Geo)TIFF, bilinear interpolation, georeferencing, errors.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/image_io.h"
#include "tests/support/test_support.h"

#include "bathymetry/terrain.h"
#include "core/error.h"

namespace lb = littoral::bathymetry;
namespace fs = std::filesystem;
using littoral::InputError;

namespace {

fs::path tempDir() {
    const fs::path d = fs::path(::testing::TempDir()) / "littoral_bathymetry_raster";
    fs::create_directories(d);
    return d;
}

fs::path writeText(const std::string& name, const std::string& text) {
    return littoral::testing_support::writeTextFile(tempDir(), name, text);
}
using littoral::testing_support::inputErrorOf;

// A minimal single-strip TIFF writer with optional GeoTIFF tags (TIFF 6.0 + GeoTIFF 1.1), so the
// tests control every tag. sampleFormat 3 = IEEE float (32 bit), 2 = signed integer (16 bit).
struct TiffSpec {
    int width = 0, height = 0;
    bool bigEndian = false;
    int sampleFormat = 3;
    std::vector<double> values;  // row-major, row 0 first (north)
    std::vector<double> pixelScale, tiepoint, transformation;
    std::vector<uint16_t> geoKeys;  // full GeoKeyDirectory (header + entries)
    std::string gdalNodata;
};

class Bytes {
public:
    explicit Bytes(bool big) : big_(big) {}
    void u(uint64_t v, int n) {
        for (int i = 0; i < n; ++i) data.push_back(uint8_t(v >> (8 * (big_ ? n - 1 - i : i))));
    }
    void f64(double d) {
        uint64_t b;
        std::memcpy(&b, &d, 8);
        u(b, 8);
    }
    std::vector<uint8_t> data;

private:
    bool big_;
};

fs::path writeTiff(const std::string& name, const TiffSpec& s) {
    Bytes b(s.bigEndian);
    const int bytesPerSample = s.sampleFormat == 3 ? 4 : 2;
    b.data = {uint8_t(s.bigEndian ? 'M' : 'I'), uint8_t(s.bigEndian ? 'M' : 'I')};
    b.u(42, 2);
    b.u(0, 4);  // IFD offset, patched below
    const uint32_t pixelOffset = uint32_t(b.data.size());
    for (double v : s.values) {
        if (s.sampleFormat == 3) {
            float f = float(v);
            uint32_t bits;
            std::memcpy(&bits, &f, 4);
            b.u(bits, 4);
        } else {
            b.u(uint16_t(int16_t(v)), 2);
        }
    }
    struct Entry { uint16_t tag, type; uint32_t count, value; };
    std::vector<Entry> e;
    const auto arrayD = [&](const std::vector<double>& v) {
        const uint32_t off = uint32_t(b.data.size());
        for (double d : v) b.f64(d);
        return off;
    };
    if (!s.pixelScale.empty()) e.push_back({33550, 12, uint32_t(s.pixelScale.size()), arrayD(s.pixelScale)});
    if (!s.tiepoint.empty()) e.push_back({33922, 12, uint32_t(s.tiepoint.size()), arrayD(s.tiepoint)});
    if (!s.transformation.empty())
        e.push_back({34264, 12, uint32_t(s.transformation.size()), arrayD(s.transformation)});
    if (!s.geoKeys.empty()) {
        const uint32_t off = uint32_t(b.data.size());
        for (uint16_t k : s.geoKeys) b.u(k, 2);
        e.push_back({34735, 3, uint32_t(s.geoKeys.size()), off});
    }
    if (!s.gdalNodata.empty()) {
        const uint32_t off = uint32_t(b.data.size());
        for (char c : s.gdalNodata) b.data.push_back(uint8_t(c));
        b.data.push_back(0);
        while (b.data.size() % 2) b.data.push_back(0);
        e.push_back({42113, 2, uint32_t(s.gdalNodata.size() + 1), off});
    }
    const uint32_t stripBytes = uint32_t(s.values.size()) * bytesPerSample;
    e.push_back({256, 4, 1, uint32_t(s.width)});
    e.push_back({257, 4, 1, uint32_t(s.height)});
    e.push_back({258, 3, 1, uint32_t(bytesPerSample * 8)});
    e.push_back({259, 3, 1, 1});  // no compression
    e.push_back({262, 3, 1, 1});  // min-is-black
    e.push_back({273, 4, 1, pixelOffset});
    e.push_back({277, 3, 1, 1});
    e.push_back({278, 4, 1, uint32_t(s.height)});
    e.push_back({279, 4, 1, stripBytes});
    e.push_back({339, 3, 1, uint32_t(s.sampleFormat)});
    std::sort(e.begin(), e.end(), [](const Entry& a, const Entry& c) { return a.tag < c.tag; });
    while (b.data.size() % 2) b.data.push_back(0);
    const uint32_t ifd = uint32_t(b.data.size());
    b.u(e.size(), 2);
    for (const Entry& x : e) {
        b.u(x.tag, 2);
        b.u(x.type, 2);
        b.u(x.count, 4);
        if (x.type == 3 && x.count == 1) {  // a SHORT sits left-justified in the 4-byte field
            b.u(x.value, 2);
            b.u(0, 2);
        } else {
            b.u(x.value, 4);
        }
    }
    b.u(0, 4);
    Bytes off(s.bigEndian);
    off.u(ifd, 4);
    std::copy(off.data.begin(), off.data.end(), b.data.begin() + 4);
    const fs::path p = tempDir() / name;
    std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(b.data.data()), std::streamsize(b.data.size()));
    return p;
}

// A bilinear function f = a + b x + c y + d x y is reproduced exactly by bilinear interpolation
// (it is in the interpolant's span), so any query point has an exact reference.
double bilinearField(double x, double y) { return -3.0 + 0.05 * x - 0.11 * y + 0.002 * x * y; }

}  // namespace

// ESRI ASCII grid, corner registration: 4 columns x 3 rows, cell 10 m, lower-left corner at
// (100, 200). Sample centres are x = 105, 115, 125, 135 and y = 205, 215, 225 (first data row is
// north, y = 225). With the local origin at (100, 200) the extent of centres is [5, 35] x [5, 25].
TEST(AsciiGrid, NodesAndMidpointsExact) {
    std::string text = "ncols 4\nnrows 3\nxllcorner 100\nyllcorner 200\ncellsize 10\nNODATA_value -9999\n";
    const double rowsY[] = {25, 15, 5};
    for (double y : rowsY) {
        for (int i = 0; i < 4; ++i) {
            if (i) text += ' ';
            text += std::to_string(bilinearField(5 + 10 * i, y));
        }
        text += "\n";
    }
    lb::RasterOptions opt;
    opt.originX = 100;
    opt.originY = 200;
    const auto t = lb::loadRaster(writeText("grid.asc", text), opt);
    const lb::Extent e = t->extent();
    EXPECT_DOUBLE_EQ(e.x0, 5);
    EXPECT_DOUBLE_EQ(e.x1, 35);
    EXPECT_DOUBLE_EQ(e.y0, 5);
    EXPECT_DOUBLE_EQ(e.y1, 25);
    // std::to_string keeps 6 decimals, so node values carry up to 5e-7 m of rounding; bilinear
    // weights sum to 1, so interpolated values inherit at most the same. Tolerance 6e-7 m.
    for (double y : rowsY)
        for (int i = 0; i < 4; ++i) EXPECT_NEAR(t->elevation(5 + 10 * i, y), bilinearField(5 + 10 * i, y), 6e-7);
    for (double x : {10.0, 20.0, 30.0, 7.3, 33.1})
        for (double y : {10.0, 20.0, 5.0, 12.9, 24.2}) EXPECT_NEAR(t->elevation(x, y), bilinearField(x, y), 6e-7);
    // Outside the extent the value clamps to the nearest edge point.
    EXPECT_NEAR(t->elevation(-50, 10), bilinearField(5, 10), 6e-7);
}

// Arbitrary (non-bilinear) data: the midpoint of a cell is the mean of its four corners and the
// midpoint of an edge the mean of its two ends (the bilinear weights there are 1/4 and 1/2).
// Centre registration (xllcenter/yllcenter) and z_scale = -1 (a depth grid) are used here.
TEST(AsciiGrid, CellMidpointsAreCornerMeans) {
    const auto path = writeText("depths.asc",
                                "NCOLS 3\r\nNROWS 2\r\nXLLCENTER 0\r\nYLLCENTER 0\r\nCELLSIZE 2\r\n"
                                "1.5 2.25 7\r\n4 -1 0.5\r\n");
    lb::RasterOptions opt;
    opt.zScale = -1;  // file holds depths, positive down
    const auto t = lb::loadRaster(path, opt);
    // Row 1 (north) is y = 2, row 2 is y = 0; columns at x = 0, 2, 4.
    EXPECT_DOUBLE_EQ(t->elevation(0, 2), -1.5);
    EXPECT_DOUBLE_EQ(t->elevation(4, 0), -0.5);
    EXPECT_NEAR(t->elevation(1, 1), -(1.5 + 2.25 + 4 - 1) / 4, 1e-15);
    EXPECT_NEAR(t->elevation(3, 1), -(2.25 + 7 - 1 + 0.5) / 4, 1e-15);
    EXPECT_NEAR(t->elevation(3, 2), -(2.25 + 7) / 2, 1e-15);
    EXPECT_NEAR(t->elevation(0, 1), -(1.5 + 4) / 2, 1e-15);
}

TEST(AsciiGrid, MalformedFilesNameLineAndProblem) {
    const std::string head = "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\nnodata_value -9999\n";
    const auto err = [](const std::string& name, const std::string& text) {
        return inputErrorOf([&] { lb::loadRaster(writeText(name, text)); });
    };
    std::string m = err("short_row.asc", head + "1 2 3\n4 5\n");
    EXPECT_NE(m.find("short_row.asc:8"), std::string::npos) << m;
    EXPECT_NE(m.find("row 2 has 2 values; ncols = 3"), std::string::npos) << m;

    m = err("bad_number.asc", head + "1 2 3\n4 x5 6\n");
    EXPECT_NE(m.find("bad_number.asc:8:3"), std::string::npos) << m;
    EXPECT_NE(m.find("'x5'"), std::string::npos) << m;

    m = err("nodata.asc", head + "1 2 3\n4 -9999 6\n");
    EXPECT_NE(m.find("nodata.asc:8:3"), std::string::npos) << m;
    EXPECT_NE(m.find("NODATA"), std::string::npos) << m;

    m = err("few_rows.asc", head + "1 2 3\n");
    EXPECT_NE(m.find("ends after 1 rows; nrows = 2"), std::string::npos) << m;

    m = err("extra_rows.asc", head + "1 2 3\n4 5 6\n7 8 9\n");
    EXPECT_NE(m.find("extra_rows.asc:9"), std::string::npos) << m;

    m = err("typo.asc", "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsiz 1\n1 2 3\n4 5 6\n");
    EXPECT_NE(m.find("typo.asc:5:1"), std::string::npos) << m;
    EXPECT_NE(m.find("did you mean 'cellsize'"), std::string::npos) << m;

    m = err("no_cellsize.asc", "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\n1 2 3\n4 5 6\n");
    EXPECT_NE(m.find("cellsize"), std::string::npos) << m;

    m = err("one_col.asc", "ncols 1\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1\n2\n");
    EXPECT_NE(m.find("one_col.asc:1"), std::string::npos) << m;

    m = err("header_only.asc", "ncols 3\nnrows 2\n");
    EXPECT_NE(m.find("no grid data"), std::string::npos) << m;

    m = inputErrorOf([] { lb::loadRaster(tempDir() / "does_not_exist.asc"); });
    EXPECT_NE(m.find("not found"), std::string::npos) << m;
}

// GeoTIFF, pixel-is-area: ModelPixelScale (2, 2) and tie point raster (0, 0) -> model
// (500000, 4000100). Pixel (i, j) centres at X = 500001 + 2 i, Y = 4000099 - 2 j. With the local
// origin at (500000, 4000000): x = 1 + 2 i, y = 99 - 2 j. float32 storage rounds the bilinear
// field's values (|f| < 30) to 2^-19 relative, ~5e-5 m: tolerance 1e-4 m.
TEST(GeoTiff, GeoreferencedFloatRasterBothByteOrders) {
    for (bool big : {false, true}) {
        TiffSpec s;
        s.width = 5;
        s.height = 4;
        s.bigEndian = big;
        for (int j = 0; j < s.height; ++j)
            for (int i = 0; i < s.width; ++i) s.values.push_back(bilinearField(1 + 2 * i, 99 - 2 * j));
        s.pixelScale = {2, 2, 0};
        s.tiepoint = {0, 0, 0, 500000, 4000100, 0};
        s.geoKeys = {1, 1, 0, 2, 1024, 0, 1, 1, 3072, 0, 1, 32618};  // projected, EPSG:32618 (UTM 18N)
        const auto path = writeTiff(big ? "geo_be.tif" : "geo_le.tif", s);
        lb::RasterOptions opt;
        opt.originX = 500000;
        opt.originY = 4000000;
        const auto t = lb::loadRaster(path, opt);
        const lb::Extent e = t->extent();
        EXPECT_DOUBLE_EQ(e.x0, 1);
        EXPECT_DOUBLE_EQ(e.x1, 9);
        EXPECT_DOUBLE_EQ(e.y0, 93);
        EXPECT_DOUBLE_EQ(e.y1, 99);
        for (double x : {1.0, 2.0, 4.5, 9.0})
            for (double y : {93.0, 96.0, 98.2, 99.0}) EXPECT_NEAR(t->elevation(x, y), bilinearField(x, y), 1e-4);
    }
}

// GeoKey GTRasterType = 2 (PixelIsPoint): the tie point is the first sample's centre itself.
TEST(GeoTiff, PixelIsPointRegistration) {
    TiffSpec s;
    s.width = 2;
    s.height = 2;
    s.values = {1, 2, 3, 4};
    s.pixelScale = {10, 5, 0};
    s.tiepoint = {0, 0, 0, 1000, 2000, 0};
    s.geoKeys = {1, 1, 0, 2, 1024, 0, 1, 1, 1025, 0, 1, 2};
    const auto t = lb::loadRaster(writeTiff("point.tif", s), {});
    const lb::Extent e = t->extent();
    EXPECT_DOUBLE_EQ(e.x0, 1000);
    EXPECT_DOUBLE_EQ(e.x1, 1010);
    EXPECT_DOUBLE_EQ(e.y0, 1995);
    EXPECT_DOUBLE_EQ(e.y1, 2000);
    EXPECT_DOUBLE_EQ(t->elevation(1005, 1997.5), 2.5);  // centre: mean of 1, 2, 3, 4
}

// ModelTransformation (GeoTIFF 1.1, 7.3): X = 3 I + 700, Y = -4 J + 950 for raster (I, J). Pixel
// centres (pixel-is-area) at I = i + 0.5: x = 701.5 + 3 i, y = 948 - 4 j. A rotated matrix is refused.
TEST(GeoTiff, ModelTransformationNorthUpOnly) {
    TiffSpec s;
    s.width = 3;
    s.height = 2;
    s.values = {1, 2, 3, 4, 5, 6};
    s.transformation = {3, 0, 0, 700, 0, -4, 0, 950, 0, 0, 0, 0, 0, 0, 0, 1};
    const auto t = lb::loadRaster(writeTiff("matrix.tif", s), {});
    const lb::Extent e = t->extent();
    EXPECT_DOUBLE_EQ(e.x0, 701.5);
    EXPECT_DOUBLE_EQ(e.x1, 707.5);
    EXPECT_DOUBLE_EQ(e.y0, 944);
    EXPECT_DOUBLE_EQ(e.y1, 948);
    EXPECT_DOUBLE_EQ(t->elevation(706, 946), (2 + 3 + 5 + 6) / 4.0);
    s.transformation[1] = 0.5;  // shear / rotation
    const std::string m = inputErrorOf([&] { lb::loadRaster(writeTiff("rotated.tif", s), {}); });
    EXPECT_NE(m.find("rotated"), std::string::npos) << m;
}

// A plain TIFF needs an extent from the caller (the sample-centre rectangle). int16 samples are
// metres as stored (no normalisation to [-1, 1]).
TEST(GeoTiff, PlainInt16TiffWithCallerExtent) {
    TiffSpec s;
    s.width = 3;
    s.height = 2;
    s.sampleFormat = 2;
    s.values = {-15, -10, -5, 3, 0, 12};
    const auto path = writeTiff("plain.tif", s);
    const std::string m = inputErrorOf([&] { lb::loadRaster(path); });
    EXPECT_NE(m.find("no georeferencing"), std::string::npos) << m;
    lb::RasterOptions opt;
    opt.extent = lb::Extent{0, 0, 90, 60};
    opt.zOffset = 0.5;
    const auto t = lb::loadRaster(path, opt);
    EXPECT_DOUBLE_EQ(t->elevation(0, 60), -14.5);  // first sample: north-west corner
    EXPECT_DOUBLE_EQ(t->elevation(90, 0), 12.5);   // last sample: south-east corner
    // Samples at x = 0, 45, 90 and y = 60 (row 1), 0 (row 2). (45, 30): halfway between -10 and 0;
    // (22.5, 30): centre of the cell -15, -10, 3, 0. Plus the 0.5 m offset.
    EXPECT_DOUBLE_EQ(t->elevation(45, 30), -5 + 0.5);
    EXPECT_DOUBLE_EQ(t->elevation(22.5, 30), (-15 - 10 + 3 + 0) / 4.0 + 0.5);
}

// A tiled, zip-compressed float TIFF written by OpenImageIO (not by the minimal writer above),
// read through GDAL's decoder. Caller extent [0, 30] x [0, 20] m over 4 x 3
// samples: centres every 10 m. Values are exactly representable in float32: exact.
TEST(GeoTiff, CompressedTiledTiffFromOpenImageIO) {
    const fs::path path = tempDir() / "oiio_tiled.tif";
    const float px[12] = {0, 1, 2, 3, 10, 11, 12, 13, 20, 21, 22, 23.5f};
    littoral::imageio::WriteSpec spec{4, 3, 1, littoral::imageio::PixelType::Float, {}, {{"compression", "zip"}}};
    spec.tileWidth = spec.tileHeight = 16;
    littoral::imageio::writeFile(path, spec, px);
    lb::RasterOptions opt;
    opt.extent = lb::Extent{0, 0, 30, 20};
    const auto t = lb::loadRaster(path, opt);
    EXPECT_DOUBLE_EQ(t->elevation(0, 20), 0.0);    // row 1 (north), column 1
    EXPECT_DOUBLE_EQ(t->elevation(30, 0), 23.5);   // row 3, column 4
    EXPECT_DOUBLE_EQ(t->elevation(15, 15), (1 + 2 + 11 + 12) / 4.0);
}

TEST(GeoTiff, RejectsNodataGeographicAndCorruptFiles) {
    TiffSpec s;
    s.width = 3;
    s.height = 2;
    s.values = {1, 2, 3, 4, -9999, 6};
    s.pixelScale = {1, 1, 0};
    s.tiepoint = {0, 0, 0, 0, 2, 0};
    s.gdalNodata = "-9999";
    std::string m = inputErrorOf([&] { lb::loadRaster(writeTiff("nodata.tif", s)); });
    EXPECT_NE(m.find("pixel (column 2, row 2; counted from 1, row 1 = north), channel 0 is NODATA"), std::string::npos) << m;
    EXPECT_NE(m.find("NODATA"), std::string::npos) << m;

    s.gdalNodata.clear();
    s.values[4] = 5;
    s.geoKeys = {1, 1, 0, 1, 1024, 0, 1, 2};  // GTModelType 2: geographic (degrees)
    m = inputErrorOf([&] { lb::loadRaster(writeTiff("geographic.tif", s)); });
    EXPECT_NE(m.find("geographic"), std::string::npos) << m;

    // A TIFF whose directory offset points past the end of the file.
    m = inputErrorOf([] { lb::loadRaster(writeText("truncated.tif", std::string("II*\0\xff\xff\x00\x00", 8))); });
    EXPECT_NE(m.find("truncated.tif"), std::string::npos) << m;
    EXPECT_NE(m.find("not a readable elevation raster"), std::string::npos) << m;

    m = inputErrorOf([] { lb::loadRaster(writeText("garbage.tif", "this is not an image\n")); });
    EXPECT_NE(m.find("garbage.tif"), std::string::npos) << m;

    lb::RasterOptions bad;
    bad.channel = 2;
    s.geoKeys.clear();
    m = inputErrorOf([&] { lb::loadRaster(writeTiff("one_channel.tif", s), bad); });
    EXPECT_NE(m.find("channel = 2"), std::string::npos) << m;
}

// Every truncation of a valid GeoTIFF is either read (if the cut spares what is needed) or
// rejected with an InputError naming the file; never a crash or another exception type.
// The IFD sits at the end of the file, so most prefixes lose it.
TEST(GeoTiff, TruncatedFilesAreInputErrors) {
    TiffSpec s;
    s.width = 3;
    s.height = 2;
    s.values = {1, 2, 3, 4, 5, 6};
    s.pixelScale = {1, 1, 0};
    s.tiepoint = {0, 0, 0, 0, 2, 0};
    s.geoKeys = {1, 1, 0, 1, 1024, 0, 1, 1};
    const fs::path full = writeTiff("full.tif", s);
    std::ifstream in(full, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    int rejected = 0;
    for (size_t n = 1; n < bytes.size(); ++n) {
        const fs::path cut = writeText("cut.tif", bytes.substr(0, n));
        try {
            lb::loadRaster(cut);
        } catch (const InputError& e) {
            ++rejected;
            EXPECT_NE(std::string(e.what()).find("cut.tif"), std::string::npos) << e.what();
        }
    }
    // At least every cut inside the directory (13 entries: the last 2 + 13 * 12 + 4 bytes) must be
    // rejected.
    EXPECT_GE(rejected, 2 + 13 * 12 + 4);
}

// A NaN sample of a float GeoTIFF is refused at its pixel and channel; an elevation beyond any on
// Earth (an undeclared NODATA such as -3.4e38, or an overflow by z_scale) likewise.
TEST(GeoTiff, NonFiniteAndImpossibleSamplesNameTheirPixel) {
    TiffSpec s;
    s.width = 3;
    s.height = 2;
    s.values = {1, 2, 3, 4, std::nan(""), 6};
    s.pixelScale = {1, 1, 0};
    s.tiepoint = {0, 0, 0, 0, 2, 0};
    std::string m = inputErrorOf([&] { lb::loadRaster(writeTiff("nan.tif", s)); });
    EXPECT_NE(m.find("nan.tif"), std::string::npos) << m;
    EXPECT_NE(m.find("pixel (column 2, row 2; counted from 1, row 1 = north), channel 0 is not finite (nan)"),
              std::string::npos)
        << m;
    s.values[4] = -3.4e38;
    m = inputErrorOf([&] { lb::loadRaster(writeTiff("huge.tif", s)); });
    EXPECT_NE(m.find("sample (column 2, row 2; counted from 1, row 1 = north) holds -3.4e+38"), std::string::npos) << m;
    EXPECT_NE(m.find("allowed -12000 to 9000 m"), std::string::npos) << m;
    s.values[4] = 5;
    lb::RasterOptions opt;
    opt.zScale = 2000;  // 5 m becomes 10 km
    m = inputErrorOf([&] { lb::loadRaster(writeTiff("scaled.tif", s), opt); });
    EXPECT_NE(m.find("sample (column 2, row 2; counted from 1, row 1 = north) holds 5, which is an elevation of "
                     "10000 m after z_scale 2000"),
              std::string::npos)
        << m;
}

// A raster's footprint is its cells: the rectangle of sample centres grown by half a cell.
TEST(AsciiGrid, FootprintIsTheCellsAroundTheSampleCentres) {
    const auto t = lb::parseAsciiGridTerrain(
        "ncols 3\nnrows 2\nxllcorner 10\nyllcorner 20\ncellsize 2\n1 2 3\n4 5 6\n", "fp.asc");
    const lb::Extent c = t->extent(), f = t->footprint();
    EXPECT_DOUBLE_EQ(c.x0, 11);
    EXPECT_DOUBLE_EQ(c.x1, 15);
    EXPECT_DOUBLE_EQ(f.x0, 10);
    EXPECT_DOUBLE_EQ(f.x1, 16);
    EXPECT_DOUBLE_EQ(f.y0, 20);
    EXPECT_DOUBLE_EQ(f.y1, 24);
}

// Placed by hand (origin_x_m / origin_y_m): the file's own coordinates less the origin, which
// needs a projected system in metres. WGS 84 and NAD83 UTM are read; a state plane in US survey
// feet is refused (shifting feet as if they were metres would misplace it by a factor 3.28), with
// the way out: origin: scene, which reprojects (tests/bathymetry/gdal_raster_test.cpp).
TEST(GeoTiff, PlacedByHandNeedsAProjectedSystemInMetres) {
    TiffSpec s;
    s.width = 3;
    s.height = 2;
    s.values = {1, 2, 3, 4, 5, 6};
    s.pixelScale = {1, 1, 0};
    s.tiepoint = {0, 0, 0, 412000, 4004002, 0};
    lb::RasterOptions opt;
    opt.originX = 412000;
    opt.originY = 4004000;
    const auto withCrs = [&](int epsg) {
        s.geoKeys = {1, 1, 0, 2, 1024, 0, 1, 1, 3072, 0, 1, uint16_t(epsg)};
        return writeTiff("crs_" + std::to_string(epsg) + ".tif", s);
    };
    for (int epsg : {32618, 26918}) {
        const auto t = lb::loadRaster(withCrs(epsg), opt);
        EXPECT_DOUBLE_EQ(t->extent().x0, 0.5) << epsg;
        EXPECT_DOUBLE_EQ(t->extent().y1, 1.5) << epsg;
    }
    const std::string m = inputErrorOf([&] { lb::loadRaster(withCrs(2264), opt); });  // NAD83 / North Carolina (ftUS)
    EXPECT_NE(m.find("cannot be placed by shifting its coordinates: its coordinate system (NAD83 / North Carolina "
                     "(ftUS)) counts in US survey foot"),
              std::string::npos)
        << m;
    EXPECT_NE(m.find("origin: scene"), std::string::npos) << m;
}
