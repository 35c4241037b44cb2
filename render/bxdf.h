#pragma once
// Surface scattering: Fresnel optics and the BxDF interface every estimator uses.
//
// One interface (BxDF below): f, pdf, sample(wo, uc, u2, mode) and flags. The implementations are
// plain structs held in a std::variant (LambertianBxDF, DielectricBxDF; the rough Cox–Munk
// interface plugs in as one more alternative), so the per-sample hot path has no virtual calls.
// Transport code asks a BxDF for its flags (delta? transmissive?), never for the material type.
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
#include <type_traits>
#include <variant>

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

// Lambertian reflection with reflectance r (one band): f = r / pi, cosine-weighted sampling on the
// side of wo (two-sided).
struct LambertianBxDF {
    double r = 0;
    uint8_t flags() const { return kReflection | kDiffuse; }
    double f(const Vec3& wo, const Vec3& wi, TransportMode = TransportMode::Radiance) const;
    double pdf(const Vec3& wo, const Vec3& wi, TransportMode = TransportMode::Radiance) const;
    std::optional<BSDFSample> sample(const Vec3& wo, double uc, const Vec2& u,
                                     TransportMode = TransportMode::Radiance) const;
};

// Smooth dielectric interface between an outside medium (index nOut, the +z side) and an inside
// medium (nIn). f and pdf are zero (both lobes are Dirac deltas); sample() picks reflection with
// probability r_f and transmission with probability 1 - r_f (reflection only under total internal
// reflection); specularPair() returns both lobes for deterministic splitting.
struct DielectricBxDF {
    double nOut = 1.0, nIn = 1.34;
    uint8_t flags() const {
        return nOut == nIn ? uint8_t(kTransmission | kSpecular) : uint8_t(kReflection | kTransmission | kSpecular);
    }
    double f(const Vec3&, const Vec3&, TransportMode = TransportMode::Radiance) const { return 0.0; }
    double pdf(const Vec3&, const Vec3&, TransportMode = TransportMode::Radiance) const { return 0.0; }
    std::optional<BSDFSample> sample(const Vec3& wo, double uc, const Vec2& u = {},
                                     TransportMode mode = TransportMode::Radiance) const;
    // Both lobes; returns false for the transmission lobe under total internal reflection.
    bool specularPair(const Vec3& wo, TransportMode mode, BSDFSample* refl, BSDFSample* trans) const;
};

// The BxDF interface: a value holding one implementation. Directions are in the local frame of
// the surface (+z = outward normal). `isDelta()` BxDFs (smooth interfaces) have f = pdf = 0 and
// only sample(); `isSpecularPair()` ones can also hand both lobes at once for deterministic splits.
class BxDF {
public:
    using Variant = std::variant<LambertianBxDF, DielectricBxDF>;
    template <class T>
        requires std::is_constructible_v<Variant, T>
    BxDF(T b) : v_(std::move(b)) {}  // NOLINT: implicit from any implementation
    uint8_t flags() const {
        return std::visit([](const auto& b) { return b.flags(); }, v_);
    }
    bool isDelta() const { return flags() & kSpecular; }
    bool isTransmissive() const { return flags() & kTransmission; }
    bool isDiffuse() const { return flags() & kDiffuse; }
    double f(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
        return std::visit([&](const auto& b) { return b.f(wo, wi, mode); }, v_);
    }
    double pdf(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
        return std::visit([&](const auto& b) { return b.pdf(wo, wi, mode); }, v_);
    }
    std::optional<BSDFSample> sample(const Vec3& wo, double uc, const Vec2& u,
                                     TransportMode mode = TransportMode::Radiance) const {
        return std::visit([&](const auto& b) { return b.sample(wo, uc, u, mode); }, v_);
    }
    // Both specular lobes (smooth dielectric only); false if this BxDF has no such pair.
    bool specularPair(const Vec3& wo, TransportMode mode, BSDFSample* refl, BSDFSample* trans, bool* canTransmit) const {
        if (const auto* d = std::get_if<DielectricBxDF>(&v_)) {
            *canTransmit = d->specularPair(wo, mode, refl, trans);
            return true;
        }
        return false;
    }
    const Variant& variant() const { return v_; }

private:
    Variant v_;
};

}  // namespace littoral::render
