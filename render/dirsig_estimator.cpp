// The `dirsig` estimator: recursive ray tracing with the dissertation's per-material radiometry
// solvers (Table 10.4), chosen per material by RenderConfig::solvers.
//
//  * Fresnel (delta interfaces): specular reflection and refraction with unpolarised Fresnel
//    weights r_f and T_f = 1 - r_f (Eq. 4.2), Snell directions (Eq. 4.1), total internal
//    reflection, and the n^2 radiance law. The first `splits` interface events of a path trace
//    both lobes (deterministic, noise-free images of smooth water); later events choose one lobe
//    with probability r_f (unbiased). Rough (Cox–Munk) interfaces: the microfacet BxDF of
//    render/rough_dielectric.h, the sun by next-event estimation on the air side combined with
//    BSDF sampling by the power heuristic, and one sampled direction per event.
//  * Classic (diffuse): direct sun by next-event estimation plus the sky seen over a stratified
//    jittered skydome of mu x phi equal-projected-solid-angle quads, one ray per quad: the
//    fraction of quad rays that reach the sky is the visible sky fraction F of Eq. 6.1. Sky rays
//    pass through interfaces but any opaque surface they meet contributes 0.
//  * Generic (diffuse): the same sun term plus Monte Carlo sampling of the BxDF, rays that reach
//    other surfaces recursing (background reflections). The first diffuse vertex of a path shoots
//    `hemisphereSamples` rays, deeper vertices one each; at most `maxBounces` diffuse vertices
//    per path (DIRSIG GRS semantics: 0 -> black, 1 -> sky fraction only, 2 -> plus the
//    neighbours' sky fraction, ...).
//  * SurfacePM (diffuse materials): the surface photon map's irradiance, L = r E / pi, with
//    E = sum Phi_i / (A f): the photons within the search radius on the same surface (normal within
//    25 deg, within 0.1 r of its plane, arriving on the side seen), A = pi r^2, and f the fraction
//    of the search disc that the surface covers (boundary compensation: 16 equal-area points of
//    the disc are probed for the surface, 64 if any is missing; a disc cut by an edge counts only
//    its covered part).
//    The map carries all the light the surface receives: direct sun and sky (refracted through
//    any waves: caustics), and every scattered and reflected path.
//  * MediumPM (media): in-scattered radiance along every ray segment from the volume photon map,
//    the beam estimate of DIRSIG's kernel (Eqs. 9.12–9.13; seed-ch08-09.md §2.2): photons within
//    distance r of the ray, L_in = sum Phi_i p(w_i -> -d) T(0, t_i) / (pi r^2), gathered in steps
//    of `march_step_m` along the ray.
//  * Media attenuate every segment by exp(-Int c ds), c = a + b (Eq. 2.4): without MediumPM,
//    scattering counts as loss (the dissertation's behaviour without a volume photon map); with
//    `effective_scattering` the extinction is a + b (1 - f_cone) (Ch. 6.4.7).
#include <algorithm>
#include <cmath>

#include "core/frame.h"
#include "core/units.h"
#include "render/estimator.h"
#include "render/interaction.h"
#include "render/photon_pass.h"
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
    Normal3 startNormal{0, 0, 0};  // the surface the ray leaves (zero if it starts in a medium or at a wall)
};

// Fraction of a disc of radius r whose points lie within distance h (>= 0) of its centre on one
// side of a line through the disc at distance h from the centre, plus the whole other side:
// 1 - (acos x - x sqrt(1 - x^2)) / pi, x = min(h / r, 1). 1/2 when the line passes through the
// centre, 1 when it misses the disc.
double discFractionInside(double h, double r) {
    // The line misses the disc (most photons of a segment that a surface starts or ends): the
    // formula's value, 1, without its acos and square root.
    if (h >= r) return 1.0;
    const double x = std::min(1.0, std::max(0.0, h / r));
    return 1.0 - (std::acos(x) - x * std::sqrt(1.0 - x * x)) / kPi;
}

