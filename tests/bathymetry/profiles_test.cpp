// Analytic terrains and terrain meshing: Dean profile depths, wedge volume, bar and trough.
#include <cmath>

#include <gtest/gtest.h>

#include "bathymetry/terrain.h"
#include "core/error.h"

namespace lb = littoral::bathymetry;
using littoral::InputError;
using littoral::TriMesh;

// Dean (1991) h = A x^(2/3). With A = 0.1 m^(1/3): x = 27 m -> 0.1 * 9 = 0.9 m; x = 1000 m ->
// 0.1 * 100 = 10 m; x = 125 m -> 2.5 m (perfect cubes make the reference exact). Tolerance:
// double round-off of cbrt and the product, 1e-12 m.
TEST(DeanProfile, DepthAtKnownDistances) {
    const lb::Extent e{0, 0, 1200, 50};
    lb::DeanProfile p;
    p.A = 0.1;
    p.shorelineX = 100;
    p.beachSlope = 0.05;
    p.bermHeight = 2.0;
    const auto t = lb::makeDeanProfile(e, p);
    EXPECT_NEAR(t->elevation(100 + 27, 10), -0.9, 1e-12);
    EXPECT_NEAR(t->elevation(100 + 125, 10), -2.5, 1e-12);
    EXPECT_NEAR(t->elevation(100 + 1000, 33), -10.0, 1e-12);
    EXPECT_NEAR(t->elevation(100, 0), 0.0, 1e-15);  // shoreline at still-water level
    // Land continues the same terrain: beach face 0.05 up to the 2 m berm (reached 40 m inland).
    EXPECT_NEAR(t->elevation(100 - 20, 0), 1.0, 1e-12);
    EXPECT_NEAR(t->elevation(100 - 40, 0), 2.0, 1e-12);
    EXPECT_NEAR(t->elevation(0, 0), 2.0, 1e-12);

    // Offshore toward -x mirrors the profile.
    p.offshoreTowardPositiveX = false;
    const auto m = lb::makeDeanProfile(e, p);
    EXPECT_NEAR(m->elevation(100 - 27, 0), -0.9, 1e-12);
    EXPECT_NEAR(m->elevation(100 + 20, 0), 1.0, 1e-12);

    // Flat bottom beyond max_depth.
    p.offshoreTowardPositiveX = true;
    p.maxDepth = 3.0;
    EXPECT_NEAR(lb::makeDeanProfile(e, p)->elevation(100 + 1000, 0), -3.0, 1e-12);
}

// Dean (1987) fit A = 0.21 D^0.48 (D in mm): A(1 mm) = 0.21 exactly; A(0.2 mm) = 0.21 * 0.2^0.48
// = 0.09699 m^(1/3); doubling D multiplies A by 2^0.48 = 1.39474. Round-off only: 1e-15.
TEST(DeanProfile, ScaleFromGrainSize) {
    EXPECT_NEAR(lb::deanScaleFromGrainSize(1.0), 0.21, 1e-15);
    EXPECT_NEAR(lb::deanScaleFromGrainSize(0.2), 0.096987037, 1e-9);
    EXPECT_NEAR(lb::deanScaleFromGrainSize(0.4) / lb::deanScaleFromGrainSize(0.2), std::pow(2.0, 0.48), 1e-14);
    EXPECT_THROW(lb::deanScaleFromGrainSize(0.0), InputError);
    EXPECT_THROW(lb::deanScaleFromGrainSize(50.0), InputError);
}

// Dune: cosine ramp from the berm (1.5 m) to the dune crest (4 m) over 10 m, starting 5 m landward
// of the berm crest. Berm crest at 1.5 / 0.1 = 15 m inland, ramp from 20 m to 30 m inland; its
// midpoint (25 m) is at the mean height 2.75 m.
TEST(DeanProfile, DuneRamp) {
    lb::DeanProfile p;
    p.shorelineX = 50;
    p.bermHeight = 1.5;
    p.beachSlope = 0.1;
    p.duneHeight = 4.0;
    p.duneOffset = 5;
    p.duneWidth = 10;
    const auto t = lb::makeDeanProfile({0, 0, 100, 10}, p);
    EXPECT_NEAR(t->elevation(50 - 18, 0), 1.5, 1e-12);
    EXPECT_NEAR(t->elevation(50 - 25, 0), 2.75, 1e-12);
    EXPECT_NEAR(t->elevation(50 - 30, 0), 4.0, 1e-12);
    EXPECT_NEAR(t->elevation(50 - 45, 0), 4.0, 1e-12);
}

