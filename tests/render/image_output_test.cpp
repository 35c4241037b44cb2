// Tests of render/image_output: EXR / ENVI round trips, headers and channel names, PNG display
// mapping, Gaussian blur moments, truth images, and atomic failure behaviour.
#include "render/image_output.h"

#include <gtest/gtest.h>

#include "tests/support/test_support.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <array>
#include <set>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/units.h"

using namespace littoral;
using namespace littoral::render;
namespace fs = std::filesystem;

namespace {

// A fresh directory per test under the build tree.
fs::path scratchDir(const std::string& name) { return testing_support::scratchDir("image_output", name); }

std::vector<std::string> listDir(const fs::path& d) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(d)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

// Film with awkward band edges and values spanning many magnitudes, signs, NaN and inf.
Film testFilm(int w, int h) {
    Film f(w, h, {Band{0.4123456789, 0.4312345678}, Band{0.55, 0.5625}, Band{1.6, 1.7}, Band{10.5, 11.5}});
    std::mt19937 rng(12345);
    std::uniform_real_distribution<float> u(-3.0f, 3.0f);
    for (float& v : f.pixels) v = std::pow(10.0f, u(rng)) * (u(rng) < -2.0f ? -1.0f : 1.0f);
    f.pixels[0] = std::numeric_limits<float>::quiet_NaN();
    f.pixels[1] = std::numeric_limits<float>::infinity();
    f.pixels[2] = 0.0f;
    f.pixels[3] = std::numeric_limits<float>::denorm_min();
    return f;
}

void expectBitIdentical(const Film& a, const Film& b) {
    ASSERT_EQ(a.width, b.width);
    ASSERT_EQ(a.height, b.height);
    ASSERT_EQ(a.bands.size(), b.bands.size());
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    EXPECT_EQ(std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)), 0);
}

}  // namespace

// ---- EXR --------------------------------------------------------------------------------------

TEST(Exr, RoundTripIsBitExactWithBandsAndMetadata) {
    const fs::path dir = scratchDir("exr_roundtrip");
    const Film f = testFilm(37, 23);
    writeExr(dir / "radiance.exr", f, {{"scene", "checkerboard"}, {"seed", "7"}});
    std::map<std::string, std::string> meta;
    const Film g = readExr(dir / "radiance.exr", &meta);
    expectBitIdentical(f, g);
    for (std::size_t b = 0; b < f.bands.size(); ++b) {
        // Edges are written as shortest round-trip decimals: exact.
        EXPECT_EQ(g.bands[b].lo, f.bands[b].lo);
        EXPECT_EQ(g.bands[b].hi, f.bands[b].hi);
    }
    EXPECT_EQ(meta.at("scene"), "checkerboard");
    EXPECT_EQ(meta.at("seed"), "7");
    EXPECT_EQ(listDir(dir), std::vector<std::string>{"radiance.exr"});  // no temporary left behind
}

TEST(Exr, ChannelNamesAndAttributesInTheFile) {
    const fs::path dir = scratchDir("exr_channels");
    const Film f = testFilm(4, 3);
    writeExr(dir / "r.exr", f);
    // Read as a generic image (core/image_io.h, OpenImageIO), as a user's tool would.
    imageio::Reader in(dir / "r.exr");
    ASSERT_TRUE(in.ok()) << in.error();
    const imageio::Header& spec = in.header();
    EXPECT_EQ(spec.channels, 4);
    EXPECT_EQ(spec.storedType, "float");
    std::set<std::string> names(spec.channelNames.begin(), spec.channelNames.end());
    // Centres: (0.4123456789 + 0.4312345678)/2 = 0.42179012335 -> "0.4218"; 0.55625; 1.65; 11.0.
    EXPECT_EQ(names, (std::set<std::string>{"L_0.4218um", "L_0.5563um", "L_1.6500um", "L_11.0000um"}));
    auto attr = [&](const char* name) { return spec.stringAttribute(name) ? *spec.stringAttribute(name) : "(none)"; };
    EXPECT_EQ(attr("littoral:units"), "W m^-2 sr^-1 um^-1");
    EXPECT_EQ(attr("littoral:band_lo_um"), "0.4123456789,0.55,1.6,10.5");
    EXPECT_EQ(attr("littoral:band_hi_um"), "0.4312345678,0.5625,1.7,11.5");
}

