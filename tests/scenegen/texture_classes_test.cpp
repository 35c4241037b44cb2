// Classification maps and the per-class mean/variance remap of textures.
#include <gtest/gtest.h>

#include "tests/support/test_support.h"

#include <cmath>
#include <filesystem>

#include "core/image_io.h"

#include "scenegen/texture_classes.h"

using namespace littoral;
using namespace littoral::scenegen;
namespace fs = std::filesystem;

namespace {


template <class T>
void writeImage(const fs::path& p, int w, int h, int nc, const std::vector<T>& data, imageio::PixelType type) {
    imageio::writeFile(p, {w, h, nc, type, {}, {}}, data.data());
}

}  // namespace

TEST(TextureRemap, HitsTheTargetMeanAndStandardDeviationOverTheClassOnly) {
    // t = 0, 1, 2, ..., 9 on the masked pixels (mean 4.5, population sd sqrt(8.25)); remapped to
    // mean 0.8, sd 0.1 the values are 0.8 + (t - 4.5) 0.1 / sqrt(8.25), all positive, so the
    // targets are met to rounding. Unmasked pixels (value 100) must not influence the statistics.
    std::vector<float> t;
    std::vector<char> mask;
    for (int i = 0; i < 10; ++i) {
        t.push_back(static_cast<float>(i));
        mask.push_back(1);
        t.push_back(100.0f);
        mask.push_back(0);
    }
    RemapStats s;
    const auto out = remapMeanStd(t, mask, 0.8, 0.1, &s);
    EXPECT_EQ(s.pixels, 10u);
    EXPECT_NEAR(s.meanBefore, 4.5, 1e-12);
    EXPECT_NEAR(s.stdBefore, std::sqrt(8.25), 1e-12);
    // float storage: relative rounding 6e-8 on values near 0.8.
    EXPECT_NEAR(s.meanAfter, 0.8, 1e-6);
    EXPECT_NEAR(s.stdAfter, 0.1, 1e-6);
    EXPECT_NEAR(out[0], 0.8 - 4.5 * 0.1 / std::sqrt(8.25), 1e-6);
    EXPECT_FLOAT_EQ(out[1], 0.8f);  // outside the class: the target mean
    EXPECT_EQ(s.clampedToZero, 0u);
    // A large sd forces negatives, which are clamped and counted.
    RemapStats s2;
    remapMeanStd(t, mask, 0.1, 1.0, &s2);
    EXPECT_GT(s2.clampedToZero, 0u);
    // A constant texture cannot be given a spread.
    EXPECT_THROW(remapMeanStd(std::vector<float>(4, 1.0f), std::vector<char>(4, 1), 1.0, 0.1, nullptr), InputError);
}

TEST(TextureClasses, MapLookupRemapAndUnknownClass) {
    const fs::path dir = testing_support::scratchDir("scenegen", "texture_classes");
    // 4 x 2 map: west half class 3, east half class 7 (row 0 = north).
    const std::vector<uint8_t> map = {3, 3, 7, 7, 3, 3, 7, 7};
    writeImage(dir / "classes.png", 4, 2, 1, map, imageio::PixelType::UInt8);
    // Texture 2 x 1 grey: values 0 and 1 (8-bit 0 and 255).
    writeImage(dir / "tex.png", 2, 1, 1, std::vector<uint8_t>{0, 255}, imageio::PixelType::UInt8);
    TextureClassesSpec spec;
    spec.map = dir / "classes.png";
    spec.extent = bathymetry::Extent{0, 0, 40, 10};
    TextureClassSpec sand;
    sand.index = 3;
    sand.name = "sand";
    sand.reflectance = Spectrum::constant(0.3);
    sand.texture = dir / "tex.png";
    sand.mean = 1.0;
    sand.stddev = 0.2;
    TextureClassSpec grass;
    grass.index = 7;
    grass.name = "grass";
    grass.reflectance = Spectrum::constant(0.1);
    spec.classes = {sand, grass};
    const TextureClasses tc = buildTextureClasses(spec, {0, 0, 1, 1});
    // Pixel columns are 10 m wide: x = 5 is column 0 (sand), x = 35 column 3 (grass).
    EXPECT_EQ(tc.slotAt(5, 5), 0);
    EXPECT_EQ(tc.slotAt(35, 5), 1);
    EXPECT_EQ(tc.slotAt(-100, 5), 0);  // clamped to the west edge
    // Sand pixels tile the texture 0, 1 / 0, 1: mean 0.5, sd 0.5 -> remapped to 0.8 and 1.2.
    EXPECT_NEAR(tc.textures[0][0], 0.8, 1e-6);
    EXPECT_NEAR(tc.textures[0][1], 1.2, 1e-6);
    EXPECT_NEAR(tc.stats[0].stdAfter, 0.2, 1e-6);
    EXPECT_TRUE(tc.textures[1].empty());
    const auto mats = tc.materials();
    EXPECT_EQ(mats[0].type, ir::Material::Type::Textured);
    EXPECT_EQ(mats[0].texture, "textures/sand.tif");
    EXPECT_EQ(mats[0].textureX1, 40.0);
    EXPECT_EQ(mats[1].type, ir::Material::Type::Lambertian);
    EXPECT_NEAR(tc.coverage()[0], 0.5, 1e-15);
    tc.writeTextures(dir / "ir");
    {
        imageio::Reader in(dir / "ir" / "textures" / "sand.tif");
        ASSERT_TRUE(in.ok()) << in.error();
        EXPECT_EQ(in.header().width, 4);
        EXPECT_EQ(in.header().storedType, "float");
    }

    // A map value without a class names the pixel and the defined classes.
    spec.classes.pop_back();
    try {
        buildTextureClasses(spec, {0, 0, 1, 1});
        FAIL() << "unclassified pixel accepted";
    } catch (const InputError& e) {
        const std::string w = e.what();
        EXPECT_NE(w.find("holds class value 7 (4 pixels, the first at column 2, row 0), but no class has index 7"), std::string::npos) << w;
        EXPECT_NE(w.find("defined: 3"), std::string::npos) << w;
    }
}

TEST(TextureClasses, FloatMapIsRefused) {
    const fs::path dir = testing_support::scratchDir("scenegen", "texture_classes_float");
    writeImage(dir / "classes.tif", 2, 2, 1, std::vector<float>{0, 1, 2, 3}, imageio::PixelType::Float);
    EXPECT_THROW(readClassMap(dir / "classes.tif", {0, 0, 1, 1}), InputError);
}

// A 16-bit map keeps indices above 255 as they are, and an 8-bit one is not rescaled to 16 bits
// (OpenImageIO would turn 7 into 7 x 257 = 1799 if asked for 16-bit values).
TEST(TextureClasses, SixteenBitIndicesAreReadAsStoredAndEightBitOnesAreNotRescaled) {
    const fs::path dir = testing_support::scratchDir("scenegen", "texture_classes_16bit");
    writeImage(dir / "classes16.png", 2, 1, 1, std::vector<uint16_t>{300, 4000}, imageio::PixelType::UInt16);
    EXPECT_EQ(readClassMap(dir / "classes16.png", {0, 0, 2, 1}).value, (std::vector<uint16_t>{300, 4000}));
    writeImage(dir / "classes8.png", 2, 1, 1, std::vector<uint8_t>{7, 255}, imageio::PixelType::UInt8);
    EXPECT_EQ(readClassMap(dir / "classes8.png", {0, 0, 2, 1}).value, (std::vector<uint16_t>{7, 255}));
}