// Planar wedge: z = 2 - 0.05 x over [0, 100] x [0, 50] m. The shoreline is x = 40 m and the depth
// at x = 100 m is 3 m, so the water above the seabed is a wedge of cross-section 0.5 * 60 * 3 =
// 90 m^2 and volume 90 * 50 = 4500 m^3. A triangulated plane is the plane itself, and volumeBelow
// clips triangles at z = 0 exactly, so only round-off remains: relative tolerance 1e-12. The
// spacing 0.7 m puts the shoreline inside cells (not on grid lines), exercising the clipping.
TEST(TerrainMesh, PlanarWedgeVolume) {
    const lb::Extent e{0, 0, 100, 50};
    const auto t = lb::makePlanarSlope(e, 2.0, -0.05, 0.0);
    const TriMesh m = lb::terrainMesh(*t, e, 0.7);
    EXPECT_NEAR(lb::volumeBelow(m, 0.0), 4500.0, 4500.0 * 1e-12);
    // Tilted along y too: z = 1 - 0.02 x - 0.01 y. Water where 0.02 x + 0.01 y > 1. Volume of
    // max(0, 0.02x + 0.01y - 1) over the rectangle, by direct integration over y of the wedge in x:
    // for each y the wedge runs from x_s = 50 - 0.5 y to 100 with depth 0.02 (100 - x_s) at x = 100,
    // area 0.5 * 0.02 (100 - x_s)^2 = 0.01 (50 + 0.5 y)^2; integral over y in [0, 50] =
    // 0.01 * [(50 + 0.5 y)^3 / 1.5] from 0 to 50 = 0.01 * (75^3 - 50^3) / 1.5 = 1979.1666... m^3.
    const auto t2 = lb::makePlanarSlope(e, 1.0, -0.02, -0.01);
    const double expect = 0.01 * (75.0 * 75 * 75 - 50.0 * 50 * 50) / 1.5;
    EXPECT_NEAR(lb::volumeBelow(lb::terrainMesh(*t2, e, 0.9), 0.0), expect, expect * 1e-12);
}

// Mesh structure: boundary vertices on the extent edges exactly, counter-clockwise triangles (every
// face normal has +z), cell counts from ceil(width / spacing) without a sliver cell at exact ratios.
TEST(TerrainMesh, GridStructure) {
    const lb::Extent e{-10, 5, 80, 65};  // 90 m x 60 m
    const auto t = lb::makePlanarSlope(e, 0.0, 0.0, 0.0);
    const TriMesh m = lb::terrainMesh(*t, e, 0.3);  // 90 / 0.3 = 300.00000000000006 in floating point
    const size_t nx = 300, ny = 200;
    ASSERT_EQ(m.numVertices(), (nx + 1) * (ny + 1));
    ASSERT_EQ(m.numTriangles(), 2 * nx * ny);
    EXPECT_EQ(m.positions.back().x, 80.0);
    EXPECT_EQ(m.positions.back().y, 65.0);
    EXPECT_EQ(m.positions[nx].x, 80.0);
    for (size_t f = 0; f < m.numTriangles(); ++f) ASSERT_GT(m.faceNormalArea(f).z, 0) << "face " << f;
    // Plan area of a flat mesh equals the extent area, 90 * 60 = 5400 m^2. Summing 120 000 face
    // areas accumulates round-off of order n * eps = 1.2e5 * 1.1e-16 = 1.3e-11 relative: tolerance 1e-10.
    EXPECT_NEAR(m.area(), 5400.0, 5400.0 * 1e-10);
    EXPECT_THROW(lb::terrainMesh(*t, e, 0.0), InputError);
    EXPECT_THROW(lb::terrainMesh(*t, lb::Extent{0, 0, 0, 1}, 1.0), InputError);
    EXPECT_THROW(lb::terrainMesh(*t, e, 1e-3), InputError);  // 5.4e9 vertices: refused
}

