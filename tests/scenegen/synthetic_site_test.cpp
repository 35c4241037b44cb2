// The synthetic coastal site: reproducible files, and a full build that passes every check.
#include <gtest/gtest.h>

#include "tests/support/test_support.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/scene_ir.h"
#include "scenegen/assemble.h"
#include "scenegen/synthetic_site.h"

using namespace littoral;
using namespace littoral::scenegen;
namespace fs = std::filesystem;

namespace {

std::string slurpBinary(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}


}  // namespace

TEST(SyntheticSite, SameSeedSameBytesAndSmallFiles) {
    const fs::path a = testing_support::scratchDir("scenegen", "site_a"), b = testing_support::scratchDir("scenegen", "site_b");
    SiteOptions opt;
    opt.seed = 7;
    const SiteSummary sa = writeSyntheticSite(a, opt);
    const SiteSummary sb = writeSyntheticSite(b, opt);
    ASSERT_EQ(sa.files.size(), sb.files.size());
    for (size_t i = 0; i < sa.files.size(); ++i)
        EXPECT_EQ(slurpBinary(sa.files[i]), slurpBinary(sb.files[i])) << sa.files[i].filename();
    // Commit-worthy: the whole site under 2 MB.
    EXPECT_LT(sa.totalBytes, 2u * 1024 * 1024);
    // Step targets 0.75 m apart in depth (spec/seed-ch05-10.md §3.1).
    ASSERT_EQ(sa.targetTopDepths.size(), 4u);
    for (size_t k = 1; k < 4; ++k) EXPECT_DOUBLE_EQ(sa.targetTopDepths[k] - sa.targetTopDepths[k - 1], 0.75);
    // Another seed changes the random parts (the classification map's patches).
    opt.seed = 8;
    const fs::path c = testing_support::scratchDir("scenegen", "site_c");
    writeSyntheticSite(c, opt);
    EXPECT_NE(slurpBinary(a / "classes.png"), slurpBinary(c / "classes.png"));
}

// Inside a command's output set (demo) the site must be complete on disk when the function returns:
// the build that follows reads it back, and its sizes are read from disk.
TEST(SyntheticSite, IsPublishedInsideAnOutputSet) {
    const fs::path d = testing_support::scratchDir("scenegen", "site_in_set");
    OutputSet set;
    const SiteSummary s = writeSyntheticSite(d, SiteOptions{});
    for (const auto& f : s.files) EXPECT_TRUE(fs::is_regular_file(f)) << f;
    EXPECT_GT(s.totalBytes, 0u);
    set.commit();
}

