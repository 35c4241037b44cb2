// Soundings: CSV parsing, geodetic -> local conversion, constrained Delaunay TIN, interpolation.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "tests/support/test_support.h"

#include "bathymetry/geo_frame.h"
#include "bathymetry/terrain.h"
#include "core/error.h"
#include "core/rng.h"

namespace lb = littoral::bathymetry;
namespace fs = std::filesystem;
using littoral::InputError;
using littoral::Point3;
using littoral::RandomStream;

namespace {

fs::path writeSoundingsText(const std::string& name, const std::string& text) {
    return littoral::testing_support::writeTextFile(fs::path(::testing::TempDir()) / "littoral_bathymetry_soundings",
                                                    name, text);
}
using littoral::testing_support::inputErrorOf;

// Seabed plane used as the reference field: z = -8 + 0.006 x - 0.004 y (metres); below the water
// (z < 0) for |x|, |y| < 500 m since 0.006 * 500 + 0.004 * 500 = 5 < 8.
double plane(double x, double y) { return -8.0 + 0.006 * x - 0.004 * y; }

}  // namespace

// A TIN is exact for a plane: every triangle's linear interpolant is the plane itself. 300
// soundings scattered (counter-based RNG, fixed seed) over +-0.004 deg (~ +-440 m) about the origin,
// plus the 4 corners so the query rectangle is inside the hull; depths from the plane at each
// sounding's local position. Queries at 2000 random points. Residual is round-off only: barycentric
// weights of O(1) times elevations of O(10 m) with coordinates of O(500 m) give ~1e-12 m; tolerance
// 1e-9 m. Both frame kinds.
TEST(Soundings, TinReproducesPlaneExactly) {
    const double lat0 = 36.18, lon0 = -75.75;
    for (const auto& frame : {lb::GeoFrame::localCartesian(lat0, lon0, 0), lb::GeoFrame::utm(lat0, lon0, 0)}) {
        std::vector<lb::Sounding> s;
        const auto add = [&](double lat, double lon) {
            const Point3 p = frame.toLocal(lat, lon, 0);
            s.push_back({lat, lon, -plane(p.x, p.y), 0});
        };
        for (double dlat : {-0.004, 0.004})
            for (double dlon : {-0.005, 0.005}) add(lat0 + dlat, lon0 + dlon);
        for (uint64_t i = 0; i < 300; ++i) {
            RandomStream r(7, 0, i);
            add(lat0 - 0.004 + 0.008 * r.uniform(), lon0 - 0.005 + 0.010 * r.uniform());
        }
        const auto tin = lb::fromSoundings(s, frame);
        const lb::Extent e = tin->extent();
        EXPECT_GT(e.width(), 800);  // 0.01 deg of longitude at 36 N is ~ 900 m
        EXPECT_GT(e.height(), 850);
        for (uint64_t i = 0; i < 2000; ++i) {
            RandomStream r(11, 1, i);
            // Stay 12 m inside the bounding box: its corners are soundings, but in UTM grid north is
            // turned from true north by the meridian convergence (0.75 deg from the central
            // meridian * sin 36 deg = 0.44 deg), so the hull's meridian edges lean by up to
            // 900 m * 0.0077 = 6.9 m within the box.
            const double x = e.x0 + 12 + (e.width() - 24) * r.uniform();
            const double y = e.y0 + 12 + (e.height() - 24) * r.uniform();
            ASSERT_NEAR(tin->elevation(x, y), plane(x, y), 1e-9) << frame.describe() << " at " << x << ", " << y;
        }
        // A terrain mesh of the TIN is a mesh of the plane: water volume = closed form. The depth
        // -plane is positive over the box, so V = Int -plane dA = area * -plane(centroid) (a linear
        // function's mean over a rectangle is its centre value). Round-off over 2 * 130^2 faces:
        // tolerance 1e-10 relative.
        const lb::Extent box{e.x0 + 15, e.y0 + 15, e.x1 - 15, e.y1 - 15};
        const double cx = 0.5 * (box.x0 + box.x1), cy = 0.5 * (box.y0 + box.y1);
        const double expect = box.width() * box.height() * -plane(cx, cy);
        EXPECT_NEAR(lb::volumeBelow(lb::terrainMesh(*tin, box, 7.0), 0.0), expect, expect * 1e-10);
    }
}

