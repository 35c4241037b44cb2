// Validity checks on hand-made meshes whose defects are known exactly, and the repair path.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "scenegen/mesh_validity.h"
#include "scenegen/primitives.h"

using namespace littoral;
using namespace littoral::scenegen;

namespace {

bool hasReason(const ValidityReport& r, const std::string& fragment) {
    for (const auto& s : r.reasons())
        if (s.find(fragment) != std::string::npos) return true;
    return false;
}

// Unit tetrahedron (0,0,0) (1,0,0) (0,1,0) (0,0,1), outward; volume 1/6.
TriMesh tetra(Vec3 offset = {}) {
    TriMesh m;
    m.positions = {offset + Vec3{0, 0, 0}, offset + Vec3{1, 0, 0}, offset + Vec3{0, 1, 0}, offset + Vec3{0, 0, 1}};
    m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    return m;
}

}  // namespace

TEST(MeshValidity, BoxIsAValidClosedVolumeWithItsExactVolume) {
    const TriMesh box = makeBox(2.0, 3.0, 4.0, -1.0);
    const ValidityReport r = checkMesh(box);
    EXPECT_TRUE(r.valid()) << ::testing::PrintToString(r.reasons());
    EXPECT_TRUE(r.closed);
    EXPECT_TRUE(r.manifold);
    EXPECT_TRUE(r.boundsVolume);
    EXPECT_TRUE(r.outward);
    EXPECT_EQ(r.components, 1u);
    EXPECT_TRUE(r.boundaryEdges.empty());
    // Divergence-theorem volume of a box with exactly representable corners: 2*3*4 = 24 m^3 up to
    // a few ulps of the summation (12 terms of size <= 24): 1e-12 relative.
    EXPECT_NEAR(r.volume, 24.0, 24.0 * 1e-12);
    // Surface area 2(6 + 8 + 12) = 52 m^2.
    EXPECT_NEAR(r.area, 52.0, 52.0 * 1e-12);
}

TEST(MeshValidity, RemovedFaceIsReportedAsItsThreeBoundaryEdges) {
    TriMesh box = makeBox(1, 1, 1);
    const auto removed = box.triangles[5];
    box.triangles.erase(box.triangles.begin() + 5);
    box.faceMaterial.erase(box.faceMaterial.begin() + 5);
    const ValidityReport r = checkMesh(box);
    EXPECT_FALSE(r.valid());
    EXPECT_FALSE(r.closed);
    ASSERT_EQ(r.boundaryEdges.size(), 3u);
    // The open edges are exactly the removed triangle's edges.
    for (int k = 0; k < 3; ++k) {
        const EdgeKey e{std::min(removed[k], removed[(k + 1) % 3]), std::max(removed[k], removed[(k + 1) % 3])};
        EXPECT_NE(std::find(r.boundaryEdges.begin(), r.boundaryEdges.end(), e), r.boundaryEdges.end());
    }
    EXPECT_TRUE(hasReason(r, "not closed: 3 boundary edges"));
    EXPECT_FALSE(r.boundsVolume);
}

TEST(MeshValidity, FlippedFaceIsNamed) {
    TriMesh box = makeBox(1, 1, 1);
    std::swap(box.triangles[7][1], box.triangles[7][2]);
    const ValidityReport r = checkMesh(box);
    EXPECT_FALSE(r.valid());
    EXPECT_TRUE(r.closed);
    EXPECT_FALSE(r.consistentlyOriented);
    // A flipped triangle disagrees with its three neighbours across all three of its edges.
    EXPECT_EQ(r.inconsistentEdges.size(), 3u);
    ASSERT_EQ(r.flippedFaces.size(), 1u);
    EXPECT_EQ(r.flippedFaces[0], 7u);
    EXPECT_TRUE(hasReason(r, "flipped"));
}

TEST(MeshValidity, TwoCrossingTrianglesAreASelfIntersectingPair) {
    TriMesh m;
    // Triangle 0 in the plane z = 0; triangle 1 in the plane x = 0.25 piercing it.
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.25, 0.2, -1}, {0.25, 0.2, 1}, {0.25, 0.5, 0}};
    m.triangles = {{0, 1, 2}, {3, 5, 4}};
    const ValidityReport r = checkMesh(m);
    ASSERT_TRUE(r.selfIntersectionTested);
    ASSERT_EQ(r.selfIntersections.size(), 1u);
    EXPECT_EQ(r.selfIntersections[0], (FacePair{0, 1}));
    EXPECT_TRUE(hasReason(r, "self-intersecting: 1 face pairs intersect: faces 0 x 1"));
    EXPECT_FALSE(r.valid());
}

TEST(MeshValidity, InterpenetratingClosedSolidsAreCaughtOnlyBySelfIntersection) {
    TriMesh m = makeBox(1, 1, 1);
    m.append(makeBox(1, 1, 1, 0.5));  // overlaps the first box over z in [0.5, 1]
    const ValidityReport r = checkMesh(m);
    EXPECT_TRUE(r.closed);
    EXPECT_TRUE(r.manifold);
    EXPECT_TRUE(r.consistentlyOriented);
    EXPECT_EQ(r.components, 2u);
    EXPECT_FALSE(r.selfIntersections.empty());
    EXPECT_FALSE(r.boundsVolume);
    EXPECT_FALSE(r.valid());
}

