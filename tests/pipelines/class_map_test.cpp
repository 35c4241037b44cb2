// Classification maps looked up where each ray lands (issue 10): the ground's class, and so its
// material and texture, is read from the class map at the hit point's plan position, not once per
// terrain face. A 0.25 m checkerboard whose edges fall between the nodes of a 0.125 m terrain grid
// (the case) renders with every pixel that lies inside one check in that check's class,
// both in the material truth image and in radiance; a map that does not cover the terrain is a
// located error.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>

#include "core/atomic_file.h"
#include "core/units.h"
#include "render/film.h"
#include "render/image_output.h"
#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using namespace littoral;
using namespace littoral::testing_support;

namespace {


// The checkerboard: W x H pixels of 0.25 m over the extent [ex0, ex0 + 0.25 W] x [ey0, ey0 + 0.25 H],
// row 0 north; class (column + row) % 2.
constexpr int kW = 44, kH = 44;
constexpr double kPix = 0.25, kEx0 = -5.4, kEy0 = -5.35;  // edges 0.1 m / 0.15 m off the 0.125 m grid

int classAt(double x, double y) {
    const int i = static_cast<int>(std::floor((x - kEx0) / kPix));
    const int j = static_cast<int>(std::floor((kEy0 + kH * kPix - y) / kPix));
    return (i + j) % 2;
}

// Distance from (x, y) to the nearest check edge.
double edgeDistance(double x, double y) {
    const double u = (x - kEx0) / kPix, v = (y - kEy0) / kPix;
    return kPix * std::min(std::abs(u - std::round(u)), std::abs(v - std::round(v)));
}

// Binary PGM (P5, 8-bit): OpenImageIO reads it as a single-channel 8-bit image.
std::string checkerboardPgm() {
    std::string s = "P5\n" + std::to_string(kW) + " " + std::to_string(kH) + "\n255\n";
    for (int j = 0; j < kH; ++j)
        for (int i = 0; i < kW; ++i) s += static_cast<char>((i + j) % 2);
    return s;
}

std::string extentScene(const std::string& extent) {
    return "scene:\n  name: classes\n  domain: {x: [-5, 5], y: [-5, 5]}\n"
           "sun: {zenith_deg: 0, azimuth_deg: 0, irradiance: 1000}\n"
           "sky: {radiance: 0}\n"
           "bathymetry: {type: planar_slope, z0_m: 0.5, spacing_m: 0.125}\n"
           "texture_classes:\n  map: checks.pgm\n  extent: " + extent + "\n"
           "  classes:\n    - {index: 0, name: dark, reflectance: 0.2}\n    - {index: 1, name: light, reflectance: 0.6}\n"
           "sensors:\n  - {name: nadir, type: orthographic, position: [0.013, -0.021, 10], direction: [0, 0, -1], "
           "up: [0, 1, 0], pixel_size_m: 0.05, width: 160, height: 160}\n"
           "render:\n  hemisphere_samples: 1\n";
}

}  // namespace

