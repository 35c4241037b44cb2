#include "render/sources.h"

#include <cmath>

#include <fmt/format.h>

#include "core/error.h"
#include "core/frame.h"
#include "core/units.h"
#include "render/sampling.h"

namespace littoral::render {

Vec3 sunDirection(double zenith, double azimuth) {
    const double s = std::sin(zenith);
    return {s * std::cos(azimuth), s * std::sin(azimuth), std::cos(zenith)};
}

Vec3 SunSource::sampleDirection(double u1, double u2) const {
    const Frame f = Frame::fromNormal(direction);
    return normalize(f.toWorld(sampleUniformCone(u1, u2, cosHalfAngle)));
}

SunSource makeSun(const ir::Sun& sun, const std::vector<Band>& bands) {
    SunSource s;
    if (!(sun.halfAngle > 0 && sun.halfAngle < 0.5 * kPi))
        throw InputError(fmt::format("sun.half_angle_rad: {} rad must lie in (0, pi/2)", sun.halfAngle));
    if (!(sun.zenith >= 0 && sun.zenith <= kPi))
        throw InputError(fmt::format("sun.zenith_rad: {} rad must lie in [0, pi]", sun.zenith));
    s.direction = sunDirection(sun.zenith, sun.azimuth);
    s.halfAngle = sun.halfAngle;
    s.cosHalfAngle = std::cos(sun.halfAngle);
    s.solidAngle = 2.0 * kPi * (1.0 - s.cosHalfAngle);
    s.irradiance = sun.irradiance.bandAverages(bands, "sun.irradiance");
    bool any = false;
    for (double e : s.irradiance) {
        if (!(e >= 0)) throw InputError("sun.irradiance: negative or non-finite value");
        any |= e > 0;
    }
    s.enabled = sun.enabled && any;
    return s;
}

SkySource makeSky(const ir::Sky& sky, const std::vector<Band>& bands) {
    SkySource s;
    s.radiance = sky.radiance.bandAverages(bands, "sky.radiance");
    for (double l : s.radiance)
        if (!(l >= 0)) throw InputError("sky.radiance: negative or non-finite value");
    return s;
}

SkyFractionSplit skyFractionSplit(double Eh, double skyFraction, double sunZenith) {
    const double c = std::cos(sunZenith);
    return {skyFraction * Eh * kInvPi, c > 0 ? (1.0 - skyFraction) * Eh / c : 0.0};
}

}  // namespace littoral::render
