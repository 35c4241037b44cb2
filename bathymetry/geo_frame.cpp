// GeoFrame: WGS84 geodetic <-> local metres through GeographicLib.
#include "bathymetry/geo_frame.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include <GeographicLib/Constants.hpp>
#include <GeographicLib/LocalCartesian.hpp>
#include <GeographicLib/TransverseMercator.hpp>
#include <GeographicLib/UTMUPS.hpp>
#include <fmt/format.h>

#include "core/error.h"
#include "core/units.h"

namespace littoral::bathymetry {

namespace {

constexpr double kFalseEasting = 500000.0;     // m, UTM
constexpr double kFalseNorthingS = 10000000.0;  // m, UTM southern hemisphere

void checkLatLon(double latDeg, double lonDeg, const char* what) {
    if (!std::isfinite(latDeg) || latDeg < -90 || latDeg > 90)
        throw InputError(fmt::format("{}: latitude {} deg is out of range; allowed [-90, 90] degrees", what, latDeg));
    if (!std::isfinite(lonDeg) || lonDeg < -180 || lonDeg > 180)
        throw InputError(fmt::format("{}: longitude {} deg is out of range; allowed [-180, 180] degrees", what, lonDeg));
}

void checkUtmLatitude(double latDeg, const char* what) {
    // UTM is defined for 80 S .. 84 N; beyond that UPS applies (not offered as a local frame).
    if (latDeg < -80 || latDeg > 84)
        throw InputError(fmt::format("{}: latitude {} deg is outside the UTM band; allowed [-80, 84] degrees", what,
                                     latDeg));
}

void checkZone(int zone, const char* what) {
    if (zone < 1 || zone > 60)
        throw InputError(fmt::format("{}: UTM zone {} is out of range; allowed 1..60 (or 0 to choose automatically)",
                                     what, zone));
}

// Central meridian of a UTM zone, degrees: 6 zone - 183.
double centralMeridian(int zone) { return 6.0 * zone - 183.0; }

}  // namespace

int utmStandardZone(double latDeg, double lonDeg) {
    checkLatLon(latDeg, lonDeg, "UTM zone");
    checkUtmLatitude(latDeg, "UTM zone");
    return GeographicLib::UTMUPS::StandardZone(latDeg, lonDeg);
}

UtmCoord toUtm(double latDeg, double lonDeg, int zone) {
    checkLatLon(latDeg, lonDeg, "UTM");
    checkUtmLatitude(latDeg, "UTM");
    if (zone == 0) zone = GeographicLib::UTMUPS::StandardZone(latDeg, lonDeg);
    checkZone(zone, "UTM");
    double x = 0, y = 0;
    GeographicLib::TransverseMercator::UTM().Forward(centralMeridian(zone), latDeg, lonDeg, x, y);
    UtmCoord c;
    c.zone = zone;
    c.north = latDeg >= 0;
    c.easting = x + kFalseEasting;
    c.northing = c.north ? y : y + kFalseNorthingS;
    return c;
}

Geodetic fromUtm(const UtmCoord& c) {
    checkZone(c.zone, "UTM");
    if (!std::isfinite(c.easting) || !std::isfinite(c.northing))
        throw InputError(fmt::format("UTM: easting {} / northing {} m must be finite", c.easting, c.northing));
    const double x = c.easting - kFalseEasting;
    const double y = c.north ? c.northing : c.northing - kFalseNorthingS;
    Geodetic g;
    GeographicLib::TransverseMercator::UTM().Reverse(centralMeridian(c.zone), x, y, g.latDeg, g.lonDeg);
    return g;
}

struct GeoFrame::Impl {
    std::optional<GeographicLib::LocalCartesian> enu;  // LocalCartesian kind
    double lon0 = 0;                                   // central meridian, degrees (Utm kind)
    double x0 = 0, y0 = 0;                             // TM coordinates of the origin, no false offsets
};

GeoFrame GeoFrame::localCartesian(double lat0Deg, double lon0Deg, double h0) {
    checkLatLon(lat0Deg, lon0Deg, "geo frame origin");
    if (!std::isfinite(h0)) throw InputError(fmt::format("geo frame origin: height {} m must be finite", h0));
    GeoFrame f;
    f.kind_ = Kind::LocalCartesian;
    f.origin_ = {lat0Deg, lon0Deg, h0};
    f.impl_ = std::make_unique<Impl>();
    f.impl_->enu.emplace(lat0Deg, lon0Deg, h0, GeographicLib::Geocentric::WGS84());
    return f;
}

GeoFrame GeoFrame::utm(double lat0Deg, double lon0Deg, double h0, int zone) {
    checkLatLon(lat0Deg, lon0Deg, "geo frame origin");
    checkUtmLatitude(lat0Deg, "geo frame origin");
    if (!std::isfinite(h0)) throw InputError(fmt::format("geo frame origin: height {} m must be finite", h0));
    if (zone != 0) checkZone(zone, "geo frame");
    GeoFrame f;
    f.kind_ = Kind::Utm;
    f.origin_ = {lat0Deg, lon0Deg, h0};
    f.originUtm_ = toUtm(lat0Deg, lon0Deg, zone);
    f.zone_ = f.originUtm_.zone;
    f.impl_ = std::make_unique<Impl>();
    f.impl_->lon0 = centralMeridian(f.zone_);
    GeographicLib::TransverseMercator::UTM().Forward(f.impl_->lon0, lat0Deg, lon0Deg, f.impl_->x0, f.impl_->y0);
    return f;
}

GeoFrame::GeoFrame(const GeoFrame& o)
    : kind_(o.kind_), origin_(o.origin_), zone_(o.zone_), originUtm_(o.originUtm_),
      impl_(o.impl_ ? std::make_unique<Impl>(*o.impl_) : nullptr) {}
GeoFrame& GeoFrame::operator=(const GeoFrame& o) {
    if (this != &o) {
        kind_ = o.kind_;
        origin_ = o.origin_;
        zone_ = o.zone_;
        originUtm_ = o.originUtm_;
        impl_ = o.impl_ ? std::make_unique<Impl>(*o.impl_) : nullptr;
    }
    return *this;
}
GeoFrame::GeoFrame(GeoFrame&&) noexcept = default;
GeoFrame& GeoFrame::operator=(GeoFrame&&) noexcept = default;
GeoFrame::~GeoFrame() = default;

Point3 GeoFrame::toLocal(double latDeg, double lonDeg, double h) const {
    checkLatLon(latDeg, lonDeg, "geo frame");
    if (!std::isfinite(h)) throw InputError(fmt::format("geo frame: height {} m must be finite", h));
    Point3 p;
    if (kind_ == Kind::LocalCartesian) {
        impl_->enu->Forward(latDeg, lonDeg, h, p.x, p.y, p.z);
    } else {
        // Projected in the frame's zone whatever the point's own zone, so the frame is continuous.
        checkUtmLatitude(latDeg, "geo frame");
        GeographicLib::TransverseMercator::UTM().Forward(impl_->lon0, latDeg, lonDeg, p.x, p.y);
        p.x -= impl_->x0;
        p.y -= impl_->y0;
        p.z = h - origin_.h;
    }
    return p;
}

Geodetic GeoFrame::toGeodetic(double x, double y, double z) const {
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
        throw InputError(fmt::format("geo frame: local point ({}, {}, {}) m must be finite", x, y, z));
    Geodetic g;
    if (kind_ == Kind::LocalCartesian) {
        impl_->enu->Reverse(x, y, z, g.latDeg, g.lonDeg, g.h);
    } else {
        GeographicLib::TransverseMercator::UTM().Reverse(impl_->lon0, x + impl_->x0, y + impl_->y0, g.latDeg,
                                                         g.lonDeg);
        g.h = z + origin_.h;
    }
    return g;
}

double GeoFrame::northAzimuthDeg(double latDeg, double lonDeg) const {
    checkLatLon(latDeg, lonDeg, "geo frame");
    // Central difference along the meridian, +-1e-5 deg (~1.1 m): the local images of the two
    // points give the direction of north. Local coordinates are good to ~1 nm, so over the 2.2 m
    // baseline the angle is good to ~5e-10 rad (3e-8 deg); the meridian image's curvature over
    // 2 m is far below that.
    const double d = 1e-5;
    const double lo = std::max(-90.0, latDeg - d), hi = std::min(90.0, latDeg + d);
    const Point3 a = toLocal(lo, lonDeg, origin_.h), b = toLocal(hi, lonDeg, origin_.h);
    return rad2deg(std::atan2(b.x - a.x, b.y - a.y));
}

std::string GeoFrame::describe() const {
    if (kind_ == Kind::LocalCartesian)
        return fmt::format("LocalCartesian about {:.8f}, {:.8f} deg, h = {} m", origin_.latDeg, origin_.lonDeg,
                           origin_.h);
    return fmt::format("UTM {}{}, origin {:.8f}, {:.8f} deg = E {:.3f} N {:.3f} m, h = {} m", zone_,
                       originUtm_.north ? 'N' : 'S', origin_.latDeg, origin_.lonDeg, originUtm_.easting,
                       originUtm_.northing, origin_.h);
}

}  // namespace littoral::bathymetry
