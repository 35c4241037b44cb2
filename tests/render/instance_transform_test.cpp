// Instance transforms are checked before Embree sees them (issue 20: a singular or extreme
// transform in a hand-edited IR tripped an Embree assertion, SIGABRT). Each bad transform must be
// one InputError naming the instance and what is allowed; good ones (rotations, moderate scales,
// a mirror) must still render.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"
#include "render/scene.h"
#include "tests/render/render_test_scenes.h"

using namespace littoral;
using namespace littoral::render;
using namespace littoral::render::testing;

namespace {

ir::SceneIR sceneWithInstance(const double (&R)[9], Vec3 t = {0, 0, 0}) {
    ir::SceneIR s = uniformSkyScene();
    s.materials.push_back(material("grey", ir::Material::Type::Lambertian, ir::Material::Solver::Classic, 0.5));
    s.meshes.push_back(meshOf("cube", box({-0.5, -0.5, 0}, {0.5, 0.5, 1}), {"grey"}, "", "", true));
    ir::Instance in;
    in.mesh = "cube";
    std::copy(R, R + 9, in.rotation);
    in.translation = t;
    s.instances.push_back(in);
    return s;
}

std::string errorOf(const ir::SceneIR& s) {
    try {
        Scene scene(s, ".");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(InstanceTransform, BadTransformsAreLocatedErrors) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double singular[9] = {1, 1, 0, 0, 0, 0, 0, 0, 1};           // x and y columns equal: flattens y
    const double tiny[9] = {1e-30, 0, 0, 0, 1e-30, 0, 0, 0, 1e-30};   // scaled by 1e-30
    const double huge[9] = {1e9, 0, 0, 0, 1, 0, 0, 0, 1};
    const double nearlyFlat[9] = {1, 1, 0, 0, 1e-9, 0, 0, 0, 1};       // two columns 1e-9 rad apart
    const double notFinite[9] = {1, 0, 0, 0, nan, 0, 0, 0, 1};
    const double ok[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    EXPECT_NE(errorOf(sceneWithInstance(singular)).find("instances[0] (mesh 'cube'): the rotation is singular"),
              std::string::npos)
        << errorOf(sceneWithInstance(singular));
    EXPECT_NE(errorOf(sceneWithInstance(tiny)).find("allowed [1e-6, 1e6]"), std::string::npos);
    EXPECT_NE(errorOf(sceneWithInstance(huge)).find("allowed [1e-6, 1e6]"), std::string::npos);
    EXPECT_NE(errorOf(sceneWithInstance(nearlyFlat)).find("singular"), std::string::npos);
    EXPECT_NE(errorOf(sceneWithInstance(notFinite)).find("rotation element 4 is nan"), std::string::npos);
    EXPECT_NE(errorOf(sceneWithInstance(ok, {0, std::numeric_limits<double>::infinity(), 0})).find("translation is not finite"),
              std::string::npos);
}

TEST(InstanceTransform, RotationsScalesAndMirrorsAreAccepted) {
    const double c = std::cos(0.3), s = std::sin(0.3);
    const double rotated[9] = {c, -s, 0, s, c, 0, 0, 0, 1};
    const double scaled[9] = {2e-3, 0, 0, 0, 5, 0, 0, 0, 40};
    const double mirror[9] = {-1, 0, 0, 0, 1, 0, 0, 0, 1};
    for (const auto* R : {&rotated, &scaled, &mirror}) {
        const ir::SceneIR ir = sceneWithInstance(*R, {1, 2, 0});
        const Scene scene(ir, ".");
        // The placed cube is there: a ray down onto its top (z = R33 at the instance's centre) hits.
        Ray r;
        r.o = {1, 2, 100};
        r.d = {0, 0, -1};
        SurfaceHit h;
        EXPECT_TRUE(scene.geometry().intersect(r, &h));
        EXPECT_NEAR(h.p.z, (*R)[8], 1e-9 * std::max(1.0, (*R)[8]));
    }
}

// A vertex far beyond the scene (a hand-edited PLY or a translation of 1e30, both found by
// fuzz_ir_render as Embree SIGABRTs) is a located error: geometry must lie within kMaxGeometryM.
TEST(InstanceTransform, FarVerticesAndTranslationsAreLocatedErrors) {
    const double ok[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    const std::string farMove = errorOf(sceneWithInstance(ok, {1e30, 0, 0}));
    EXPECT_NE(farMove.find("instances[0] (mesh 'cube', placed): vertex 0 at (1e+30"), std::string::npos) << farMove;
    EXPECT_NE(farMove.find("within 1e+07 m in each coordinate"), std::string::npos) << farMove;
    // Just inside the bound it is accepted: 9e6 m east is a far but legal placement.
    EXPECT_EQ(errorOf(sceneWithInstance(ok, {9e6, 0, 0})), "");

    ir::SceneIR s = uniformSkyScene();
    s.materials.push_back(material("grey", ir::Material::Type::Lambertian, ir::Material::Solver::Classic, 0.5));
    s.meshes.push_back(meshOf("floor", box({-0.5, -0.5, 0}, {0.5, 0.5, 1}), {"grey"}, "", "", true));
    s.meshes.back().data.positions[3].z = -1e20;
    const std::string farVertex = errorOf(s);
    EXPECT_NE(farVertex.find("mesh 'floor': vertex 3 at (") , std::string::npos) << farVertex;
    EXPECT_NE(farVertex.find("-1e+20) lies beyond 1e+07 m"), std::string::npos) << farVertex;
    s.meshes.back().data.positions[3].z = std::numeric_limits<double>::infinity();
    EXPECT_NE(errorOf(s).find("mesh 'floor': vertex 3 at"), std::string::npos) << errorOf(s);
}
