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
// lobes for the first few events and then choose one; rough (glossy) interfaces estimate the sun
// on their air side by next-event estimation combined with BSDF sampling by multiple importance
// sampling (power heuristic) and continue along one sampled direction. Russian roulette on the throughput after
// three scattering vertices, as a weight window (see roulette()), keeps the estimate unbiased.
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "core/frame.h"
#include "core/stats.h"
#include "core/units.h"
#include "render/estimator.h"
#include "render/interaction.h"
#include "render/sampling.h"

namespace littoral::render {
namespace {

constexpr double kTauCut = 40.0;  // optical depth beyond which an infinite segment is cut
constexpr int kMaxSunPoints = 16;
constexpr double kSunGuide = 0.25;  // fraction of scattering directions drawn around the sun
constexpr int kSunScatterDims = 7;   // random numbers sunScattered() draws
constexpr double kNearSunDeg = 10.0;
// Segments (counted from the sensor or probe) whose single scattering is estimated by marching;
// two cover the light scattered twice on its way down and up (upwelling radiance at depth is
// mostly backscattered diffuse light that was scattered near the surface).
constexpr int kMarchedSegments = 2;

// Russian roulette as a weight window: after kRouletteDepth vertices, a path whose throughput has
// fallen below kRouletteWeight survives with probability max(beta) / kRouletteWeight and then
// carries weight kRouletteWeight (unbiased: E[beta'] = beta). Survivors keep a small weight, so in
// low-albedo water (where every path's throughput is small) the few survivors do not carry the
// whole estimate, as they do when roulette restores the weight to 1. Returns false if the path ends.
constexpr int kRouletteDepth = 3;
constexpr double kRouletteWeight = 0.05;
// No roulette for a path heading within kNearSunDeg of the refracted sun (`exempt`): such paths
// got there by the sun guide with a small weight that their next sun estimates, in the forward
// peak, are meant to spend; restoring it by roulette makes 1000x outliers (measured on Lu under a
// shading instrument). Skipping roulette is always unbiased.
bool roulette(Spec& beta, int vertices, RandomStream& rng, bool exempt) {
    const double u = rng.uniform();  // drawn always: the stream layout does not depend on depth
    if (vertices <= kRouletteDepth || exempt) return true;
    const double m = beta.maxValue();
    if (m >= kRouletteWeight) return true;
    const double q = m / kRouletteWeight;
    if (u >= q) return false;
    beta *= 1.0 / q;
    return true;
}

class PathEstimator final : public Estimator {
public:
    PathEstimator(const Scene& scene, const RenderConfig& config, BandGroup group)
        : Estimator(scene, config, group),
          step_(scene, group, TransportMode::Radiance, &sun_, config.maxSpecularDepth, InterfaceDraws{true, false}) {
        for (size_t m = 0; m < scene.media().size(); ++m)
            sunGuide_.push_back(scene.media()[m].scattering() ? sun_.refractedDirection(static_cast<int>(m))
                                                               : std::nullopt);
    }