TEST(Exr, ChannelNamesGainDecimalsOnlyWhenNeeded) {
    EXPECT_EQ(bandChannelNames({Band{0.44, 0.46}}), std::vector<std::string>{"L_0.4500um"});
    // Centres 0.450010 and 0.450020 coincide at 4 decimals and differ at 5.
    const std::vector<std::string> n = bandChannelNames({Band{0.45000, 0.45002}, Band{0.45001, 0.45003}});
    EXPECT_EQ(n, (std::vector<std::string>{"L_0.45001um", "L_0.45002um"}));
}

TEST(Exr, MissingOrForeignFilesAreInputErrors) {
    const fs::path dir = scratchDir("exr_errors");
    EXPECT_THROW(readExr(dir / "absent.exr"), InputError);
    // An EXR without Littoral's band attributes.
    {
        const float px[4] = {1, 2, 3, 4};
        imageio::writeFile(dir / "foreign.exr", {2, 2, 1, imageio::PixelType::Float, {}, {}}, px);
    }
    EXPECT_THROW(readExr(dir / "foreign.exr"), InputError);
}

// ---- ENVI -------------------------------------------------------------------------------------

TEST(Envi, RoundTripIsBitExact) {
    const fs::path dir = scratchDir("envi_roundtrip");
    const Film f = testFilm(29, 17);
    writeEnvi(dir / "radiance.img", f, "unit test {braces}");
    const Film g = readEnvi(dir / "radiance.img");
    expectBitIdentical(f, g);
    for (std::size_t b = 0; b < f.bands.size(); ++b) {
        // Edges come back as centre -+ fwhm/2 from exactly written centre and width: a few ulp.
        EXPECT_NEAR(g.bands[b].lo, f.bands[b].lo, 1e-14);
        EXPECT_NEAR(g.bands[b].hi, f.bands[b].hi, 1e-14);
    }
    EXPECT_EQ(listDir(dir), (std::vector<std::string>{"radiance.hdr", "radiance.img"}));
}

TEST(Envi, HeaderContentsAndBsqLayout) {
    const fs::path dir = scratchDir("envi_header");
    Film f(3, 2, {Band{0.4, 0.5}, Band{0.5, 0.7}});
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x)
            for (int b = 0; b < 2; ++b) f.at(x, y, b) = static_cast<float>(100 * b + 10 * y + x);
    writeEnvi(dir / "r.img", f, "Test {scene}");
    const EnviHeader h = parseEnviHeader(readTextFile(dir / "r.hdr"), "r.hdr");
    EXPECT_EQ(h.getInt("samples"), 3);
    EXPECT_EQ(h.getInt("lines"), 2);
    EXPECT_EQ(h.getInt("bands"), 2);
    EXPECT_EQ(h.getInt("data type"), 4);
    EXPECT_EQ(h.getInt("byte order"), 0);
    EXPECT_EQ(h.getInt("header offset"), 0);
    EXPECT_EQ(h.get("interleave"), "bsq");
    EXPECT_EQ(h.get("file type"), "ENVI Standard");
    EXPECT_EQ(h.get("wavelength units"), "Micrometers");
    const std::vector<double> wl = h.getDoubles("wavelength"), fw = h.getDoubles("fwhm");
    ASSERT_EQ(wl.size(), 2u);
    EXPECT_DOUBLE_EQ(wl[0], 0.45);
    EXPECT_DOUBLE_EQ(wl[1], 0.6);
    EXPECT_NEAR(fw[0], 0.1, 1e-15);
    EXPECT_NEAR(fw[1], 0.2, 1e-15);
    EXPECT_EQ(h.list("band names"), (std::vector<std::string>{"L_0.4500um", "L_0.6000um"}));
    // Braces in the description would end the field early; they are replaced.
    EXPECT_NE(h.get("description").find("Test (scene)"), std::string::npos);
    EXPECT_NE(h.get("description").find("W m^-2 sr^-1 um^-1"), std::string::npos);

    // Raw file: 3*2*2 float32 little endian, band 0 plane first (BSQ), rows top first.
    EXPECT_EQ(fs::file_size(dir / "r.img"), 3u * 2u * 2u * 4u);
    std::ifstream in(dir / "r.img", std::ios::binary);
    unsigned char bytes[48];
    in.read(reinterpret_cast<char*>(bytes), 48);
    float v[12];
    for (int i = 0; i < 12; ++i) {
        const uint32_t u = bytes[4 * i] | (bytes[4 * i + 1] << 8) | (bytes[4 * i + 2] << 16) |
                           (static_cast<uint32_t>(bytes[4 * i + 3]) << 24);  // explicit little endian
        std::memcpy(&v[i], &u, 4);
    }
    const float expected[12] = {0, 1, 2, 10, 11, 12, 100, 101, 102, 110, 111, 112};
    for (int i = 0; i < 12; ++i) EXPECT_EQ(v[i], expected[i]) << i;
}

