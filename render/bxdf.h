#pragma once
// Surface scattering: Fresnel optics and the BxDF interface every estimator uses.
//
// One interface (BxDF below): f, pdf, sample(wo, uc, u2, mode) and flags. The implementations are
// plain structs held in a std::variant (LambertianBxDF, DielectricBxDF, and the rough Cox–Munk
// interface RoughDielectricBxDF of render/rough_dielectric.h), so the per-sample hot path has no
// virtual calls. Transport code asks a BxDF for its flags (delta? transmissive? glossy?), never
// for the material type. The shared types (TransportMode, flags, BSDFSample, fresnelDielectric)
// are in render/bxdf_types.h.
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
#include "render/bxdf_types.h"
#include "render/rough_dielectric.h"

namespace littoral::render {

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

// Inline: both run once per interface event.
inline bool DielectricBxDF::specularPair(const Vec3& wo, TransportMode mode, BSDFSample* refl, BSDFSample* trans) const {
    const bool outside = wo.z > 0;
    const double nO = outside ? nOut : nIn, nT = outside ? nIn : nOut;
    const double cosO = std::abs(wo.z);
    const double R = fresnelDielectric(cosO, nO, nT);
    refl->wi = Vec3{-wo.x, -wo.y, wo.z};
    refl->f = R / cosO;
    refl->pdf = 1.0;
    refl->flags = kReflection | kSpecular;
    refl->etap = 1.0;
    Vec3 wt;
    const Vec3 n{0, 0, outside ? 1.0 : -1.0};
    if (R >= 1.0 || !refract(wo, n, nO / nT, &wt)) return false;
    const double cosT = std::abs(wt.z);
    // n^2 law: radiance crossing from index n_t into n_o scales by (n_o / n_t)^2 (radiance / n^2
    // is invariant along a ray, Sec. 4.0), on top of the Fresnel transmittance T_f = 1 - r_f.
    const double radianceScale = mode == TransportMode::Radiance ? (nO / nT) * (nO / nT) : 1.0;
    trans->wi = wt;
    trans->f = (1.0 - R) * radianceScale / cosT;
    trans->pdf = 1.0;
    trans->flags = kTransmission | kSpecular;
    trans->etap = nT / nO;
    return true;
}

inline std::optional<BSDFSample> DielectricBxDF::sample(const Vec3& wo, double u, const Vec2&,
                                                       TransportMode mode) const {
    BSDFSample r, t;
    const bool canTransmit = specularPair(wo, mode, &r, &t);
    if (!canTransmit) return r;  // TIR: reflection with probability 1 (f |cos| = 1)
    const double R = r.f * std::abs(wo.z);
    if (u < R) {
        r.pdf = R;
        return r;
    }
    t.pdf = 1.0 - R;
    return t;
}

// The BxDF interface: a value holding one implementation. Directions are in the local frame of
// the surface (+z = outward normal). `isDelta()` BxDFs (smooth interfaces) have f = pdf = 0 and
// only sample(); `isSpecularPair()` ones can also hand both lobes at once for deterministic splits.
// `isGlossy()` ones (the rough interface) have real f and pdf on both sides of the surface and
// suit next-event estimation combined with BSDF sampling.
class BxDF {
public:
    using Variant = std::variant<LambertianBxDF, DielectricBxDF, RoughDielectricBxDF>;
    template <class T>
        requires std::is_constructible_v<Variant, T>
    BxDF(T b) : v_(std::move(b)) {}  // NOLINT: implicit from any implementation
    uint8_t flags() const {
        return std::visit([](const auto& b) { return b.flags(); }, v_);
    }
    bool isDelta() const { return flags() & kSpecular; }
    bool isTransmissive() const { return flags() & kTransmission; }
    bool isDiffuse() const { return flags() & kDiffuse; }
    bool isGlossy() const { return flags() & kGlossy; }
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