// Share of the beam estimate's disc (radius r, centre at height z, on a ray whose direction makes
// sin = sinToVertical with the vertical) that lies in layer `l` of a layered medium: the boundaries
// between layers are horizontal planes, a plane at height distance dz from the centre crosses the
// disc at an in-disc distance dz / sin (a vertical ray's disc is horizontal and never cut). The
// water's own top and bottom are surfaces, cut by the caller; only boundaries between layers are
// counted here.
double layerDiscFraction(const Medium& md, int l, double z, double sinToVertical, double r) {
    if (sinToVertical < 1e-9) return 1.0;
    const MediumLayer& layer = md.layers()[static_cast<size_t>(l)];
    double f = 1.0;
    if (l > 0) f *= discFractionInside((layer.zTop - z) / sinToVertical, r);
    if (l + 1 < static_cast<int>(md.layers().size())) f *= discFractionInside((z - layer.zBottom) / sinToVertical, r);
    return f;
}

// The end of a gather step from t0, in layer l0, that would end at t1: earlier where the ray
// leaves that layer (toBoundary then set), so that the step's transmittance is the exact
// exponential of one layer. A step that crosses a boundary by rounding takes the transmittance
// walk instead.
double gatherStepEnd(const Medium& md, const Ray& ray, double t0, int l0, double t1, bool* toBoundary) {
    if (md.layers().size() < 2 || ray.d.z == 0) return t1;
    const MediumLayer& here = md.layers()[static_cast<size_t>(l0)];
    const double tb = ((ray.d.z < 0 ? here.zBottom : here.zTop) - ray.o.z) / ray.d.z;
    if (!(tb > t0 + 1e-9 && tb < t1)) return t1;
    *toBoundary = true;
    return tb;
}

constexpr int kCoverageProbes = 16, kCoverageHits = 16, kMaxCoverageProbes = 4096;

class DirsigEstimator final : public Estimator {
public:
    DirsigEstimator(const Scene& scene, const RenderConfig& config, BandGroup group, const PhotonMaps* maps, int pass)
        : Estimator(scene, config, group, effectiveMedia(scene, config, maps)), maps_(maps),
          rS_(config.radiusAt(config.surfaceRadius, pass)), rV_(config.radiusAt(config.volumeRadius, pass)),
          step_(scene, group, TransportMode::Radiance, &sun_, config.maxSpecularDepth, InterfaceDraws{false, true}) {}

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
        st.chain = sun_.chainAfterVertex(medium);
        return trace(ray, st, rng);
    }

protected:
    const InteractionStep& interactionStep() const override { return step_; }
    Spec continuePath(const Continuation& c, bool, int splits, int specular, int wraps, const Normal3& startNormal,
                      RandomStream& rng) const override {
        PathState ps;  // as shadeInterface continues a sensor path
        ps.medium = c.medium;
        ps.chain = c.chain;
        ps.splits = splits;
        ps.specularDepth = specular;
        ps.wraps = wraps;
        ps.startNormal = startNormal;
        return trace(c.ray, ps, rng) * c.weight;
    }

