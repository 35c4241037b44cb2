// The `path` estimator: an unbiased volumetric path tracer, the reference the dissertation's
// solvers and the photon maps are checked against (docs/rendering.md, "The path estimator").
//
// Radiance along a ray in a medium is the integral of in-scattered radiance weighted by the
// transmittance, plus the transmitted radiance of whatever ends the segment (the RTE). Sunlight
// enters the water along one known direction (refracted through the facet above), so the
// estimator connects to the sun deterministically wherever light can scatter ("next-event
// estimation"), and samples everything else:
//  1. On the first two segments of a path (from the sensor or probe, and from the first scattering
//     vertex: seen from depth, the sunlit water near the surface is far away along an upward ray,
//     and upwelling light at depth is mostly diffuse light scattered near the surface and then
//     back up), sunlight scattered once is estimated at points spread along the whole segment
//     ("marching"). The points come from two strategies, each stratified into
//     K = ceil(length / march_step) strata (at most 16): distances proportional to the
//     transmittance from the segment's start, and, on rising segments, distances uniform over the
//     segment (where the sun grows brighter toward the surface). They are combined by the
//     multi-sample balance heuristic (Veach 1997, Sec. 9.2). An infinite segment is cut where the
//     optical depth of every scattering band exceeds 40 (relative bias below e^-40 = 4e-18).
//  2. A scattering event is sampled by free flight (Medium::sampleFreeFlight) and the path goes on
//     in a direction sampled from the phase function. At every later scattering event the sun is
//     estimated once at the event itself (the classic collision estimator).
// Either way a ray leaving a scattering event does not count the solar disc along the chains the
// sun estimate covers (SunChain), so nothing is counted twice. Diffuse surfaces get the sun by
// next-event estimation and continue by BxDF sampling; delta interfaces split into both Fresnel
// lobes for the first few events and then choose one. Russian roulette on the throughput after
// three scattering vertices keeps the estimate unbiased.
#include <algorithm>
#include <cmath>

#include "core/frame.h"
#include "core/stats.h"
#include "core/units.h"
#include "render/estimator.h"
#include "render/sampling.h"

namespace littoral::render {

namespace {

constexpr double kTauCut = 40.0;  // optical depth beyond which an infinite segment is cut
constexpr int kMaxSunPoints = 16;
// Segments (counted from the sensor or probe) whose single scattering is estimated by marching;
// two cover the light scattered twice on its way down and up (upwelling radiance at depth is
// mostly backscattered diffuse light that was scattered near the surface).
constexpr int kMarchedSegments = 2;

class PathEstimator final : public Estimator {
public:
    PathEstimator(const Scene& scene, const RenderConfig& config, BandGroup group)
        : Estimator(scene, config, group) {}

