// The sensor model from a scene file: `psf` and `detector` on a sensor write NAME_psf.exr,
// NAME_noisy.exr and NAME_detector.json beside the untouched radiance; bad kernels and misplaced
// detectors are located errors from check-scene, build and run alike.
#include <string>

#include <gtest/gtest.h>

#include "render/image_output.h"
#include "core/atomic_file.h"
#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using namespace littoral;
using namespace littoral::testing_support;

namespace {

std::string sensorScene(const std::string& sensorExtra) {
    return "scene: {name: sensor, domain: {x: [-5, 5], y: [-5, 5]}}\n"
           "sun: {zenith_deg: 30, irradiance: 1000}\n"
           "sky: {radiance: 0}\n"
           "bathymetry: {type: planar_slope, z0_m: 0, material: floor}\n"
           "materials: [{name: floor, reflectance: 0.3}]\n"
           "sensors:\n"
           "  - {name: cam, type: frame, elevation_deg: 90, azimuth_deg: 0, range_m: 50, gsd_m: 0.5, width: 16, height: 16" +
           sensorExtra + "}\n"
           "render: {hemisphere_samples: 4}\n";
}

}  // namespace

TEST(SensorModelCli, PsfAndDetectorWriteTheirImagesBesideTheRadiance) {
    const fs::path dir = scratchDir("sensor_model_cli", "run");
    writeTextFile(dir, "psf.csv", "# a 3 x 3 kernel\n0, 1, 0\n1, 4, 1\n0, 1, 0\n");
    const fs::path file = writeTextFile(
        dir, "scene.yaml",
        sensorScene(", psf: {type: kernel, file: psf.csv},\n      detector: {aperture_mm: 0.5, integration_ms: 1, quantum_efficiency: "
              "0.5, read_noise_e: 20, full_well_e: 1000000, bits: 16}"));
    const auto r = runLittoral("run " + file.string() + " --out " + (dir / "out").string());
    ASSERT_EQ(r.status, 0) << r.output;
    const render::Film clean = render::readExr(dir / "out" / "cam.exr");
    const render::Film blurred = render::readExr(dir / "out" / "cam_psf.exr");
    const render::Film noisy = render::readExr(dir / "out" / "cam_noisy.exr");
    // The blurred pixel is the kernel's weighted sum of the clean ones, (4 c + n + s + e + w) / 8.
    // The frame camera (10 um pitch, focal 1 mm: Omega = 1e-4 sr) behind a 0.5 mm aperture collects
    // N = 4e5 electrons per pixel in 1 ms, below the 1e6 full well: the noisy image's mean over the
    // 256 pixels is the blurred radiance's within 5 of its standard errors.
    const double expect = (4 * clean.at(8, 8, 0) + clean.at(7, 8, 0) + clean.at(9, 8, 0) + clean.at(8, 7, 0) +
                           clean.at(8, 9, 0)) / 8;
    double mean = 0, var = 0;
    for (size_t p = 0; p < noisy.pixels.size(); ++p) mean += noisy.pixels[p];
    mean /= noisy.pixels.size();
    for (size_t p = 0; p < noisy.pixels.size(); ++p) var += (noisy.pixels[p] - mean) * (noisy.pixels[p] - mean);
    var /= noisy.pixels.size() - 1;
    EXPECT_NEAR(blurred.at(8, 8, 0), expect, 1e-5 * expect);
    double blurredMean = 0;  // the detector records the blurred radiance
    for (float v : blurred.pixels) blurredMean += v;
    blurredMean /= blurred.pixels.size();
    EXPECT_NEAR(mean, blurredMean, 5 * std::sqrt(var / noisy.pixels.size()));
    EXPECT_GT(var, 0.0);
    const std::string report = littoral::readTextFile(dir / "out" / "cam_detector.json");
    EXPECT_NE(report.find("\"snr\""), std::string::npos) << report;
    EXPECT_NE(r.output.find("sensor 'cam' band [0.4, 0.6] um: mean signal"), std::string::npos) << r.output;
    // The run ends with its time and peak memory.
    EXPECT_NE(r.output.find(" s, peak memory "), std::string::npos) << r.output;
}

TEST(SensorModelCli, BadKernelsAndDetectorsAreLocatedErrors) {
    const fs::path dir = scratchDir("sensor_model_cli", "bad");
    struct Case {
        std::string name, kernel, extra, where, message;
    };
    const Case cases[] = {
        {"negative", "0, 1, 0\n1, -4, 1\n0, 1, 0\n", ", psf: {type: kernel, file: k.csv}", "k.csv:2:1",
         "PSF value '-4' is not a finite number >= 0"},
        {"ragged", "0, 1, 0\n1, 4\n0, 1, 0\n", ", psf: {type: kernel, file: k.csv}", "k.csv:2:1",
         "this row has 2 values, the first row 3"},
        {"even", "1, 1\n1, 1\n", ", psf: {type: kernel, file: k.csv}", "k.csv", "its width and height must be odd"},
        {"fwhm", "", ", psf: {type: gaussian, fwhm_px: 0}", "scene.yaml:7:", "0 is out of range"},
        {"qe", "", ", detector: {aperture_mm: 50, integration_ms: 1, quantum_efficiency: 1.5, full_well_e: 1000}",
         "scene.yaml:7:", "1.5 is out of range"},
        {"unknown", "", ", detector: {aperture_mm: 50, integration_ms: 1, quantum_efficiency: 0.5, full_well_e: 1000, "
                        "gain: 2}", "scene.yaml:7:", "gain"},
    };
    for (const Case& c : cases) {
        const fs::path d = dir / c.name;
        fs::create_directories(d);
        if (!c.kernel.empty()) writeTextFile(d, "k.csv", c.kernel);
        const fs::path file = writeTextFile(d, "scene.yaml", sensorScene(c.extra));
        for (const std::string cmd : {"check-scene", "build", "run"}) {
            const fs::path out = d / ("out-" + cmd);
            const auto r = runLittoral("-q " + cmd + " " + file.string() + (cmd == "check-scene" ? "" : " --out " + out.string()));
            EXPECT_EQ(r.status, 1) << c.name << " " << cmd << ": " << r.output;
            EXPECT_NE(r.output.find(c.where), std::string::npos) << c.name << " " << cmd << ": " << r.output;
            EXPECT_NE(r.output.find(c.message), std::string::npos) << c.name << " " << cmd << ": " << r.output;
            EXPECT_FALSE(fs::exists(out)) << c.name << " " << cmd;
        }
    }
}
