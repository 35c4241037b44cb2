// The `dirsig` estimator: recursive ray tracing with the dissertation's per-material radiometry
// solvers (Table 10.4), chosen per material by RenderConfig::solvers.
//
//  * Fresnel (delta interfaces): specular reflection and refraction with unpolarised Fresnel
//    weights r_f and T_f = 1 - r_f (Eq. 4.2), Snell directions (Eq. 4.1), total internal
//    reflection, and the n^2 radiance law. The first `splits` interface events of a path trace
//    both lobes (deterministic, noise-free images of smooth water); later events choose one lobe
//    with probability r_f (unbiased).
//  * Classic (diffuse): direct sun by next-event estimation plus the sky seen over a stratified
//    jittered skydome of mu x phi equal-projected-solid-angle quads, one ray per quad: the
//    fraction of quad rays that reach the sky is the visible sky fraction F of Eq. 6.1. Sky rays
//    pass through interfaces but any opaque surface they meet contributes 0.
//  * Generic (diffuse): the same sun term plus Monte Carlo sampling of the BxDF, rays that reach
//    other surfaces recursing (background reflections). The first diffuse vertex of a path shoots
//    `hemisphereSamples` rays, deeper vertices one each; at most `maxBounces` diffuse vertices
//    per path (DIRSIG GRS semantics: 0 -> black, 1 -> sky fraction only, 2 -> plus the
//    neighbours' sky fraction, ...).
//  * Media attenuate every segment by exp(-Int c ds), c = a + b (Eq. 2.4): scattering counts as
//    loss (the dissertation's behaviour without a volume photon map).
#include <algorithm>
#include <cmath>

#include "core/frame.h"
#include "core/units.h"
#include "render/estimator.h"
#include "render/sampling.h"

namespace littoral::render {

namespace {

struct PathState {
    int medium = 0;        // index into Scene::media of the medium the ray travels in
    int diffuseDepth = 0;  // diffuse vertices already on the path
    int specularDepth = 0; // interface events already on the path
    int splits = 0;        // remaining deterministic two-lobe Fresnel splits
    int wraps = 0;         // periodic-wall crossings
    SunChain chain;
    bool skyOnly = false;  // Classic sky rays: opaque surfaces contribute 0
};

class DirsigEstimator final : public Estimator {
public:
    DirsigEstimator(const Scene& scene, const RenderConfig& config, BandGroup group)
        : Estimator(scene, config, group) {}

