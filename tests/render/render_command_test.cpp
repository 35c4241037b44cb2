// The `littoral render` path: Scene IR written to disk (ir::writeIR), read back and rendered by
// runRenderJob(irDir, ...) and by the command-line tool, outputs read back.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>

#include "core/error.h"
#include "core/units.h"
#include "render/image_output.h"
#include "render/render_job.h"
#include "tests/render/render_test_scenes.h"

namespace littoral::render {
namespace {

using namespace testing;
using M = ir::Material;

ir::SceneIR snellScene() {
    // The submerged camera of test C at a reduced size (c = 0, z = 2 m): on-axis radiance
    // (E_h/pi) T_f(0) n^2 = 0.55949 (seed-ch01-04.md §4.3 table).
    ir::SceneIR s = uniformSkyScene();
    s.media.push_back(water(0, 0, 1.34));
    s.materials.push_back(material("surface", M::Type::Dielectric, M::Solver::Fresnel));
    s.materials.push_back(material("black", M::Type::Black, M::Solver::Classic));
    s.meshes.push_back(meshOf("water", box({-50, -50, -10}, {50, 50, 0}, 0, 1), {"surface", "black"}, "water", "",
                              true));
    s.sensors.push_back(pinhole("up", {0, 0, -2}, {0, 0, 1}, {0, 1, 0}, 21, 21, 0.005, 1e-4, "water"));
    ir::Probe p;
    p.name = "p1";
    p.position = {0, 0, -1};
    p.medium = "water";
    p.quantities = {"Ed", "Lu"};
    s.probes.push_back(p);
    s.render.settings.set("probe_samples", 4096);
    return s;
}

std::filesystem::path scratch(const std::string& name) {
    const auto d = std::filesystem::path(LITTORAL_BINARY_DIR) / "test_output" / name;
    std::filesystem::remove_all(d);
    return d;
}

TEST(RenderCommand, IrOnDiskRoundTripAndOutputs) {
    const auto dir = scratch("cmd_ir");
    ir::writeIR(snellScene(), dir / "ir");
    RenderJobOptions o;
    o.progress = false;
    const auto res = runRenderJob(dir / "ir", dir / "out", o);
    ASSERT_EQ(res.images.size(), 1u);
    const Film f = readExr(dir / "out" / "up.exr");
    ASSERT_EQ(f.width, 21);
    EXPECT_NEAR(f.at(10, 10, 0), 0.55949, 2e-5);  // Eq. 4.7 with c = 0, on axis
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / "up.hdr"));
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / "probes.csv"));
    // Probe in lossless water under a uniform sky seen through a flat surface: every upward
    // sample inside Snell's window carries T_f n^2 / pi, TIR samples see the black floor:
    // Ed = n^2 Int_window T_f(theta_w) cos(theta_w) dOmega / pi ... = Int_air T_f cos dOmega / pi
    // = the cosine-weighted mean air->water transmittance, 0.932489 for n = 1.34 (numerical
    // quadrature of Eq. 4.2). Tolerance: 4 standard errors reported by the probe (conservative:
    // computed as for independent samples, the layout is stratified). Lu = 0.
    ASSERT_EQ(res.probes.size(), 2u);
    EXPECT_NEAR(res.probes[0].mean[0], 0.932489, 4 * res.probes[0].stderr_[0]);
    EXPECT_LT(res.probes[0].stderr_[0], 0.02);
    std::printf("[ probe ] Ed below the surface %.5f +- %.5f (predicted 0.932489)\n", res.probes[0].mean[0],
                res.probes[0].stderr_[0]);
    EXPECT_EQ(res.probes[1].mean[0], 0.0);
}

// The command-line tool itself (the executable must have been built: a missing one fails).
TEST(RenderCommand, ExitCodesAndNoOutputOnBadInput) {
    const auto exe = std::filesystem::path(LITTORAL_BINARY_DIR) / "bin" / "littoral";
    ASSERT_TRUE(std::filesystem::exists(exe)) << exe << " not built";
    const auto dir = scratch("cmd_cli");
    ir::writeIR(snellScene(), dir / "good");
    ir::SceneIR bad = snellScene();
    bad.sensors[0].height = 0;
    ir::writeIR(bad, dir / "bad");
    auto run = [&](const std::string& args) {
        const std::string cmd = exe.string() + " --quiet render " + args + " > /dev/null 2>&1";
        const int rc = std::system(cmd.c_str());
        return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
    };
    EXPECT_EQ(run((dir / "good").string() + " --out " + (dir / "out_good").string() + " --threads 2"), 0);
    EXPECT_TRUE(std::filesystem::exists(dir / "out_good" / "up.exr"));
    EXPECT_EQ(run((dir / "bad").string() + " --out " + (dir / "out_bad").string()), 1);
    EXPECT_FALSE(std::filesystem::exists(dir / "out_bad"));
    EXPECT_EQ(run((dir / "good").string() + " --out " + (dir / "out_sensor").string() + " --sensor nope"), 1);
    EXPECT_FALSE(std::filesystem::exists(dir / "out_sensor"));
}

}  // namespace
}  // namespace littoral::render