TEST(Soundings, CsvFileRoundTrip) {
    // Columns in another order, an extra column, comments, blank lines, CRLF, whitespace.
    const auto frame = lb::GeoFrame::localCartesian(50.0, -1.0, 0);
    std::string text = "# survey 2026-11-02\r\ndepth, time ,Longitude,LATITUDE\r\n";
    std::vector<Point3> pts;
    const double lats[] = {50.0, 50.001, 50.0005, 49.9995, 50.0012};
    const double lons[] = {-1.0, -1.0, -0.9985, -1.001, -0.9992};
    const double depths[] = {3.0, 5.5, 4.25, -0.5, 6.0};
    for (int k = 0; k < 5; ++k) {
        text += fmt::format("{}, 12:00:0{}, {:.7f}, {:.7f}\r\n", depths[k], k, lons[k], lats[k]);
        if (k == 2) text += "\r\n";
    }
    const auto path = writeSoundingsText("survey.csv", text);
    const auto soundings = lb::readSoundingsCsv(path);
    ASSERT_EQ(soundings.size(), 5u);
    EXPECT_EQ(soundings[0].line, 3);
    EXPECT_EQ(soundings[3].line, 7);  // after the blank line
    EXPECT_DOUBLE_EQ(soundings[2].depth, 4.25);
    const auto tin = lb::fromSoundings(path, frame);
    // At a sounding the TIN returns its elevation exactly (-depth; the frame's height is ignored).
    for (int k = 0; k < 5; ++k) {
        const Point3 p = frame.toLocal(lats[k], lons[k], 0);
        EXPECT_NEAR(tin->elevation(p.x, p.y), -depths[k], 1e-12) << "sounding " << k;
    }
    EXPECT_NE(tin->describe().find("5 vertices"), std::string::npos) << tin->describe();
}

TEST(Soundings, MalformedCsvNamesLineAndColumn) {
    const auto err = [](const std::string& name, const std::string& text) {
        return inputErrorOf([&] { lb::readSoundingsCsv(writeSoundingsText(name, text)); });
    };
    std::string m = err("bad_number.csv", "latitude,longitude,depth\n36.1,-75.7,3\n36.2,-75.7,3.x\n");
    EXPECT_NE(m.find("bad_number.csv:3:12"), std::string::npos) << m;
    EXPECT_NE(m.find("depth '3.x' is not a finite number"), std::string::npos) << m;

    m = err("lat_range.csv", "latitude,longitude,depth\n36.1,-75.7,3\n96.1,-75.7,3\n");
    EXPECT_NE(m.find("lat_range.csv:3:1"), std::string::npos) << m;
    EXPECT_NE(m.find("[-90, 90]"), std::string::npos) << m;

    m = err("lon_range.csv", "latitude,longitude,depth\n36.1,-275.7,3\n");
    EXPECT_NE(m.find("lon_range.csv:2:6"), std::string::npos) << m;
    EXPECT_NE(m.find("[-180, 180]"), std::string::npos) << m;

    m = err("fields.csv", "latitude,longitude,depth\n36.1,-75.7\n");
    EXPECT_NE(m.find("fields.csv:2"), std::string::npos) << m;
    EXPECT_NE(m.find("2 field(s); the header has 3"), std::string::npos) << m;

    m = err("empty_field.csv", "latitude,longitude,depth\n36.1,,3\n");
    EXPECT_NE(m.find("empty_field.csv:2:6"), std::string::npos) << m;
    EXPECT_NE(m.find("longitude is missing"), std::string::npos) << m;

    m = err("header.csv", "latitud,longitude,depth\n36.1,-75.7,3\n");
    EXPECT_NE(m.find("header.csv:1"), std::string::npos) << m;
    EXPECT_NE(m.find("missing: latitude"), std::string::npos) << m;
    EXPECT_NE(m.find("did you mean 'latitude'"), std::string::npos) << m;

    m = err("empty.csv", "");
    EXPECT_NE(m.find("empty soundings file"), std::string::npos) << m;
    m = err("header_only.csv", "lat,lon,depth\n");
    EXPECT_NE(m.find("no data rows"), std::string::npos) << m;
    m = inputErrorOf([] { lb::readSoundingsCsv("/nonexistent/soundings.csv"); });
    EXPECT_NE(m.find("soundings file does not exist"), std::string::npos) << m;
}

