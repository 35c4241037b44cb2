#pragma once
// Light sources of the "simple atmosphere" (Sec. 4.0): a solar disc and a uniform sky dome.
//
// Sun: a disc of angular half-width alpha (0.265 deg for the 0.53 deg sun) centred on the unit
// direction s toward the sun (zenith theta_s, azimuth phi_s counter-clockwise from +x east):
//   s = (sin theta_s cos phi_s, sin theta_s sin phi_s, cos theta_s).
// Its irradiance E_sun (W m^-2 um^-1, on a plane normal to the beam) is spread uniformly over
// the disc's exact cone solid angle Omega_sun = 2 pi (1 - cos alpha), so a ray that lands inside
// the disc sees radiance L_sun = E_sun / Omega_sun. This is the physically exact glint rule: a
// specular reflection (or refraction) that points into the disc returns r_f E_sun / Omega_sun.
// DIRSIG's Fresnel solver (Eq. 4.6) instead spreads the glint over the detector solid angle
// Omega_d, L = r_f E_sun / Omega_d; the two agree only when a pixel is larger than the sun,
// and the exact rule makes a glint's brightness independent of the sensor.
//
// Sky: uniform radiance L_sky over the upper hemisphere (z > 0); zero below the horizon (no
// ground beyond the scene). The downwelling irradiance of the sky alone is E_sky = pi L_sky;
// the thesis' "skyfraction" F_u maps to L_sky = F_u E_h / pi and E_sun = (1 - F_u) E_h / cos
// theta_s for a hemisphere irradiance E_h (the horizontal convention; skyFractionSplit below).
#include <vector>

#include "core/scene_ir.h"
#include "core/vec.h"
#include "render/spectral.h"

namespace littoral::render {

struct SunSource {
    bool enabled = false;
    Vec3 direction{0, 0, 1};     // unit, from the scene toward the sun
    double halfAngle = 0.0;      // rad
    double cosHalfAngle = 1.0;
    double solidAngle = 0.0;     // sr, 2 pi (1 - cos alpha)
    std::vector<double> irradiance;  // per render band, W m^-2 um^-1 normal to the beam

    // Is the unit direction w inside the solar disc?
    bool inDisc(const Vec3& w) const { return enabled && dot(w, direction) >= cosHalfAngle; }
    // Uniform direction over the disc (for soft shadows); pdf 1 / solidAngle.
    Vec3 sampleDirection(double u1, double u2) const;
};

struct SkySource {
    std::vector<double> radiance;  // per render band, W m^-2 sr^-1 um^-1, upper hemisphere
};

// Direction toward the sun from zenith and azimuth (radians; azimuth from +x toward +y).
Vec3 sunDirection(double zenith, double azimuth);

SunSource makeSun(const ir::Sun& sun, const std::vector<Band>& bands);
SkySource makeSky(const ir::Sky& sky, const std::vector<Band>& bands);

// The thesis' simple atmosphere: total horizontal irradiance E_h split by skyfraction F_u into a
// uniform sky of radiance F_u E_h / pi and a sun whose horizontal irradiance is (1 - F_u) E_h,
// i.e. beam-normal irradiance (1 - F_u) E_h / cos(theta_s) (scene files: sky.sun_plane:
// horizontal, the default; DIRSIG's Eq. 4.5 itself puts (1 - F_u) E_h normal to the beam, which
// scene files offer as sun_plane: normal, scenegen/scene_file.cpp).
struct SkyFractionSplit {
    double skyRadiance;
    double sunBeamIrradiance;
};
SkyFractionSplit skyFractionSplit(double Eh, double skyFraction, double sunZenith);

}  // namespace littoral::render
