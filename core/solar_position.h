#pragma once
// Solar position from date, time and place: the NREL Solar Position Algorithm (SPA),
// Reda & Andreas (2004), "Solar position algorithm for solar radiation applications",
// Solar Energy 76(5):577-589; corrigendum Solar Energy 81(6):838 (2007); NREL/TP-560-34302
// (revised 2008). Stated uncertainty: +-0.0003 deg in zenith and azimuth for years -2000 to 6000
// (it is the truncated VSOP87 theory of the Earth's heliocentric position, IAU 1980 nutation,
// aberration, topocentric parallax, and a Bennett/Saemundsson-type refraction correction).
//
// Angle conventions — read carefully, two conventions meet here:
//   * At this interface (user-facing, like the SPA paper and every sun-position table):
//     DEGREES; azimuth measured CLOCKWISE FROM NORTH (eastward: N = 0, E = 90, S = 180, W = 270);
//     zenith from the local vertical; latitude north positive; longitude EAST positive.
//   * Inside the Scene IR (core/scene_ir.h, ir::Sun): RADIANS; azimuth COUNTER-CLOCKWISE FROM +x
//     (EAST) TOWARD +y (NORTH). Convert with irAzimuthFromCompass / compassAzimuthFromIr, or set
//     an ir::Sun with sunAnglesForIr.
//   ir_azimuth = pi/2 - compass_azimuth (wrapped to [0, 2 pi)).
#include <limits>
#include <string>

namespace littoral {

struct SolarPositionInput {
    // Civil date and time; with timezoneHours = 0 it is UTC. Local standard time is accepted with
    // its offset from UTC, e.g. -7 for US Mountain Standard Time (UTC = local - timezoneHours).
    int year = 2000, month = 1, day = 1;  // Gregorian calendar (Julian before 1582-10-15)
    int hour = 12, minute = 0;
    double second = 0.0;
    double timezoneHours = 0.0;
    double latitudeDeg = 0.0;     // north positive, [-90, 90]
    double longitudeDeg = 0.0;    // EAST positive, [-180, 180]
    double elevationM = 0.0;      // observer height above the ellipsoid, m
    double pressureMbar = 1013.25;  // annual mean local pressure, mbar (hPa), for refraction
    double temperatureC = 15.0;     // annual mean local temperature, deg C, for refraction
    // TT - UT1, seconds. NaN = estimate with deltaTEstimate(year). An error of 1 s moves the sun by
    // only 1.1e-5 deg (the Sun's ecliptic motion), so the estimate is ample.
    double deltaTSeconds = std::numeric_limits<double>::quiet_NaN();
    double atmosRefractionDeg = 0.5667;  // refraction at sunrise/sunset (SPA default)
    bool applyRefraction = true;         // false: geometric (airless) topocentric position
};

struct SolarPosition {
    double zenithDeg = 0;        // topocentric zenith angle (refraction applied if requested)
    double azimuthDeg = 0;       // topocentric azimuth, degrees CLOCKWISE FROM NORTH, [0, 360)
    double elevationDeg = 0;     // 90 - zenith
    // Intermediate SPA quantities (degrees unless stated), exposed for verification against the
    // worked example in Reda & Andreas (2004) Table A5.1.
    double julianDay = 0;
    double julianEphemerisDay = 0;
    double heliocentricLongitude = 0;  // L
    double heliocentricLatitude = 0;   // B
    double earthRadiusVectorAu = 0;    // R, astronomical units
    double nutationLongitude = 0;      // delta psi
    double nutationObliquity = 0;      // delta epsilon
    double trueObliquity = 0;          // epsilon
    double apparentSunLongitude = 0;   // lambda
    double apparentSiderealTime = 0;   // nu
    double geocentricRightAscension = 0;  // alpha
    double geocentricDeclination = 0;     // delta
    double observerHourAngle = 0;         // H
    double topocentricRightAscension = 0; // alpha'
    double topocentricDeclination = 0;    // delta'
    double topocentricHourAngle = 0;      // H'
    double refractionCorrection = 0;      // delta e
};

// Computes the solar position. InputError for out-of-range inputs (month, day, hour, minute,
// second, latitude, longitude, pressure, temperature, year outside -2000..6000).
SolarPosition solarPosition(const SolarPositionInput& in);

// TT - UT1 estimate, seconds: Espenak & Meeus (2006) polynomials (NASA "Polynomial expressions
// for Delta T") for 1900-2150; outside that, their long-term parabola -20 + 32 u^2,
// u = (y - 1820) / 100.
double deltaTEstimate(double decimalYear);

// Compass azimuth (degrees clockwise from north) -> IR azimuth (radians counter-clockwise from +x
// east), in [0, 2 pi). And back (degrees in [0, 360)).
double irAzimuthFromCompass(double compassAzimuthDeg);
double compassAzimuthFromIr(double irAzimuthRad);

// The pair (zenith, azimuth) in the IR convention (radians), ready for ir::Sun::zenith/azimuth.
struct SunAnglesIr {
    double zenith = 0;   // rad
    double azimuth = 0;  // rad, counter-clockwise from +x (east)
};
SunAnglesIr sunAnglesForIr(const SolarPosition& p);

}  // namespace littoral
