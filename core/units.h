#pragma once
// Constants and unit conversions. Inside the code: metres, radians, micrometres for wavelength,
// W m^-2 sr^-1 um^-1 for spectral radiance. Degrees exist only at the user interface and are
// converted on the way in with deg2rad.
#include <numbers>

namespace littoral {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kInvPi = 1.0 / std::numbers::pi;
inline constexpr double kGravity = 9.80665;  // m s^-2, standard gravity

constexpr double deg2rad(double deg) { return deg * (kPi / 180.0); }
constexpr double rad2deg(double rad) { return rad * (180.0 / kPi); }
constexpr double nm2um(double nm) { return nm * 1e-3; }
constexpr double um2nm(double um) { return um * 1e3; }
constexpr double sqr(double x) { return x * x; }

}  // namespace littoral
