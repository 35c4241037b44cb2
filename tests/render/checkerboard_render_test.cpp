// Refraction checkerboard (seed-ch01-04.md §4.5, test CH4-E): a nadir pinhole camera over a water
// box standing on a checkerboard of 0.3 m checks, water depths 4.9 m and 9.9 m. Every pixel's
// binarised check colour must equal that of the independent analytic ray caster
// tests/render/checkerboard_reference.h (Snell at the top face, total internal reflection at the
// walls); at most 1% of the pixels may differ, and only pixels whose footprint straddles a check
// or box edge.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>

#include "core/units.h"
#include "render/renderer.h"
#include "tests/render/checkerboard_reference.h"
#include "tests/render/render_test_scenes.h"

namespace littoral::render {
namespace {

using namespace testing;
using M = ir::Material;

// The dirsig estimator (Classic, 32 stratified sky samples per hit) at 200 x 200 pixels, and the
// path estimator (one cosine-sampled ray per path, 400 paths per pixel) at 100 x 100 pixels of
// twice the pitch (the same view): a white check then has a standard error of about 0.01 against
// a binarisation margin of 0.04 (next to a wall, where the sky fraction halves, 0.04 is 4 standard
// errors away).
class CheckerboardRefraction : public ::testing::TestWithParam<ir::Estimator> {};

TEST_P(CheckerboardRefraction, MatchesAnalyticRayCaster) {
    const ir::Estimator estimator = GetParam();
    const bool path = estimator == ir::Estimator::Path;
    for (double depth : {4.9, 9.9}) {
        testref::CheckerboardSetup ref;
        // Slightly off the box axis so that no pixel centre lands exactly on a check edge or a box
        // corner (exact ties that either side may resolve either way).
        ref.camera = {0.0131, -0.0077, 20};
        ref.width = ref.height = path ? 100 : 200;
        ref.focalLength = 0.035;
        ref.pixelPitch = path ? 4e-5 : 2e-5;  // 11 (22) mm per pixel on the dry ground: a 0.3 m check spans ~26 (13) px
        ref.x0 = ref.y0 = -0.6;
        ref.x1 = ref.y1 = 0.6;  // the box edges fall near pixels 30 and 170
        ref.depth = depth;
        ref.n = 1.34;
        ref.checkSize = 0.3;

        ir::SceneIR s = uniformSkyScene();
        s.render.estimator = estimator;
        if (!path) s.render.settings.set("hemisphere_samples", 32);
        s.media.push_back(water(0, 0, ref.n));
        s.materials.push_back(material("water", M::Type::Dielectric, M::Solver::Fresnel));
        s.materials.push_back(material("white", M::Type::Lambertian, M::Solver::Classic, 1.0));
        s.materials.push_back(material("dark", M::Type::Lambertian, M::Solver::Classic, 0.0));
        if (path)
            for (auto& m : s.materials) m.solver.reset();
        // Checkerboard ground: one grid cell per check over [-3, 3]^2 (x0 = -10 checks), per-face
        // material slot by the parity rule of Eq. 4.9 ((i - 10) + (j - 10) has the parity of i + j).
        s.meshes.push_back(meshOf("ground", grid(-3, 3, -3, 3, 0, 20, 20, [](int i, int j) { return (i + j) % 2; }),
                                  {"dark", "white"}));
        // The water box without its floor (the ground is the floor): top and four walls.
        TriMesh wbox = box({ref.x0, ref.y0, 0}, {ref.x1, ref.y1, depth});
        wbox.triangles.erase(wbox.triangles.begin(), wbox.triangles.begin() + 2);
        wbox.faceMaterial.clear();
        s.meshes.push_back(meshOf("waterbox", wbox, {"water"}, "water", ""));
        s.sensors.push_back(pinhole("nadir", {ref.camera.x, ref.camera.y, ref.camera.z}, {0, 0, -1}, {0, 1, 0},
                                    ref.width, ref.height, ref.focalLength, ref.pixelPitch));
        if (path) s.sensors.back().samplesPerPixel = 400;
        const Scene scene(s, ".");
        const SensorImage img = renderSensor(scene, s.sensors[0], quiet());

        // Binarisation: a dark check returns only the sky reflected by the water surface,
        // r_f/pi <= 0.0092 for the incidences in view (< 5 deg: 0.0067); a white check returns at
        // least its sky fraction through the surface, T_f^2 F_snell / pi ~ 0.16 (0.08 next to a
        // wall), and 1/pi on dry ground. 0.04 separates the two by a factor 2 on either side.
        const double threshold = 0.04;
        int differ = 0, differUniform = 0, straddle = 0, tir = 0, top = 0;
        for (int j = 0; j < ref.height; ++j)
            for (int i = 0; i < ref.width; ++i) {
                const testref::CheckerboardTrace t = testref::traceCheckerboardPixel(ref, i, j);
                ASSERT_GE(t.colour, 0);
                tir += t.fate == testref::RayFate::TopTirThenGround;
                top += t.fate != testref::RayFate::Ground;
                const int mine = img.film.at(i, j, 0) > threshold ? 1 : 0;
                const bool uniform = testref::checkerboardPixelUniform(ref, i, j);
                straddle += !uniform;
                if (mine != t.colour) {
                    if (differ < 8 && std::getenv("LITTORAL_DEBUG_CHECKER"))
                        std::printf("differ %d,%d L=%g ref=%d edge=%g boxedge=%g fate=%d\n", i, j,
                                    img.film.at(i, j, 0), t.colour, t.edgeDistance, t.boxEdgeDistance, int(t.fate));
                    ++differ;
                    if (uniform) ++differUniform;
                }
            }
        const int total = ref.width * ref.height;
        // Centre rays (dirsig): at most 1 % may differ, all of them straddling an edge. Jittered
        // paths (path estimator) average a straddling pixel's colours, so any straddling pixel may
        // differ there; a pixel inside one check still may not.
        EXPECT_LE(differ, path ? straddle : total / 100) << "depth " << depth;
        EXPECT_EQ(differUniform, 0) << "depth " << depth << ": pixels inside one check disagree";
        // The scene exercises what it claims: refraction through the top and TIR at the walls.
        EXPECT_GT(top, total / 3);
        EXPECT_GT(tir, path ? 50 : 200);
        std::printf("[ checkerboard %s ] depth %.1f m: %d of %d pixels differ (%d straddle an edge), %d through the "
                    "top, %d with wall TIR\n",
                    std::string(nameOf(estimator)).c_str(), depth, differ, total, straddle, top, tir);
    }
}

INSTANTIATE_TEST_SUITE_P(Estimators, CheckerboardRefraction, ::testing::Values(ir::Estimator::Dirsig, ir::Estimator::Path),
                         [](const ::testing::TestParamInfo<ir::Estimator>& i) { return std::string(nameOf(i.param)); });

}  // namespace
}  // namespace littoral::render
