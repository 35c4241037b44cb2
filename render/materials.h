#pragma once
// Surface scattering: Fresnel optics and the BxDFs the radiometry solvers use.
//
// BSDF convention (pbrt-v4): directions live in a local shading frame whose +z is the surface
// normal on the *outside* of the surface; wo (toward the viewer or the previous vertex) and wi
// (toward the light) both point away from the surface. f(wo, wi) is the BSDF in sr^-1,
// pdf(wo, wi) the sampling density per unit solid angle, and sample(wo, u) returns the triple
// (f, wi, pdf) plus flags; specular lobes return pdf = 1 for a Dirac delta and f already
// divided by |cos(theta_i)| so that f |cos| / pdf is the lobe weight. TransportMode tells
// radiance (camera paths) from importance (photon paths): the (eta)^2 radiance scaling at a
// refracting boundary (the n^2 law) applies only to radiance.
#include <cstdint>
#include <optional>

#include "core/vec.h"

namespace littoral::render {

enum class TransportMode { Radiance, Importance };

enum BxDFFlags : uint8_t {
    kReflection = 1,
    kTransmission = 2,
    kDiffuse = 4,
    kSpecular = 8,
};

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
double fresnelDielectric(double cosI, double n1, double n2);

// Lambertian reflection with reflectance r (one band): f = r / pi, cosine-weighted sampling.
struct LambertianBxDF {
    double r = 0;
    double f(const Vec3& wo, const Vec3& wi) const;
    double pdf(const Vec3& wo, const Vec3& wi) const;
    std::optional<BSDFSample> sample(const Vec3& wo, double u1, double u2) const;
};

// Smooth dielectric interface between an outside medium (index nOut, the +z side) and an inside
// medium (nIn). f and pdf are zero (both lobes are Dirac deltas); sample() picks reflection with
// probability r_f and transmission with probability 1 - r_f (reflection only under total internal
// reflection); specularPair() returns both lobes for deterministic splitting.
struct DielectricBxDF {
    double nOut = 1.0, nIn = 1.34;
    double f(const Vec3&, const Vec3&) const { return 0.0; }
    double pdf(const Vec3&, const Vec3&) const { return 0.0; }
    std::optional<BSDFSample> sample(const Vec3& wo, double u, TransportMode mode) const;
    // Both lobes; returns false for the transmission lobe under total internal reflection.
    bool specularPair(const Vec3& wo, TransportMode mode, BSDFSample* refl, BSDFSample* trans) const;
};

}  // namespace littoral::render
