// Estimator::LiParts: a sensor ray's radiance split by where it meets the sea surface
// (RadianceParts, render/estimator.h), and Ed(0+) at that point.
//
// The split is made at the first event only, and it follows Li exactly: the ray is walked through
// periodic walls to its first surface; if that is the sea surface seen from the air, the event is
// the estimator's own interaction step (the same random numbers, the same splits) and each
// continuation is traced by the estimator as Li would trace it (continuePath). So the parts add up
// to Li for the same ray and stream (to the rounding of a different order of summation):
//  * the transmitted continuation is the water-leaving radiance;
//  * a rough interface's sun estimate is glint;
//  * a reflected continuation that escapes is split into the solar disc it meets (glint, with the
//    chain's MIS weight) and the sky (sky-reflected); one that meets a surface (another wave, an
//    object) is sky-reflected as a whole.
// Any other first surface, or none, leaves the whole radiance in `other`.
//
// Ed(0+) is the irradiance on a horizontal plane at the sea point: the sun from a uniformly drawn
// point of the disc, E_sun cos, and the sky from one cosine-distributed direction, pi L_sky, each
// counted when a straight ray upward reaches the sky past everything but the sea surface (a ship
// shadows it; the sea's own crests do not, as Ed(0+) is defined on a plane over the mean surface).
#include <cmath>

#include "core/error.h"
#include "core/frame.h"
#include "core/stats.h"
#include "core/units.h"
#include "render/estimator.h"
#include "render/sampling.h"