private:
    bool mediumPM(int medium) const { return medium > 0 && config_.mediumPM[static_cast<size_t>(medium - 1)] && maps_; }
    // Per medium: transmittance uses the effective extinction a + b (1 - f) (the dissertation's
    // effective scattering coefficient) for MediumPM media when render.photons.effective_scattering
    // is set, so that the direct sun, the camera rays and the volume map (which then stores no
    // forward-cone events) agree.
    static std::vector<bool> effectiveMedia(const Scene& scene, const RenderConfig& config, const PhotonMaps* maps) {
        std::vector<bool> e(scene.media().size(), false);
        for (size_t m = 1; m < e.size() && m - 1 < config.mediumPM.size(); ++m)
            e[m] = config.effectiveScattering && config.mediumPM[m - 1] && maps;
        return e;
    }
    bool effectiveExtinction(int medium) const { return sun_.effectiveExtinction(medium); }
    Spec transmittance(const Ray& ray, double t, int medium) const { return sun_.transmittance(ray, t, medium); }
    // MediumPM: in-scattered radiance along ray.o + t ray.d, t in [0, tMax), from the volume map.
    // In-scattered radiance along ray over [0, tMax) in `medium` from the volume map (beam
    // estimate). endNormal / startNormal: the surfaces that end and start the segment (zero when
    // there is none, e.g. a periodic wall or a point inside the medium); photons exist only on
    // the medium's side of them, so near them the search disc is cut and each photon's weight is
    // divided by the fraction of its disc inside (boundary compensation for a locally flat surface).
    Spec volumeInScatter(const Ray& ray, double tMax, int medium, const Normal3& endNormal = {0, 0, 0},
                         const Normal3& startNormal = {0, 0, 0}) const;
    // SurfacePM: irradiance at a diffuse hit from the surface map (n: the normal on the side seen).
    Spec surfaceIrradiance(const SurfaceHit& h, const Normal3& n) const;
    Spec trace(const Ray& ray, const PathState& st, RandomStream& rng) const;
    // trace() once the ray's closest hit is known (found: whether it hit; h: the hit).
    Spec traceHit(const Ray& ray, bool found, const SurfaceHit& h, const PathState& st, RandomStream& rng) const;
    // traceHit() for a segment that does not end at a periodic wall.
    Spec traceSegment(const Ray& ray, bool found, const SurfaceHit& h, const PathState& st, RandomStream& rng) const;
    // The Fresnel solver at a smooth or rough interface (the shared step, render/interaction.h).
    Spec shadeInterface(const Ray& ray, const SurfaceHit& h, const BxDF& bxdf, const PathState& st,
                        RandomStream& rng) const;
    Spec shadeDiffuse(const SurfaceHit& h, const Vec3& wo, const PathState& st, RandomStream& rng) const;

    // Calls f(shift) for the domain-period shifts under which a query reaching from lo to hi must
    // also be made: {0} in a bounded domain; in a periodic one, also the shifts that bring the
    // parts of the query outside the domain back inside, where the photons are.
    template <class F> void forEachPeriodicImage(const Point3& lo, const Point3& hi, F&& f) const;
    // A point moved into the domain by whole periods (periodic domains; unchanged otherwise).
    Point3 wrapIntoDomain(Point3 p) const;

    const PhotonMaps* maps_;
    double rS_, rV_;  // search radii of this pass
    InteractionStep step_;
};

template <class F> void DirsigEstimator::forEachPeriodicImage(const Point3& lo, const Point3& hi, F&& f) const {
    const ir::Domain& d = scene_.domain();
    if (!d.periodic) {
        f(Vec3{0, 0, 0});
        return;
    }
    const double lx = d.x1 - d.x0, ly = d.y1 - d.y0;
    double sx[3] = {0, 0, 0}, sy[3] = {0, 0, 0};
    int nx = 1, ny = 1;
    if (lo.x < d.x0) sx[nx++] = lx;
    if (hi.x > d.x1) sx[nx++] = -lx;
    if (lo.y < d.y0) sy[ny++] = ly;
    if (hi.y > d.y1) sy[ny++] = -ly;
    for (int i = 0; i < nx; ++i)
        for (int j = 0; j < ny; ++j) f(Vec3{sx[i], sy[j], 0});
}

Point3 DirsigEstimator::wrapIntoDomain(Point3 p) const {
    const ir::Domain& d = scene_.domain();
    if (!d.periodic) return p;
    const double lx = d.x1 - d.x0, ly = d.y1 - d.y0;
    p.x -= std::floor((p.x - d.x0) / lx) * lx;
    p.y -= std::floor((p.y - d.y0) / ly) * ly;
    return p;
}

