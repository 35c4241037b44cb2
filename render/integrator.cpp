#include "render/integrator.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/frame.h"
#include "core/units.h"
#include "render/sampling.h"

namespace littoral::render {

std::vector<BandGroup> bandGroups(const Scene& scene) {
    std::vector<BandGroup> groups;
    const int nb = scene.bandCount();
    auto sameIndex = [&](int a, int b) {
        for (const MediumData& m : scene.media())
            if (m.n[a] != m.n[b]) return false;
        return true;
    };
    int b = 0;
    while (b < nb) {
        BandGroup g{b, 1};
        while (b + g.count < nb && g.count < kMaxGroupBands && sameIndex(b, b + g.count)) ++g.count;
        groups.push_back(g);
        b += g.count;
    }
    return groups;
}

Integrator::Integrator(const Scene& scene, BandGroup group)
    : scene_(scene), group_(group), maxBounces_(scene.ir().render.maxBounces),
      maxSpecular_(scene.ir().render.maxSpecularDepth), hemisphereSamples_(scene.ir().render.hemisphereSamples) {
    LITTORAL_CHECK(group.count >= 1 && group.count <= kMaxGroupBands);
    LITTORAL_CHECK(group.begin >= 0 && group.begin + group.count <= scene.bandCount());
    if (maxBounces_ < 0) throw InputError("render.maxBounces must be >= 0");
    if (maxSpecular_ < 0) throw InputError("render.maxSpecularDepth must be >= 0");
    if (hemisphereSamples_ < 1) throw InputError("render.hemisphereSamples must be >= 1");
}

Spec Integrator::bandValues(const std::vector<double>& v) const {
    Spec s(group_.count);
    for (int i = 0; i < group_.count; ++i) s[i] = v[group_.begin + i];
    return s;
}

Spec Integrator::environment(const Vec3& d, bool withSun) const {
    Spec L(group_.count);
    if (d.z > 0) L = bandValues(scene_.sky().radiance);
    const SunSource& sun = scene_.sun();
    if (withSun && sun.inDisc(d)) {
        // Uniform disc radiance L_sun = E_sun / Omega_sun (exact cone solid angle).
        for (int i = 0; i < group_.count; ++i) L[i] += sun.irradiance[group_.begin + i] / sun.solidAngle;
    }
    return L;
}

Spec Integrator::mediumSegment(const Ray& ray, double t, int medium, RandomStream& rng, Spec* inScatter) const {
    const MediumData& m = scene_.media()[medium];
    if (!m.attenuating) return Spec(group_.count, 1.0);
    if (!std::isfinite(t)) return Spec(group_.count, 0.0);
    // Beer–Lambert, Eq. 2.4: every scattering event counts as a loss here; in-scatter is added
    // by a volume photon map (not yet present), which leaves *inScatter at zero.
    (void)ray;
    (void)rng;
    (void)inScatter;
    return beerLambert(bandValues(m.c), t);
}

Spec Integrator::sunIrradiance(const Point3& p, const Normal3& ng, const Normal3& n, int medium,
                               RandomStream& rng, bool scalar) const {
    Spec E(group_.count);
    const SunSource& sun = scene_.sun();
    // Draw the two numbers unconditionally so the random stream layout does not depend on
    // geometry (keeps neighbouring pixels' streams aligned).
    const double u1 = rng.uniform(), u2 = rng.uniform();
    if (!sun.enabled) return E;
    const Vec3 ws = sun.sampleDirection(u1, u2);  // uniform over the disc, pdf 1 / Omega_sun
    const MediumData& md = scene_.media()[medium];
    const double nm = md.n[group_.begin];
    if (nm == 1.0 && !md.attenuating) {
        // In air: straight shadow ray. E = E_sun cos(theta) (plane) or E_sun (scalar).
        const double c = dot(ws, n);
        if (c <= 0 || scene_.geometry().occluded(spawnRay(p, ng, ws))) return E;
        for (int i = 0; i < group_.count; ++i) E[i] = sun.irradiance[group_.begin + i] * (scalar ? 1.0 : c);
        return E;
    }
    // In a denser medium: the sun refracted through the interface above. The direction in the
    // medium that a horizontal interface refracts toward ws (Snell, Eq. 4.1, air index 1):
    Vec3 wt;
    if (!refract(ws, Vec3{0, 0, 1}, 1.0 / nm, &wt)) return E;
    const Vec3 up = normalize(-wt);
    const double cRecv = dot(up, n);
    if (cRecv <= 0) return E;
    SurfaceHit h;
    const Ray toSurface = spawnRay(p, ng, up);
    if (!scene_.geometry().intersect(toSurface, &h)) return E;
    const MaterialData& m = scene_.materials()[scene_.materialIndex(h)];
    if (!m.isSpecularInterface()) return E;
    const int mNear = h.front ? scene_.outsideMedium(h.mesh) : scene_.insideMedium(h.mesh);
    const int mFar = h.front ? scene_.insideMedium(h.mesh) : scene_.outsideMedium(h.mesh);
    if (mNear != medium) return E;
    const MediumData& far = scene_.media()[mFar];
    if (far.attenuating) return E;
    const double nFar = far.n[group_.begin];
    const Normal3 nf = h.front ? h.ng : -h.ng;  // facet normal on the medium side
    const double cosW = std::abs(dot(up, nf));
    Vec3 out;
    if (!refract(-up, nf, nm / nFar, &out)) return E;  // TIR at this facet
    out = normalize(out);
    if (!sun.inDisc(out)) return E;                     // a tilted facet sends it elsewhere
    if (scene_.geometry().occluded(spawnRay(h.p, h.ng, out))) return E;
    const double cosA = std::abs(dot(out, nf));
    const double T = 1.0 - fresnelDielectric(cosW, nm, nFar);
    // Radiance in the medium T (nm/nFar)^2 L_sun over a solid angle compressed by
    // (nFar/nm)^2 cos(theta_far)/cos(theta_medium): beam irradiance E_sun T cosA / cosW.
    const Spec atten = beerLambert(bandValues(md.c), h.t);
    const double geom = T * cosA / cosW * (scalar ? 1.0 : cRecv);
    for (int i = 0; i < group_.count; ++i) E[i] = sun.irradiance[group_.begin + i] * geom * atten[i];
    return E;
}

Spec Integrator::Li(const Ray& ray, const PathState& st, RandomStream& rng) const {
    SurfaceHit h;
    if (!scene_.geometry().intersect(ray, &h)) {
        // An infinitely long path through an attenuating medium carries nothing.
        if (scene_.media()[st.medium].attenuating) return Spec(group_.count);
        return environment(ray.d, st.sunVisible());
    }
    const MaterialData& m = scene_.materials()[scene_.materialIndex(h)];
    // The segment's medium: an interface knows its own sides (trusted over the carried medium);
    // an opaque surface is reached through whatever medium the ray carries.
    const int segMedium =
        m.isSpecularInterface() ? (h.front ? scene_.outsideMedium(h.mesh) : scene_.insideMedium(h.mesh)) : st.medium;
    Spec Lsurf(group_.count);
    if (m.isSpecularInterface()) {
        Lsurf = shadeInterface(ray, h, segMedium, st, rng);
    } else if (m.type != ir::Material::Type::Black && !st.skyOnly) {
        PathState s2 = st;
        s2.medium = segMedium;
        Lsurf = shadeDiffuse(h, -ray.d, m, s2, rng);
    }
    // Nothing to attenuate and no in-scatter source yet: skip the segment (a volume photon map
    // will have to gather in-scatter here even in front of a black surface).
    if (Lsurf.isBlack()) return Lsurf;
    Spec inScatter(group_.count);
    Spec Tr = mediumSegment(ray, h.t, segMedium, rng, &inScatter);
    Tr *= Lsurf;
    Tr += inScatter;
    return Tr;
}

Spec Integrator::shadeInterface(const Ray& ray, const SurfaceHit& h, int mIncident, const PathState& st,
                                RandomStream& rng) const {
    Spec L(group_.count);
    if (st.specularDepth >= maxSpecular_) return L;
    const int mIn = scene_.insideMedium(h.mesh), mOut = scene_.outsideMedium(h.mesh);
    const int mOther = h.front ? mIn : mOut;
    const double nOut = scene_.media()[mOut].n[group_.begin];
    const double nIn = scene_.media()[mIn].n[group_.begin];

    PathState next = st;
    next.specularDepth = st.specularDepth + 1;

    if (nOut == nIn) {
        // Index-matched boundary (e.g. between two water bodies): no reflection, no bending.
        next.medium = mOther;
        return Li(spawnRay(h.p, h.ng, ray.d), next, rng);
    }
    const Frame frame = Frame::fromNormal(h.ng);  // +z on the mesh's outside
    const Vec3 wo = frame.toLocal(-ray.d);
    if (std::abs(wo.z) < 1e-12) {
        // Exactly tangent to the face: r_f = 1 at grazing incidence and the mirror direction is
        // the ray's own, so it continues unchanged (the Fresnel weights would be 0 * inf).
        next.reflected = true;
        next.medium = mIncident;
        return Li(spawnRay(h.p, h.ng, ray.d), next, rng);
    }
    const DielectricBxDF bxdf{nOut, nIn};

    auto follow = [&](const BSDFSample& s, double weight, PathState ps) {
        ps.medium = s.isTransmission() ? mOther : mIncident;
        if (s.isTransmission()) ++ps.transmissions;
        else ps.reflected = true;
        const Vec3 wi = frame.toWorld(s.wi);  // orthonormal frame: unit to rounding
        return Li(spawnRay(h.p, h.ng, wi), ps, rng) * weight;
    };
    if (st.splits > 0) {
        // Deterministic split: L = r_f L_r + T_f (n_o/n_t)^2 L_t (Eq. 4.2 weights, n^2 law).
        next.splits = st.splits - 1;
        BSDFSample r, t;
        const bool canTransmit = bxdf.specularPair(wo, TransportMode::Radiance, &r, &t);
        const double wr = r.f * std::abs(r.wi.z);
        if (wr > 0) L += follow(r, wr, next);
        if (canTransmit) {
            const double wt = t.f * std::abs(t.wi.z);
            if (wt > 0) L += follow(t, wt, next);
        }
        return L;
    }
    const auto s = bxdf.sample(wo, rng.uniform(), TransportMode::Radiance);
    if (!s || s->pdf <= 0) return L;
    return follow(*s, s->f * std::abs(s->wi.z) / s->pdf, next);
}

Spec Integrator::shadeDiffuse(const SurfaceHit& h, const Vec3& wo_world, const MaterialData& m,
                              const PathState& st, RandomStream& rng) const {
    const int nb = group_.count;
    Spec L(nb);
    if (st.diffuseDepth >= maxBounces_) return L;
    Spec rho = bandValues(m.reflectance);
    if (m.texture) rho *= m.texture->lookup(h.p.x, h.p.y);
    if (rho.isBlack()) return L;
    // Shade the side the ray arrived on (surfaces are two-sided).
    const Normal3 n = h.front ? h.ng : -h.ng;

    // Direct sun: Lambertian radiance r E_sun cos(theta_s) / pi.
    Spec Es = sunIrradiance(h.p, h.ng, n, st.medium, rng);
    L += rho * Es * kInvPi;

    // Sky (Classic) or sky plus background (Generic): cosine-weighted hemisphere sampling, for
    // which f cos / pdf = (r/pi) cos / (cos/pi) = r per sample.
    const bool classic = m.solver == ir::Material::Solver::Classic;
    PathState next;
    next.medium = st.medium;
    next.diffuseDepth = st.diffuseDepth + 1;
    next.specularDepth = st.specularDepth;
    next.splits = 1;
    next.fromSensor = false;
    next.reflected = false;
    next.transmissions = 0;
    next.skyOnly = classic;
    // The first diffuse vertex of a path integrates its hemisphere with N stratified rays; deeper
    // vertices (reached through another diffuse vertex) use one ray, so a path tree grows
    // linearly, not as N^depth.
    const int count = st.diffuseDepth == 0 ? hemisphereSamples_ : 1;
    const Frame frame = Frame::fromNormal(n);
    Spec sum(nb);
    if (classic) {
        // Fixed stratified skydome: one jittered ray per equal-projected-solid-angle quad.
        const StratifiedLayout layout(count);
        for (int k = 0; k < count; ++k) {
            const Vec2 u = layout.point(k, rng.uniform(), rng.uniform());
            const Vec3 w = frame.toWorld(sampleCosineHemisphere(u.x, u.y));
            sum += Li(spawnRay(h.p, h.ng, w), next, rng);
        }
    } else {
        // Monte Carlo: independent samples of the BSDF's own importance sampling (the BxDF
        // triple; a microfacet or Ward BxDF plugs in here). Weight f |cos| / pdf.
        const LambertianBxDF bxdf{1.0};  // reflectance applied per band below
        const Vec3 wo = frame.toLocal(wo_world);
        for (int k = 0; k < count; ++k) {
            const double u1 = rng.uniform(), u2 = rng.uniform();
            const auto bs = bxdf.sample(wo, u1, u2);
            if (!bs || bs->pdf <= 0) continue;
            const double weight = bs->f * std::abs(bs->wi.z) / bs->pdf;
            sum += Li(spawnRay(h.p, h.ng, frame.toWorld(bs->wi)), next, rng) * weight;
        }
    }
    L += rho * sum * (1.0 / count);
    return L;
}

}  // namespace littoral::render
