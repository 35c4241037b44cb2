// GeoFrame and UTM: published coordinates, round trips, range errors.
#include <cmath>

#include <gtest/gtest.h>

#include "bathymetry/geo_frame.h"
#include "core/error.h"

namespace lb = littoral::bathymetry;
using littoral::InputError;

namespace {

// Metres per degree of latitude is at most 111.7 km (at the poles), of longitude at most 111.3 km,
// so an angular error e (degrees) is at most 111.7e3 * e metres on the ground.
constexpr double kMetresPerDegreeMax = 111.7e3;

double groundError(const lb::Geodetic& a, const lb::Geodetic& b) {
    const double dlat = (a.latDeg - b.latDeg) * kMetresPerDegreeMax;
    const double dlon = (a.lonDeg - b.lonDeg) * kMetresPerDegreeMax * std::cos(a.latDeg * M_PI / 180);
    return std::sqrt(dlat * dlat + dlon * dlon + (a.h - b.h) * (a.h - b.h));
}

}  // namespace

// Published point: the GeographicLib GeoConvert(1) manual (versions 1.45 to 2.x, "UTM/UPS" input
// examples) gives Baghdad, 33.3 N 44.4 E (WGS84), as "38n 444140.54 3684706.36". The published
// figures are rounded to 0.01 m, so they carry +-0.005 m; GeographicLib's transverse Mercator is
// accurate to 5 nm. Tolerance: 0.005 m + 1e-6 m round-off margin.
TEST(Utm, PublishedGeoConvertExample) {
    const lb::UtmCoord c = lb::toUtm(33.3, 44.4);
    EXPECT_EQ(c.zone, 38);
    EXPECT_TRUE(c.north);
    EXPECT_NEAR(c.easting, 444140.54, 0.005 + 1e-6);
    EXPECT_NEAR(c.northing, 3684706.36, 0.005 + 1e-6);
    EXPECT_EQ(lb::utmStandardZone(33.3, 44.4), 38);

    // Inverse of the published coordinates: back to 33.3, 44.4 within the same 0.005 m
    // (converted to degrees with the largest metres-per-degree, which makes the bound conservative
    // for latitude and longitude alike: 0.005 m / 110.5 km is the smallest-scale case).
    const lb::Geodetic g = lb::fromUtm({38, true, 444140.54, 3684706.36});
    EXPECT_NEAR(g.latDeg, 33.3, 0.0051 / 110.5e3);
    EXPECT_NEAR(g.lonDeg, 44.4, 0.0051 / (110.5e3 * std::cos(33.3 * M_PI / 180)));
}

// Standard zones: 6-degree bands from 180 W, with the Norway (32V) and Svalbard exceptions
// (DMA TM 8358.2, section 2-2).
TEST(Utm, StandardZones) {
    EXPECT_EQ(lb::utmStandardZone(0.0, -177.0), 1);
    EXPECT_EQ(lb::utmStandardZone(0.0, 3.0), 31);
    EXPECT_EQ(lb::utmStandardZone(60.0, 5.0), 32);   // Norway exception: 32V widened west
    EXPECT_EQ(lb::utmStandardZone(78.0, 10.0), 33);  // Svalbard: zones 31X, 33X, 35X, 37X only
    EXPECT_EQ(lb::utmStandardZone(-34.0, 151.2), 56);
}

// Southern hemisphere: false northing 10 000 km; forward then inverse returns the point.
// Tolerance 1 mm on the ground (the round trip is exact to nanometres in GeographicLib).
TEST(Utm, SouthernHemisphereRoundTrip) {
    const lb::UtmCoord c = lb::toUtm(-33.8568, 151.2153);  // Sydney
    EXPECT_EQ(c.zone, 56);
    EXPECT_FALSE(c.north);
    EXPECT_GT(c.northing, 6e6);  // 10 000 km false northing minus ~3750 km to the equator
    EXPECT_LT(c.northing, 6.3e6);
    const lb::Geodetic g = lb::fromUtm(c);
    EXPECT_LT(groundError(g, {-33.8568, 151.2153, 0}), 1e-3);
}

// Round trip lat/lon -> local -> lat/lon within 1 mm, for points up to 20 km away (the brief asks
// for 5 km) at several heights, in both frame kinds.
TEST(GeoFrame, RoundTripWithinOneMillimetre) {
    const double lat0 = 36.1833, lon0 = -75.7500, h0 = -35.2;  // Duck, NC (FRF pier), ellipsoidal height
    const lb::GeoFrame frames[] = {lb::GeoFrame::localCartesian(lat0, lon0, h0), lb::GeoFrame::utm(lat0, lon0, h0)};
    // Offsets in degrees: 0.045 deg latitude ~ 5.0 km, 0.056 deg longitude ~ 5.0 km at 36 N.
    const double offsets[][3] = {{0, 0, 0},          {0.0009, 0.0011, 0}, {0.045, 0, 0},  {0, 0.056, 3.0},
                                 {-0.045, -0.056, -40}, {0.03, -0.04, 25},  {0.18, 0.22, 0}};
    for (const auto& frame : frames) {
        for (const auto& o : offsets) {
            const lb::Geodetic in{lat0 + o[0], lon0 + o[1], h0 + o[2]};
            const auto p = frame.toLocal(in);
            const lb::Geodetic out = frame.toGeodetic(p);
            EXPECT_LT(groundError(in, out), 1e-3) << frame.describe() << " offset " << o[0] << ", " << o[1];
        }
    }
}

