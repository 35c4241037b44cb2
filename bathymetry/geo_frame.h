#pragma once
// GeoFrame: the scene's georeferencing, mapping WGS84 geodetic coordinates to the local frame
// (x east, y north, z up, metres) and back. Two kinds:
//   LocalCartesian – GeographicLib::LocalCartesian about (lat0, lon0, h0): a true east-north-up
//                    tangent frame; exact (round trip to nanometres) at any distance.
//   Utm            – GeographicLib transverse Mercator in a UTM zone (chosen from the origin or
//                    given), origin subtracted: x = E - E0, y = N - N0, z = h - h0. x and y are
//                    grid east/north (they differ from true east/north by the meridian
//                    convergence) and distances carry the UTM scale factor (0.9996 on the central
//                    meridian). Points are always projected in the frame's zone, even across a
//                    zone boundary or the equator, so the frame is continuous.
// Angles are degrees at this interface (user-facing coordinates); heights are ellipsoidal, metres.
// Latitude must lie in [-90, 90] and longitude in [-180, 180]; anything else (or a non-finite
// value) is an InputError that names the offending value and the allowed range.
#include <memory>
#include <string>

#include "core/vec.h"

namespace littoral::bathymetry {

struct Geodetic {
    double latDeg = 0, lonDeg = 0, h = 0;  // degrees, degrees, metres above the WGS84 ellipsoid
};

// A UTM coordinate: zone 1..60, hemisphere, easting/northing in metres (false easting 500 km,
// false northing 10 000 km in the south).
struct UtmCoord {
    int zone = 0;
    bool north = true;
    double easting = 0, northing = 0;
};

// Standard UTM zone of a point (GeographicLib::UTMUPS::StandardZone, including the Norway and
// Svalbard exceptions). Latitudes outside [-80, 84] are outside UTM: InputError.
int utmStandardZone(double latDeg, double lonDeg);
// Forward UTM projection (WGS84). zone = 0 chooses the standard zone; otherwise 1..60 forces it.
UtmCoord toUtm(double latDeg, double lonDeg, int zone = 0);
// Inverse UTM projection.
Geodetic fromUtm(const UtmCoord& c);

class GeoFrame {
public:
    enum class Kind { LocalCartesian, Utm };

    static GeoFrame localCartesian(double lat0Deg, double lon0Deg, double h0 = 0);
    // zone = 0: the standard zone of the origin; 1..60 forces a zone (InputError otherwise).
    static GeoFrame utm(double lat0Deg, double lon0Deg, double h0 = 0, int zone = 0);

    GeoFrame(const GeoFrame&);
    GeoFrame& operator=(const GeoFrame&);
    GeoFrame(GeoFrame&&) noexcept;
    GeoFrame& operator=(GeoFrame&&) noexcept;
    ~GeoFrame();

    // Geodetic -> local metres. h is ellipsoidal height; z = h - h0 for Utm, the ENU up
    // component for LocalCartesian (which includes earth curvature: a point 5 km away at h = h0
    // has z ~ -2 m).
    Point3 toLocal(double latDeg, double lonDeg, double h = 0) const;
    Point3 toLocal(const Geodetic& g) const { return toLocal(g.latDeg, g.lonDeg, g.h); }
    Geodetic toGeodetic(double x, double y, double z = 0) const;
    Geodetic toGeodetic(const Point3& p) const { return toGeodetic(p.x, p.y, p.z); }

    // Direction of true north at a point, as an angle in the local frame: degrees clockwise from
    // the local +y axis (grid north). Zero at a LocalCartesian origin; in a UTM frame it is minus
    // the meridian convergence (about (lon - lon_CM) sin(lat)). An object whose heading is given
    // clockwise from true north has local heading = heading + northAzimuthDeg(lat, lon).
    double northAzimuthDeg(double latDeg, double lonDeg) const;

    Kind kind() const { return kind_; }
    Geodetic origin() const { return origin_; }
    // Utm only (0 / zero for LocalCartesian): the zone and the origin's projected coordinates.
    int zone() const { return zone_; }
    UtmCoord originUtm() const { return originUtm_; }
    // "LocalCartesian about 36.18N 75.75W h=0 m" / "UTM 18N, origin E 412345.6 N 4001234.5".
    std::string describe() const;

private:
    GeoFrame() = default;
    struct Impl;
    Kind kind_ = Kind::LocalCartesian;
    Geodetic origin_;
    int zone_ = 0;
    UtmCoord originUtm_;
    std::unique_ptr<Impl> impl_;
};

}  // namespace littoral::bathymetry