    Spec Li(const Ray& ray, int medium, RandomStream& rng) const override {
        Walk w;
        w.splits = 3;
        return trace(ray, medium, SunChain{}, w, rng);
    }
    Spec LiIndirect(const Ray& ray, int medium, RandomStream& rng) const override {
        Walk w;
        w.splits = 1;
        return trace(ray, medium, sun_.chainAfterVertex(medium), w, rng);
    }

protected:
    const InteractionStep& interactionStep() const override { return step_; }
    Spec continuePath(const Continuation& c, bool split, int splits, int specular, int wraps, const Normal3&,
                      RandomStream& rng) const override {
        Walk w;  // as atSurface continues a sensor path
        w.splits = splits;
        w.specular = specular;
        w.wraps = wraps;
        // A split lobe is traced on its own and weighted; a sampled one goes on with the weight in
        // its throughput (which Russian roulette reads).
        if (split) return trace(c.ray, c.medium, c.chain, w, rng) * c.weight;
        return trace(c.ray, c.medium, c.chain, w, rng, c.weight);
    }

private:
    // Counters along a path. The first `splits` delta-interface events trace both the reflected
    // and the refracted ray with their Fresnel weights (splitting: unbiased, and smooth water is
    // rendered without noise); later ones choose one by Fresnel probability.
    struct Walk {
        int vertices = 0, specular = 0, wraps = 0, splits = 0;
    };
    // (beta0: the throughput the path starts with.)
    Spec trace(Ray ray, int medium, SunChain chain, Walk w, RandomStream& rng, double beta0 = 1.0) const;
    // A path in flight: its ray, medium, sun chain and counters, the radiance gathered so far and
    // the throughput.
    struct PathState {
        Ray ray;
        int medium;
        SunChain chain;
        Walk w;
        Spec L, beta;
    };
    enum class Flight { Scattered, Reached, Ended };  // Reached: the surface *h if *hit, else escaped
    static Flight cutAtMaxBounces();  // counts a path cut with weight left; Ended
    // The segment from s.ray to the next medium collision (sun estimates, roulette and the new
    // direction: Scattered) or to the surface or the sky (Reached); Ended if the path ends.
    Flight fly(PathState& s, SurfaceHit* h, bool* hit, RandomStream& rng) const;
    // The event at surface h (walls, interfaces, diffuse vertices); false if the path ends there.
    bool atSurface(PathState& s, const SurfaceHit& h, RandomStream& rng) const;
    // A diffuse vertex: the sun by next-event estimation, roulette, and a direction from the BxDF
    // mixed with the sun guide in scattering water. False if the path ends.
    bool diffuseVertex(PathState& s, const SurfaceHit& h, const BxDF& bxdf, RandomStream& rng) const;
    bool nearSun(int medium, const Vec3& d) const {
        const auto& g = sunGuide_[medium];
        return g && dot(*g, d) > std::cos(kNearSunDeg * kPi / 180.0);
    }