Spec DirsigEstimator::volumeInScatter(const Ray& ray, double tMax, int medium, const Normal3& endNormal,
                                      const Normal3& startNormal) const {
    Spec L(group_.count);
    const PhotonMap& vm = maps_->volume;
    if (vm.size() == 0) return L;
    const Medium& md = scene_.media()[medium];
    double cMin = ir::kInfinity;
    for (const MediumLayer& l : md.layers())
        for (int i = 0; i < group_.count; ++i) cMin = std::min(cMin, l.c[group_.begin + i]);
    // Cut where every band's transmittance is below e^-12 = 6e-6 in the clearest layer; what lies
    // beyond adds at most that share of the in-scatter seen so far in a homogeneous medium.
    const double tEnd = std::min(tMax, cMin > 0 ? 12.0 / cMin : 1e4);
    const double inv = 1.0 / (kPi * rV_ * rV_);
    const bool eff = effectiveExtinction(medium);
    const double cosCone = 1.0 - kEffectiveConeSr / (2.0 * kPi);
    const Vec3 toEye = -ray.d;
    // The distance from the disc's centre at t to a boundary plane, within the disc, grows as
    // k t (start) or k (tMax - t) (end), k = |cos| / sin of the ray's angle to the plane's normal;
    // a ray along the normal never has its disc cut (k = inf).
    auto slope = [&](const Normal3& n) {
        const double c = std::abs(dot(ray.d, n)), s2 = 1.0 - c * c;
        return s2 > 1e-12 ? c / std::sqrt(s2) : ir::kInfinity;
    };
    const bool cutEnd = lengthSquared(endNormal) > 0 && std::isfinite(tMax), cutStart = lengthSquared(startNormal) > 0;
    const bool layered = md.layers().size() > 1;
    const double sinToVertical = std::sqrt(std::max(0.0, 1.0 - ray.d.z * ray.d.z));
    const double kEnd = cutEnd ? slope(endNormal) : ir::kInfinity, kStart = cutStart ? slope(startNormal) : ir::kInfinity;
    for (double t0 = 0, t1; t0 < tEnd; t0 = t1) {
        const int l0 = md.layerAt(ray.at(t0).z);
        bool toBoundary = false;
        t1 = gatherStepEnd(md, ray, t0, l0, std::min(tEnd, t0 + config_.marchStep), &toBoundary);
        // Transmittance at the step's start, then exp(-c (t - t0)) in the layer there (exact unless
        // the step crosses a layer boundary, where the walk is used).
        const Spec T0 = md.transmittance(ray, t0, group_, eff);
        // Past e^-12 in every band (through a dense layer, long before the cut by the clearest layer's
        // c above) nothing more counts.
        if (T0.maxValue() < 6e-6) break;
        const int l1 = toBoundary ? l0 : md.layerAt(ray.at(t1).z);
        const MediumLayer& layer = md.layers()[l0];
        const Point3 a = ray.at(t0), b = ray.at(t1);
        const Point3 lo{std::min(a.x, b.x) - rV_, std::min(a.y, b.y) - rV_, 0};
        const Point3 hi{std::max(a.x, b.x) + rV_, std::max(a.y, b.y) + rV_, 0};
        forEachPeriodicImage(lo, hi, [&](const Vec3& shift) {
        vm.forEachNearSegment(ray.o + shift, ray.d, t0, t1, rV_, [&](size_t i, double t) {
            // A layer boundary cuts the disc like a surface: only photons of the layer the ray is in
            // at t count, over the share of the disc on that layer's side.
            const double zc = ray.at(t).z;
            const int li = layered ? md.layerAt(vm.position(i).z) : 0;
            const int lc = !layered ? 0 : l0 == l1 ? l0 : md.layerAt(zc);
            if (li != lc) return;
            const Vec3 dir = vm.direction(i);
            // Effective scattering: the map holds only events outside the 0.01 sr forward cone (at
            // the rate b (1 - f)); the phase function is the part outside the cone, over 1 - f. An
            // eye direction inside the photon's cone is unscattered light, carried by the
            // transmittance with a + b (1 - f).
            if (eff && dot(dir, toEye) > cosCone) return;
            Spec p = md.phase(li, group_, dir, toEye);
            if (eff)
                for (int b = 0; b < group_.count; ++b) p[b] *= md.layers()[li].outsideCone[group_.begin + b];
            Spec T(group_.count);
            if (l0 == l1) {
                for (int b = 0; b < group_.count; ++b)
                    T[b] = T0[b] * std::exp(-(eff ? layer.cEff : layer.c)[group_.begin + b] * (t - t0));
            } else {
                T = md.transmittance(ray, t, group_, eff);
            }
            double cut = layered ? layerDiscFraction(md, lc, zc, sinToVertical, rV_) : 1.0;
            if (cutEnd && std::isfinite(kEnd)) cut *= discFractionInside(kEnd * (tMax - t), rV_);
            if (cutStart && std::isfinite(kStart)) cut *= discFractionInside(kStart * t, rV_);
            const double wgt = inv / cut;
            for (int b = 0; b < group_.count; ++b) L[b] += T[b] * p[b] * vm.power(i, b) * vm.fluxScale[b] * wgt;
        });
        });
    }
    return L;
}

