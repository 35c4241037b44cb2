#include "render/bxdf.h"

#include <algorithm>
#include <cmath>

#include "core/units.h"
#include "render/sampling.h"

namespace littoral::render {

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

}  // namespace littoral::render