    InteractionStep step_;
    std::vector<std::optional<Vec3>> sunGuide_;  // per medium: toward the refracted sun (scattering media)
    // The direction a path leaves a scattering event in (sampled, with its per-band weight p / pdf).
    // With the sun up, a fraction kSunGuide of the directions is drawn from the phase function
    // around the refracted sun direction instead of around the incoming ray, and the two are
    // combined as a mixture density: the sun estimate at the next event is proportional to the
    // phase function between that direction and the sun, which for Petzold's forward power law
    // (p ~ psi^-1.35) has infinite variance unless directions near the sun are sampled in
    // proportion to it. With the mixture the product of the two phase values over the density is
    // bounded by 1 / kSunGuide times the other. Even for flat phase functions the guide pays: it
    // sends paths from depth up toward the sunlit water, where their sun estimates are large
    // (measured on Mobley et al.'s problem 1 at albedo 0.9: 3x less variance of Ed at tau = 5).
    Vec3 sampleContinuation(const Medium& md, int medium, int layer, const Vec3& dir, RandomStream& rng, Spec* weight) const;
    // Sunlight scattered at x (in `layer` of `medium`) toward -dir, per unit scattering coefficient:
    // Int_disc L_sun(w) p(w -> -dir) dw (sr^-1 x radiance). The disc is tiny (0.53 deg, and
    // refracted) and the phase function may have a forward power law (Petzold: p ~ psi^-1.35), so
    // sampling a point of the disc and evaluating p there has infinite variance when dir nearly
    // meets the sun. In forward-peaked media the estimate is one-sample MIS (balance heuristic) of
    // two strategies: a uniform point of the disc (pdf 1/Omega) and a direction drawn from the
    // phase function around dir, kept if it reaches the disc (pdf p); each contribution is then
    // at most twice the disc's radiance. Draws kSunScatterDims numbers.
    Spec sunScattered(const Point3& x, int layer, const Vec3& dir, int medium, RandomStream& rng) const;
    // Single-scattered sunlight along ray.o + t ray.d, t in [0, tMax), in `medium` (part 1 above).
    Spec sunInScatter(const Ray& ray, double tMax, int medium, RandomStream& rng) const;
};

Vec3 PathEstimator::sampleContinuation(const Medium& md, int medium, int layer, const Vec3& dir, RandomStream& rng,
                                       Spec* weight) const {
    const auto& guide = sunGuide_[medium];
    const double ut = rng.uniform(), u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
    if (!guide) {
        const Vec3 w = md.sampleAround(layer, group_, dir, u0, u1, u2, u3);
        const double pdf = md.pdfAround(layer, group_, dir, w);
        *weight = pdf > 0 ? md.phase(layer, group_, -dir, -w) * (1.0 / pdf) : Spec(group_.count);
        return w;
    }
    const Vec3 w = ut < kSunGuide ? md.sampleAround(layer, group_, *guide, u0, u1, u2, u3)
                                  : md.sampleAround(layer, group_, dir, u0, u1, u2, u3);
    const double pdf = kSunGuide * md.pdfAround(layer, group_, *guide, w) +
                       (1.0 - kSunGuide) * md.pdfAround(layer, group_, dir, w);
    *weight = pdf > 0 ? md.phase(layer, group_, -dir, -w) * (1.0 / pdf) : Spec(group_.count);
    return w;
}

Spec PathEstimator::sunScattered(const Point3& x, int layer, const Vec3& dir, int medium, RandomStream& rng) const {
    const Medium& md = scene_.media()[medium];
    const double us = rng.uniform(), u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform(),
                 u3 = rng.uniform();
    const Normal3 none{0, 0, 0};
    if (!md.forwardPeaked()) {
        const SunBeam sun = sun_.sample(x, none, Vec3{0, 0, 0}, medium, rng);
        // Light travelling along -toSun scatters into -dir (toward the ray's origin).
        return sun.valid ? md.phase(layer, group_, -sun.toSun, -dir) * sun.E : Spec(group_.count);
    }
    SunBeam sun;
    if (us < 0.5) {
        sun = sun_.sample(x, none, Vec3{0, 0, 0}, medium, rng);
    } else {
        // The disc strategy's numbers (two, and two more under a rough interface): the disc point
        // is shared by both strategies, which differ in how the direction toward it is chosen.
        const double d1 = rng.uniform(), d2 = rng.uniform();
        if (sun_.roughAbove(medium)) rng.uniform(), rng.uniform();
        // A direction toward the light w with density p(angle(w, dir)): light arriving along -w
        // scatters into -dir at that same angle.
        const Vec3 w = md.sampleAround(layer, group_, dir, u0, u1, u2, u3);
        sun = sun_.along(x, none, w, medium, Vec2{d1, d2});
    }
    if (!sun.valid) return Spec(group_.count);
    const double pMix = md.pdfAround(layer, group_, dir, sun.toSun);
    const double mix = 0.5 * sun.pdf + 0.5 * pMix;
    if (!(mix > 0)) return Spec(group_.count);
    // f / mix with f = L p (balance heuristic over the two strategies' densities of toSun).
    return md.phase(layer, group_, -sun.toSun, -dir) * sun.L * (1.0 / mix);
}

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
            const int layer = md.layerAt(x.z);
            const Spec Ls = sunScattered(x, layer, ray.d, medium, rng);
            if (Ls.isBlack() || !(denom > 0)) continue;
            L += md.transmittance(ray, t, group_) * md.b(layer, group_) * Ls * (1.0 / denom);
        }
    }
    return L;
}

// A path whose weight is not zero ends at render.max_bounces: counted, so that the render can say
// how much radiance the limit cut (render_job.cpp warns).
PathEstimator::Flight PathEstimator::cutAtMaxBounces() {
    static StatCounter& cut = statCounter(kPathsCut);
    cut.add();
    return Flight::Ended;
}