Spec DirsigEstimator::surfaceIrradiance(const SurfaceHit& h, const Normal3& n) const {
    Spec E(group_.count);
    const PhotonMap& sm = maps_->surface;
    if (sm.size() == 0) return E;
    const double slab = 0.1 * rS_;
    const Vec3 rr{rS_, rS_, rS_};
    forEachPeriodicImage(h.p - rr, h.p + rr, [&](const Vec3& shift) {
        const Point3 c = h.p + shift;
        sm.forEachInSphere(c, rS_, [&](size_t i) {
            if (dot(sm.normal(i), n) < 0.9) return;                  // another surface orientation or side
            if (std::abs(dot(sm.position(i) - c, n)) > slab) return;   // off this surface's plane
            for (int b = 0; b < group_.count; ++b) E[b] += sm.power(i, b) * sm.fluxScale[b];
        });
    });
    if (E.isBlack()) return E;
    // Boundary compensation: the fraction of the search disc that this surface covers, from 16
    // equal-area points (a Vogel spiral) each probed with a short ray across the surface.
    const Frame f = Frame::fromNormal(n);
    auto covered = [&](int probes) {
        int count = 0;
        for (int k = 0; k < probes; ++k) {
            const double rho = rS_ * std::sqrt((k + 0.5) / probes), phi = 2.399963229728653 * k;
            const Point3 q = wrapIntoDomain(h.p + f.toWorld(Vec3{rho * std::cos(phi), rho * std::sin(phi), 0}));
            Ray probe;
            probe.o = q + n * slab;
            probe.d = -n;
            probe.tMax = 2 * slab;
            SurfaceHit ph;
            if (scene_.geometry().intersect(probe, &ph) && dot(ph.front ? ph.ng : -ph.ng, n) > 0.9) ++count;
        }
        return count;
    };
    // 16 probes settle the common case of a fully covered disc. A cut disc is measured with 64, and
    // with 4x more (up to kMaxCoverageProbes) while fewer than kCoverageHits of them land on the
    // surface: a small photon-mapped object under a large disc is measured, not floored at 1/64
    // (the quantisation is then at most about 1/kCoverageHits of the covered share).
    int probes = kCoverageProbes, hits = covered(probes);
    if (hits < probes) hits = covered(probes = 4 * kCoverageProbes);
    while (hits < kCoverageHits && probes < kMaxCoverageProbes) hits = covered(probes *= 4);
    const double fraction = std::max(hits, 1) / static_cast<double>(probes);
    return E * (1.0 / (kPi * rS_ * rS_ * fraction));
}

Spec DirsigEstimator::trace(const Ray& ray, const PathState& st, RandomStream& rng) const {
    SurfaceHit h;
    const bool found = scene_.geometry().intersect(ray, &h);
    return traceHit(ray, found, h, st, rng);
}

Spec DirsigEstimator::traceHit(const Ray& ray0, bool found0, const SurfaceHit& h0, const PathState& st0,
                               RandomStream& rng) const {
    if (!found0 || !scene_.isPeriodicWall(h0)) return traceSegment(ray0, found0, h0, st0, rng);
    // Periodic walls are followed in a loop, not by recursion (a grazing ray in a small periodic
    // domain wraps hundreds of times, and a stack frame per wrap overflowed worker threads' stacks
    // under the sanitizers): L = sum over the wrapped segments of their in-scatter times the
    // transmittance before them, plus the last segment's radiance times the whole transmittance.
    Spec L(group_.count), T(group_.count, 1.0);
    Ray ray = ray0;
    SurfaceHit h = h0;
    PathState st = st0;
    bool found = true;
    while (found && scene_.isPeriodicWall(h)) {
        const auto next = step_.wrap(h, ray.d, &st.wraps);
        if (mediumPM(st.medium)) L += T * volumeInScatter(ray, h.t, st.medium, {0, 0, 0}, st.startNormal);
        if (!next) return L;
        T *= transmittance(ray, h.t, st.medium);
        st.chain.hitSurface();
        st.startNormal = Normal3{0, 0, 0};
        ray = *next;
        found = scene_.geometry().intersect(ray, &h);
    }
    return L + T * traceSegment(ray, found, h, st, rng);
}

