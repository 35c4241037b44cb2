// Procedural solids, mesh file I/O and object placement.
#include <gtest/gtest.h>

#include "tests/support/test_support.h"

#include <cmath>
#include <filesystem>
#include <fstream>

#include "bathymetry/geo_frame.h"
#include "core/units.h"
#include "scenegen/mesh_io.h"
#include "scenegen/mesh_validity.h"
#include "scenegen/objects.h"
#include "scenegen/primitives.h"

using namespace littoral;
using namespace littoral::scenegen;
namespace fs = std::filesystem;

namespace {


double areaWithSlot(const TriMesh& m, uint16_t slot) {
    double a = 0;
    for (size_t f = 0; f < m.numTriangles(); ++f)
        if (m.materialOf(f) == slot) a += 0.5 * length(m.faceNormalArea(f));
    return a;
}

}  // namespace

TEST(Primitives, EveryShapeIsAValidClosedVolume) {
    PierParams pp;
    pp.length = 12;
    const std::vector<std::pair<std::string, TriMesh>> shapes = {
        {"box", makeBox(1, 2, 3)},           {"barge", makeBarge(4, 12, 1.5)}, {"boat", makeBoat(6, 2.2, 0.9)},
        {"cylinder", makeCylinder(0.3, -1, 2)}, {"buoy", makeBuoy(0.5, 2)},       {"pier", makePier(pp)},
        {"step", makeStepTarget(3, 1)}};
    for (const auto& [name, m] : shapes) {
        const ValidityReport r = checkMesh(m);
        EXPECT_TRUE(r.valid()) << name << ": " << ::testing::PrintToString(r.reasons());
        EXPECT_EQ(r.components, 1u) << name;
    }
}

TEST(Primitives, ClosedFormVolumesAndAreas) {
    // Cylinder with n sides: prism volume n r^2 sin(2 pi / n) / 2 * height.
    const double r = 0.3, n = 16;
    EXPECT_NEAR(makeCylinder(r, -1, 2, 16).signedVolume(), n * r * r * std::sin(2 * kPi / n) / 2 * 3, 1e-12);
    // Step target: the bright half of the top is size^2 / 2, the rest (dark half + 4 sides + bottom)
    // size^2 / 2 + 4 size height + size^2.
    const TriMesh st = makeStepTarget(3, 1);
    EXPECT_NEAR(areaWithSlot(st, 0), 4.5, 1e-12);
    EXPECT_NEAR(areaWithSlot(st, 1), 4.5 + 12 + 9, 1e-12);
    EXPECT_NEAR(st.signedVolume(), 9.0, 1e-12);
    // Boat: the deck (slot 1) is the flat top, so its area is the deck's plan area, which must be
    // below the bounding rectangle length * beam and above half of it for this hull form.
    const TriMesh boat = makeBoat(6, 2.2, 0.9);
    const double deck = areaWithSlot(boat, 1);
    EXPECT_GT(deck, 0.5 * 6 * 2.2);
    EXPECT_LT(deck, 6 * 2.2);
    // Pier: the union keeps the deck volume plus the pilings below the deck underside.
    PierParams pp;
    pp.length = 12;
    pp.pilingSpacing = 5;
    const TriMesh pier = makePier(pp);
    const double pile = 12 * pp.pilingRadius * pp.pilingRadius * std::sin(2 * kPi / 12) / 2 * (pp.deckBottom - pp.pilingBottom);
    const int pairs = 3;  // floor((12 - 0.4) / 5) + 1
    EXPECT_NEAR(pier.signedVolume(), pp.width * pp.length * pp.deckThickness + 2 * pairs * pile, 1e-9);
}

TEST(MeshIO, RoundTripThroughEveryFormat) {
    const fs::path dir = testing_support::scratchDir("scenegen", "mesh_io");
    const TriMesh box = makeBox(2, 3, 4);
    for (const char* ext : {".obj", ".off", ".stl", ".ply"}) {
        const fs::path p = dir / (std::string("box") + ext);
        writeMeshFile(p, box);
        const TriMesh back = readMeshFile(p);
        const ValidityReport r = checkMesh(back);
        EXPECT_TRUE(r.valid()) << ext << ": " << ::testing::PrintToString(r.reasons());
        // OBJ/OFF/PLY keep doubles; STL stores 32-bit floats, exact for these small integers.
        EXPECT_NEAR(r.volume, 24.0, 1e-9) << ext;
        EXPECT_EQ(back.numTriangles(), 12u) << ext;
    }
}

TEST(MeshIO, UnreadableFilesRaiseMeshReadError) {
    const fs::path dir = testing_support::scratchDir("scenegen", "mesh_io_bad");
    std::ofstream(dir / "empty.obj").close();
    EXPECT_THROW(readMeshFile(dir / "empty.obj"), MeshReadError);
    EXPECT_THROW(readMeshFile(dir / "missing.obj"), MeshReadError);
    std::ofstream(dir / "box.xyz") << "1 2 3\n";
    EXPECT_THROW(readMeshFile(dir / "box.xyz"), MeshReadError);
    // A face that refers to vertex 7 of 3.
    std::ofstream(dir / "bad.off") << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n";
    EXPECT_THROW(readMeshFile(dir / "bad.off"), MeshReadError);
}

TEST(MeshIO, KeepsAFlippedFaceAsStored) {
    // OpenMesh's own importer would detach a face it cannot insert; the soup importer must keep it
    // so the check can call it flipped.
    const fs::path dir = testing_support::scratchDir("scenegen", "mesh_io_flip");
    TriMesh box = makeBox(1, 1, 1);
    std::swap(box.triangles[2][1], box.triangles[2][2]);
    writeMeshFile(dir / "flip.obj", box);
    const ValidityReport r = checkMesh(readMeshFile(dir / "flip.obj"));
    ASSERT_EQ(r.flippedFaces.size(), 1u);
    EXPECT_EQ(r.flippedFaces[0], 2u);
    EXPECT_TRUE(r.closed);
}

