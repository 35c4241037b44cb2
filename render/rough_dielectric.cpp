#include "render/rough_dielectric.h"

#include <cmath>

#include <fmt/format.h>

#include "core/error.h"

namespace littoral::render {

RoughDielectricBxDF::RoughDielectricBxDF(double nOut_, double nIn_, CoxMunkDistribution slopes_,
                                         MicrofacetShadowing shadowing_)
    : nOut(nOut_), nIn(nIn_), slopes(std::move(slopes_)), shadowing(shadowing_) {
    if (!(nOut > 0) || !(nIn > 0) || !std::isfinite(nOut) || !std::isfinite(nIn))
        throw InputError(fmt::format("rough interface: refractive indices must be finite and > 0 (got {} and {})",
                                     nOut, nIn));
    if (std::abs(nOut - nIn) <= 1e-6)
        throw InputError(fmt::format("rough interface: the indices on its two sides are equal ({}); a rough interface "
                                     "needs different indices (else it refracts nothing)",
                                     nOut));
}

double RoughDielectricBxDF::G(const Vec3& wo, const Vec3& wi, const Vec3& h, TransportMode mode) const {
    switch (shadowing) {
    case MicrofacetShadowing::None: return 1.0;
    case MicrofacetShadowing::SmithLight:
        // The light arrives from wi on a camera path and from wo on a photon path.
        return slopes.G1(mode == TransportMode::Radiance ? wi : wo, h);
    case MicrofacetShadowing::SmithSeparable: return slopes.G1(wo, h) * slopes.G1(wi, h);  // Walter eq. 23
    }
    return 1.0;
}

RoughDielectricBxDF::Evaluation RoughDielectricBxDF::evaluate(const Vec3& wo, const Vec3& wi,
                                                              TransportMode mode) const {
    Evaluation e;
    if (wo.z == 0.0 || wi.z == 0.0) return e;
    const bool oAbove = wo.z > 0, iAbove = wi.z > 0;
    const double etaO = oAbove ? nOut : nIn;
    if (oAbove == iAbove) {
        // Reflection: h_r = normalize(wo + wi) (Walter eq. 13), turned to the upper hemisphere.
        Vec3 h = wo + wi;
        const double len = length(h);
        if (!(len > 0)) return e;
        h = h / len;
        if (h.z < 0) h = -h;
        if (!(h.z > 0)) return e;
        const double oh = dot(wo, h);  // = wi.h
        if (oh * wo.z <= 0) return e;  // the facet faces away from both directions
        const double F = fresnelDielectric(std::abs(oh), etaO, oAbove ? nIn : nOut);
        // Walter eq. 20 (digest Eq. 5.4 = this times cos(theta_i) with G = 1).
        e.f = F * slopes.D(h) * G(wo, wi, h, mode) / (4.0 * std::abs(wo.z) * std::abs(wi.z));
        // Sampling density: pdf(h) = D_gauss h.z, times the lobe choice F, times
        // d omega_h / d omega_i = 1 / (4 |wi.h|) (Walter eq. 14).
        e.pdf = slopes.gaussianD(h) * h.z * F / (4.0 * std::abs(oh));
        e.flags = kReflection | kGlossy;
        return e;
    }
    // Transmission: h_t = -(eta_o wo + eta_i wi), normalised, upper hemisphere (Walter eq. 16).
    const double etaI = iAbove ? nOut : nIn;
    Vec3 h = -(etaO * wo + etaI * wi);
    const double len = length(h);
    if (!(len > 0)) return e;
    h = h / len;
    if (h.z < 0) h = -h;
    if (!(h.z > 0)) return e;
    const double oh = dot(wo, h), ih = dot(wi, h);
    if (oh * wo.z <= 0 || ih * wi.z <= 0) return e;  // each direction on its own side of the facet
    const double F = fresnelDielectric(std::abs(oh), etaO, etaI);
    if (F >= 1.0) return e;
    // |eta_o wo.h + eta_i wi.h| = |eta_o wo + eta_i wi| >= |eta_o - eta_i| > 0.
    const double denom = etaO * oh + etaI * ih;
    const double denom2 = denom * denom;
    // Walter eq. 21 in Radiance mode (eta_o^2: the n^2 law); eta_i^2 for the adjoint (Importance).
    const double scale = mode == TransportMode::Radiance ? etaO * etaO : etaI * etaI;
    e.f = std::abs(ih) * std::abs(oh) / (std::abs(wi.z) * std::abs(wo.z)) * scale * (1.0 - F) *
          G(wo, wi, h, mode) * slopes.D(h) / denom2;
    // pdf(h) (1 - F) d omega_h / d omega_i, with d omega_h / d omega_i = eta_i^2 |wi.h| / denom^2
    // (Walter eq. 17).
    e.pdf = slopes.gaussianD(h) * h.z * (1.0 - F) * etaI * etaI * std::abs(ih) / denom2;
    e.flags = kTransmission | kGlossy;
    e.etap = etaI / etaO;
    return e;
}

double RoughDielectricBxDF::f(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
    return evaluate(wo, wi, mode).f;
}

double RoughDielectricBxDF::pdf(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
    return evaluate(wo, wi, mode).pdf;
}

std::optional<BSDFSample> RoughDielectricBxDF::sample(const Vec3& wo, double uc, const Vec2& u,
                                                      TransportMode mode) const {
    if (wo.z == 0.0) return std::nullopt;
    const Vec3 h = slopes.sampleNormal(u);
    const double oh = dot(wo, h);
    if (oh * wo.z <= 0) return std::nullopt;  // a facet seen from behind: no interaction
    const bool oAbove = wo.z > 0;
    const double etaO = oAbove ? nOut : nIn, etaT = oAbove ? nIn : nOut;
    const double F = fresnelDielectric(std::abs(oh), etaO, etaT);
    Vec3 wi;
    if (uc < F) {
        wi = reflect(wo, h);
        if (wi.z * wo.z <= 0) return std::nullopt;  // reflected into the wrong hemisphere
    } else {
        // Snell at the facet (refract() wants the normal on wo's side).
        if (!refract(wo, oh > 0 ? h : -h, etaO / etaT, &wi)) return std::nullopt;
        if (wi.z * wo.z >= 0) return std::nullopt;  // refracted back to wo's side of the macrosurface
    }
    // f and pdf from the pair itself, so that sample() and pdf() agree to the last bit.
    const Evaluation e = evaluate(wo, wi, mode);
    if (!(e.pdf > 0)) return std::nullopt;
    BSDFSample s;
    s.f = e.f;
    s.wi = wi;
    s.pdf = e.pdf;
    s.flags = e.flags;
    s.etap = e.etap;
    return s;
}

std::optional<Vec3> RoughDielectricBxDF::sampleTransmission(const Vec3& wo, const Vec2& u) const {
    if (wo.z == 0.0) return std::nullopt;
    const Vec3 h = slopes.sampleNormal(u);
    const double oh = dot(wo, h);
    if (oh * wo.z <= 0) return std::nullopt;
    const bool oAbove = wo.z > 0;
    const double etaO = oAbove ? nOut : nIn, etaT = oAbove ? nIn : nOut;
    Vec3 wi;
    if (!refract(wo, oh > 0 ? h : -h, etaO / etaT, &wi)) return std::nullopt;
    if (wi.z * wo.z >= 0) return std::nullopt;
    if (!(pdfTransmission(wo, wi) > 0)) return std::nullopt;  // the same conditions as the density
    return wi;
}

double RoughDielectricBxDF::pdfTransmission(const Vec3& wo, const Vec3& wi) const {
    if (wo.z == 0.0 || wi.z == 0.0 || (wo.z > 0) == (wi.z > 0)) return 0.0;
    const bool oAbove = wo.z > 0;
    const double etaO = oAbove ? nOut : nIn, etaI = oAbove ? nIn : nOut;
    Vec3 h = -(etaO * wo + etaI * wi);
    const double len = length(h);
    if (!(len > 0)) return 0.0;
    h = h / len;
    if (h.z < 0) h = -h;
    if (!(h.z > 0)) return 0.0;
    const double oh = dot(wo, h), ih = dot(wi, h);
    if (oh * wo.z <= 0 || ih * wi.z <= 0) return 0.0;
    if (fresnelDielectric(std::abs(oh), etaO, etaI) >= 1.0) return 0.0;  // total internal reflection
    const double denom = etaO * oh + etaI * ih;
    // Walter et al. (2007) eq. 17: d omega_h / d omega_i = eta_i^2 |wi.h| / denom^2.
    return slopes.gaussianD(h) * h.z * etaI * etaI * std::abs(ih) / (denom * denom);
}

}  // namespace littoral::render