Spec DirsigEstimator::traceSegment(const Ray& ray, bool found, const SurfaceHit& h, const PathState& st,
                                   RandomStream& rng) const {
    const Medium& medium = scene_.media()[st.medium];
    if (!found) {
        Spec L = mediumPM(st.medium) ? volumeInScatter(ray, ir::kInfinity, st.medium, {0, 0, 0}, st.startNormal)
                                     : Spec(group_.count);
        // An infinitely long path through an attenuating medium carries nothing more.
        if (medium.attenuating()) return L;
        return L + sun_.environment(ray.d, st.chain);
    }
    // A Classic sky ray ends at an opaque surface with nothing (unless the medium it crossed
    // in-scatters): settled before any BxDF or path state is built (a third of a Classic frame's rays).
    if (st.skyOnly && !(scene_.bxdfFlags(h) & kTransmission) && !mediumPM(st.medium)) return Spec(group_.count);
    // The segment's medium: an interface knows its own sides (trusted over the carried medium);
    // an opaque surface is reached through whatever medium the ray carries.
    const BxDF bxdf = scene_.bxdf(h, group_);
    const int segMedium = bxdf.isTransmissive() ? scene_.nearMedium(h) : st.medium;
    Spec Lsurf(group_.count);
    PathState s2 = st;
    s2.medium = segMedium;
    s2.chain.hitSurface();
    if (bxdf.isDelta() || bxdf.isGlossy()) {
        Lsurf = shadeInterface(ray, h, bxdf, s2, rng);
    } else if (!st.skyOnly) {
        InteractionStep::requireDiffuse(bxdf);
        Lsurf = shadeDiffuse(h, -ray.d, s2, rng);
    }
    if (!mediumPM(segMedium)) {
        // No in-scatter: the surface's radiance through the segment (nothing to do in the air).
        if (!scene_.media()[segMedium].attenuating() || Lsurf.isBlack()) return Lsurf;
        return Lsurf * transmittance(ray, h.t, segMedium);
    }
    const Spec inScatter = volumeInScatter(ray, h.t, segMedium, h.ng, st.startNormal);
    if (Lsurf.isBlack()) return inScatter;
    return Lsurf * transmittance(ray, h.t, segMedium) + inScatter;
}