TEST(MeshValidity, NonManifoldEdgeWithAThirdFace) {
    TriMesh box = makeBox(1, 1, 1);
    // A fin: a third face on the bottom edge (0, 1) of the box.
    box.positions.push_back({0, -1.5, -0.5});
    box.triangles.push_back({0, 1, static_cast<uint32_t>(box.positions.size() - 1)});
    box.faceMaterial.push_back(0);
    const ValidityReport r = checkMesh(box);
    EXPECT_FALSE(r.manifold);
    ASSERT_EQ(r.nonManifoldEdges.size(), 1u);
    EXPECT_EQ(r.nonManifoldEdges[0], (EdgeKey{0, 1}));
    EXPECT_TRUE(hasReason(r, "shared by three or more faces: edge (0, 1)"));
    EXPECT_FALSE(r.valid());
}

TEST(MeshValidity, NonManifoldVertexWhereTwoSolidsTouch) {
    // Two tetrahedra sharing only vertex 0 (the second is mirrored through the origin).
    TriMesh m = tetra();
    m.positions.push_back({-1, 0, 0});
    m.positions.push_back({0, -1, 0});
    m.positions.push_back({0, 0, -1});
    m.triangles.push_back({0, 4, 5});
    m.triangles.push_back({0, 6, 4});
    m.triangles.push_back({0, 5, 6});
    m.triangles.push_back({4, 6, 5});
    const ValidityReport r = checkMesh(m);
    EXPECT_TRUE(r.closed);
    EXPECT_TRUE(r.nonManifoldEdges.empty());
    ASSERT_EQ(r.nonManifoldVertices.size(), 1u);
    EXPECT_EQ(r.nonManifoldVertices[0], 0u);
    EXPECT_FALSE(r.manifold);
    EXPECT_FALSE(r.valid());
}

TEST(MeshValidity, NanVertexIsNamedAndBlocksGeometricTests) {
    TriMesh box = makeBox(1, 1, 1);
    box.positions[3].x = std::numeric_limits<double>::quiet_NaN();
    const ValidityReport r = checkMesh(box);
    ASSERT_EQ(r.nonFiniteVertices.size(), 1u);
    EXPECT_EQ(r.nonFiniteVertices[0], 3u);
    EXPECT_TRUE(hasReason(r, "NaN or infinite coordinates: vertex 3"));
    EXPECT_FALSE(r.selfIntersectionTested);
    EXPECT_FALSE(r.valid());
}

TEST(MeshValidity, EmptyMesh) {
    const ValidityReport r = checkMesh(TriMesh{});
    EXPECT_TRUE(r.empty);
    EXPECT_FALSE(r.valid());
    EXPECT_TRUE(hasReason(r, "mesh is empty"));
    EXPECT_EQ(r.toJson()["closed"], false);
}

TEST(MeshValidity, InwardBoxBoundsAVolumeButIsNotOutward) {
    TriMesh box = makeBox(1, 2, 3);
    for (auto& t : box.triangles) std::swap(t[1], t[2]);
    const ValidityReport r = checkMesh(box);
    EXPECT_TRUE(r.boundsVolume);
    EXPECT_FALSE(r.outward);
    EXPECT_NEAR(r.volume, -6.0, 6e-12);
    EXPECT_TRUE(hasReason(r, "oriented inward"));
}

TEST(MeshValidity, DegenerateFaceIsNamed) {
    TriMesh m = tetra();
    m.positions.push_back({0.5, 0.5, 0});  // midpoint of the hypotenuse (1,0,0)-(0,1,0)
    m.triangles.push_back({1, 4, 2});      // collinear corners: zero area
    const ValidityReport r = checkMesh(m);
    ASSERT_EQ(r.degenerateFaces.size(), 1u);
    EXPECT_EQ(r.degenerateFaces[0], 4u);
}

TEST(MeshValidity, JsonHasTheDocumentedKeys) {
    const nlohmann::json j = checkMesh(tetra()).toJson();
    for (const char* k : {"closed", "manifold", "self_intersections", "bounds_volume", "outward", "volume_m3",
                          "boundary_edges", "components"})
        EXPECT_TRUE(j.contains(k)) << k;
    EXPECT_NEAR(j["volume_m3"].get<double>(), 1.0 / 6.0, 1e-15);
}

TEST(MeshRepair, SoupWithAFlippedFaceBecomesTheExactBox) {
    // An STL-style soup: every triangle has its own three vertices (36), and one face is flipped.
    const TriMesh box = makeBox(2, 3, 4);
    TriMesh soup;
    for (const auto& t : box.triangles) {
        const auto base = static_cast<uint32_t>(soup.positions.size());
        for (uint32_t v : t) soup.positions.push_back(box.positions[v]);
        soup.triangles.push_back({base, base + 1, base + 2});
    }
    std::swap(soup.triangles[4][1], soup.triangles[4][2]);
    ASSERT_FALSE(checkMesh(soup).valid());
    const RepairReport rr = repairMesh(soup);
    EXPECT_EQ(rr.verticesMerged, 36u - 8u);
    // Whatever the intermediate steps flipped, exactly the one flipped face ends up reversed.
    EXPECT_EQ(rr.facesReversedNet, 1u);
    const ValidityReport after = checkMesh(soup);
    EXPECT_TRUE(after.valid()) << ::testing::PrintToString(after.reasons());
    EXPECT_NEAR(after.volume, 24.0, 24e-12);
}

TEST(MeshRepair, InwardBoxIsTurnedOutward) {
    TriMesh box = makeBox(1, 1, 1);
    for (auto& t : box.triangles) std::swap(t[1], t[2]);
    const RepairReport rr = repairMesh(box);
    EXPECT_EQ(rr.facesReversedNet, 12u);
    EXPECT_TRUE(checkMesh(box).valid());
}

TEST(MeshRepair, NonFiniteVertexIsNotRepairable) {
    TriMesh box = makeBox(1, 1, 1);
    box.positions[0].z = std::numeric_limits<double>::infinity();
    EXPECT_THROW(repairMesh(box), InputError);
}