TEST(SyntheticSite, BuildsAndPassesEveryValidityCheck) {
    const fs::path site = testing_support::scratchDir("scenegen", "site_build"), out = testing_support::scratchDir("scenegen", "site_build_ir");
    SiteOptions opt;
    opt.seed = 2010;
    opt.surfaceTriangles = 6000;  // the full 30,000-triangle build is the benchmark (bench_build)
    const SiteSummary s = writeSyntheticSite(site, opt);
    const AssembledScene sc = buildScene(s.sceneFile, out);
    EXPECT_TRUE(sc.valid) << sc.validity.dump(2);
    const auto& v = sc.validity;
    ASSERT_TRUE(v.contains("water"));
    for (const char* k : {"closed", "manifold", "bounds_volume", "outward"}) EXPECT_EQ(v["water"][k], true) << k;
    EXPECT_EQ(v["water"]["self_intersections"], 0);
    EXPECT_EQ(v["water"]["boundary_edges"], 0);
    EXPECT_GT(v["water"]["volume_m3"].get<double>(), 0.0);
    // Every object is a valid closed solid, and the floating/submerged ones displaced water.
    for (const char* name : {"pier", "boat", "buoy", "step-target-1", "step-target-2", "step-target-3", "step-target-4"}) {
        ASSERT_TRUE(v["objects"].contains(name)) << name;
        EXPECT_EQ(v["objects"][name]["valid"], true) << name;
        EXPECT_GT(v["objects"][name]["displaced_water_m3"].get<double>(), 0.0) << name;
    }
    // All six classes occur on the map.
    ASSERT_EQ(v["texture_classes"].size(), 6u);
    for (const auto& [name, c] : v["texture_classes"].items()) {
        EXPECT_GT(c["coverage"].get<double>(), 0.005) << name;
        if (c["pixels"].get<size_t>() > 1) {
            // The remap targets mean 1 and the class's sd; float storage and rare clamping aside,
            // met to 1e-4.
            EXPECT_NEAR(c["mean_after"].get<double>(), 1.0, 1e-4) << name;
        }
    }
    // The water mesh carries the interface, the classified seabed (its class looked up per hit point
    // in the class map), object contacts and domain walls.
    const ir::Mesh* w = sc.ir.findMesh("water");
    ASSERT_NE(w, nullptr);
    EXPECT_TRUE(w->closed);
    EXPECT_EQ(w->inside, "water");
    auto has = [&](const std::string& m) { return std::find(w->materials.begin(), w->materials.end(), m) != w->materials.end(); };
    EXPECT_TRUE(has("air-water-interface"));
    EXPECT_TRUE(has("domain-wall"));
    EXPECT_TRUE(has("texture-classes"));
    const ir::Material* classified = sc.ir.findMaterial("texture-classes");
    ASSERT_NE(classified, nullptr);
    EXPECT_EQ(classified->type, ir::Material::Type::Classified);
    EXPECT_NE(std::find(classified->classMaterials.begin(), classified->classMaterials.end(), "wet-sand"),
              classified->classMaterials.end());
    EXPECT_TRUE(fs::exists(out / "textures" / "class-map.tif"));
    EXPECT_TRUE(has("target-bright"));
    // Written IR reads back, and validity.json is there.
    EXPECT_TRUE(fs::exists(out / "validity.json"));
    const ir::SceneIR back = ir::readIR(out);
    EXPECT_EQ(back.meshes.size(), sc.ir.meshes.size());
    EXPECT_TRUE(fs::exists(out / "textures" / "dry-sand.tif"));
}

TEST(Assembly, DryScenesGetLandOnlyAndBadReferencesAreNamed) {
    // No water section: the whole terrain over the domain is land. A planar slope over a
    // 30 m x 20 m domain has plan area 600 m^2 and true area 600 sqrt(1 + 0.1^2) m^2.
    const fs::path dir = testing_support::scratchDir("scenegen", "dry_scene");
    std::ofstream(dir / "dry.yaml") << "scene: {name: dry, domain: {x: [0, 30], y: [0, 20]}}\nsky: {model: uniform, radiance: 10}\n"
                                       "bathymetry: {type: planar_slope, z0_m: 1, slope_x: 0.1, material: sand, spacing_m: 2}\n"
                                       "materials:\n  - {name: sand, reflectance: 0.3}\n";
    const AssembledScene s = buildScene(dir / "dry.yaml", dir / "ir");
    EXPECT_EQ(s.ir.findMesh("water"), nullptr);
    const ir::Mesh* land = s.ir.findMesh("land");
    ASSERT_NE(land, nullptr);
    double plan = 0;
    for (size_t f = 0; f < land->data.numTriangles(); ++f) plan += 0.5 * land->data.faceNormalArea(f).z;
    EXPECT_NEAR(plan, 600.0, 1e-9);
    EXPECT_NEAR(land->data.area(), 600.0 * std::sqrt(1.01), 1e-9);

    // A ground material that no section defines is named with the section's location.
    std::ofstream(dir / "bad.yaml") << "scene: {name: dry, domain: {x: [0, 30], y: [0, 20]}}\nsky: {model: uniform, radiance: 10}\n"
                                       "bathymetry: {type: planar_slope, z0_m: 1, material: snad}\n"
                                       "materials:\n  - {name: sand, reflectance: 0.3}\n";
    try {
        buildScene(dir / "bad.yaml", "");
        FAIL() << "undefined material accepted";
    } catch (const InputError& e) {
        const std::string w = e.what();
        EXPECT_NE(w.find("bad.yaml:3:"), std::string::npos) << w;
        EXPECT_NE(w.find("'snad' is not defined"), std::string::npos) << w;
    }
}