Spec DirsigEstimator::shadeInterface(const Ray& ray, const SurfaceHit& h, const BxDF& bxdf, const PathState& st,
                                     RandomStream& rng) const {
    // Smooth interfaces: the first `splits` events trace both lobes with their Fresnel weights
    // (deterministic, noise-free images of smooth water), later ones one lobe chosen with
    // probability r_f. Rough ones: the sun by next-event estimation with MIS, then one sampled
    // direction (Walter et al. 2007). Classic sky rays pass interfaces the same way, with the disc
    // counted by the chain rules.
    PathState next = st;
    Spec L(group_.count);
    const Interaction it = step_.atInterface(ray, h, bxdf, st.chain, &next.specularDepth, st.splits, rng, &L);
    if (it.kind == Interaction::Kind::Ended) return L;
    if (it.kind == Interaction::Kind::Split) next.splits = st.splits - 1;
    const int n = it.kind == Interaction::Kind::Split ? 2 : 1;
    for (int k = 0; k < n; ++k) {
        const Continuation& c = it.out[k];
        if (!(c.weight > 0)) continue;
        PathState ps = next;
        ps.medium = c.medium;
        ps.chain = c.chain;
        ps.startNormal = h.ng;
        L += trace(c.ray, ps, rng) * c.weight;
    }
    return L;
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
    if (config_.solvers[scene_.materialIndex(h)] == ir::Material::Solver::SurfacePM) {
        rng.uniform(), rng.uniform();  // the sun estimate's numbers: keep the stream layout
        return maps_ ? rho * surfaceIrradiance(h, n) * kInvPi : L;
    }

    // Direct sun: Lambertian radiance r E_sun cos(theta_s) / pi.
    const SunBeam sun = sun_.sample(h.p, h.ng, n, st.medium, rng);
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
    next.chain = sun_.chainAfterVertex(st.medium);
    next.skyOnly = classic;
    next.startNormal = n;
    // The first diffuse vertex of a path integrates its hemisphere with N stratified rays; deeper
    // vertices use one ray, so a path tree grows linearly, not as N^depth.
    const int count = st.diffuseDepth == 0 ? config_.hemisphereSamples : 1;
    const Frame frame = Frame::fromNormal(n);
    const BxDF bxdf = scene_.bxdf(h, group_);
    const Vec3 wo = frame.toLocal(woWorld);
    Spec sum(nb);
    if (classic) {
        // Fixed stratified skydome: one jittered ray per equal-projected-solid-angle quad. The rays
        // share their origin, so their first hits are traced together as packets (8 at a time).
        const StratifiedLayout layout(count);
        constexpr int kBatch = 32;
        Ray rays[kBatch];
        SurfaceHit hits[kBatch];
        bool found[kBatch];
        for (int k0 = 0; k0 < count; k0 += kBatch) {
            const int m = std::min(kBatch, count - k0);
            for (int k = 0; k < m; ++k) {
                const Vec2 u = layout.point(k0 + k, rng.uniform(), rng.uniform());
                rays[k] = spawnRay(h.p, h.ng, frame.toWorld(sampleCosineHemisphere(u.x, u.y)));
            }
            scene_.geometry().intersectCoherent(rays, m, hits, found);
            for (int k = 0; k < m; ++k) sum += traceHit(rays[k], found[k], hits[k], next, rng);
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

std::unique_ptr<Estimator> makeDirsigEstimator(const Scene& scene, const RenderConfig& config, BandGroup group,
                                               const PhotonMaps* maps, int pass) {
    return std::make_unique<DirsigEstimator>(scene, config, group, maps, pass);
}

}  // namespace littoral::render

// ---------------------------------------------------------------------------------------------
// The dirsig estimator's descriptor: the render settings it reads, in the order scene.json
// writes them (makeRenderConfig reads them; the photon-map settings only when a material uses
// solver surface-pm or the water uses solver medium-pm).

namespace littoral::render {

const KindInfo& dirsigEstimatorKind() {
    static const KindInfo kind = [] {
        using T = ParamType;
        KindInfo k{"estimator", "dirsig",
                   "the dissertation's per-material radiometry solvers (classic, generic, fresnel, surface-pm, "
                   "medium-pm)",
                   {}};
        k.params = {
            maxBouncesSetting(8),
            maxSpecularDepthSetting(16),
            {"hemisphere_samples", "", T::Integer, 64, 1, 1 << 20, "", "sky and background rays at the first diffuse vertex"},
            probeSamplesSetting(),
            probeBatchesSetting(),
            targetRelativeErrorSetting(),
            maxSamplesPerPixelSetting(),
            {"surface_photons", "photons.surface", T::Integer, std::nullopt, 1, 1e10, "",
             "photons in the surface map (required by solver surface-pm)"},
            {"volume_photons", "photons.volume", T::Integer, kDefaultVolumePhotons, 1, 1e10, "",
             "photons in the volume map (read by water solver medium-pm)"},
            {"surface_search_radius_m", "search_radius_m.surface", T::Real, 0.4, 1e-4, 100, "m",
             "surface-map search radius of the first pass (at most the domain's smaller side)"},
            {"volume_search_radius_m", "search_radius_m.volume", T::Real, 0.4, 1e-4, 100, "m",
             "volume-map search radius of the first pass (at most the domain's smaller side)"},
            marchStepSetting(),
            {"photon_max_bounces", "photons.max_bounces", T::Integer, 200, 1, 100000, "",
             "scattering and diffuse events per photon path"},
            {"effective_scattering", "photons.effective_scattering", T::Boolean, 0, 0, 1, "",
             "DIRSIG's effective scattering coefficient (scattering within 0.01 sr of forward is unscattered)"},
            {"photon_depth_splitting", "photons.depth_splitting", T::Boolean, 0, 0, 1, "",
             "volume photons split by depth (I = Eo(top) / Eo(z) from a pilot), so deep water gets photons"},
            {"probe_collisions", "photons.probe_collisions", T::Boolean, 0, 0, 1, "",
             "irradiance probes of a horizontally invariant scene from the volume map's collisions in a slab "
             "(at least 2 progressive passes) instead of its gather along directions"},
            {"photon_importance", "photons.importance", T::Boolean, 1, 0, 1, "",
             "importance emission: photons start where a pilot found they store, weighted so the estimate is unchanged"},
            {"progressive_passes", "progressive.passes", T::Integer, 1, 1, 100000, "",
             "photon-map passes with shrinking radii"},
            {"progressive_alpha", "progressive.alpha", T::Real, 2.0 / 3.0, 0.05, 0.99, "",
             "radius reduction, r_i^2 = r_1^2 i^(alpha - 1) (Knaus and Zwicker 2011)"},
        };
        return k;
    }();
    return kind;
}

}  // namespace littoral::render