// Shoreline constraint. Points B = (0, 2, +2) (beach) and D = (0, -2, -4) (seabed); the shoreline
// runs from A = (-10, 0) to C = (10, 0) at z = 0. Unconstrained Delaunay joins B-D (D lies inside
// the circumcircle of A, B, C: centre (0, -24), radius 26, |D - centre| = 22), so at (0, 1) the
// value comes from segment B-D: -4 + (3/4) * 6 = 0.5 m. With A-C constrained, (0, 1) lies in
// triangle A, B, C whose plane is z = y: 1 m; and (0, 0) is on the shoreline: 0 m.
TEST(Soundings, ShorelineConstraintChangesTriangulation) {
    const std::vector<Point3> pts = {{0, 2, 2}, {0, -2, -4}, {-10, 0, 0}, {10, 0, 0}};
    const auto free = lb::fromLocalPoints(pts);
    EXPECT_NEAR(free->elevation(0, 1), 0.5, 1e-12);
    EXPECT_NEAR(free->elevation(0, 0), -1.0, 1e-12);

    const auto constrained = lb::fromLocalPoints({{0, 2, 2}, {0, -2, -4}}, {{{-10, 0, 0}, {10, 0, 0}}});
    EXPECT_NEAR(constrained->elevation(0, 1), 1.0, 1e-12);
    EXPECT_NEAR(constrained->elevation(0, 0), 0.0, 1e-12);
    EXPECT_NEAR(constrained->elevation(0, -1), -2.0, 1e-12);  // triangle A, D, C: z = 2 y

    // The same through geodetic coordinates: soundings and shoreline given as latitude/longitude.
    // The local -> geodetic -> local round trip adds < 1 nm; tolerance 1e-6 m.
    const auto frame = lb::GeoFrame::localCartesian(-33.9, 18.4, 0);
    const auto geo = [&](double x, double y) { return frame.toGeodetic(x, y, 0); };
    std::vector<lb::Sounding> s = {{geo(0, 2).latDeg, geo(0, 2).lonDeg, -2.0, 0},
                                   {geo(0, -2).latDeg, geo(0, -2).lonDeg, 4.0, 0}};
    lb::SoundingsOptions opt;
    opt.shorelines = {{{geo(-10, 0).latDeg, geo(-10, 0).lonDeg}, {geo(10, 0).latDeg, geo(10, 0).lonDeg}}};
    const auto tin = lb::fromSoundings(s, frame, opt);
    EXPECT_NEAR(tin->elevation(0, 1), 1.0, 1e-6);
    EXPECT_NEAR(tin->elevation(0, 0), 0.0, 1e-6);
}

TEST(Soundings, OutsideHullPolicies) {
    // Unit square of side 10 with corner elevations -1, -3 (x = 10), -2 (y = 10), -4.
    const std::vector<Point3> pts = {{0, 0, -1}, {10, 0, -3}, {0, 10, -2}, {10, 10, -4}};
    const auto strict = lb::fromLocalPoints(pts);
    const std::string m = inputErrorOf([&] { strict->elevation(15, 5); });
    EXPECT_NE(m.find("outside the convex hull"), std::string::npos) << m;
    const auto clamp = lb::fromLocalPoints(pts, {}, lb::OutsideHull::NearestHullPoint);
    // Nearest hull point of (15, 5) is (10, 5): midway between -3 and -4 on the edge x = 10.
    EXPECT_NEAR(clamp->elevation(15, 5), -3.5, 1e-12);
    // Nearest hull point of (-3, -4) is the corner (0, 0).
    EXPECT_NEAR(clamp->elevation(-3, -4), -1.0, 1e-12);
    EXPECT_NEAR(clamp->elevation(5, 5), strict->elevation(5, 5), 0.0);  // inside: same interpolant
}

TEST(Soundings, DegenerateInputsAreErrors) {
    std::string m = inputErrorOf([] { lb::fromLocalPoints({{0, 0, 0}, {1, 1, 0}}); });
    EXPECT_NE(m.find("at least 3"), std::string::npos) << m;
    m = inputErrorOf([] { lb::fromLocalPoints({{0, 0, 0}, {1, 1, 0}, {2, 2, 1}, {3, 3, 0}}); });
    EXPECT_NE(m.find("collinear"), std::string::npos) << m;
    // Two shorelines crossing at (5, 5), which would need a constructed vertex.
    m = inputErrorOf([] {
        lb::fromLocalPoints({{0, 0, -1}, {10, 0, -1}, {0, 10, -1}, {10, 10, -1}},
                            {{{1, 1, 0}, {9, 9, 0}}, {{1, 9, 0}, {9, 1, 0}}});
    });
    EXPECT_NE(m.find("constraint polyline 2 crosses"), std::string::npos) << m;
    m = inputErrorOf([] { lb::fromLocalPoints({{0, 0, 0}, {1, 0, 0}, {0, 1, NAN}}); });
    EXPECT_NE(m.find("non-finite"), std::string::npos) << m;
    // Out-of-range geodetic sounding from code (not a file) names its index.
    m = inputErrorOf([] {
        lb::fromSoundings({{10, 10, 1, 0}, {10.001, 10, 1, 0}, {10, 190, 1, 0}}, lb::GeoFrame::localCartesian(10, 10));
    });
    EXPECT_NE(m.find("sounding 3"), std::string::npos) << m;
}

// Soundings within the merge distance become one vertex with the mean elevation: two surveys
// reporting 2 m and 4 m at the same spot give 3 m there.
TEST(Soundings, CoincidentSoundingsMerge) {
    const auto tin = lb::fromLocalPoints({{0, 0, -2}, {0.0004, 0, -4}, {10, 0, -1}, {0, 10, -1}});
    EXPECT_NEAR(tin->elevation(0, 0), -3.0, 1e-12);
    EXPECT_NE(tin->describe().find("3 vertices"), std::string::npos) << tin->describe();
}