namespace littoral::render {

namespace {

constexpr int kMaxSeaCrossings = 64;  // sea-surface facets an upward Ed(0+) ray may pass

bool isSeaSurface(const Scene& scene, const SurfaceHit& h, int water) {
    if (water < 0 || !scene.material(h).isInterface()) return false;
    const int a = scene.nearMedium(h), b = scene.farMedium(h);
    return (a == 0 && b == water) || (a == water && b == 0);
}

// From p (on the sea surface) along d (upward): does the ray reach the sky past periodic walls and
// sea-surface facets only?
bool reachesSky(const Scene& scene, int water, const Point3& p, const Vec3& d) {
    Ray r;
    r.o = p;
    r.d = d;
    int wraps = 0;
    for (int k = 0; k < kMaxSeaCrossings;) {
        SurfaceHit h;
        if (!scene.geometry().intersect(r, &h)) return true;
        if (scene.isPeriodicWall(h)) {
            const auto next = scene.wrapRay(h, r.d);
            if (!next || ++wraps > Scene::kMaxWraps) return false;
            r = *next;
            continue;
        }
        if (!isSeaSurface(scene, h, water)) return false;
        r = spawnRay(h.p, dot(h.ng, d) > 0 ? h.ng : -h.ng, d);
        ++k;
    }
    return false;
}

// Ed(0+) on the horizontal plane at the sea point p (four numbers, drawn after the radiance's).
Spec ed0At(const Scene& scene, const SunConnection& sun, BandGroup group, int water, const Point3& p, RandomStream& rng) {
    Spec E(group.count);
    const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform(), u4 = rng.uniform();
    const SunSource& s = scene.sun();
    if (s.enabled) {
        const Vec3 ws = s.sampleDirection(u1, u2);
        if (ws.z > 0 && reachesSky(scene, water, p, ws))
            for (int b = 0; b < group.count; ++b) E[b] += s.irradiance[group.begin + b] * ws.z;
    }
    const Vec3 wsky = sampleCosineHemisphere(u3, u4);  // about +z: pdf cos / pi
    if (wsky.z > 0 && reachesSky(scene, water, p, wsky)) E += sun.environment(wsky, false) * kPi;
    return E;
}

}  // namespace

int waterMediumIndex(const Scene& scene) {
    for (size_t m = 1; m < scene.media().size(); ++m)
        if (scene.media()[m].name() == "water") return static_cast<int>(m);
    return scene.media().size() > 1 ? 1 : -1;
}

bool isSeaSurface(const Scene& scene, const SurfaceHit& h) { return isSeaSurface(scene, h, waterMediumIndex(scene)); }

bool seaBelow(const Scene& scene, const Point3& p) {
    Ray r;
    r.o = p;
    r.d = {0, 0, -1};
    SurfaceHit h;
    for (int wraps = 0; scene.geometry().intersect(r, &h); ++wraps) {
        if (!scene.isPeriodicWall(h)) return isSeaSurface(scene, h) && scene.nearMedium(h) == 0;
        const auto next = scene.wrapRay(h, r.d);
        if (!next || wraps > Scene::kMaxWraps) return false;
        r = *next;
    }
    return false;
}

bool Estimator::walkWalls(Ray* ray, SurfaceHit* h, int* wraps, Spec* T) const {
    const bool airAttenuates = scene_.media()[0].attenuating();
    bool found = scene_.geometry().intersect(*ray, h);
    while (found && scene_.isPeriodicWall(*h)) {
        const auto next = interactionStep().wrap(*h, ray->d, wraps);
        if (!next) return true;  // a wall the path cannot pass: Li ends it there
        if (airAttenuates) *T *= sun_.transmittance(*ray, h->t, 0);
        *ray = *next;
        found = scene_.geometry().intersect(*ray, h);
    }
    if (found && airAttenuates) *T *= sun_.transmittance(*ray, h->t, 0);
    return found;
}

RadianceParts Estimator::LiParts(const Ray& ray0, int medium, RandomStream& rng) const {
    if (medium != 0) throw InternalError("Estimator::LiParts: the sensor is not in the air");
    const int nb = group_.count;
    RadianceParts parts(nb);
    const int water = waterMediumIndex(scene_);
    const bool airAttenuates = scene_.media()[0].attenuating();
    // The first surface through periodic walls (Li's walk in the air: no in-scatter there).
    Ray ray = ray0;
    SurfaceHit h;
    Spec T(nb, 1.0);
    int wraps = 0;
    bool found = walkWalls(&ray, &h, &wraps, &T);
    if (!found || scene_.isPeriodicWall(h) || !isSeaSurface(scene_, h, water) || scene_.nearMedium(h) != 0) {
        parts.other = Li(ray0, medium, rng);
        return parts;
    }
    static StatCounter& paths = statCounter(kPathsTraced);
    paths.add();
    parts.sea = true;

    // The event, as the estimators make it at the first interface of a sensor path (3 splits).
    constexpr int kSplits = 3;
    const BxDF bxdf = scene_.bxdf(h, group_);
    SunChain chain;
    chain.hitSurface();
    int specular = 0;
    Spec sun(nb);
    const Interaction it = interactionStep().atInterface(ray, h, bxdf, chain, &specular, kSplits, rng, &sun);
    if (bxdf.isGlossy()) parts.glint += sun;
    const bool split = it.kind == Interaction::Kind::Split;
    const int splits = split ? kSplits - 1 : kSplits;
    const int n = it.kind == Interaction::Kind::Split ? 2 : it.kind == Interaction::Kind::Continued ? 1 : 0;
    const double side = dot(-ray.d, h.ng);
    for (int k = 0; k < n; ++k) {
        const Continuation& c = it.out[k];
        if (!(c.weight > 0)) continue;
        if (dot(c.ray.d, h.ng) * side <= 0) {
            parts.waterLeaving += continuePath(c, split, splits, specular, wraps, h.ng, rng);
            continue;
        }
        // The reflected ray through periodic walls: a wall ends the direct flight (as in Li).
        Continuation r = c;
        SurfaceHit h2;
        Spec T2(nb, 1.0);
        int wraps2 = wraps;
        const bool hit = walkWalls(&r.ray, &h2, &wraps2, &T2);
        if (wraps2 > wraps) r.chain.hitSurface();
        if (hit && scene_.isPeriodicWall(h2)) continue;  // the wrap failed: Li ends the path there
        if (hit) {
            parts.skyReflected +=
                T2 * continuePath(r, split, splits, specular, wraps2, wraps2 > wraps ? Normal3{0, 0, 0} : h.ng, rng);
            continue;
        }
        // Escaped: an infinite ray in attenuating air carries nothing (as Li has it).
        if (airAttenuates) continue;
        const Spec sky = sun_.environment(r.ray.d, false);
        parts.skyReflected += sky * c.weight;
        parts.glint += (sun_.environment(r.ray.d, r.chain) - sky) * c.weight;
    }
    if (airAttenuates) {
        parts.waterLeaving *= T;
        parts.skyReflected *= T;
        parts.glint *= T;
    }

    parts.ed0 = ed0At(scene_, sun_, group_, water, h.p, rng);
    return parts;
}

}  // namespace littoral::render
