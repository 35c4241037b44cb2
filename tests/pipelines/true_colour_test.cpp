// The true-colour preview (NAME_rgb.png) of a white Lambertian floor in air under the sun shows
// the sun's own colour: CIE D65 sunlight gives the D65 white point and R = G = B; an equal-energy
// sun gives x = y = 1/3. The references are the CIE's published chromaticities, and the test
// decodes the PNG with its own copy of the sRGB standard (IEC 61966-2-1).
#include <cmath>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/image_io.h"
#include "core/colour.h"
#include "render/image_output.h"
#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using namespace littoral;
using littoral::testing_support::runLittoral;
using littoral::testing_support::scratchDir;
using littoral::testing_support::writeTextFile;

namespace {

// CIE standard illuminant D65, relative spectral power 380-780 nm every 5 nm (CIE 15:2004 Table T.1).
constexpr double kD65[81] = {
    49.98,  52.31,  54.65,  68.70,  82.75,  87.12,  91.49,  92.46,  93.43,  90.06,  86.68,  95.77,  104.86, 110.94,
    117.01, 117.41, 117.81, 116.34, 114.86, 115.39, 115.92, 112.37, 108.81, 109.08, 109.35, 108.58, 107.80, 106.30,
    104.79, 106.24, 107.69, 106.05, 104.41, 104.23, 104.05, 102.02, 100.00, 98.17,  96.33,  96.06,  95.79,  92.24,
    88.69,  89.35,  90.01,  89.80,  89.60,  88.65,  87.70,  85.49,  83.29,  83.49,  83.69,  81.86,  80.03,  80.12,
    80.21,  81.25,  82.28,  80.28,  78.28,  74.00,  69.72,  70.67,  71.61,  72.98,  74.35,  67.98,  61.60,  65.74,
    69.89,  72.49,  75.09,  69.34,  63.59,  55.01,  46.42,  56.61,  66.81,  65.09,  63.38};

std::string d65Irradiance() {
    std::string wl, v;
    for (int i = 0; i < 81; ++i) {
        wl += fmt::format("{}{:.3f}", i ? ", " : "", 0.380 + 0.005 * i);
        v += fmt::format("{}{}", i ? ", " : "", 10 * kD65[i]);  // about 1000 W m^-2 um^-1 at 560 nm
    }
    return "{wavelengths_um: [" + wl + "], values: [" + v + "]}";
}

std::string floorScene(const std::string& irradiance) {
    return "scene: {name: colour, domain: {x: [-5, 5], y: [-5, 5]}}\n"
           "sun: {zenith_deg: 30, irradiance: " + irradiance + "}\n"
           "sky: {radiance: 0}\n"
           "bathymetry: {type: planar_slope, z0_m: 0, material: white}\n"
           "materials: [{name: white, reflectance: 0.8}]\n"
           "sensors:\n"
           "  - {name: nadir, type: frame, elevation_deg: 90, azimuth_deg: 0, range_m: 50, gsd_m: 0.5, width: 8, height: 8}\n"
           // 16 bands of 25 nm: band-averaging D65 moves its chromaticity by 0.0003 (x) and 0.0002
           // (y) from the 5 nm value (computed separately from the CIE tables).
           "render: {bands: {range_um: [0.38, 0.78], count: 16}, hemisphere_samples: 4}\n";
}

// The standard's decoding: 8-bit code -> linear sRGB -> XYZ -> (x, y).
std::array<double, 2> decodedChromaticity(const uint8_t* px) {
    double l[3];
    for (int c = 0; c < 3; ++c) {
        const double e = px[c] / 255.0;
        l[c] = e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4);
    }
    const double X = 0.4124 * l[0] + 0.3576 * l[1] + 0.1805 * l[2];
    const double Y = 0.2126 * l[0] + 0.7152 * l[1] + 0.0722 * l[2];
    const double Z = 0.0193 * l[0] + 0.1192 * l[1] + 0.9505 * l[2];
    return {X / (X + Y + Z), Y / (X + Y + Z)};
}

std::vector<uint8_t> readRgbPng(const fs::path& p) {
    littoral::imageio::Reader in(p);
    EXPECT_TRUE(in.ok()) << p << ": " << in.error();
    if (!in.ok()) return {};
    const littoral::imageio::Header spec = in.header();
    EXPECT_EQ(spec.channels, 3);
    std::vector<uint8_t> px(static_cast<size_t>(spec.width) * spec.height * spec.channels);
    EXPECT_TRUE(in.read(spec.channels, littoral::imageio::PixelType::UInt8, px.data())) << in.error();
    return px;
}