    Spec Li(const Ray& ray, int medium, RandomStream& rng) const override {
        Walk w;
        w.splits = 3;
        return trace(ray, medium, SunChain{}, w, rng);
    }
    Spec LiIndirect(const Ray& ray, int medium, RandomStream& rng) const override {
        Walk w;
        w.splits = 1;
        return trace(ray, medium, SunChain::afterVertex(), w, rng);
    }

private:
    // Counters along a path. The first `splits` delta-interface events trace both the reflected
    // and the refracted ray with their Fresnel weights (splitting: unbiased, and smooth water is
    // rendered without noise); later ones choose one by Fresnel probability.
    struct Walk {
        int vertices = 0, specular = 0, wraps = 0, splits = 0;
    };
    Spec trace(Ray ray, int medium, SunChain chain, Walk w, RandomStream& rng) const;
    // Single-scattered sunlight along ray.o + t ray.d, t in [0, tMax), in `medium` (part 1 above).
    Spec sunInScatter(const Ray& ray, double tMax, int medium, RandomStream& rng) const;
};

Spec PathEstimator::sunInScatter(const Ray& ray, double tMax, int medium, RandomStream& rng) const {
    const int nb = group_.count;
    Spec L(nb);
    if (!scene_.sun().enabled) return L;
    const Medium& md = scene_.media()[medium];
    // Reference extinction: the smallest c of a scattering band over the layers (the cut length
    // must cover every band that can scatter).
    double cRef = ir::kInfinity, cMean = 0;
    for (const MediumLayer& l : md.layers())
        for (int i = 0; i < nb; ++i)
            if (l.b[group_.begin + i] > 0) cRef = std::min(cRef, l.c[group_.begin + i]);
    if (!std::isfinite(cRef)) return L;  // nothing scatters in these bands
    {
        const Spec c0 = md.c(md.layerAt(ray.o.z), group_);
        for (int i = 0; i < nb; ++i) cMean += c0[i];
        cMean /= nb;
    }
    const double tEnd = std::min(tMax, kTauCut / cRef);
    if (!(tEnd > 0)) return L;
    const int K = std::clamp(static_cast<int>(std::ceil(tEnd / config_.marchStep)), 1, kMaxSunPoints);
    // The uniform strategy only on rising rays: along a level or sinking ray the sun's beam weakens
    // as fast as the transmittance from the start, which strategy A follows already. (Choosing the
    // strategies from the ray, not from random numbers, keeps the estimate unbiased.)
    const int strategies = ray.d.z > 0 ? 2 : 1;
    // Strategy A: exponential with rate cMean truncated to [0, tEnd]; strategy B: uniform.
    const double massA = -std::expm1(-cMean * tEnd);  // 1 - exp(-c tEnd)
    auto pdfA = [&](double t) { return cMean > 0 ? cMean * std::exp(-cMean * t) / massA : 1.0 / tEnd; };
    const double pdfB = strategies == 2 ? 1.0 / tEnd : 0.0;
    auto sampleA = [&](double u) {
        return cMean > 0 ? std::min(tEnd, -std::log1p(-u * massA) / cMean) : u * tEnd;
    };
    for (int strategy = 0; strategy < strategies; ++strategy) {
        for (int k = 0; k < K; ++k) {
            const double u = (k + rng.uniform()) / K;
            const double t = strategy == 0 ? sampleA(u) : u * tEnd;
            const double denom = K * (pdfA(t) + pdfB);
            const Point3 x = ray.at(t);
            const SunBeam sun = sunBeam(x, Normal3{0, 0, 0}, Vec3{0, 0, 0}, medium, rng);
            if (!sun.valid || !(denom > 0)) continue;
            const int layer = md.layerAt(x.z);
            // Light travelling along -toSun scatters into -ray.d (toward the ray's origin).
            const Spec p = md.phase(layer, group_, -sun.toSun, -ray.d);
            L += md.transmittance(ray, t, group_) * md.b(layer, group_) * p * sun.E * (1.0 / denom);
        }
    }
    return L;
}

Spec PathEstimator::trace(Ray ray, int medium, SunChain chain, Walk w, RandomStream& rng) const {
    const int nb = group_.count;
    Spec L(nb), beta(nb, 1.0);
    int& vertices = w.vertices;
    int& specular = w.specular;
    int& wraps = w.wraps;
    for (;;) {
        SurfaceHit h;
        const bool hit = scene_.geometry().intersect(ray, &h);
        const Medium& md = scene_.media()[medium];
        if (md.scattering()) {
            const double tMax = hit ? h.t : ir::kInfinity;
            // Segments that start at the sensor/probe or at the first scattering vertex are marched;
            // later ones get the collision estimate at their end (vertices counts the vertices so far).
            const bool marched = vertices < kMarchedSegments;
            if (marched) L += beta * sunInScatter(ray, tMax, medium, rng);
            const double uBand = rng.uniform(), uDist = rng.uniform();
            const FreeFlight ff = md.sampleFreeFlight(ray, tMax, group_, uBand, uDist);
            beta *= ff.weight;
            if (ff.scattered) {
                if (beta.isBlack() || ++vertices > config_.maxBounces) break;
                const Point3 x = ray.at(ff.t);
                if (!marched) {
                    // Collision estimator of the sun scattered here toward the previous vertex.
                    const SunBeam sun = sunBeam(x, Normal3{0, 0, 0}, Vec3{0, 0, 0}, medium, rng);
                    if (sun.valid) L += beta * md.phase(ff.layer, group_, -sun.toSun, -ray.d) * sun.E;
                } else {
                    rng.uniform(), rng.uniform();
                }
                Spec w;
                const Vec3 wi = md.samplePhase(ff.layer, group_, ray.d, rng, &w);
                beta *= w;
                ray = Ray{x, wi};
                chain = SunChain::afterVertex();
                if (vertices > 3) {  // Russian roulette
                    const double q = std::min(1.0, beta.maxValue());
                    if (rng.uniform() >= q) break;
                    beta *= 1.0 / q;
                } else {
                    rng.uniform();  // keep the stream layout independent of the depth
                }
                continue;
            }
            if (beta.isBlack()) break;
        } else if (md.attenuating()) {
            if (!hit) break;  // an infinite path through absorbing water carries nothing
            beta *= md.transmittance(ray, h.t, group_);
        }
        if (!hit) {
            L += beta * environment(ray.d, chain.countsSun());
            break;
        }
        const MaterialData& m = scene_.material(h);
        if (m.isPeriodicWall()) {
            const auto next = scene_.wrapRay(h, ray.d);
            if (!next || ++wraps > Scene::kMaxWraps) break;
            ray = *next;
            continue;
        }
        const BxDF bxdf = scene_.bxdf(h, group_);
        if (bxdf.isDelta()) {
            if (++specular > config_.maxSpecularDepth) break;
            const Frame frame = Frame::fromNormal(h.ng);
            const Vec3 wo = frame.toLocal(-ray.d);
            const double uc = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
            if (std::abs(wo.z) < 1e-12) {  // tangent: continues unchanged (see the dirsig estimator)
                chain.reflected = true;
                ray = spawnRay(h.p, h.ng, ray.d);
                medium = scene_.nearMedium(h);
                continue;
            }
            BSDFSample r, t;
            bool canTransmit = false;
            if (w.splits > 0 && bxdf.specularPair(wo, TransportMode::Radiance, &r, &t, &canTransmit)) {
                Walk w2 = w;
                --w2.splits;
                SunChain cr = chain, ct = chain;
                cr.reflected = true;
                ++ct.transmissions;
                const double wr = r.f * std::abs(r.wi.z);
                if (wr > 0)
                    L += beta * trace(spawnRay(h.p, h.ng, frame.toWorld(r.wi)), scene_.nearMedium(h), cr, w2, rng) * wr;
                if (canTransmit) {
                    const double wt = t.f * std::abs(t.wi.z);
                    if (wt > 0)
                        L += beta * trace(spawnRay(h.p, h.ng, frame.toWorld(t.wi)), scene_.farMedium(h), ct, w2, rng) *
                             wt;
                }
                break;
            }
            const auto s = bxdf.sample(wo, uc, Vec2{u1, u2}, TransportMode::Radiance);
            if (!s || s->pdf <= 0) break;
            beta *= s->f * std::abs(s->wi.z) / s->pdf;
            if (s->isTransmission()) {
                ++chain.transmissions;
                medium = scene_.farMedium(h);
            } else {
                chain.reflected = true;
                medium = scene_.nearMedium(h);
            }
            ray = spawnRay(h.p, h.ng, frame.toWorld(s->wi));
            continue;
        }
        // Diffuse surface.
        const Spec rho = scene_.albedo(h, group_);
        if (rho.isBlack()) break;
        if (++vertices > config_.maxBounces) break;
        const Normal3 n = h.front ? h.ng : -h.ng;
        const SunBeam sun = sunBeam(h.p, h.ng, n, medium, rng);
        if (sun.valid) L += beta * rho * sun.E * (std::max(0.0, dot(sun.toSun, n)) * kInvPi);
        const Frame frame = Frame::fromNormal(n);
        const double u1 = rng.uniform(), u2 = rng.uniform();
        const auto bs = bxdf.sample(frame.toLocal(-ray.d), 0.5, Vec2{u1, u2});
        if (!bs || bs->pdf <= 0) break;
        beta *= rho * (bs->f * std::abs(bs->wi.z) / bs->pdf);
        ray = spawnRay(h.p, h.ng, frame.toWorld(bs->wi));
        chain = SunChain::afterVertex();
        if (vertices > 3) {
            const double q = std::min(1.0, beta.maxValue());
            if (rng.uniform() >= q) break;
            beta *= 1.0 / q;
        } else {
            rng.uniform();
        }
    }
    return L;
}

}  // namespace

std::unique_ptr<Estimator> makePathEstimator(const Scene& scene, const RenderConfig& config, BandGroup group) {
    return std::make_unique<PathEstimator>(scene, config, group);
}

}  // namespace littoral::render