TEST(Envi, ReaderHandlesBilBigEndianNanometresAndOffset) {
    // A hand-made file as another tool would write it: 2 x 1 px, 2 bands, BIL, big endian,
    // 8-byte header offset, wavelengths in nanometres.
    const fs::path dir = scratchDir("envi_foreign");
    writeTextFileAtomic(dir / "x.hdr",
                        "ENVI\nsamples = 2\nlines = 1\nbands = 2\nheader offset = 8\ndata type = 4\n"
                        "interleave = BIL\nbyte order = 1\nwavelength units = Nanometers\n"
                        "wavelength = {\n 450.0,\n 550.0}\nfwhm = {100, 100}\n");
    // BIL: line 0 band 0 (x = 0, 1), then line 0 band 1.
    const float vals[4] = {1.5f, 2.5f, -3.0f, 4.25f};
    std::ofstream f(dir / "x.img", std::ios::binary);
    const char pad[8] = {};
    f.write(pad, 8);
    for (float v : vals) {
        uint32_t u;
        std::memcpy(&u, &v, 4);
        const unsigned char be[4] = {static_cast<unsigned char>(u >> 24), static_cast<unsigned char>(u >> 16),
                                     static_cast<unsigned char>(u >> 8), static_cast<unsigned char>(u)};
        f.write(reinterpret_cast<const char*>(be), 4);
    }
    f.close();
    const Film g = readEnvi(dir / "x.img");
    EXPECT_EQ(g.at(0, 0, 0), 1.5f);
    EXPECT_EQ(g.at(1, 0, 0), 2.5f);
    EXPECT_EQ(g.at(0, 0, 1), -3.0f);
    EXPECT_EQ(g.at(1, 0, 1), 4.25f);
    EXPECT_NEAR(g.bands[0].lo, 0.40, 1e-12);
    EXPECT_NEAR(g.bands[1].hi, 0.60, 1e-12);
}

TEST(Envi, BadFilesAreInputErrors) {
    const fs::path dir = scratchDir("envi_bad");
    EXPECT_THROW(parseEnviHeader("not envi\n", "h"), InputError);
    EXPECT_THROW(parseEnviHeader("ENVI\nwavelength = {1, 2\n", "h"), InputError);
    // Size mismatch between header and data.
    writeTextFileAtomic(dir / "s.hdr", "ENVI\nsamples = 2\nlines = 2\nbands = 1\ndata type = 4\n"
                                       "interleave = bsq\nbyte order = 0\nwavelength = {0.5}\nfwhm = {0.1}\n");
    writeTextFileAtomic(dir / "s.img", std::string(12, '\0'));  // needs 16 bytes
    EXPECT_THROW(readEnvi(dir / "s.img"), InputError);
    // Unsupported data type (2 = int16).
    writeTextFileAtomic(dir / "t.hdr", "ENVI\nsamples = 1\nlines = 1\nbands = 1\ndata type = 2\n"
                                       "wavelength = {0.5}\nfwhm = {0.1}\n");
    writeTextFileAtomic(dir / "t.img", std::string(2, '\0'));
    EXPECT_THROW(readEnvi(dir / "t.img"), InputError);
    Film f(1, 1, {Band{0.4, 0.6}});
    EXPECT_THROW(writeEnvi(dir / "u.hdr", f), InputError);  // must name the data file
}

// ---- Atomic failure behaviour ----------------------------------------------------------------

