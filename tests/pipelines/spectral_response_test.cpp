// Bands with a spectral response (render.bands entries {centre_um, fwhm_um} and {response}): a
// render with such a band equals the response-weighted mean of a finely banded render of the same
// scene, the weights computed here from the response itself (the Gaussian's error function, the
// triangle's exact integral), within 0.1 % (single-precision images: the two agree to 1e-6). The
// scene is deterministic (the sun on a Lambertian floor in air, no sky) so that the comparison has
// no sampling noise, and its reflectance peaks inside the band so that a rectangle of the same
// width reads 13 % differently: the test would see a wrong weighting.
#include <cmath>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "render/image_output.h"
#include "core/atomic_file.h"
#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using namespace littoral;
using namespace littoral::testing_support;

namespace {

std::string bandsScene(const std::string& bands) {
    return "scene: {name: srf, domain: {x: [-5, 5], y: [-5, 5]}}\n"
           "sun: {zenith_deg: 30, irradiance: 1000}\n"
           "sky: {radiance: 0}\n"
           "bathymetry: {type: planar_slope, z0_m: 0, material: floor}\n"
           "materials: [{name: floor, reflectance: {wavelengths_um: [0.4, 0.53, 0.55, 0.57, 0.7], values: [0.1, 0.1, "
           "0.6, 0.1, 0.1]}}]\n"
           "sensors:\n"
           "  - {name: cam, type: frame, elevation_deg: 90, azimuth_deg: 0, range_m: 50, gsd_m: 0.5, width: 4, height: 4}\n"
           "render: {bands: " + bands + ", hemisphere_samples: 4}\n";
}

render::Film runBands(const std::string& name, const std::string& bands, const std::string& extraFile = "",
                      const std::string& extraText = "") {
    const fs::path dir = scratchDir("spectral_response", name);
    if (!extraFile.empty()) writeTextFile(dir, extraFile, extraText);
    const fs::path file = writeTextFile(dir, "scene.yaml", bandsScene(bands));
    const auto r = runLittoral("-q run " + file.string() + " --out " + (dir / "out").string());
    EXPECT_EQ(r.status, 0) << r.output;
    return render::readExr(dir / "out" / "cam.exr");
}

double phi(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

}  // namespace

TEST(SpectralResponse, GaussianBandIsTheResponseWeightedMeanOfAFineRender) {
    // centre 0.55, FWHM 0.04 um: support 0.47-0.63 um in 32 sub-bands of 5 nm (core/spectral_response.h).
    const render::Film g = runBands("gaussian", "[{centre_um: 0.55, fwhm_um: 0.04}]");
    const render::Film fine = runBands("fine_gaussian", "{range_um: [0.47, 0.63], count: 32}");
    const render::Film rect = runBands("rectangle", "[[0.53, 0.57]]");
    ASSERT_EQ(g.bandCount(), 1);
    EXPECT_NEAR(g.bands[0].lo, 0.53, 1e-12);  // nominal band: centre +- FWHM / 2
    EXPECT_NEAR(g.bands[0].hi, 0.57, 1e-12);
    const double sigma = 0.04 / (2 * std::sqrt(2 * std::log(2.0)));
    double sum = 0, norm = 0;
    for (int i = 0; i < 32; ++i) {
        const double lo = 0.47 + 0.005 * i, hi = lo + 0.005;
        const double w = phi((hi - 0.55) / sigma) - phi((lo - 0.55) / sigma);
        sum += w * fine.at(2, 2, i);
        norm += w;
    }
    const double expected = sum / norm;
    EXPECT_NEAR(g.at(2, 2, 0), expected, 1e-3 * expected);
    EXPECT_GT(std::abs(rect.at(2, 2, 0) - expected), 0.05 * expected);  // a rectangle is not the same band
    const std::string hdr = littoral::readTextFile(fs::path(LITTORAL_BINARY_DIR) / "test_scratch" / "spectral_response" / "gaussian" / "out" / "cam.hdr");
    EXPECT_NE(hdr.find("wavelength = {0.55}"), std::string::npos) << hdr;
    EXPECT_NE(hdr.find("fwhm = {0.04}"), std::string::npos) << hdr;
}

TEST(SpectralResponse, TabulatedResponseIsWeightedByItsOwnIntegral) {
    // A triangle from 0.50 to 0.60 um peaking at 0.55: over the 5 nm sub-band [l, h] its integral is
    // the trapezoid of its values at l and h (it is linear there). Centroid 0.55, FWHM 0.05 um.
    const std::string srf = "wavelength_um, response\n0.50, 0\n0.55, 1\n0.60, 0\n";
    const render::Film t = runBands("table", "[{response: {file: srf.csv}}]", "srf.csv", srf);
    const render::Film fine = runBands("fine_table", "{range_um: [0.5, 0.6], count: 20}");
    auto tri = [](double x) { return std::max(0.0, 1 - std::abs(x - 0.55) / 0.05); };
    double sum = 0, norm = 0;
    for (int i = 0; i < 20; ++i) {
        const double lo = 0.5 + 0.005 * i, hi = lo + 0.005, w = 0.5 * (tri(lo) + tri(hi));
        sum += w * fine.at(1, 1, i);
        norm += w;
    }
    EXPECT_NEAR(t.at(1, 1, 0), sum / norm, 1e-3 * sum / norm);
    EXPECT_NEAR(t.bands[0].lo, 0.525, 1e-9);
    EXPECT_NEAR(t.bands[0].hi, 0.575, 1e-9);
}

TEST(SpectralResponse, BadResponsesAreLocatedErrors) {
    struct Case {
        std::string name, bands, file, text, where, message;
    };
    const Case cases[] = {
        {"negative", "[{response: {file: srf.csv}}]", "srf.csv", "0.50, 0\n0.55, -1\n0.60, 0\n", "srf.csv:2:1",
         "value -1 is out of range; allowed [0, 1000000]"},
        {"uncovered", "[{response: {file: srf.csv}}]", "srf.csv", "0.50, 0\n0.55, 1\n0.60, 0.4\n", "scene.yaml:8:",
         "does not cover its band: the response at its long end, 0.6 um, is 40 % of its peak"},
        {"outside", "[{centre_um: 0.25, fwhm_um: 0.05}]", "", "", "scene.yaml:8:", "leaves the allowed 0.2 to 20 um"},
        {"too_many", "[{centre_um: 0.55, fwhm_um: 0.001}, [0.4, 0.7]]", "", "", "scene.yaml:8:",
         "internal sub-bands"},
        {"both", "[{centre_um: 0.55, fwhm_um: 0.04, response: 1}]", "", "", "scene.yaml:8:", "either"},
    };
    for (const Case& c : cases) {
        const fs::path dir = scratchDir("spectral_response", "bad_" + c.name);
        if (!c.file.empty()) writeTextFile(dir, c.file, c.text);
        const fs::path file = writeTextFile(dir, "scene.yaml", bandsScene(c.bands));
        for (const std::string cmd : {"check-scene", "run"}) {
            const fs::path out = dir / ("out-" + cmd);
            const auto r = runLittoral("-q " + cmd + " " + file.string() + (cmd == "run" ? " --out " + out.string() : ""));
            EXPECT_EQ(r.status, 1) << c.name << " " << cmd << ": " << r.output;
            EXPECT_NE(r.output.find(c.where), std::string::npos) << c.name << ": " << r.output;
            EXPECT_NE(r.output.find(c.message), std::string::npos) << c.name << ": " << r.output;
            EXPECT_FALSE(fs::exists(out)) << c.name;
        }
    }
}
