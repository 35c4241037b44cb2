#include "render/bxdf.h"

#include <algorithm>
#include <cmath>

#include "core/units.h"
#include "render/sampling.h"

namespace littoral::render {

double fresnelDielectric(double cosI, double n1, double n2) {
    cosI = std::clamp(cosI, 0.0, 1.0);
    const double eta = n1 / n2;
    const double sin2T = eta * eta * std::max(0.0, 1.0 - cosI * cosI);  // Snell, Eq. 4.1
    if (sin2T >= 1.0) return 1.0;                                       // total internal reflection
    const double cosT = std::sqrt(1.0 - sin2T);
    const double rs = (n1 * cosI - n2 * cosT) / (n1 * cosI + n2 * cosT);
    const double rp = (n2 * cosI - n1 * cosT) / (n2 * cosI + n1 * cosT);
    return 0.5 * (rs * rs + rp * rp);
}

double LambertianBxDF::f(const Vec3& wo, const Vec3& wi, TransportMode) const {
    return (wo.z > 0) == (wi.z > 0) ? r * kInvPi : 0.0;
}

double LambertianBxDF::pdf(const Vec3& wo, const Vec3& wi, TransportMode) const {
    return (wo.z > 0) == (wi.z > 0) ? std::abs(wi.z) * kInvPi : 0.0;
}

std::optional<BSDFSample> LambertianBxDF::sample(const Vec3& wo, double, const Vec2& u, TransportMode) const {
    Vec3 wi = sampleCosineHemisphere(u.x, u.y);
    if (wo.z < 0) wi.z = -wi.z;
    if (wi.z == 0) return std::nullopt;
    BSDFSample s;
    s.f = r * kInvPi;
    s.wi = wi;
    s.pdf = std::abs(wi.z) * kInvPi;
    s.flags = kReflection | kDiffuse;
    return s;
}

bool DielectricBxDF::specularPair(const Vec3& wo, TransportMode mode, BSDFSample* refl, BSDFSample* trans) const {
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

std::optional<BSDFSample> DielectricBxDF::sample(const Vec3& wo, double u, const Vec2&, TransportMode mode) const {
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

}  // namespace littoral::render