// The volume of water over a Dean profile: Int_0^W A d^(2/3) dd = (3/5) A W^(5/3) per metre of
// shore. The mesh interpolates the concave depth linearly, so it under-estimates; the trapezoid
// error is at most 0.1 A s^(5/3) in the first cell plus (s^2 / 12) Int |h''| dd <= (1/18) A s^(5/3)
// elsewhere, i.e. below 0.16 A s^(5/3) per metre of shore (s = spacing). Spacing 1 m, shoreline on
// a grid line.
TEST(TerrainMesh, DeanProfileVolume) {
    const double A = 0.12, W = 200, L = 30, s = 1.0;
    const lb::Extent e{-20, 0, W, L};
    const auto t = lb::makeDeanProfile(e, A, 0.0, 1.5, 0.1);
    const double exact = 0.6 * A * std::pow(W, 5.0 / 3.0) * L;
    const double v = lb::volumeBelow(lb::terrainMesh(*t, e, s), 0.0);
    EXPECT_LE(v, exact);
    EXPECT_NEAR(v, exact, 0.16 * A * std::pow(s, 5.0 / 3.0) * L);
}

// Bar and trough: the bar crest adds barHeight (minus the trough's tail, exp(-20^2/(2*8^2)) * 0.4 =
// 0.0176 m at 20 m from the trough centre) to the Dean depth; the trough centre removes
// troughDepth (minus the bar's tail 0.8 * exp(-20^2 / (2 * 10^2)) = 0.1083 m). Ramp = 1 there.
TEST(BarTrough, CrestAndTroughHeights) {
    lb::BarTrough p;
    p.dean.A = 0.1;
    p.dean.shorelineX = 10;
    p.barCrestDistance = 60;
    p.barHeight = 0.8;
    p.barWidth = 10;
    p.troughDistance = 40;
    p.troughDepth = 0.4;
    p.troughWidth = 8;
    const lb::Extent e{0, 0, 200, 100};
    const auto t = lb::makeBarTrough(e, p);
    const auto dean = [&](double d) { return -0.1 * std::cbrt(d * d); };
    EXPECT_NEAR(t->elevation(10 + 60, 3), dean(60) + 0.8 - 0.4 * std::exp(-400.0 / 128), 1e-12);
    EXPECT_NEAR(t->elevation(10 + 40, 3), dean(40) - 0.4 + 0.8 * std::exp(-400.0 / 200), 1e-12);
    EXPECT_NEAR(t->elevation(10, 3), 0.0, 1e-15);   // shoreline unchanged
    EXPECT_NEAR(t->elevation(5, 3), 0.5, 1e-12);    // land unchanged: beach slope 0.1, 5 m inland
    // Crescentic bar: a quarter wavelength along y (sin = 1) shifts bar and trough offshore by the full
    // amplitude, so at d = 65 m the perturbation equals the straight bar's at d = 60 m.
    p.crescentAmplitude = 5;
    p.crescentWavelength = 80;
    const auto c = lb::makeBarTrough(e, p);
    const double straightBump = t->elevation(10 + 60, 0) - dean(60);
    EXPECT_NEAR(c->elevation(10 + 65, 20), dean(65) + straightBump, 1e-12);
    EXPECT_NEAR(c->elevation(10 + 55, 60), dean(55) + straightBump, 1e-12);  // three quarters: shifted landward
}

TEST(BarTrough, RejectsEmergentBarAndBadParameters) {
    lb::BarTrough p;
    p.dean.A = 0.1;
    p.barCrestDistance = 30;  // Dean depth 0.97 m there
    p.barHeight = 1.5;        // would stand 0.5 m above the water
    p.troughDistance = 20;
    try {
        lb::makeBarTrough({0, 0, 100, 10}, p);
        FAIL() << "emergent bar accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("breaks the surface"), std::string::npos) << e.what();
    }
    p.barHeight = 0.3;
    p.troughDistance = 35;  // landward of the bar is required
    EXPECT_THROW(lb::makeBarTrough({0, 0, 100, 10}, p), InputError);
    lb::DeanProfile d;
    d.A = -0.1;
    try {
        lb::makeDeanProfile({0, 0, 10, 10}, d);
        FAIL() << "negative A accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("dean.A = -0.1"), std::string::npos) << e.what();
    }
    EXPECT_THROW(lb::makePlanarSlope({0, 0, 10, 10}, NAN, 0, 0), InputError);
    EXPECT_THROW(lb::makePlanarSlope({10, 0, 0, 10}, 0, 0, 0), InputError);
}