    Spec Li(const Ray& ray, int medium, RandomStream& rng) const override {
        PathState st;
        st.medium = medium;
        st.splits = 3;
        return trace(ray, st, rng);
    }
    Spec LiIndirect(const Ray& ray, int medium, RandomStream& rng) const override {
        PathState st;
        st.medium = medium;
        st.splits = 1;
        st.chain = SunChain::afterVertex();
        return trace(ray, st, rng);
    }

private:
    Spec trace(const Ray& ray, const PathState& st, RandomStream& rng) const;
    Spec shadeInterface(const Ray& ray, const SurfaceHit& h, const BxDF& bxdf, const PathState& st,
                        RandomStream& rng) const;
    Spec shadeDiffuse(const SurfaceHit& h, const Vec3& wo, const PathState& st, RandomStream& rng) const;
};

Spec DirsigEstimator::trace(const Ray& ray, const PathState& st, RandomStream& rng) const {
    SurfaceHit h;
    const Medium& medium = scene_.media()[st.medium];
    if (!scene_.geometry().intersect(ray, &h)) {
        // An infinitely long path through an attenuating medium carries nothing.
        if (medium.attenuating()) return Spec(group_.count);
        return environment(ray.d, st.chain.countsSun());
    }
    const MaterialData& m = scene_.material(h);
    if (m.isPeriodicWall()) {
        const auto next = scene_.wrapRay(h, ray.d);
        if (!next || st.wraps >= Scene::kMaxWraps) return Spec(group_.count);
        PathState s2 = st;
        ++s2.wraps;
        return trace(*next, s2, rng) * medium.transmittance(ray, h.t, group_);
    }
    // The segment's medium: an interface knows its own sides (trusted over the carried medium);
    // an opaque surface is reached through whatever medium the ray carries.
    const BxDF bxdf = scene_.bxdf(h, group_);
    const int segMedium = bxdf.isTransmissive() ? scene_.nearMedium(h) : st.medium;
    Spec Lsurf(group_.count);
    if (bxdf.isDelta()) {
        PathState s2 = st;
        s2.medium = segMedium;
        Lsurf = shadeInterface(ray, h, bxdf, s2, rng);
    } else if (!st.skyOnly) {
        PathState s2 = st;
        s2.medium = segMedium;
        Lsurf = shadeDiffuse(h, -ray.d, s2, rng);
    }
    if (Lsurf.isBlack()) return Lsurf;
    return Lsurf * scene_.media()[segMedium].transmittance(ray, h.t, group_);
}

Spec DirsigEstimator::shadeInterface(const Ray& ray, const SurfaceHit& h, const BxDF& bxdf, const PathState& st,
                                     RandomStream& rng) const {
    Spec L(group_.count);
    if (st.specularDepth >= config_.maxSpecularDepth) return L;
    const int mOther = scene_.farMedium(h);
    PathState next = st;
    next.specularDepth = st.specularDepth + 1;

    const Frame frame = Frame::fromNormal(h.ng);  // +z on the mesh's outside
    const Vec3 wo = frame.toLocal(-ray.d);
    if (std::abs(wo.z) < 1e-12) {
        // Exactly tangent to the face: r_f = 1 at grazing incidence and the mirror direction is
        // the ray's own, so it continues unchanged (the Fresnel weights would be 0 * inf).
        next.chain.reflected = true;
        return trace(spawnRay(h.p, h.ng, ray.d), next, rng);
    }
    auto follow = [&](const BSDFSample& s, double weight, PathState ps) {
        ps.medium = s.isTransmission() ? mOther : st.medium;
        if (s.isTransmission()) ++ps.chain.transmissions;
        else ps.chain.reflected = true;
        const Vec3 wi = frame.toWorld(s.wi);  // orthonormal frame: unit to rounding
        return trace(spawnRay(h.p, h.ng, wi), ps, rng) * weight;
    };
    BSDFSample r, t;
    bool canTransmit = false;
    if (st.splits > 0 && bxdf.specularPair(wo, TransportMode::Radiance, &r, &t, &canTransmit)) {
        // Deterministic split: L = r_f L_r + T_f (n_o/n_t)^2 L_t (Eq. 4.2 weights, n^2 law).
        next.splits = st.splits - 1;
        const double wr = r.f * std::abs(r.wi.z);
        if (wr > 0) L += follow(r, wr, next);
        if (canTransmit) {
            const double wt = t.f * std::abs(t.wi.z);
            if (wt > 0) L += follow(t, wt, next);
        }
        return L;
    }
    const auto s = bxdf.sample(wo, rng.uniform(), Vec2{rng.uniform(), rng.uniform()}, TransportMode::Radiance);
    if (!s || s->pdf <= 0) return L;
    return follow(*s, s->f * std::abs(s->wi.z) / s->pdf, next);
}

Spec DirsigEstimator::shadeDiffuse(const SurfaceHit& h, const Vec3& woWorld, const PathState& st,
                                   RandomStream& rng) const {
    const int nb = group_.count;
    Spec L(nb);
    if (st.diffuseDepth >= config_.maxBounces) return L;
    const Spec rho = scene_.albedo(h, group_);
    if (rho.isBlack()) return L;
    // Shade the side the ray arrived on (surfaces are two-sided).
    const Normal3 n = h.front ? h.ng : -h.ng;

    // Direct sun: Lambertian radiance r E_sun cos(theta_s) / pi.
    const SunBeam sun = sunBeam(h.p, h.ng, n, st.medium, rng);
    if (sun.valid) L += rho * sun.E * (std::max(0.0, dot(sun.toSun, n)) * kInvPi);

    // Sky (Classic) or sky plus background (Generic): BxDF importance sampling, for which
    // f cos / pdf = (r/pi) cos / (cos/pi) = r per sample for the Lambertian.
    const bool classic = config_.solvers[scene_.materialIndex(h)] == ir::Material::Solver::Classic;
    PathState next;
    next.medium = st.medium;
    next.diffuseDepth = st.diffuseDepth + 1;
    next.specularDepth = st.specularDepth;
    next.splits = 1;
    next.wraps = st.wraps;
    next.chain = SunChain::afterVertex();
    next.skyOnly = classic;
    // The first diffuse vertex of a path integrates its hemisphere with N stratified rays; deeper
    // vertices use one ray, so a path tree grows linearly, not as N^depth.
    const int count = st.diffuseDepth == 0 ? config_.hemisphereSamples : 1;
    const Frame frame = Frame::fromNormal(n);
    const BxDF bxdf = scene_.bxdf(h, group_);
    const Vec3 wo = frame.toLocal(woWorld);
    Spec sum(nb);
    if (classic) {
        // Fixed stratified skydome: one jittered ray per equal-projected-solid-angle quad.
        const StratifiedLayout layout(count);
        for (int k = 0; k < count; ++k) {
            const Vec2 u = layout.point(k, rng.uniform(), rng.uniform());
            const Vec3 w = frame.toWorld(sampleCosineHemisphere(u.x, u.y));
            sum += trace(spawnRay(h.p, h.ng, w), next, rng);
        }
    } else {
        for (int k = 0; k < count; ++k) {
            const double u1 = rng.uniform(), u2 = rng.uniform();
            const auto bs = bxdf.sample(wo, 0.5, Vec2{u1, u2});
            if (!bs || bs->pdf <= 0) continue;
            const double weight = bs->f * std::abs(bs->wi.z) / bs->pdf;
            sum += trace(spawnRay(h.p, h.ng, frame.toWorld(bs->wi)), next, rng) * weight;
        }
    }
    L += rho * sum * (1.0 / count);
    return L;
}

}  // namespace

std::unique_ptr<Estimator> makeDirsigEstimator(const Scene& scene, const RenderConfig& config, BandGroup group) {
    return std::make_unique<DirsigEstimator>(scene, config, group);
}

}  // namespace littoral::render
