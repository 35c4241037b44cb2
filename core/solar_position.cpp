#include "core/solar_position.h"

#include <cmath>
#include <string>

#include <fmt/format.h>

#include "core/error.h"
#include "core/units.h"

namespace littoral {

namespace {

// Periodic terms of the Earth's heliocentric longitude L, latitude B and radius vector R:
// Reda & Andreas (2004), Table A4.2 (a truncation of VSOP87, Bretagnon & Francou 1988).
// Each row {A, B, C} contributes A cos(B + C * JME).
struct Term { double a, b, c; };

constexpr Term L0[] = {
    {175347046.0, 0, 0}, {3341656.0, 4.6692568, 6283.07585}, {34894.0, 4.6261, 12566.1517},
    {3497.0, 2.7441, 5753.3849}, {3418.0, 2.8289, 3.5231}, {3136.0, 3.6277, 77713.7715},
    {2676.0, 4.4181, 7860.4194}, {2343.0, 6.1352, 3930.2097}, {1324.0, 0.7425, 11506.7698},
    {1273.0, 2.0371, 529.691}, {1199.0, 1.1096, 1577.3435}, {990.0, 5.233, 5884.927},
    {902.0, 2.045, 26.298}, {857.0, 3.508, 398.149}, {780.0, 1.179, 5223.694},
    {753.0, 2.533, 5507.553}, {505.0, 4.583, 18849.228}, {492.0, 4.205, 775.523},
    {357.0, 2.92, 0.067}, {317.0, 5.849, 11790.629}, {284.0, 1.899, 796.298},
    {271.0, 0.315, 10977.079}, {243.0, 0.345, 5486.778}, {206.0, 4.806, 2544.314},
    {205.0, 1.869, 5573.143}, {202.0, 2.458, 6069.777}, {156.0, 0.833, 213.299},
    {132.0, 3.411, 2942.463}, {126.0, 1.083, 20.775}, {115.0, 0.645, 0.98},
    {103.0, 0.636, 4694.003}, {102.0, 0.976, 15720.839}, {102.0, 4.267, 7.114},
    {99.0, 6.21, 2146.17}, {98.0, 0.68, 155.42}, {86.0, 5.98, 161000.69},
    {85.0, 1.3, 6275.96}, {85.0, 3.67, 71430.7}, {80.0, 1.81, 17260.15},
    {79.0, 3.04, 12036.46}, {75.0, 1.76, 5088.63}, {74.0, 3.5, 3154.69},
    {74.0, 4.68, 801.82}, {70.0, 0.83, 9437.76}, {62.0, 3.98, 8827.39},
    {61.0, 1.82, 7084.9}, {57.0, 2.78, 6286.6}, {56.0, 4.39, 14143.5},
    {56.0, 3.47, 6279.55}, {52.0, 0.19, 12139.55}, {52.0, 1.33, 1748.02},
    {51.0, 0.28, 5856.48}, {49.0, 0.49, 1194.45}, {41.0, 5.37, 8429.24},
    {41.0, 2.4, 19651.05}, {39.0, 6.17, 10447.39}, {37.0, 6.04, 10213.29},
    {37.0, 2.57, 1059.38}, {36.0, 1.71, 2352.87}, {36.0, 1.78, 6812.77},
    {33.0, 0.59, 17789.85}, {30.0, 0.44, 83996.85}, {30.0, 2.74, 1349.87},
    {25.0, 3.16, 4690.48}};
constexpr Term L1[] = {
    {628331966747.0, 0, 0}, {206059.0, 2.678235, 6283.07585}, {4303.0, 2.6351, 12566.1517},
    {425.0, 1.59, 3.523}, {119.0, 5.796, 26.298}, {109.0, 2.966, 1577.344},
    {93.0, 2.59, 18849.23}, {72.0, 1.14, 529.69}, {68.0, 1.87, 398.15},
    {67.0, 4.41, 5507.55}, {59.0, 2.89, 5223.69}, {56.0, 2.17, 155.42},
    {45.0, 0.4, 796.3}, {36.0, 0.47, 775.52}, {29.0, 2.65, 7.11},
    {21.0, 5.34, 0.98}, {19.0, 1.85, 5486.78}, {19.0, 4.97, 213.3},
    {17.0, 2.99, 6275.96}, {16.0, 0.03, 2544.31}, {16.0, 1.43, 2146.17},
    {15.0, 1.21, 10977.08}, {12.0, 2.83, 1748.02}, {12.0, 3.26, 5088.63},
    {12.0, 5.27, 1194.45}, {12.0, 2.08, 4694.0}, {11.0, 0.77, 553.57},
    {10.0, 1.3, 6286.6}, {10.0, 4.24, 1349.87}, {9.0, 2.7, 242.73},
    {9.0, 5.64, 951.72}, {8.0, 5.3, 2352.87}, {6.0, 2.65, 9437.76},
    {6.0, 4.67, 4690.48}};
constexpr Term L2[] = {
    {52919.0, 0, 0}, {8720.0, 1.0721, 6283.0758}, {309.0, 0.867, 12566.152},
    {27.0, 0.05, 3.52}, {16.0, 5.19, 26.3}, {16.0, 3.68, 155.42},
    {10.0, 0.76, 18849.23}, {9.0, 2.06, 77713.77}, {7.0, 0.83, 775.52},
    {5.0, 4.66, 1577.34}, {4.0, 1.03, 7.11}, {4.0, 3.44, 5573.14},
    {3.0, 5.14, 796.3}, {3.0, 6.05, 5507.55}, {3.0, 1.19, 242.73},
    {3.0, 6.12, 529.69}, {3.0, 0.31, 398.15}, {3.0, 2.28, 553.57},
    {2.0, 4.38, 5223.69}, {2.0, 3.75, 0.98}};
constexpr Term L3[] = {
    {289.0, 5.844, 6283.076}, {35.0, 0, 0}, {17.0, 5.49, 12566.15}, {3.0, 5.2, 155.42},
    {1.0, 4.72, 3.52}, {1.0, 5.3, 18849.23}, {1.0, 5.97, 242.73}};
constexpr Term L4[] = {{114.0, 3.142, 0}, {8.0, 4.13, 6283.08}, {1.0, 3.84, 12566.15}};
constexpr Term L5[] = {{1.0, 3.14, 0}};
constexpr Term B0[] = {
    {280.0, 3.199, 84334.662}, {102.0, 5.422, 5507.553}, {80.0, 3.88, 5223.69},
    {44.0, 3.7, 2352.87}, {32.0, 4.0, 1577.34}};
constexpr Term B1[] = {{9.0, 3.9, 5507.55}, {6.0, 1.73, 5223.69}};
constexpr Term R0[] = {
    {100013989.0, 0, 0}, {1670700.0, 3.0984635, 6283.07585}, {13956.0, 3.05525, 12566.1517},
    {3084.0, 5.1985, 77713.7715}, {1628.0, 1.1739, 5753.3849}, {1576.0, 2.8469, 7860.4194},
    {925.0, 5.453, 11506.77}, {542.0, 4.564, 3930.21}, {472.0, 3.661, 5884.927},
    {346.0, 0.964, 5507.553}, {329.0, 5.9, 5223.694}, {307.0, 0.299, 5573.143},
    {243.0, 4.273, 11790.629}, {212.0, 5.847, 1577.344}, {186.0, 5.022, 10977.079},
    {175.0, 3.012, 18849.228}, {110.0, 5.055, 5486.778}, {98.0, 0.89, 6069.78},
    {86.0, 5.69, 15720.84}, {86.0, 1.27, 161000.69}, {65.0, 0.27, 17260.15},
    {63.0, 0.92, 529.69}, {57.0, 2.01, 83996.85}, {56.0, 5.24, 71430.7},
    {49.0, 3.25, 2544.31}, {47.0, 2.58, 775.52}, {45.0, 5.54, 9437.76},
    {43.0, 6.01, 6275.96}, {39.0, 5.36, 4694.0}, {38.0, 2.39, 8827.39},
    {37.0, 0.83, 19651.05}, {37.0, 4.9, 12139.55}, {36.0, 1.67, 12036.46},
    {35.0, 1.84, 2942.46}, {33.0, 0.24, 7084.9}, {32.0, 0.18, 5088.63},
    {32.0, 1.78, 398.15}, {28.0, 1.21, 6286.6}, {28.0, 1.9, 6279.55},
    {26.0, 4.59, 10447.39}};
constexpr Term R1[] = {
    {103019.0, 1.10749, 6283.07585}, {1721.0, 1.0644, 12566.1517}, {702.0, 3.142, 0},
    {32.0, 1.02, 18849.23}, {31.0, 2.84, 5507.55}, {25.0, 1.32, 5223.69},
    {18.0, 1.42, 1577.34}, {10.0, 5.91, 10977.08}, {9.0, 1.42, 6275.96},
    {9.0, 0.27, 5486.78}};
constexpr Term R2[] = {
    {4359.0, 5.7846, 6283.0758}, {124.0, 5.579, 12566.152}, {12.0, 3.14, 0},
    {9.0, 3.63, 77713.77}, {6.0, 1.87, 5573.14}, {3.0, 5.47, 18849.23}};
constexpr Term R3[] = {{145.0, 4.273, 6283.076}, {7.0, 3.92, 12566.15}};
constexpr Term R4[] = {{4.0, 2.56, 6283.08}};

// Nutation in longitude and obliquity, IAU 1980 theory as tabulated in Reda & Andreas (2004)
// Table A4.3: multipliers of X0..X4 and coefficients a, b (delta psi) and c, d (delta epsilon),
// in units of 0.0001 arcsec.
struct NutationTerm { int y[5]; double a, b, c, d; };
constexpr NutationTerm kNutation[] = {
    {{0, 0, 0, 0, 1}, -171996, -174.2, 92025, 8.9},
    {{-2, 0, 0, 2, 2}, -13187, -1.6, 5736, -3.1},
    {{0, 0, 0, 2, 2}, -2274, -0.2, 977, -0.5},
    {{0, 0, 0, 0, 2}, 2062, 0.2, -895, 0.5},
    {{0, 1, 0, 0, 0}, 1426, -3.4, 54, -0.1},
    {{0, 0, 1, 0, 0}, 712, 0.1, -7, 0},
    {{-2, 1, 0, 2, 2}, -517, 1.2, 224, -0.6},
    {{0, 0, 0, 2, 1}, -386, -0.4, 200, 0},
    {{0, 0, 1, 2, 2}, -301, 0, 129, -0.1},
    {{-2, -1, 0, 2, 2}, 217, -0.5, -95, 0.3},
    {{-2, 0, 1, 0, 0}, -158, 0, 0, 0},
    {{-2, 0, 0, 2, 1}, 129, 0.1, -70, 0},
    {{0, 0, -1, 2, 2}, 123, 0, -53, 0},
    {{2, 0, 0, 0, 0}, 63, 0, 0, 0},
    {{0, 0, 1, 0, 1}, 63, 0.1, -33, 0},
    {{2, 0, -1, 2, 2}, -59, 0, 26, 0},
    {{0, 0, -1, 0, 1}, -58, -0.1, 32, 0},
    {{0, 0, 1, 2, 1}, -51, 0, 27, 0},
    {{-2, 0, 2, 0, 0}, 48, 0, 0, 0},
    {{0, 0, -2, 2, 1}, 46, 0, -24, 0},
    {{2, 0, 0, 2, 2}, -38, 0, 16, 0},
    {{0, 0, 2, 2, 2}, -31, 0, 13, 0},
    {{0, 0, 2, 0, 0}, 29, 0, 0, 0},
    {{-2, 0, 1, 2, 2}, 29, 0, -12, 0},
    {{0, 0, 0, 2, 0}, 26, 0, 0, 0},
    {{-2, 0, 0, 2, 0}, -22, 0, 0, 0},
    {{0, 0, -1, 2, 1}, 21, 0, -10, 0},
    {{0, 2, 0, 0, 0}, 17, -0.1, 0, 0},
    {{2, 0, -1, 0, 1}, 16, 0, -8, 0},
    {{-2, 2, 0, 2, 2}, -16, 0.1, 7, 0},
    {{0, 1, 0, 0, 1}, -15, 0, 9, 0},
    {{-2, 0, 1, 0, 1}, -13, 0, 7, 0},
    {{0, -1, 0, 0, 1}, -12, 0, 6, 0},
    {{0, 0, 2, -2, 0}, 11, 0, 0, 0},
    {{2, 0, -1, 2, 1}, -10, 0, 5, 0},
    {{2, 0, 1, 2, 2}, -8, 0, 3, 0},
    {{0, 1, 0, 2, 2}, 7, 0, -3, 0},
    {{-2, 1, 1, 0, 0}, -7, 0, 0, 0},
    {{0, -1, 0, 2, 2}, -7, 0, 3, 0},
    {{2, 0, 0, 2, 1}, -7, 0, 3, 0},
    {{2, 0, 1, 0, 0}, 6, 0, 0, 0},
    {{-2, 0, 2, 2, 2}, 6, 0, -3, 0},
    {{-2, 0, 1, 2, 1}, 6, 0, -3, 0},
    {{2, 0, -2, 0, 1}, -6, 0, 3, 0},
    {{2, 0, 0, 0, 1}, -6, 0, 3, 0},
    {{0, -1, 1, 0, 0}, 5, 0, 0, 0},
    {{-2, -1, 0, 2, 1}, -5, 0, 3, 0},
    {{-2, 0, 0, 0, 1}, -5, 0, 3, 0},
    {{0, 0, 2, 2, 1}, -5, 0, 3, 0},
    {{-2, 0, 2, 0, 1}, 4, 0, 0, 0},
    {{-2, 1, 0, 2, 1}, 4, 0, 0, 0},
    {{0, 0, 1, -2, 0}, 4, 0, 0, 0},
    {{-1, 0, 1, 0, 0}, -4, 0, 0, 0},
    {{-2, 1, 0, 0, 0}, -4, 0, 0, 0},
    {{1, 0, 0, 0, 0}, -4, 0, 0, 0},
    {{0, 0, 1, 2, 0}, 3, 0, 0, 0},
    {{0, 0, -2, 2, 2}, -3, 0, 0, 0},
    {{-1, -1, 1, 0, 0}, -3, 0, 0, 0},
    {{0, 1, 1, 0, 0}, -3, 0, 0, 0},
    {{0, -1, 1, 2, 2}, -3, 0, 0, 0},
    {{2, -1, -1, 2, 2}, -3, 0, 0, 0},
    {{0, 0, 3, 2, 2}, -3, 0, 0, 0},
    {{2, -1, 0, 2, 2}, -3, 0, 0, 0}};

template <std::size_t N>
double series(const Term (&t)[N], double jme) {
    double s = 0.0;
    for (const Term& x : t) s += x.a * std::cos(x.b + x.c * jme);
    return s;
}

double wrap360(double deg) {
    double d = std::fmod(deg, 360.0);
    return d < 0 ? d + 360.0 : d;
}

double sind(double d) { return std::sin(deg2rad(d)); }
double cosd(double d) { return std::cos(deg2rad(d)); }
double tand(double d) { return std::tan(deg2rad(d)); }

// Julian Day of a calendar date with day fraction; Reda & Andreas (2004) eq. 4 (Meeus 1998
// eq. 7.1): Gregorian correction B = 2 - A + INT(A / 4) from 1582-10-15 on.
double julianDay(int year, int month, double day) {
    if (month <= 2) { year -= 1; month += 12; }
    double jd = std::floor(365.25 * (year + 4716.0)) + std::floor(30.6001 * (month + 1)) + day - 1524.5;
    if (jd > 2299160.0) {
        const double a = std::floor(year / 100.0);
        jd += 2.0 - a + std::floor(a / 4.0);
    }
    return jd;
}

void require(bool ok, const std::string& what) {
    if (!ok) throw InputError("solar position: " + what);
}

}  // namespace

double deltaTEstimate(double y) {
    // Espenak & Meeus (2006), NASA Five Millennium Canon of Solar Eclipses, section 2.6.
    if (y >= 1900 && y < 1920) {
        const double t = y - 1900;
        return -2.79 + 1.494119 * t - 0.0598939 * t * t + 0.0061966 * t * t * t - 0.000197 * t * t * t * t;
    }
    if (y >= 1920 && y < 1941) {
        const double t = y - 1920;
        return 21.20 + 0.84493 * t - 0.076100 * t * t + 0.0020936 * t * t * t;
    }
    if (y >= 1941 && y < 1961) {
        const double t = y - 1950;
        return 29.07 + 0.407 * t - t * t / 233.0 + t * t * t / 2547.0;
    }
    if (y >= 1961 && y < 1986) {
        const double t = y - 1975;
        return 45.45 + 1.067 * t - t * t / 260.0 - t * t * t / 718.0;
    }
    if (y >= 1986 && y < 2005) {
        const double t = y - 2000;
        return 63.86 + 0.3345 * t - 0.060374 * t * t + 0.0017275 * t * t * t + 0.000651814 * t * t * t * t +
               0.00002373599 * t * t * t * t * t;
    }
    if (y >= 2005 && y < 2050) {
        const double t = y - 2000;
        return 62.92 + 0.32217 * t + 0.005589 * t * t;
    }
    const double u = (y - 1820.0) / 100.0;
    if (y >= 2050 && y < 2150) return -20.0 + 32.0 * u * u - 0.5628 * (2150.0 - y);
    return -20.0 + 32.0 * u * u;
}

namespace {

// The steps of solarPosition: Reda & Andreas (2004), section 3, numbered as there. Each step
// records its results in the SolarPosition, where the later steps read them.

void checkSolarInput(const SolarPositionInput& in) {
    require(in.year >= -2000 && in.year <= 6000,
            fmt::format("year {} is outside the algorithm's valid range -2000..6000", in.year));
    require(in.month >= 1 && in.month <= 12, fmt::format("month {} is not in 1..12", in.month));
    {
        static constexpr int kDays[12] = {31, 29, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
        const bool leap = (in.year % 4 == 0 && in.year % 100 != 0) || in.year % 400 == 0 ||
                          (in.year < 1583 && in.year % 4 == 0);  // Julian calendar before 1583
        const int maxDay = in.month == 2 ? (leap ? 29 : 28) : kDays[(in.month - 1) % 12];
        require(in.day >= 1 && in.day <= maxDay,
                fmt::format("day {} does not exist in {:04d}-{:02d} (1..{})", in.day, in.year, in.month, maxDay));
    }
    require(in.hour >= 0 && in.hour <= 24, fmt::format("hour {} is not in 0..24", in.hour));
    require(in.minute >= 0 && in.minute <= 59, fmt::format("minute {} is not in 0..59", in.minute));
    require(in.second >= 0 && in.second < 61, fmt::format("second {} is not in [0, 61)", in.second));
    require(std::abs(in.timezoneHours) <= 18, fmt::format("timezone {} h is not in [-18, 18]", in.timezoneHours));
    require(std::abs(in.latitudeDeg) <= 90, fmt::format("latitude {} deg is not in [-90, 90]", in.latitudeDeg));
    require(std::abs(in.longitudeDeg) <= 180, fmt::format("longitude {} deg is not in [-180, 180] (east positive)", in.longitudeDeg));
    require(in.elevationM >= -6500000 && std::isfinite(in.elevationM), fmt::format("elevation {} m is invalid", in.elevationM));
    require(in.pressureMbar >= 0 && in.pressureMbar <= 5000, fmt::format("pressure {} mbar is not in [0, 5000]", in.pressureMbar));
    require(in.temperatureC > -273 && in.temperatureC <= 6000, fmt::format("temperature {} C is not in (-273, 6000]", in.temperatureC));
    require(std::abs(in.atmosRefractionDeg) <= 5, fmt::format("horizon refraction {} deg is not in [-5, 5]", in.atmosRefractionDeg));
}

struct TimeScales {
    double jd, jde;     // Julian Day, Julian Ephemeris Day
    double jc, jce;     // Julian century, Julian ephemeris century
    double jme;         // Julian ephemeris millennium
};

// 3.1 Time scales. The day fraction is UT: local time minus the zone offset.
TimeScales timeScales(const SolarPositionInput& in) {
    const double dayFrac = in.day + (in.hour - in.timezoneHours + (in.minute + in.second / 60.0) / 60.0) / 24.0;
    const double jd = julianDay(in.year, in.month, dayFrac);
    const double deltaT = std::isnan(in.deltaTSeconds)
                              ? deltaTEstimate(in.year + (in.month - 0.5) / 12.0)
                              : in.deltaTSeconds;
    const double jde = jd + deltaT / 86400.0;                 // eq. 5
    const double jc = (jd - 2451545.0) / 36525.0;             // eq. 6
    const double jce = (jde - 2451545.0) / 36525.0;           // eq. 7
    const double jme = jce / 10.0;                            // eq. 8
    return {jd, jde, jc, jce, jme};
}

// 3.2 Earth heliocentric longitude, latitude, radius vector (eqs. 9-12).
void heliocentricPosition(double jme, SolarPosition& out) {
    const double jme2 = jme * jme, jme3 = jme2 * jme, jme4 = jme3 * jme, jme5 = jme4 * jme;
    const double Lrad = (series(L0, jme) + series(L1, jme) * jme + series(L2, jme) * jme2 +
                         series(L3, jme) * jme3 + series(L4, jme) * jme4 + series(L5, jme) * jme5) / 1e8;
    out.heliocentricLongitude = wrap360(rad2deg(Lrad));
    out.heliocentricLatitude = rad2deg((series(B0, jme) + series(B1, jme) * jme) / 1e8);
    out.earthRadiusVectorAu = (series(R0, jme) + series(R1, jme) * jme + series(R2, jme) * jme2 +
                               series(R3, jme) * jme3 + series(R4, jme) * jme4) / 1e8;
}

// 3.4 Nutation (eqs. 15-23): fundamental arguments in degrees.
void nutation(double jce, SolarPosition& out) {
    const double jce2 = jce * jce, jce3 = jce2 * jce;
    const double X[5] = {
        297.85036 + 445267.111480 * jce - 0.0019142 * jce2 + jce3 / 189474.0,  // mean elongation Moon-Sun
        357.52772 + 35999.050340 * jce - 0.0001603 * jce2 - jce3 / 300000.0,   // mean anomaly Sun
        134.96298 + 477198.867398 * jce + 0.0086972 * jce2 + jce3 / 56250.0,   // mean anomaly Moon
        93.27191 + 483202.017538 * jce - 0.0036825 * jce2 + jce3 / 327270.0,   // Moon argument of latitude
        125.04452 - 1934.136261 * jce + 0.0020708 * jce2 + jce3 / 450000.0};   // Moon ascending node
    double dPsi = 0.0, dEps = 0.0;
    for (const NutationTerm& t : kNutation) {
        double arg = 0.0;
        for (int k = 0; k < 5; ++k) arg += X[k] * t.y[k];
        dPsi += (t.a + t.b * jce) * sind(arg);
        dEps += (t.c + t.d * jce) * cosd(arg);
    }
    out.nutationLongitude = dPsi / 36000000.0;  // 0.0001 arcsec -> degrees
    out.nutationObliquity = dEps / 36000000.0;
}

// 3.5 True obliquity of the ecliptic (eqs. 24-25, Laskar 1986 polynomial in arcsec).
void trueObliquity(double jme, SolarPosition& out) {
    const double U = jme / 10.0;
    const double eps0 = 84381.448 +
                        U * (-4680.93 + U * (-1.55 + U * (1999.25 + U * (-51.38 + U * (-249.67 +
                        U * (-39.05 + U * (7.12 + U * (27.87 + U * (5.79 + U * 2.45)))))))));
    out.trueObliquity = eps0 / 3600.0 + out.nutationObliquity;
}

// 3.3 and 3.6-3.10: the geocentric Sun, its apparent longitude and the sidereal time.
void geocentricSun(const TimeScales& ts, SolarPosition& out) {
    // 3.3 Geocentric longitude and latitude (eqs. 13-14).
    const double theta = wrap360(out.heliocentricLongitude + 180.0);
    const double beta = -out.heliocentricLatitude;
    const double dPsi = out.nutationLongitude, eps = out.trueObliquity;

    // 3.6-3.7 Aberration and apparent Sun longitude (eqs. 26-27).
    const double dTau = -20.4898 / (3600.0 * out.earthRadiusVectorAu);
    const double lambda = theta + dPsi + dTau;
    out.apparentSunLongitude = lambda;

    // 3.8 Apparent sidereal time at Greenwich (eqs. 28-29).
    const double jc = ts.jc;
    const double nu0 = wrap360(280.46061837 + 360.98564736629 * (ts.jd - 2451545.0) + 0.000387933 * jc * jc -
                               jc * jc * jc / 38710000.0);
    out.apparentSiderealTime = nu0 + dPsi * cosd(eps);

    // 3.9-3.10 Geocentric right ascension and declination (eqs. 30-31).
    out.geocentricRightAscension =
        wrap360(rad2deg(std::atan2(sind(lambda) * cosd(eps) - tand(beta) * sind(eps), cosd(lambda))));
    out.geocentricDeclination = rad2deg(std::asin(sind(beta) * cosd(eps) + cosd(beta) * sind(eps) * sind(lambda)));
}

// 3.11-3.12 The observer's hour angle, and the topocentric right ascension, declination and hour
// angle: parallax (eqs. 32-39).
void topocentricSun(const SolarPositionInput& in, SolarPosition& out) {
    const double lat = in.latitudeDeg, lon = in.longitudeDeg;
    const double alpha = out.geocentricRightAscension, delta = out.geocentricDeclination;
    // 3.11 Observer local hour angle, westward from south (eq. 32).
    const double H = wrap360(out.apparentSiderealTime + lon - alpha);
    out.observerHourAngle = H;

    // 3.12 Topocentric right ascension and declination: parallax (eqs. 33-38).
    const double xi = 8.794 / (3600.0 * out.earthRadiusVectorAu);
    const double u = std::atan(0.99664719 * tand(lat));  // rad
    const double x = std::cos(u) + in.elevationM / 6378140.0 * cosd(lat);
    const double y = 0.99664719 * std::sin(u) + in.elevationM / 6378140.0 * sind(lat);
    const double dAlpha = rad2deg(std::atan2(-x * sind(xi) * sind(H), cosd(delta) - x * sind(xi) * cosd(H)));
    out.topocentricRightAscension = alpha + dAlpha;
    out.topocentricDeclination = rad2deg(std::atan2((sind(delta) - y * sind(xi)) * cosd(dAlpha),
                                                    cosd(delta) - x * sind(xi) * cosd(H)));
    out.topocentricHourAngle = H - dAlpha;  // eq. 39
}

// 3.14-3.15 Topocentric elevation, zenith and azimuth.
void topocentricAngles(const SolarPositionInput& in, SolarPosition& out) {
    const double lat = in.latitudeDeg;
    const double deltaP = out.topocentricDeclination, Hp = out.topocentricHourAngle;
    // 3.14 Topocentric elevation without atmosphere, refraction, zenith (eqs. 40-44). The
    // correction applies only while the Sun is above -(solar radius 0.26667 + horizon refraction).
    const double e0 = rad2deg(std::asin(sind(lat) * sind(deltaP) + cosd(lat) * cosd(deltaP) * cosd(Hp)));
    double de = 0.0;
    if (in.applyRefraction && e0 >= -(0.26667 + in.atmosRefractionDeg))
        de = (in.pressureMbar / 1010.0) * (283.0 / (273.0 + in.temperatureC)) * 1.02 /
             (60.0 * tand(e0 + 10.3 / (e0 + 5.11)));
    out.refractionCorrection = de;
    out.elevationDeg = e0 + de;
    out.zenithDeg = 90.0 - out.elevationDeg;

    // 3.15 Topocentric azimuth: astronomers' (westward from south), then +180 for eastward from
    // north (eqs. 45-46).
    const double gamma = wrap360(rad2deg(std::atan2(sind(Hp), cosd(Hp) * sind(lat) - tand(deltaP) * cosd(lat))));
    out.azimuthDeg = wrap360(gamma + 180.0);
}

}  // namespace

SolarPosition solarPosition(const SolarPositionInput& in) {
    checkSolarInput(in);
    SolarPosition out;
    const TimeScales ts = timeScales(in);
    out.julianDay = ts.jd;
    out.julianEphemerisDay = ts.jde;
    heliocentricPosition(ts.jme, out);
    nutation(ts.jce, out);
    trueObliquity(ts.jme, out);
    geocentricSun(ts, out);
    topocentricSun(in, out);
    topocentricAngles(in, out);
    return out;
}

double irAzimuthFromCompass(double compassAzimuthDeg) {
    // Compass: 0 = north, 90 = east, clockwise. IR: 0 = +x (east), pi/2 = +y (north), counter-clockwise.
    double a = std::fmod(deg2rad(90.0 - compassAzimuthDeg), 2.0 * kPi);
    if (a < 0) a += 2.0 * kPi;
    return a;
}

double compassAzimuthFromIr(double irAzimuthRad) { return wrap360(90.0 - rad2deg(irAzimuthRad)); }

SunAnglesIr sunAnglesForIr(const SolarPosition& p) {
    return SunAnglesIr{deg2rad(p.zenithDeg), irAzimuthFromCompass(p.azimuthDeg)};
}

}  // namespace littoral