TEST(Placement, HeadingIsClockwiseFromNorth) {
    // A marker vertex on the bow (+y) goes to the east (+x) at heading 90 degrees and to the west
    // at 270; draft puts the lowest point at -draft.
    TriMesh m = makeBox(1, 4, 1);
    Pose p;
    p.position = {100, 200};
    p.heading = deg2rad(90);
    p.draft = 0.25;
    const TriMesh east = placeMesh(m, p);
    const BBox3 b = east.bounds();
    EXPECT_NEAR(b.lo.x, 98, 1e-12);
    EXPECT_NEAR(b.hi.x, 102, 1e-12);
    EXPECT_NEAR(b.lo.y, 199.5, 1e-12);
    EXPECT_NEAR(b.lo.z, -0.25, 1e-12);
    EXPECT_NEAR(b.hi.z, 0.75, 1e-12);
    // A bow point (0, 2, 0.5) at heading 30: east = 2 sin 30 = 1, north = 2 cos 30.
    TriMesh pt;
    pt.positions = {{0, 2, 0.5}};
    Pose q;
    q.heading = deg2rad(30);
    q.z = 0.0;
    const Point3 w = placeMesh(pt, q).positions[0];
    EXPECT_NEAR(w.x, 1.0, 1e-12);
    EXPECT_NEAR(w.y, 2 * std::cos(deg2rad(30)), 1e-12);
    Pose bad;
    EXPECT_THROW(placeMesh(m, bad), InputError);  // neither draft nor z
}

TEST(Placement, LatLonThroughTheGeoFrameAndValidation) {
    const fs::path dir = testing_support::scratchDir("scenegen", "placement");
    writeMeshFile(dir / "buoy.ply", makeBuoy(0.5, 2));
    const auto frame = bathymetry::GeoFrame::localCartesian(36.18, -75.75, 0);
    ObjectSpec s;
    s.name = "buoy";
    s.mesh = dir / "buoy.ply";
    s.materials = {"paint"};
    // 0.0001 degrees of latitude north of the origin: about 11.1 m (WGS84 meridional radius of
    // curvature at 36.18 N is 6.3568e6 m, so 1e-4 deg = 11.095 m); the frame itself is exact, so
    // compare with its own projection of the same point.
    s.latLonDeg = std::array<double, 2>{36.1801, -75.75};
    s.draft = 1.0;
    const PlacedObject o = loadObject(s, &frame);
    const Point3 expect = frame.toLocal(36.1801, -75.75, 0);
    EXPECT_NEAR(o.pose.position.y, expect.y, 1e-9);
    EXPECT_NEAR(o.pose.position.y, 11.095, 0.01);
    EXPECT_TRUE(o.validity.valid());
    EXPECT_NEAR(o.solid.mesh.bounds().lo.z, -1.0, 1e-12);

    // An open mesh is refused with the reasons, naming the object.
    TriMesh open = makeBox(1, 1, 1);
    open.triangles.pop_back();
    open.faceMaterial.pop_back();
    writeMeshFile(dir / "open.obj", open);
    s.mesh = dir / "open.obj";
    s.latLonDeg.reset();
    s.positionLocal = Vec2{0, 0};
    try {
        loadObject(s, nullptr);
        FAIL() << "open mesh accepted";
    } catch (const InputError& e) {
        const std::string w = e.what();
        EXPECT_NE(w.find("object 'buoy'"), std::string::npos) << w;
        EXPECT_NE(w.find("not closed: 3 boundary edges"), std::string::npos) << w;
    }
}

// OBJ usemtl: each distinct name takes the next slot at its first face (slot 0 for faces before
// any usemtl); a name met again reuses its slot; a name no face follows takes none.
TEST(MeshIO, ObjUsemtlGivesFaceMaterialSlotsInOrderOfFirstUse) {
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                            "f 1 3 2\n"           // before any usemtl: slot 0
                            "usemtl unused\n"     // no face follows: no slot
                            "usemtl red paint\n"  // names may hold spaces
                            "f 1 2 4\n"           // slot 1
                            "usemtl blue\n"
                            "f 1 4 3\n"           // slot 2
                            "usemtl red paint\n"
                            "f 2 3 4\n";          // slot 1 again
    std::vector<MaterialSlotName> names;
    const TriMesh m = parseMeshData(obj, MeshFormat::Obj, "slots.obj", &names);
    EXPECT_EQ(m.faceMaterial, (std::vector<uint16_t>{0, 1, 2, 1}));
    ASSERT_EQ(names.size(), 3u);
    EXPECT_EQ(names[0].line, 0);
    EXPECT_EQ(names[1].name, "red paint");
    EXPECT_EQ(names[1].line, 7);
    EXPECT_EQ(names[2].name, "blue");
    EXPECT_EQ(names[2].line, 9);
    // One material for every face: no per-face materials, as without usemtl.
    const TriMesh one = parseMeshData("v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl hull\nf 1 2 3\n", MeshFormat::Obj, "one.obj");
    EXPECT_TRUE(one.faceMaterial.empty());
    // usemtl without a name is located.
    const std::string e = testing_support::inputErrorOf(
        [] { parseMeshData("v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl\nf 1 2 3\n", MeshFormat::Obj, "bare.obj"); });
    EXPECT_NE(e.find("bare.obj:4:1: usemtl needs a material name"), std::string::npos) << e;
}