TEST(AtomicWrites, UnwritablePathThrowsInputErrorAndLeavesNoFile) {
    const fs::path dir = scratchDir("unwritable");
    // A regular file where a directory is needed: creating "blocker/out.*" fails even for root.
    writeTextFileAtomic(dir / "blocker", "x");
    Film f(2, 2, {Band{0.4, 0.6}});
    TruthImages t(2, 2);
    EXPECT_THROW(writeExr(dir / "blocker" / "out.exr", f), InputError);
    EXPECT_THROW(writeEnvi(dir / "blocker" / "out.img", f), InputError);
    EXPECT_THROW(writePngPreview(dir / "blocker" / "out.png", f), InputError);
    EXPECT_THROW(writeTruthExr(dir / "blocker" / "t.exr", t), InputError);
    EXPECT_THROW(writeMaterialIdTiff(dir / "blocker" / "t.tif", t), InputError);
    EXPECT_THROW(writeMaterialIdPng(dir / "blocker" / "t.png", t), InputError);
    EXPECT_EQ(listDir(dir), std::vector<std::string>{"blocker"});
}

TEST(AtomicWrites, FailedRenameLeavesNoPartialFiles) {
    const fs::path dir = scratchDir("failed_rename");
    Film f(2, 2, {Band{0.4, 0.6}});
    // The final name is occupied by a non-empty directory: the data is written to the temporary,
    // the rename fails, and the temporary is removed.
    fs::create_directories(dir / "r.exr" / "keep");
    EXPECT_THROW(writeExr(dir / "r.exr", f), InputError);
    // ENVI: the header rename fails after the data rename succeeded; the data must be removed too.
    fs::create_directories(dir / "e.hdr" / "keep");
    EXPECT_THROW(writeEnvi(dir / "e.img", f), InputError);
    EXPECT_EQ(listDir(dir), (std::vector<std::string>{"e.hdr", "r.exr"}));  // only the blocking dirs
    EXPECT_TRUE(fs::is_directory(dir / "e.hdr"));
}

// ---- PNG previews -----------------------------------------------------------------------------

namespace {
std::vector<uint8_t> readPng(const fs::path& p, int* w, int* h, int* nc) {
    imageio::Reader in(p);
    EXPECT_TRUE(in.ok()) << in.error();
    const imageio::Header spec = in.header();
    *w = spec.width;
    *h = spec.height;
    *nc = spec.channels;
    std::vector<uint8_t> px(static_cast<std::size_t>(spec.width) * spec.height * spec.channels);
    EXPECT_TRUE(in.read(spec.channels, imageio::PixelType::UInt8, px.data())) << in.error();
    return px;
}
}  // namespace

TEST(Preview, GammaMappingOfKnownValues) {
    // v = clamp(L / white, 0, 1)^0.65, byte = round(255 v). Hand values:
    // 0.25^0.65 = 0.406126 -> 103.56 -> 104; 0.5^0.65 = 0.637280 -> 162.51 -> 163;
    // 0.75^0.65 = 0.829449 -> 211.51 -> 212; 1 -> 255; 2 (over white) -> 255; -1 and NaN -> 0.
    EXPECT_EQ(displayValue(0.25, 1.0, 0.65), 104);
    EXPECT_EQ(displayValue(0.5, 1.0, 0.65), 163);
    EXPECT_EQ(displayValue(0.75, 1.0, 0.65), 212);
    EXPECT_EQ(displayValue(1.0, 1.0, 0.65), 255);
    EXPECT_EQ(displayValue(2.0, 1.0, 0.65), 255);
    EXPECT_EQ(displayValue(-1.0, 1.0, 0.65), 0);
    EXPECT_EQ(displayValue(std::nan(""), 1.0, 0.65), 0);
    EXPECT_EQ(displayValue(0.5, 1.0, 1.0), 128);  // linear: 127.5 rounds half away from zero

    const fs::path dir = scratchDir("preview_gamma");
    Film f(7, 1, {Band{0.4, 0.6}});
    const float vals[7] = {0.0f, 0.25f, 0.5f, 0.75f, 1.0f, 2.0f, -1.0f};
    for (int x = 0; x < 7; ++x) f.at(x, 0, 0) = vals[x];
    PreviewOptions o;
    o.mapping = PreviewOptions::Mapping::Grey;
    o.whiteLevel = 1.0;
    writePngPreview(dir / "g.png", f, o);
    int w, h, nc;
    const std::vector<uint8_t> px = readPng(dir / "g.png", &w, &h, &nc);
    ASSERT_EQ(nc, 1);
    const uint8_t expected[7] = {0, 104, 163, 212, 255, 255, 0};
    for (int x = 0; x < 7; ++x) EXPECT_EQ(px[x], expected[x]) << x;
}