// Orthographic nadir camera (0.05 m pixels, offset from the checks) over the checkerboard; sun at the
// zenith, black sky, Classic solver: a pixel whose footprint lies inside one check shows that
// check's material in the truth image and radiance r E cos(theta) / pi (r = 0.2 or 0.6, E = 1000),
// theta the angle of the sampled point of the 0.53 deg disc: 1 - cos(theta) < 1.1e-5, so 2e-5
// relative. Pixels whose footprint touches a check edge are not judged.
TEST(ClassMap, MisalignedCheckerboardRendersPerHitPoint) {
    const fs::path dir = scratchDir("class_map", "checkerboard");
    writeTextFile(dir, "checks.pgm", checkerboardPgm());
    const fs::path file =
        writeTextFile(dir, "scene.yaml", extentScene("{x: [" + std::to_string(kEx0) + ", " + std::to_string(kEx0 + kW * kPix) +
                                               "], y: [" + std::to_string(kEy0) + ", " + std::to_string(kEy0 + kH * kPix) + "]}"));
    const fs::path out = dir / "out";
    const CommandResult r = runLittoral("--quiet run " + file.string() + " --out " + out.string());
    ASSERT_EQ(r.status, 0) << r.output;
    // Material indices of the two classes in the IR.
    const std::string json = readTextFile(out / "ir" / "scene.json");
    std::map<std::string, int> index;
    {
        int k = 0;
        size_t pos = json.find("\"materials\"");
        for (size_t q = json.find("\"name\"", pos); q != std::string::npos && q < json.find("\"meshes\"");
             q = json.find("\"name\"", q + 1)) {
            const size_t a = json.find('"', json.find(':', q) + 1) + 1;
            index[json.substr(a, json.find('"', a) - a)] = k++;
        }
    }
    ASSERT_TRUE(index.count("dark") && index.count("light") && index.count("texture-classes")) << json.substr(0, 3000);
    const render::Film film = render::readExr(out / "nadir.exr");
    const render::TruthImages truth = render::readTruthExr(out / "nadir_truth.exr");
    int judged = 0, wrongClass = 0, wrongRadiance = 0;
    for (int j = 0; j < film.height; ++j)
        for (int i = 0; i < film.width; ++i) {
            // Pixel centre on the ground (camera.cpp: right = forward x up = (1, 0, 0), image up = +y).
            const double x = 0.013 + (i + 0.5 - film.width / 2.0) * 0.05;
            const double y = -0.021 - (j + 0.5 - film.height / 2.0) * 0.05;
            if (edgeDistance(x, y) < 0.5 * 0.05 * std::sqrt(2.0) + 1e-6) continue;  // the footprint touches an edge
            ++judged;
            const int c = classAt(x, y);
            const int expectId = index[c == 0 ? "dark" : "light"];
            const int id = truth.materialId[truth.index(i, j)];
            if (id != expectId) ++wrongClass;
            const double L = film.at(i, j, 0), pred = (c == 0 ? 0.2 : 0.6) * 1000.0 / kPi;
            if (std::abs(L - pred) > 2e-5 * pred) ++wrongRadiance;
            if (id != expectId || std::abs(L - pred) > 2e-5 * pred)
                ADD_FAILURE() << "pixel " << i << "," << j << " at (" << x << ", " << y << "): material " << id
                              << " (expected " << expectId << "), radiance " << L << " (expected " << pred << ")";
            if (wrongClass + wrongRadiance > 20) return;
        }
    EXPECT_GT(judged, 160 * 160 / 2);
    EXPECT_EQ(wrongClass, 0);
    EXPECT_EQ(wrongRadiance, 0);
    std::printf("[ class map ] %d of %d pixels inside one check: %d in the wrong class, %d with the wrong radiance\n",
                judged, film.width * film.height, wrongClass, wrongRadiance);
}

// A class map whose extent leaves part of the domain's terrain uncovered is an error at `extent`.
TEST(ClassMap, MapThatDoesNotCoverTheTerrainIsALocatedError) {
    const fs::path dir = scratchDir("class_map", "uncovered");
    writeTextFile(dir, "checks.pgm", checkerboardPgm());
    const fs::path file = writeTextFile(dir, "scene.yaml", extentScene("{x: [-5, 5], y: [-4, 5]}"));
    for (const std::string cmd : {"check-scene", "run"}) {
        const fs::path out = dir / "out";
        const CommandResult r =
            runLittoral("--quiet " + cmd + " " + file.string() + (cmd == "run" ? " --out " + out.string() : ""));
        EXPECT_EQ(r.status, 1) << cmd << ": " << r.output;
        EXPECT_NE(r.output.find("scene.yaml:9:11: error: "), std::string::npos) << cmd << ": " << r.output;
        EXPECT_NE(r.output.find("does not cover the terrain of the scene domain"), std::string::npos) << r.output;
        EXPECT_FALSE(fs::exists(out));
    }
}
