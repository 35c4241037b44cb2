#include <gtest/gtest.h>

#include <sys/stat.h>

#include "tests/support/test_support.h"

#include <filesystem>
#include <fstream>
#include <set>

#include "core/atomic_file.h"
#include "core/output_names.h"
#include "core/resource_limits.h"
#include "core/text_checks.h"
#include "core/error.h"
#include "core/mesh.h"
#include "core/scene_ir.h"
#include "core/suggest.h"

using namespace littoral;
namespace fs = std::filesystem;

namespace {
fs::path freshDir(const std::string& name) { return testing_support::scratchDir("core", name); }

// A unit cube, outward-oriented: volume 1, area 6.
TriMesh unitCube() {
    TriMesh m;
    for (int i = 0; i < 8; ++i) m.positions.push_back({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
    m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                   {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    m.faceMaterial = {0, 0, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0};
    return m;
}
}  // namespace

TEST(Mesh, CubeVolumeAndArea) {
    const auto m = unitCube();
    EXPECT_NEAR(m.signedVolume(), 1.0, 1e-15);
    EXPECT_NEAR(m.area(), 6.0, 1e-15);
}

TEST(Mesh, PlyRoundTripIsExact) {
    const auto d = freshDir("ply");
    auto m = unitCube();
    m.positions[3] = {0.1 + 0.2, 1.0 / 3.0, -7e-300};  // values that text formats would round
    writePly(d / "cube.ply", m);
    const auto r = readPly(d / "cube.ply");
    EXPECT_EQ(r.positions, m.positions);
    EXPECT_EQ(r.triangles, m.triangles);
    EXPECT_EQ(r.faceMaterial, m.faceMaterial);
    // No temporary files left beside the output.
    int files = 0;
    for (auto& e : fs::directory_iterator(d)) { (void)e; ++files; }
    EXPECT_EQ(files, 1);
}

TEST(Mesh, ReadsAsciiPlyWithQuads) {
    const auto d = freshDir("ascii");
    std::ofstream(d / "q.ply") << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                                  "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                  "end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
    const auto m = readPly(d / "q.ply");
    EXPECT_EQ(m.numTriangles(), 2u);
    EXPECT_NEAR(m.area(), 1.0, 1e-12);
}

TEST(Mesh, CorruptPlyRejectedWithFileName) {
    const auto d = freshDir("corrupt");
    std::ofstream(d / "empty.ply");
    std::ofstream(d / "bad.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                    "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                    "end_header\n0 0 0\n1 0 0\n1 1 0\n3 0 1 7\n";
    std::ofstream(d / "short.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                      "property float z\nend_header\n0 0 0\n1 0\n";
    for (const char* f : {"empty.ply", "bad.ply", "short.ply", "missing.ply"}) {
        try {
            readPly(d / f);
            FAIL() << f << " should be rejected";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << e.what();
        }
    }
}

TEST(AtomicOutput, FailedWriteLeavesPreviousFileIntact) {
    const auto d = freshDir("atomic");
    writeTextFileAtomic(d / "out.txt", "good");
    try {
        AtomicOutput out(d / "out.txt");
        out.write("partial");
        throw InputError("simulated failure half-way");
    } catch (const InputError&) {
    }
    EXPECT_EQ(readTextFile(d / "out.txt"), "good");
    int files = 0;
    for (auto& e : fs::directory_iterator(d)) { (void)e; ++files; }
    EXPECT_EQ(files, 1) << "the temporary file must be removed";
}

// Inside an output set nothing is published until the set commits; a set destroyed without commit
// removes its temporaries and the folders it created; publishStagedOutputs makes what is staged
// permanent.
TEST(AtomicOutput, OutputSetPublishesAllOrNothing) {
    const auto d = freshDir("output_set");
    {
        OutputSet set;
        writeTextFileAtomic(d / "new" / "a.txt", "a");
        writeTextFileAtomic(d / "new" / "b.txt", "b");
        EXPECT_FALSE(fs::exists(d / "new" / "a.txt"));
        // rolled back here
    }
    EXPECT_FALSE(fs::exists(d / "new")) << "the folder the set created is removed too";
    {
        OutputSet set;
        writeTextFileAtomic(d / "kept.txt", "kept");
        publishStagedOutputs();
        EXPECT_EQ(readTextFile(d / "kept.txt"), "kept");
        writeTextFileAtomic(d / "late.txt", "late");
    }
    EXPECT_TRUE(fs::exists(d / "kept.txt"));
    EXPECT_FALSE(fs::exists(d / "late.txt"));
    {
        OutputSet set;
        writeTextFileAtomic(d / "x.txt", "first");
        writeTextFileAtomic(d / "x.txt", "second");  // the later content supersedes the staged one
        set.commit();
    }
    EXPECT_EQ(readTextFile(d / "x.txt"), "second");
    std::set<std::string> names;
    for (auto& e : fs::directory_iterator(d)) names.insert(e.path().filename().string());
    EXPECT_EQ(names, (std::set<std::string>{"kept.txt", "x.txt"})) << "no temporaries left";
}

// Only a regular file (or nothing) may be replaced; symlinks are refused even to regular files.
TEST(AtomicOutput, RefusesToReplaceAnythingButARegularFile) {
    const auto d = freshDir("targets");
    writeTextFileAtomic(d / "real.txt", "real");
    fs::create_symlink(d / "real.txt", d / "link.txt");
    fs::create_directories(d / "dir.txt");
    for (const char* f : {"link.txt", "dir.txt"}) {
        const std::string msg = testing_support::inputErrorOf([&] { writeTextFileAtomic(d / f, "x"); });
        EXPECT_NE(msg.find("refusing to write output"), std::string::npos) << f << ": " << msg;
    }
    EXPECT_EQ(readTextFile(d / "real.txt"), "real");
    EXPECT_TRUE(fs::is_symlink(d / "link.txt"));
    ASSERT_EQ(::mkfifo((d / "fifo.txt").c_str(), 0644), 0);
    EXPECT_NE(testing_support::inputErrorOf([&] { writeTextFileAtomic(d / "fifo.txt", "x"); }).find("a FIFO"),
              std::string::npos);
}

TEST(OutputNames, PortableUniqueAfterSuffixes) {
    for (const char* ok : {"nadir", "sim-c-nadir", "cam_2", "A.b", "x"}) EXPECT_EQ(outputNameProblem(ok), "") << ok;
    for (const std::string& bad : {std::string(""), std::string("a/b"), std::string("..\\x"), std::string("a\0b", 3),
                                  std::string(".hidden"), std::string("-rf"), std::string(".."), std::string("nul.exr"),
                                  std::string("COM3"), std::string("with space"), std::string("caf\xc3\xa9"),
                                  std::string(65, 'a')})
        EXPECT_NE(outputNameProblem(bad), "") << printableName(bad);
    EXPECT_FALSE(findOutputClash({"a", "b", "a_b"}, true).has_value());
    const auto c = findOutputClash({"cam", "x", "cam_truth"}, false);
    ASSERT_TRUE(c.has_value());
    EXPECT_EQ(c->first, 0u);
    EXPECT_EQ(c->second, 2u);
    EXPECT_EQ(c->file, "cam_truth.exr");
    EXPECT_TRUE(findOutputClash({"Cam", "cam"}, false).has_value()) << "case-insensitive file systems";
}

// RFC 3629 well-formedness, and where the first bad byte is.
TEST(TextChecks, Utf8AndLocations) {
    EXPECT_FALSE(firstInvalidUtf8("plain ascii\n").has_value());
    EXPECT_FALSE(firstInvalidUtf8("caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x8c\x8a").has_value());  // e-acute, euro, wave
    EXPECT_EQ(firstInvalidUtf8("ab\xff"), 2u);
    EXPECT_EQ(firstInvalidUtf8("\xc0\xaf"), 0u);          // overlong '/'
    EXPECT_EQ(firstInvalidUtf8("x\xed\xa0\x80"), 1u);    // UTF-16 surrogate
    EXPECT_EQ(firstInvalidUtf8("\xf4\x90\x80\x80"), 0u);  // above U+10FFFF
    EXPECT_EQ(firstInvalidUtf8("\xe2\x82"), 0u);          // truncated
    const SourceLoc l = locationOf("ab\ncd\xff", 5, "f.yaml");
    EXPECT_EQ(l.str(), "f.yaml:2:3");
}

TEST(ResourceLimits, SizesBudgetAndRefusals) {
    EXPECT_EQ(parseByteSize("512M"), 512ull << 20);
    EXPECT_EQ(parseByteSize("8g"), 8ull << 30);
    EXPECT_EQ(parseByteSize("2"), 2ull << 30);  // a bare number is GiB, as `waves --max-memory` was
    EXPECT_EQ(parseByteSize("1.5KiB"), 1536u);
    for (const char* bad : {"", "-1", "0", "lots", "5X", "1e3G", "nan"})
        EXPECT_NE(testing_support::inputErrorOf([&] { parseByteSize(bad); }).find("is not a memory size"),
                  std::string::npos) << bad;
    EXPECT_GE(defaultMemoryBudget(), 1ull << 30);
    const uint64_t saved = memoryBudget();
    setMemoryBudget(1 << 20);
    const std::string msg = testing_support::inputErrorOf([] { requireMemory(3.0 * (1 << 20), "three MiB would"); });
    EXPECT_NE(msg.find("three MiB would need 3 MiB of memory, more than the memory budget of 1 MiB (--max-memory)"),
              std::string::npos) << msg;
    EXPECT_EQ(testing_support::inputErrorOf([] { requireMemory(1 << 19, "half"); }), "");
    setMemoryBudget(saved);
    EXPECT_EQ(formatBytes(1536.0 * (1 << 30)), "1.5 TiB");
}

TEST(Suggest, DidYouMean) {
    const std::vector<std::string> keys = {"wind_speed", "wind_direction_deg", "gsd_m", "range_m"};
    EXPECT_EQ(closestMatch("wind_sped", keys), "wind_speed");
    EXPECT_EQ(closestMatch("gsd", keys), "gsd_m");
    EXPECT_EQ(closestMatch("colour", keys), "");
    EXPECT_EQ(editDistance("kitten", "sitting"), 3);
    EXPECT_EQ(editDistance("lwo", "low"), 1);
}

TEST(SourceLoc, Formatting) {
    EXPECT_EQ((SourceLoc{"a.yaml", 3, 7}).str(), "a.yaml:3:7");
    EXPECT_EQ((SourceLoc{"a.yaml", 3, 0}).str(), "a.yaml:3");
    const InputError e(SourceLoc{"a.yaml", 3, 7}, "bad");
    EXPECT_STREQ(e.what(), "a.yaml:3:7: bad");
    EXPECT_EQ(e.message(), "bad");
}

namespace {
ir::SceneIR sampleIR() {
    ir::SceneIR s;
    s.name = "round-trip";
    s.render.bands = uniformBands(0.4, 0.7, 3);
    s.render.seed = 12345678901234ULL;
    s.sun.zenith = 0.5235987755982988;
    s.sun.azimuth = -2.356194490192345;
    s.sun.irradiance = Spectrum::tabulated({0.35, 0.55, 0.75}, {1500.1, 1800.25, 1400.0 / 3.0});
    s.sky.radiance = Spectrum::constant(0.1 + 0.2);
    s.render.estimator = ir::Estimator::Path;
    s.render.settings.set("probe_samples", 1 << 20);
    s.render.settings.set("march_step_m", 0.25);
    s.domain = {-10, 10, -5, 5, true};
    // Two layers: the top one with pure water (Rayleigh-like) and particles (Fournier-Forand).
    ir::Medium w;
    w.name = "water";
    w.refractiveIndex = Spectrum::constant(1.34);
    w.layers.resize(2);
    w.layers[0].zBottom = -2.5;
    w.layers[0].absorption = Spectrum::tabulated({0.4, 0.5, 0.6}, {0.020562, 0.006904, 0.002113});
    w.layers[0].scatterers = {
        {"pure-water", Spectrum::constant(0.002), {"rayleigh", {{"k", 1.0}}}},
        {"particles", Spectrum::constant(0.3), {"fournier-forand", {{"backscatter_fraction", 0.0183}}}}};
    w.layers[1].zTop = -2.5;
    w.layers[1].absorption = Spectrum::constant(0.05);
    w.layers[1].scatterers = {{"particles", Spectrum::constant(0.1), {"henyey-greenstein", {{"g", 0.88}}}}};
    s.media.push_back(w);
    ir::Material sand, iface, tex;
    sand.name = "sand";
    sand.reflectance = Spectrum::constant(0.3);
    iface.name = "interface";
    iface.type = ir::Material::Type::Dielectric;
    iface.solver = ir::Material::Solver::Fresnel;
    tex.name = "grass";
    tex.type = ir::Material::Type::Textured;
    tex.reflectance = Spectrum::constant(0.1);
    tex.texture = "textures/grass.exr";
    tex.textureX0 = -45;
    tex.textureY0 = -30;
    tex.textureX1 = 45;
    tex.textureY1 = 30;
    // The rough interface with every setting, and a class map naming sand and grass per value.
    ir::Material rough, classes;
    rough.name = "rough-sea";
    rough.type = ir::Material::Type::RoughDielectric;
    rough.windSpeed = 6.5;
    rough.windAzimuth = 0.7;
    rough.sea = CoxMunkSea::Slick;
    rough.gramCharlier = false;
    rough.shadowing = MicrofacetShadowing::SmithSeparable;
    classes.name = "ground";
    classes.type = ir::Material::Type::Classified;
    classes.texture = "textures/class-map.tif";
    classes.textureX0 = -45.5;
    classes.textureY0 = -30;
    classes.textureX1 = 45;
    classes.textureY1 = 30.25;
    classes.classMaterials = {"sand", "", "grass"};
    s.materials = {sand, iface, tex, rough, classes};
    ir::Mesh m;
    m.name = "water";
    m.file = "meshes/water.ply";
    m.materials = {"sand", "interface"};
    m.inside = "water";
    m.closed = true;
    m.data = unitCube();
    s.meshes.push_back(m);
    ir::Instance in;
    in.mesh = "water";
    in.translation = {1, 2, 3};
    s.instances.push_back(in);
    ir::Sensor c;
    c.name = "cam";
    c.position = {0, 0, 500};
    c.width = 64;
    c.height = 48;
    c.focalLength = 0.025;
    c.pixelPitch = 1e-5;
    s.sensors.push_back(c);
    s.probes.push_back({"p", {0, 0, -1}, {"Ed", "Lu"}, "water", std::nullopt});
    s.metadata["generator"] = "test";
    return s;
}
}  // namespace

// write -> read -> write must give byte-identical files (scene.json and every PLY).
TEST(SceneIR, RoundTripIsByteIdentical) {
    const auto d1 = freshDir("ir1"), d2 = freshDir("ir2");
    const auto s = sampleIR();
    ir::writeIR(s, d1);
    const auto r = ir::readIR(d1);
    ir::writeIR(r, d2);
    EXPECT_EQ(readTextFile(d1 / "scene.json"), readTextFile(d2 / "scene.json"));
    EXPECT_EQ(readTextFile(d1 / "meshes/water.ply"), readTextFile(d2 / "meshes/water.ply"));
    EXPECT_EQ(r.render.seed, s.render.seed);
    EXPECT_EQ(r.sun.irradiance.values(), s.sun.irradiance.values());
    EXPECT_EQ(r.meshes[0].data.positions, s.meshes[0].data.positions);
    EXPECT_EQ(r.materials[2].texture, "textures/grass.exr");
    EXPECT_EQ(r.materials[3].type, ir::Material::Type::RoughDielectric);
    EXPECT_EQ(r.materials[3].windSpeed, 6.5);
    EXPECT_EQ(r.materials[3].windAzimuth, 0.7);
    EXPECT_EQ(r.materials[3].sea, CoxMunkSea::Slick);
    EXPECT_EQ(r.materials[3].shadowing, MicrofacetShadowing::SmithSeparable);
    EXPECT_EQ(r.materials[4].type, ir::Material::Type::Classified);
    EXPECT_EQ(r.materials[4].texture, "textures/class-map.tif");
    EXPECT_EQ(r.materials[4].textureX0, -45.5);
    EXPECT_EQ(r.materials[4].textureY1, 30.25);
    EXPECT_EQ(r.materials[4].classMaterials, (std::vector<std::string>{"sand", "", "grass"}));
    EXPECT_EQ(r.render.estimator, ir::Estimator::Path);
    EXPECT_EQ(r.render.settings.number("probe_samples"), 1 << 20);
    EXPECT_FALSE(r.render.settings.has("max_bounces"));  // unset stays unset
    EXPECT_TRUE(r.domain.periodic);
    ASSERT_EQ(r.media[0].layers.size(), 2u);
    EXPECT_EQ(r.media[0].layers[0].zTop, ir::kInfinity);
    EXPECT_EQ(r.media[0].layers[1].zBottom, -ir::kInfinity);
    EXPECT_EQ(r.media[0].layers[0].scatterers[1].phase.params.number("backscatter_fraction"), 0.0183);
}

TEST(SceneIR, LayerStackMustBeContiguous) {
    auto s = sampleIR();
    s.media[0].layers[1].zTop = -3.0;  // a gap between -2.5 and -3.0
    try {
        ir::fromJsonText(ir::toJsonText(s), "scene.json");
        FAIL() << "a gap between layers was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("media[0].layers: layers 0 and 1 leave a gap or overlap"), std::string::npos)
            << e.what();
    }
}

TEST(SceneIR, StrictReaderNamesThePath) {
    const auto s = sampleIR();
    std::string text = ir::toJsonText(s);
    auto expectError = [](const std::string& t, const std::string& needle) {
        try {
            ir::fromJsonText(t, "scene.json");
            FAIL() << "expected an error containing " << needle;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    std::string t1 = text;
    t1.replace(t1.find("\"solver\": \"fresnel\""), 19, "\"solver\": \"fresnell\"");
    expectError(t1, "materials[1].solver");
    std::string t2 = text;
    t2.replace(t2.find("\"inside\""), 8, "\"insde\"");
    expectError(t2, "did you mean 'inside'");
    std::string t3 = text;
    t3.replace(t3.rfind("\"sand\""), 6, "\"snad\"");  // the mesh's reference, not the definition
    expectError(t3, "material 'snad'");
    expectError("{not json", "not valid JSON");
}