Spec PathEstimator::trace(Ray ray, int medium, SunChain chain, Walk w, RandomStream& rng, double beta0) const {
    static StatCounter& paths = statCounter(kPathsTraced);
    if (w.vertices == 0 && w.specular == 0) paths.add();
    const int nb = group_.count;
    PathState s{ray, medium, chain, w, Spec(nb), Spec(nb, beta0)};
    for (;;) {
        SurfaceHit h;
        bool hit = false;
        const Flight f = fly(s, &h, &hit, rng);
        if (f == Flight::Ended) break;
        if (f == Flight::Scattered) continue;
        if (!hit) {
            s.L += s.beta * sun_.environment(s.ray.d, s.chain);
            break;
        }
        if (!atSurface(s, h, rng)) break;
    }
    return s.L;
}

PathEstimator::Flight PathEstimator::fly(PathState& s, SurfaceHit* h, bool* hit, RandomStream& rng) const {
    const Medium& md = scene_.media()[s.medium];
    if (!md.scattering()) {
        *hit = scene_.geometry().intersect(s.ray, h);
        if (md.attenuating()) {
            if (!*hit) return Flight::Ended;  // an infinite path through absorbing water carries nothing
            s.beta *= md.transmittance(s.ray, h->t, group_);
        }
        return Flight::Reached;
    }
    // Segments that start at the sensor/probe or at the first scattering vertex are marched;
    // later ones get the collision estimate at their end (vertices counts the vertices so far).
    const bool marched = s.w.vertices < kMarchedSegments;
    FreeFlight ff;
    if (marched) {  // the march needs the whole segment to the surface
        *hit = scene_.geometry().intersect(s.ray, h);
        const double tMax = *hit ? h->t : s.ray.tMax;
        s.L += s.beta * sunInScatter(s.ray, tMax, s.medium, rng);
        const double uBand = rng.uniform(), uDist = rng.uniform();
        ff = md.sampleFreeFlight(s.ray, tMax, group_, uBand, uDist);
    } else {  // the free flight first, then the geometry only up to it (the same result)
        const double uBand = rng.uniform(), uDist = rng.uniform();
        ff = scene_.flightToSurface(s.ray, s.medium, group_, uBand, uDist, h, hit);
    }
    s.beta *= ff.weight;
    if (!ff.scattered) return s.beta.isBlack() ? Flight::Ended : Flight::Reached;
    if (s.beta.isBlack()) return Flight::Ended;
    if (++s.w.vertices > config_.maxBounces) return cutAtMaxBounces();
    const Point3 x = s.ray.at(ff.t);
    if (!marched) {
        // Collision estimator of the sun scattered here toward the previous vertex.
        s.L += s.beta * sunScattered(x, ff.layer, s.ray.d, s.medium, rng);
    } else {
        for (int k = 0; k < kSunScatterDims; ++k) rng.uniform();
    }
    // Roulette before the new direction is sampled: a direction guided toward the sun
    // (sampleContinuation) gets a small weight on purpose, to be spent on the sun estimate at its
    // next vertex; rouletting it first would restore the weight of the rare survivor and undo the
    // guide (measured: 1000x outliers in Lu under a shading instrument).
    if (!roulette(s.beta, s.w.vertices, rng, nearSun(s.medium, s.ray.d))) return Flight::Ended;
    Spec weight;
    const Vec3 wi = sampleContinuation(md, s.medium, ff.layer, s.ray.d, rng, &weight);
    s.beta *= weight;
    s.ray = Ray{x, wi};
    s.chain = sun_.chainAfterVertex(s.medium);
    return Flight::Scattered;
}

bool PathEstimator::atSurface(PathState& s, const SurfaceHit& h, RandomStream& rng) const {
    s.chain.hitSurface();
    if (scene_.isPeriodicWall(h)) {
        const auto next = step_.wrap(h, s.ray.d, &s.w.wraps);
        if (!next) return false;
        s.ray = *next;
        return true;
    }
    const BxDF bxdf = scene_.bxdf(h, group_);
    if (!bxdf.isDelta() && !bxdf.isGlossy()) {
        InteractionStep::requireDiffuse(bxdf);
        return diffuseVertex(s, h, bxdf, rng);
    }
    // Interfaces: the shared step (render/interaction.h), with the first `splits` smooth events
    // traced along both lobes.
    Spec sun;
    const Interaction it = step_.atInterface(s.ray, h, bxdf, s.chain, &s.w.specular, s.w.splits, rng, &sun);
    if (bxdf.isGlossy()) s.L += s.beta * sun;
    if (it.kind == Interaction::Kind::Ended) return false;
    if (it.kind == Interaction::Kind::Split) {
        Walk w2 = s.w;
        --w2.splits;
        for (const Continuation& c : it.out)
            if (c.weight > 0) s.L += s.beta * trace(c.ray, c.medium, c.chain, w2, rng) * c.weight;
        return false;
    }
    s.beta *= it.out[0].weight;
    s.ray = it.out[0].ray;
    s.medium = it.out[0].medium;
    s.chain = it.out[0].chain;
    return true;
}