TEST(Preview, PercentileExposure) {
    // Values 1..100: the type-7 0.99 quantile is 1 + 99 * 0.99 = 99.01, so the pixel holding 50
    // shows round(255 (50 / 99.01)^0.65) = round(163.56) = 164, and 100 saturates.
    const fs::path dir = scratchDir("preview_percentile");
    Film f(100, 1, {Band{0.4, 0.6}});
    for (int x = 0; x < 100; ++x) f.at(x, 0, 0) = static_cast<float>(x + 1);
    PreviewOptions o;
    o.mapping = PreviewOptions::Mapping::Grey;
    writePngPreview(dir / "p.png", f, o);
    int w, h, nc;
    const std::vector<uint8_t> px = readPng(dir / "p.png", &w, &h, &nc);
    EXPECT_EQ(px[49], 164);
    EXPECT_EQ(px[99], 255);
    EXPECT_EQ(px[98], 255);  // 99 / 99.01 = 0.99990 -> 254.98 -> 255
    EXPECT_EQ(px[97], 253);  // (98 / 99.01)^0.65 * 255 = 0.993358 * 255 = 253.31 -> 253
}

TEST(Preview, RgbMappingPicksNearestBands) {
    // Bands centred 0.45, 0.55, 0.65, 0.85 um with constants 0.2, 0.4, 0.8, 1.0; white 1, gamma 1:
    // R <- 0.65 band (0.8 -> 204), G <- 0.55 (0.4 -> 102), B <- 0.45 (0.2 -> 51); 0.85 unused.
    const fs::path dir = scratchDir("preview_rgb");
    Film f(2, 2, {Band{0.4, 0.5}, Band{0.5, 0.6}, Band{0.6, 0.7}, Band{0.8, 0.9}});
    const float c[4] = {0.2f, 0.4f, 0.8f, 1.0f};
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x)
            for (int b = 0; b < 4; ++b) f.at(x, y, b) = c[b];
    PreviewOptions o;
    o.whiteLevel = 1.0;
    o.gamma = 1.0;
    writePngPreview(dir / "rgb.png", f, o);
    int w, h, nc;
    const std::vector<uint8_t> px = readPng(dir / "rgb.png", &w, &h, &nc);
    ASSERT_EQ(nc, 3);
    EXPECT_EQ(px[0], 204);
    EXPECT_EQ(px[1], 102);
    EXPECT_EQ(px[2], 51);
    PreviewOptions bad;
    bad.gamma = 0.0;
    EXPECT_THROW(writePngPreview(dir / "bad.png", f, bad), InputError);
    bad = PreviewOptions{};
    bad.percentile = 0.0;
    EXPECT_THROW(writePngPreview(dir / "bad.png", f, bad), InputError);
    bad = PreviewOptions{};
    bad.blurSigma = -1.0;
    EXPECT_THROW(writePngPreview(dir / "bad.png", f, bad), InputError);
}

// ---- Gaussian blur ----------------------------------------------------------------------------

TEST(GaussianBlur, KernelIsNormalisedWithStatedVariance) {
    for (double sigma : {1.0, 1.5, 2.0, 3.3, 5.0}) {
        const std::vector<double> k = gaussianKernel(sigma);
        const int r = static_cast<int>(k.size() / 2);
        EXPECT_EQ(r, static_cast<int>(std::ceil(4 * sigma)));
        double sum = 0, m1 = 0, m2 = 0;
        for (int i = -r; i <= r; ++i) {
            sum += k[i + r];
            m1 += i * k[i + r];
            m2 += double(i) * i * k[i + r];
        }
        EXPECT_NEAR(sum, 1.0, 1e-14);
        EXPECT_NEAR(m1, 0.0, 1e-14);
        // Truncating a Gaussian at 4 sigma keeps 1 - 8 phi(4) / (2 Phi(4) - 1) = 99.89% of its
        // variance; integer sampling adds a relative error ~ 8 pi^2 sigma^2 exp(-2 pi^2 sigma^2)
        // (Poisson summation), < 1e-6 for sigma >= 1. So the variance is sigma^2 within 0.2%,
        // inside the 1% requirement.
        EXPECT_NEAR(m2 / (sigma * sigma), 1.0, 0.002) << sigma;
    }
    EXPECT_EQ(gaussianKernel(0.0), std::vector<double>{1.0});
    EXPECT_THROW(gaussianKernel(-0.5), InputError);
}

