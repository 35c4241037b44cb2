#include "render/interaction.h"

#include <cmath>

#include <fmt/format.h>

#include "core/error.h"

namespace littoral::render {

InteractionStep::Numbers InteractionStep::draw(RandomStream& rng, bool ucLast) {
    Numbers n;
    if (ucLast) {
        n.u.x = rng.uniform();
        n.u.y = rng.uniform();
        n.uc = rng.uniform();
    } else {
        n.uc = rng.uniform();
        n.u.x = rng.uniform();
        n.u.y = rng.uniform();
    }
    return n;
}

InteractionStep::InteractionStep(const Scene& scene, BandGroup group, TransportMode mode, const SunConnection* sun,
                                 int maxSpecular, InterfaceDraws draws)
    : scene_(scene), group_(group), mode_(mode), sun_(sun), maxSpecular_(maxSpecular), draws_(draws) {}

std::optional<Ray> InteractionStep::wrap(const SurfaceHit& h, const Vec3& d, int* wraps) const {
    const auto next = scene_.wrapRay(h, d);
    if (!next || *wraps >= Scene::kMaxWraps) return std::nullopt;
    ++*wraps;
    return next;
}

bool InteractionStep::intoSky(const SurfaceHit& h) const { return sun_ && sun_->skyMedium(scene_.farMedium(h)); }

void InteractionStep::requireDiffuse(const BxDF& bxdf) {
    if (!bxdf.isDiffuse())
        throw InternalError(fmt::format("a BxDF with flags {:#x} reached a diffuse-vertex solver; transport has no "
                                        "rule for it",
                                        bxdf.flags()));
}

Interaction InteractionStep::atInterface(const Ray& ray, const SurfaceHit& h, const BxDF& bxdf, const SunChain& chain,
                                         int* specular, int splits, RandomStream& rng, Spec* sun) const {
    if (bxdf.isGlossy() && sun) *sun = Spec(group_.count);  // the sun estimate below, if any, replaces it
    if (*specular >= maxSpecular_) return Interaction{};
    ++*specular;
    const Frame frame = scene_.shadingFrame(h);  // +z on the mesh's outside
    const Vec3 wo = frame.toLocal(-ray.d);
    if (std::abs(wo.z) < 1e-12) {
        // Exactly tangent to the face: r_f = 1 at grazing incidence and the mirror direction is the
        // ray's own, so it continues unchanged (the Fresnel weights would be 0 * inf).
        Interaction it;
        it.kind = Interaction::Kind::Continued;
        it.out[0].ray = spawnRay(h.p, h.ng, ray.d);
        it.out[0].medium = scene_.nearMedium(h);
        it.out[0].chain = chain;
        it.out[0].chain.reflected = true;
        return it;
    }
    if (bxdf.isGlossy()) {
        // Rough interface: the sun by next-event estimation on the air side (MIS against BSDF
        // sampling; radiance paths only), then one direction sampled from the microfacet BxDF.
        int neeSide = 0;
        if (sun && sun_) *sun = sun_->atGlossyHit(h, frame, bxdf, wo, chain, rng, &neeSide);
        return sampled(h, frame, bxdf, wo, chain, neeSide, draw(rng, false));
    }
    std::optional<Numbers> n;
    if (splits > 0 && draws_.whenSplitting) n = draw(rng, draws_.deltaUcLast);
    BSDFSample r, t;
    bool canTransmit = false;
    if (splits > 0 && bxdf.specularPair(wo, mode_, &r, &t, &canTransmit)) return split(h, frame, wo, r, t, canTransmit, chain);
    if (!n) n = draw(rng, draws_.deltaUcLast);
    return sampled(h, frame, bxdf, wo, chain, 0, *n);
}

Interaction InteractionStep::split(const SurfaceHit& h, const Frame& frame, const Vec3& wo, const BSDFSample& r,
                                   const BSDFSample& t, bool canTransmit, const SunChain& chain) const {
    // Deterministic split: L = r_f L_r + T_f (n_o/n_t)^2 L_t (Eq. 4.2 weights, n^2 law).
    Interaction it;
    it.kind = Interaction::Kind::Split;
    it.out[0] = {spawnRay(h.p, h.ng, frame.toWorld(r.wi)), scene_.nearMedium(h), chain, r.f * std::abs(r.wi.z)};
    it.out[0].chain.record(false, false, false, 0.0);
    it.out[1].weight = 0;
    if (canTransmit) {
        it.out[1] = {spawnRay(h.p, h.ng, frame.toWorld(t.wi)), scene_.farMedium(h), chain, t.f * std::abs(t.wi.z)};
        it.out[1].chain.record(true, false, intoSky(h), frame.toWorld(-wo).z);
    }
    return it;
}

Interaction InteractionStep::sampled(const SurfaceHit& h, const Frame& frame, const BxDF& bxdf, const Vec3& wo,
                                     const SunChain& chain, int neeSide, const Numbers& n) const {
    const bool glossy = bxdf.isGlossy();
    const auto s = bxdf.sample(wo, n.uc, n.u, mode_);
    Interaction it;
    if (!s || !(s->pdf > 0)) return it;
    it.kind = Interaction::Kind::Continued;
    Continuation& c = it.out[0];
    c.medium = s->isTransmission() ? scene_.farMedium(h) : scene_.nearMedium(h);
    c.weight = s->f * std::abs(s->wi.z) / s->pdf;
    // The frame is orthonormal, so toWorld keeps unit length to rounding; glossy directions are
    // renormalised (they feed the next event's MIS densities).
    const Vec3 wi = frame.toWorld(s->wi);
    c.ray = spawnRay(h.p, h.ng, glossy ? normalize(wi) : wi);
    const bool toSky = s->isTransmission() && intoSky(h);
    const double legZ = frame.toWorld(-wo).z;  // the arriving ray's direction
    if (glossy && sun_) {
        c.chain = sun_->chainAfterGlossy(chain, *s, neeSide, toSky, legZ);
    } else {
        c.chain = chain;
        c.chain.glossyPdf = 0;
        c.chain.record(s->isTransmission(), glossy, toSky, legZ);
    }
    return it;
}

}  // namespace littoral::render
