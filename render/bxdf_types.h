#pragma once
// The vocabulary every BxDF shares: transport mode, lobe flags, the sample record and the Fresnel
// reflectance of a smooth dielectric boundary. Conventions are stated in render/bxdf.h; this
// header exists so that BxDF implementations in their own files (render/rough_dielectric.h) and
// the BxDF variant in render/bxdf.h can both use them.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/bxdf_flags.h"
#include "core/vec.h"

namespace littoral::render {

enum class TransportMode { Radiance, Importance };

// The lobe flags (core/bxdf_flags.h), also as render::kReflection, ...
using ::littoral::BxDFFlags;
using enum ::littoral::BxDFFlags;

struct BSDFSample {
    double f = 0;      // sr^-1 (per band group: the same for all bands of a group)
    Vec3 wi;
    double pdf = 0;    // sr^-1, or the discrete probability of a specular lobe
    uint8_t flags = 0;
    double etap = 1;   // n_t / n_o for transmission (relative index across the boundary), else 1
    bool isSpecular() const { return flags & kSpecular; }
    bool isTransmission() const { return flags & kTransmission; }
};

// Unpolarised Fresnel reflectance for light in a medium of index n1 meeting a medium of index n2
// at incidence cosine cosI in (0, 1]. Eq. 4.2 written with the s and p amplitude coefficients:
// r_f = (r_s^2 + r_p^2) / 2, which equals (1/2)[sin^2(ti - tr)/sin^2(ti + tr) +
// tan^2(ti - tr)/tan^2(ti + tr)] with Snell's law (Eq. 4.1) n1 sin ti = n2 sin tr, and stays
// finite at normal incidence (Eq. 4.3). Returns 1 beyond the critical angle (total internal
// reflection). T_f = 1 - r_f: the interface absorbs nothing.
inline double fresnelDielectric(double cosI, double n1, double n2) {
    cosI = std::clamp(cosI, 0.0, 1.0);
    const double eta = n1 / n2;
    const double sin2T = eta * eta * std::max(0.0, 1.0 - cosI * cosI);  // Snell, Eq. 4.1
    if (sin2T >= 1.0) return 1.0;                                       // total internal reflection
    const double cosT = std::sqrt(1.0 - sin2T);
    const double rs = (n1 * cosI - n2 * cosT) / (n1 * cosI + n2 * cosT);
    const double rp = (n2 * cosI - n1 * cosT) / (n2 * cosI + n1 * cosT);
    return 0.5 * (rs * rs + rp * rp);
}

}  // namespace littoral::render