// The origin maps to (0, 0, 0); a point straight above it to (0, 0, dh) in both frames; in a UTM
// frame local coordinates are UTM coordinates minus the origin's (same zone, exact up to round-off).
TEST(GeoFrame, OriginAndUtmOffsets) {
    const auto enu = lb::GeoFrame::localCartesian(33.3, 44.4, 10);
    const auto p0 = enu.toLocal(33.3, 44.4, 10);
    EXPECT_NEAR(p0.x, 0, 1e-9);
    EXPECT_NEAR(p0.y, 0, 1e-9);
    EXPECT_NEAR(p0.z, 0, 1e-9);
    const auto up = enu.toLocal(33.3, 44.4, 110);
    EXPECT_NEAR(up.x, 0, 1e-9);
    EXPECT_NEAR(up.y, 0, 1e-9);
    EXPECT_NEAR(up.z, 100, 1e-9);

    const auto utm = lb::GeoFrame::utm(33.3, 44.4, 10);
    EXPECT_EQ(utm.zone(), 38);
    EXPECT_NEAR(utm.originUtm().easting, 444140.54, 0.005 + 1e-6);  // the published point again
    const lb::UtmCoord c = lb::toUtm(33.31, 44.43);
    const auto q = utm.toLocal(33.31, 44.43, 12);
    EXPECT_NEAR(q.x, c.easting - utm.originUtm().easting, 1e-6);
    EXPECT_NEAR(q.y, c.northing - utm.originUtm().northing, 1e-6);
    EXPECT_NEAR(q.z, 2, 1e-12);

    // A forced zone keeps points in the frame's zone: 44.4 E is in zone 38, forcing 37 moves the
    // central meridian from 45 E to 39 E, so the origin's easting grows by ~500 km (5.4 deg at 33.3 N).
    const auto forced = lb::GeoFrame::utm(33.3, 44.4, 0, 37);
    EXPECT_EQ(forced.zone(), 37);
    EXPECT_GT(forced.originUtm().easting, 900e3);
}

TEST(GeoFrame, RejectsOutOfRangeCoordinates) {
    EXPECT_THROW(lb::GeoFrame::localCartesian(90.5, 0), InputError);
    EXPECT_THROW(lb::GeoFrame::localCartesian(0, 180.5), InputError);
    EXPECT_THROW(lb::GeoFrame::localCartesian(NAN, 0), InputError);
    EXPECT_THROW(lb::GeoFrame::utm(85, 0), InputError);       // beyond the UTM band
    EXPECT_THROW(lb::GeoFrame::utm(10, 0, 0, 61), InputError);  // no zone 61
    const auto f = lb::GeoFrame::localCartesian(10, 10);
    try {
        f.toLocal(-91, 10);
        FAIL() << "latitude -91 accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("[-90, 90]"), std::string::npos) << e.what();
    }
    EXPECT_THROW(f.toLocal(10, -200), InputError);
    EXPECT_THROW(lb::toUtm(-81, 10), InputError);
}

// True north in the local frame. UTM: the meridian convergence at 33.3 N 44.4 E in zone 38 (central
// meridian 45 E) is gamma = dlon sin(lat) [1 + (dlon cos lat)^2 / 3 + ...] (Snyder 1987, eq. 8-15
// for the sphere; the ellipsoidal correction is of relative order e'^2 cos^2(lat) (dlon)^2 ~ 1e-6)
// with dlon = -0.6 deg: gamma = -0.32937 deg; true north is at -gamma clockwise from grid north.
// The bracketed term is 1 + 2.5e-5, so the first-order value is good to 1e-5 deg: tolerance 2e-5 deg.
TEST(GeoFrame, NorthAzimuthIsMinusMeridianConvergence) {
    const auto utm = lb::GeoFrame::utm(33.3, 44.4);
    const double gamma = -0.6 * std::sin(33.3 * M_PI / 180);
    EXPECT_NEAR(utm.northAzimuthDeg(33.3, 44.4), -gamma, 2e-5);
    // On the central meridian grid north is true north; at a LocalCartesian origin the y axis is
    // true north. The finite-difference direction (2.2 m baseline, ~1 nm coordinate round-off) is
    // good to ~3e-8 deg: tolerance 1e-7 deg.
    EXPECT_NEAR(utm.northAzimuthDeg(33.3, 45.0), 0.0, 1e-7);
    const auto enu = lb::GeoFrame::localCartesian(33.3, 44.4);
    EXPECT_NEAR(enu.northAzimuthDeg(33.3, 44.4), 0.0, 1e-7);
}