TEST(GaussianBlur, DissertationKernel) {
    // seed-ch05-10.md §1.10: kernel values 0.2909, 1.0000, 0.2909 near the peak.
    const std::vector<double> k = gaussianKernel(kDissertationBlurSigma);
    ASSERT_EQ(k.size(), 7u);  // r = ceil(4 * 0.636) = 3
    EXPECT_NEAR(k[2] / k[3], 0.2909, 5e-5);
    EXPECT_NEAR(k[4] / k[3], 0.2909, 5e-5);
    // Further taps exp(-x^2 / (2 sigma^2)) = 0.2909^(x^2): 0.00716 at 2, 1.5e-5 at 3.
    EXPECT_NEAR(k[1] / k[3], std::pow(0.2909, 4), 1e-5);
    EXPECT_NEAR(k[0] / k[3], std::pow(0.2909, 9), 1e-7);
    // Below 1 px, integer sampling shrinks the variance: hand sum with weights 1, 0.2909,
    // 0.007161, 1.4918e-5 at x = 0, 1, 2, 3:
    // (2 * 0.2909 + 8 * 0.007161 + 18 * 1.4918e-5) / 1.596152 = 0.400561 px^2, versus
    // sigma^2 = 0.404932 (-1.1%). Tolerance 1e-5: the 4-digit inputs of the hand sum.
    double m2 = 0;
    for (int i = -3; i <= 3; ++i) m2 += double(i) * i * k[i + 3];
    EXPECT_NEAR(m2, 0.400561, 1e-5);
}

TEST(GaussianBlur, PreservesIntegralAndHasKernelVarianceIn2D) {
    // A unit impulse far from the borders spreads into the outer product of the kernel:
    // total preserved (float accumulation: 1e-6), second moment along x and y = kernel variance.
    const int n = 41;
    const double sigma = 2.0;
    std::vector<float> img(n * n, 0.0f);
    img[20 * n + 20] = 1.0f;
    const std::vector<float> out = gaussianBlur(img, n, n, sigma);
    const std::vector<double> k = gaussianKernel(sigma);
    double kvar = 0;
    for (int i = 0; i < static_cast<int>(k.size()); ++i) kvar += sqr(i - 8.0) * k[i];
    double sum = 0, mx = 0, mxx = 0, myy = 0, mxy = 0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const double v = out[y * n + x];
            sum += v;
            mx += v * (x - 20);
            mxx += v * sqr(x - 20.0);
            myy += v * sqr(y - 20.0);
            mxy += v * (x - 20.0) * (y - 20.0);
        }
    EXPECT_NEAR(sum, 1.0, 1e-6);
    EXPECT_NEAR(mx, 0.0, 1e-6);
    EXPECT_NEAR(mxx, kvar, 1e-6);
    EXPECT_NEAR(myy, kvar, 1e-6);
    EXPECT_NEAR(mxy, 0.0, 1e-6);  // separable, isotropic: no cross term
    EXPECT_NEAR(mxx / (sigma * sigma), 1.0, 0.002);  // see KernelIsNormalisedWithStatedVariance
    // Peak value is k0^2 (kernel centre index r = 8).
    EXPECT_NEAR(out[20 * n + 20], k[8] * k[8], 1e-7);
}

TEST(GaussianBlur, ConstantImageStaysConstantAtBorders) {
    std::vector<float> img(9 * 5, 3.5f);
    const std::vector<float> out = gaussianBlur(img, 9, 5, 1.7);
    for (float v : out) EXPECT_NEAR(v, 3.5f, 1e-6f);
}

