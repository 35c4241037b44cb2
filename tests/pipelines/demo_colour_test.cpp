// `littoral demo` renders water that looks like water: three bands over 0.4-0.7 um with a
// true-colour preview, and pure water's absorption in its constituents, so that the seabed fades
// faster in red than in blue-green as the water deepens.
//
// Expectation: the wet sand seen through the water is attenuated along the sun's and the view's
// paths, about exp(-(1/cos theta_w + 1) Kd z). Pure water alone absorbs 0.34 m^-1 at 650 nm
// against 0.057 at 550 nm and 0.009 at 450 nm (Pope & Fry 1997), so from 0.5-1 m to 2.5-4 m of
// depth (2.5 m more) red falls by a factor near exp(-2.1 x 0.35 x 2.5) = 0.16, green and blue by
// about exp(-2.1 x 0.1 x 2.5) = 0.6. The medians over thousands of pixels hide the glints and the
// photon-map noise; the test asks only for the order (red falls most), with a margin of 1.5x.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "render/image_output.h"
#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using namespace littoral;
using littoral::testing_support::runLittoral;
using littoral::testing_support::scratchDir;

using littoral::testing_support::legendId;
using littoral::testing_support::medianOf;

TEST(DemoColour, DeeperWaterIsDarkerInRedThanInBlueGreen) {
    const fs::path dir = scratchDir("demo_colour", "demo");
    const auto r = runLittoral("-q demo --out " + (dir / "out").string());
    ASSERT_EQ(r.status, 0) << r.output;
    const fs::path out = dir / "out";
    const render::Film film = render::readExr(out / "sim-c-nadir.exr");
    const render::TruthImages truth = render::readTruthExr(out / "sim-c-nadir_truth.exr");
    ASSERT_EQ(film.bandCount(), 3);
    EXPECT_TRUE(fs::exists(out / "sim-c-nadir_rgb.png"));
    const int sand = legendId(out / "sim-c-nadir_legend.csv", "wet-sand");
    ASSERT_GE(sand, 0);
    std::vector<double> shallow[3], deep[3];
    for (int y = 0; y < film.height; ++y)
        for (int x = 0; x < film.width; ++x) {
            const size_t i = truth.index(x, y);
            if (truth.surfaceId[i] != sand) continue;
            const double z = truth.hitDepth[i];
            for (int b = 0; b < 3; ++b) {
                if (z >= 0.5 && z <= 1.0) shallow[b].push_back(film.at(x, y, b));
                if (z >= 2.5 && z <= 4.0) deep[b].push_back(film.at(x, y, b));
            }
        }
    ASSERT_GT(shallow[0].size(), 1000u);
    ASSERT_GT(deep[0].size(), 1000u);
    double ratio[3];
    for (int b = 0; b < 3; ++b) ratio[b] = medianOf(deep[b]) / medianOf(shallow[b]);
    std::printf("deep / shallow medians: blue %.3f, green %.3f, red %.3f (%zu and %zu pixels)\n", ratio[0], ratio[1],
                ratio[2], shallow[0].size(), deep[0].size());
    // Bands in order of wavelength: 0.4-0.5 (blue), 0.5-0.6 (green), 0.6-0.7 um (red).
    EXPECT_LT(1.5 * ratio[2], ratio[1]) << ratio[0] << " " << ratio[1] << " " << ratio[2];
    EXPECT_LT(1.5 * ratio[2], ratio[0]) << ratio[0] << " " << ratio[1] << " " << ratio[2];
}