bool PathEstimator::diffuseVertex(PathState& s, const SurfaceHit& h, const BxDF& bxdf, RandomStream& rng) const {
    const Spec rho = scene_.albedo(h, group_);
    if (rho.isBlack()) return false;
    if (++s.w.vertices > config_.maxBounces) return cutAtMaxBounces() != Flight::Ended;
    const Normal3 n = h.front ? h.ng : -h.ng;
    const SunBeam sun = sun_.sample(h.p, h.ng, n, s.medium, rng);
    if (sun.valid) s.L += s.beta * rho * sun.E * (std::max(0.0, dot(sun.toSun, n)) * kInvPi);
    if (!roulette(s.beta, s.w.vertices, rng, false)) return false;  // before the (possibly guided) direction, as above
    const Frame frame = Frame::fromNormal(n);
    const Vec3 woLocal = frame.toLocal(-s.ray.d);
    const double ut = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform(), u0 = rng.uniform(), u3 = rng.uniform();
    // In scattering water, mix BxDF sampling with the phase function around the refracted sun
    // (see sampleContinuation: the sun estimate on the next segment is peaked there).
    const Medium& md = scene_.media()[s.medium];
    const auto& guide = sunGuide_[s.medium];
    Vec3 wiLocal;
    if (guide && ut < kSunGuide) {
        wiLocal = frame.toLocal(md.sampleAround(md.layerAt(h.p.z), group_, *guide, u0, u1, u2, u3));
    } else {
        const auto bs = bxdf.sample(woLocal, 0.5, Vec2{u1, u2});
        if (!bs || bs->pdf <= 0) return false;
        wiLocal = bs->wi;
    }
    if (wiLocal.z * woLocal.z <= 0) return false;  // below the surface: no reflection there
    double pdf = bxdf.pdf(woLocal, wiLocal);
    if (guide)
        pdf = (1.0 - kSunGuide) * pdf + kSunGuide * md.pdfAround(md.layerAt(h.p.z), group_, *guide, frame.toWorld(wiLocal));
    if (!(pdf > 0)) return false;
    s.beta *= rho * (bxdf.f(woLocal, wiLocal) * std::abs(wiLocal.z) / pdf);
    s.ray = spawnRay(h.p, h.ng, normalize(frame.toWorld(wiLocal)));
    s.chain = sun_.chainAfterVertex(s.medium);
    return true;
}

}  // namespace

std::unique_ptr<Estimator> makePathEstimator(const Scene& scene, const RenderConfig& config, BandGroup group) {
    return std::make_unique<PathEstimator>(scene, config, group);
}

}  // namespace littoral::render

// ---------------------------------------------------------------------------------------------
// The path estimator's descriptor: the render settings it reads, in the order scene.json writes
// them. Its path limits sit far above what Russian roulette lets a path reach: they only stop a
// path that would otherwise never end (light trapped without loss), so they do not bias results.

namespace littoral::render {

const KindInfo& pathEstimatorKind() {
    static const KindInfo kind{"estimator", "path",
                               "an unbiased volumetric path tracer, the reference the other estimators are checked "
                               "against",
                               {maxBouncesSetting(1000), maxSpecularDepthSetting(1000), probeSamplesSetting(),
                                probeBatchesSetting(), targetRelativeErrorSetting(), maxSamplesPerPixelSetting(),
                                marchStepSetting(), probePhotonsSetting()}};
    return kind;
}

}  // namespace littoral::render