TEST(GaussianBlur, FilmBlursEveryBand) {
    Film f(11, 11, {Band{0.4, 0.5}, Band{0.5, 0.6}});
    f.at(5, 5, 0) = 1.0f;
    f.at(5, 5, 1) = 2.0f;
    const Film g = gaussianBlur(f, 1.0);
    const std::vector<double> k = gaussianKernel(1.0);
    ASSERT_EQ(k.size(), 9u);  // centre index 4
    EXPECT_NEAR(g.at(5, 5, 0), k[4] * k[4], 1e-7);
    EXPECT_NEAR(g.at(6, 5, 1), 2.0 * k[4] * k[5], 1e-7);
}

// ---- Truth images -----------------------------------------------------------------------------

TEST(Truth, ExrRoundTrip) {
    const fs::path dir = scratchDir("truth_exr");
    TruthImages t(3, 2);
    const int32_t ids[6] = {-1, 0, 5, 65535, 2, 1};
    for (int p = 0; p < 6; ++p) t.materialId[p] = ids[p];
    t.range[1] = 12.5f;
    t.range[2] = 1234.0625f;
    t.hitDepth[1] = 0.0f;
    t.hitDepth[2] = 3.25f;
    writeTruthExr(dir / "truth.exr", t, {"ground", "water, clear", "100%"});
    {
        imageio::Reader in(dir / "truth.exr");
        ASSERT_TRUE(in.ok()) << in.error();
        ASSERT_NE(in.header().stringAttribute("littoral:materials"), nullptr);
        EXPECT_EQ(*in.header().stringAttribute("littoral:materials"), "ground,water%2C clear,100%25");
    }
    const TruthImages r = readTruthExr(dir / "truth.exr");
    ASSERT_EQ(r.width, 3);
    ASSERT_EQ(r.height, 2);
    EXPECT_EQ(r.materialId, t.materialId);
    EXPECT_TRUE(std::isinf(r.range[0]));
    EXPECT_EQ(r.range[1], 12.5f);
    EXPECT_EQ(r.range[2], 1234.0625f);
    EXPECT_TRUE(std::isnan(r.hitDepth[0]));
    EXPECT_EQ(r.hitDepth[1], 0.0f);
    EXPECT_EQ(r.hitDepth[2], 3.25f);
}

TEST(Truth, MaterialIdTiffIsInt32) {
    const fs::path dir = scratchDir("truth_tiff");
    TruthImages t(4, 1);
    t.materialId = {-1, 0, 70000, 2147483647};  // beyond float's exact-integer range too
    writeMaterialIdTiff(dir / "ids.tif", t);
    {
        imageio::Reader in(dir / "ids.tif");
        ASSERT_TRUE(in.ok()) << in.error();
        EXPECT_EQ(in.header().storedType, "int");
    }
    int w = 0, h = 0;
    EXPECT_EQ(readMaterialIdTiff(dir / "ids.tif", &w, &h), t.materialId);
    EXPECT_EQ(w, 4);
    EXPECT_EQ(h, 1);
}

TEST(Truth, FalseColourPng) {
    const fs::path dir = scratchDir("truth_png");
    TruthImages t(17, 1);
    for (int i = 0; i < 17; ++i) t.surfaceId[i] = i - 1;  // -1 .. 15 (the PNG shows the opaque surface)
    writeMaterialIdPng(dir / "ids.png", t);
    int w, h, nc;
    const std::vector<uint8_t> px = readPng(dir / "ids.png", &w, &h, &nc);
    ASSERT_EQ(nc, 3);
    EXPECT_EQ(px[0], 0);
    EXPECT_EQ(px[1], 0);
    EXPECT_EQ(px[2], 0);
    std::set<std::array<uint8_t, 3>> colours;
    for (int i = 1; i < 17; ++i) {
        uint8_t c[3];
        materialIdColour(i - 1, c);
        EXPECT_EQ(px[3 * i], c[0]);
        EXPECT_EQ(px[3 * i + 1], c[1]);
        EXPECT_EQ(px[3 * i + 2], c[2]);
        EXPECT_GT(int(c[0]) + c[1] + c[2], 0);  // never black: black means "nothing hit"
        colours.insert({c[0], c[1], c[2]});
    }
    EXPECT_EQ(colours.size(), 16u);  // 16 materials, 16 distinct colours
}