struct Rendered {
    std::array<double, 2> linear;  // from the EXR radiance through linearSrgbPixels
    std::vector<uint8_t> png;
};

Rendered renderFloor(const std::string& name, const std::string& irradiance) {
    const fs::path dir = scratchDir("true_colour", name);
    const fs::path scene = writeTextFile(dir, "scene.yaml", floorScene(irradiance));
    const auto r = runLittoral("-q run " + scene.string() + " --out " + (dir / "out").string());
    EXPECT_EQ(r.status, 0) << r.output;
    Rendered out;
    const render::Film film = render::readExr(dir / "out" / "nadir.exr");
    const auto rgb = render::linearSrgbPixels(film);
    const auto& c = rgb[rgb.size() / 2];
    out.linear = chromaticity(linearSrgbToXyz({c[0], c[1], c[2]}));
    out.png = readRgbPng(dir / "out" / "nadir_rgb.png");
    return out;
}

}  // namespace

// D65 sunlight on a white floor: (x, y) = (0.3127, 0.3290) (CIE 15). Before 8 bits the tolerance
// is the band averaging (0.0003) plus the 4-decimal sRGB matrices (1e-4); the exposure puts every
// channel of the white floor at 1, so the PNG holds 255, 255, 255 up to one code of rounding.
TEST(TrueColour, WhiteFloorUnderD65SunlightIsNeutralAtTheD65WhitePoint) {
    const Rendered r = renderFloor("d65", d65Irradiance());
    EXPECT_NEAR(r.linear[0], 0.3127, 1e-3);
    EXPECT_NEAR(r.linear[1], 0.3290, 1e-3);
    ASSERT_EQ(r.png.size(), 8u * 8u * 3u);
    const uint8_t* px = &r.png[3 * (4 * 8 + 4)];
    EXPECT_LE(std::abs(px[0] - px[1]), 1) << int(px[0]) << " " << int(px[1]) << " " << int(px[2]);
    EXPECT_LE(std::abs(px[1] - px[2]), 1) << int(px[0]) << " " << int(px[1]) << " " << int(px[2]);
    const auto xy = decodedChromaticity(px);
    EXPECT_NEAR(xy[0], 0.3127, 2e-3);
    EXPECT_NEAR(xy[1], 0.3290, 2e-3);
}

// An equal-energy sun (a constant irradiance): illuminant E, x = y = 1/3, which sRGB (white D65)
// shows slightly warm: R at 255, G and B near 229 and 225. Half a code in each channel moves
// (x, y) by at most 0.0025 at these levels, hence 3e-3 for the PNG.
TEST(TrueColour, WhiteFloorUnderAnEqualEnergySunIsIlluminantE) {
    const Rendered r = renderFloor("equal_energy", "1000");
    EXPECT_NEAR(r.linear[0], 1.0 / 3.0, 1e-3);
    EXPECT_NEAR(r.linear[1], 1.0 / 3.0, 1e-3);
    ASSERT_EQ(r.png.size(), 8u * 8u * 3u);
    const uint8_t* px = &r.png[3 * (4 * 8 + 4)];
    EXPECT_EQ(px[0], 255);
    EXPECT_GT(px[0], px[1]);
    const auto xy = decodedChromaticity(px);
    EXPECT_NEAR(xy[0], 1.0 / 3.0, 3e-3);
    EXPECT_NEAR(xy[1], 1.0 / 3.0, 3e-3);
}

// Two bands over 0.4-0.6 um do not span the visible: no true-colour preview is written, and one
// left in the output folder by an earlier run is removed with the run's other outputs replaced.
TEST(TrueColour, BandsThatDoNotSpanTheVisibleWriteNoTrueColourPreview) {
    const fs::path dir = scratchDir("true_colour", "two_bands");
    std::string text = floorScene("1000");
    text.replace(text.find("{range_um: [0.38, 0.78], count: 16}"), std::string("{range_um: [0.38, 0.78], count: 16}").size(),
                 "{range_um: [0.4, 0.6], count: 2}");
    const fs::path scene = writeTextFile(dir, "scene.yaml", text);
    fs::create_directories(dir / "out");
    writeTextFile(dir / "out", "nadir_rgb.png", "stale");
    const auto r = runLittoral("run " + scene.string() + " --out " + (dir / "out").string());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_FALSE(fs::exists(dir / "out" / "nadir_rgb.png"));
    EXPECT_TRUE(fs::exists(dir / "out" / "nadir.png"));
}
