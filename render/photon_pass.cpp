#include "render/photon_pass.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <optional>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/frame.h"
#include "core/log.h"
#include "core/progress.h"
#include "core/rng.h"
#include "core/stats.h"
#include "core/units.h"
#include "render/distributed.h"
#include "render/interaction.h"
#include "render/sampling.h"

namespace littoral::render {

namespace {

constexpr uint64_t kPhotonPassBase = 1ull << 50;  // random-stream passes of the photon pass
constexpr uint64_t kChunk = kPhotonChunk;         // photons per chunk

struct ChunkResult {
    PhotonMap surface, volume;
    // The pilot's counts per source and emission cell (EmissionImportance): emitted, and stored
    // anything. Empty outside the pilot.
    std::vector<uint64_t> emitted, stored;
};

}  // namespace

// One photon's walk through the scene: free flights and phase-function sampling in scattering
// media, the shared interaction step at interfaces and walls (importance transport), and diffuse
// vertices that store into the surface map and continue by cosine sampling.
class PhotonTracer {
public:
    PhotonTracer(const Scene& scene, BandGroup g, const PhotonPassSettings& st)
        : scene_(scene), g_(g), st_(st), src_(PhotonSource::of(scene, g)),
          step_(scene, g, TransportMode::Importance, nullptr, st.maxSpecularDepth, InterfaceDraws{true, false}) {}
    const PhotonSource& source() const { return src_; }
    // Photon `index`, started by `importance` (nullptr: uniformly); `observer` (optional) is told of
    // its flights.
    void trace(uint64_t index, ChunkResult& out, const EmissionImportance* importance,
               PhotonObserver* observer = nullptr) const;

private:
    // Where a photon is, and its counts: what a walk carries, and what a copy starts from.
    struct State {
        Ray ray;
        Spec w;
        int medium = 0, events = 0, specular = 0, wraps = 0;
        // The collision the current flight starts at (or continues from across a periodic wall),
        // if any: PhotonObserver::flight's `from`.
        std::optional<PhotonObserver::Scattered> from;
        const PhotonObserver::Scattered* scattered() const { return from ? &*from : nullptr; }
    };
    using Pending = std::vector<State>;  // copies still to walk (splitting by depth)

    // The importance at height z (1 without splitting by depth).
    double importance(double z) const {
        return st_.depthImportance.empty() ? 1.0 : st_.depthImportance.at(z);
    }
    // Russian roulette on the photon's power, as a weight window: a photon whose largest band
    // power, times the importance I where it is, is below st_.rouletteBelow survives with
    // probability max I / rouletteBelow and is scaled up by its inverse (unbiased). One number is
    // drawn always, so that the streams do not depend on the threshold's outcome.
    bool roulette(Spec& w, RandomStream& rng, double I) const {
        const double u = rng.uniform(), m = w.maxValue() * I;
        if (m >= st_.rouletteBelow) return true;
        const double q = m / st_.rouletteBelow;
        if (u >= q || !(q > 0)) return false;
        w *= 1.0 / q;
        return true;
    }
    // How many copies a collision where the importance is I makes of a photon of power w
    // (splitting by depth).
    int splitCount(const Spec& w, double I) const {
        if (st_.depthImportance.empty()) return 1;
        const double v = w.maxValue() * I;
        return v >= 2.0 ? static_cast<int>(std::min<double>(std::floor(v), st_.maxSplit)) : 1;
    }
    // A collision in a scattering medium: stores the event (MediumPM media), splits the photon by
    // depth (the copies go to `pending`) and turns it. False if the photon ends.
    bool scatter(State& s, const FreeFlight& ff, RandomStream& rng, ChunkResult& out, PhotonObserver* observer,
                 Pending& pending) const;
    // Turns a photon of power w at x (stores it first where its medium keeps a volume map); then the
    // roulette at importance I. False if it ends.
    bool turn(State& s, const Point3& x, int layer, double I, RandomStream& rng, ChunkResult& out) const;
    // A diffuse vertex: stores the photon (SurfacePM materials) and reflects it. False if it ends.
    bool reflectDiffuse(State& s, const SurfaceHit& h, RandomStream& rng, ChunkResult& out,
                        PhotonObserver* observer) const;
    // The photon's walk from its emission until it ends, with every copy it splits into.
    void walk(Ray ray, Spec w, RandomStream& rng, ChunkResult& out, PhotonObserver* observer) const;
    // One copy's walk from `s` until it ends.
    void walkFrom(State s, RandomStream& rng, ChunkResult& out, PhotonObserver* observer, Pending& pending) const;

    const Scene& scene_;
    BandGroup g_;
    const PhotonPassSettings& st_;
    PhotonSource src_;
    InteractionStep step_;
};

bool PhotonTracer::scatter(State& s, const FreeFlight& ff, RandomStream& rng, ChunkResult& out,
                           PhotonObserver* observer, Pending& pending) const {
    if (s.w.isBlack()) return false;
    const Point3 x = s.ray.at(ff.t);
    if (observer) observer->collision(x, s.ray.d, s.medium, ff.layer, s.w);
    if (++s.events > st_.maxBounces) {
        if (observer) observer->cut(s.w);
        return false;
    }
    const double I = importance(x.z);
    if (const int n = splitCount(s.w, I); n > 1) {
        s.w *= 1.0 / n;
        for (int c = 1; c < n; ++c) {
            State copy = s;
            if (turn(copy, x, ff.layer, I, rng, out)) pending.push_back(copy);
        }
    }
    return turn(s, x, ff.layer, I, rng, out);
}

bool PhotonTracer::turn(State& s, const Point3& x, int layer, double I, RandomStream& rng, ChunkResult& out) const {
    static const double cosCone = 1.0 - kEffectiveConeSr / (2.0 * kPi);
    const Medium& md = scene_.media()[static_cast<size_t>(s.medium)];
    Spec pw;
    const Vec3 wi = md.samplePhase(layer, g_, s.ray.d, rng, &pw);
    s.from = PhotonObserver::Scattered{s.ray.d, layer, x.z};
    const bool forward = st_.effectiveScattering && dot(wi, s.ray.d) > cosCone;
    if (!forward && st_.volumeMedium[static_cast<size_t>(s.medium)]) out.volume.add(x, s.ray.d, Vec3{0, 0, 1}, s.w);
    if (!forward) {
        s.w *= pw;
        s.ray = Ray{x, wi};
    } else {
        s.ray = Ray{x, s.ray.d};
    }
    return roulette(s.w, rng, I);
}

bool PhotonTracer::reflectDiffuse(State& s, const SurfaceHit& h, RandomStream& rng, ChunkResult& out,
                                  PhotonObserver* observer) const {
    const Spec rho = scene_.albedo(h, g_);
    if (observer) observer->diffuse(h, s.medium, rho, s.w);
    const Normal3 n = h.front ? h.ng : -h.ng;
    if (st_.surfaceMaterial[static_cast<size_t>(scene_.materialIndex(h))]) out.surface.add(h.p, s.ray.d, n, s.w);
    if (rho.isBlack() || ++s.events > st_.maxBounces) return false;
    s.w *= rho;
    if (!roulette(s.w, rng, importance(h.p.z))) return false;
    const Frame frame = Frame::fromNormal(n);
    const double v1 = rng.uniform(), v2 = rng.uniform();
    s.ray = spawnRay(h.p, h.ng, normalize(frame.toWorld(sampleCosineHemisphere(v1, v2))));
    s.from.reset();
    return true;
}

void PhotonTracer::trace(uint64_t index, ChunkResult& out, const EmissionImportance* importance,
                         PhotonObserver* observer) const {
    RandomStream rng(st_.seed, kPhotonPassBase + st_.pass, index);
    const EmittedPhoton e = emitPhoton(scene_, src_, rng, importance);
    const size_t before = out.surface.size() + out.volume.size();
    walk(e.ray, e.power, rng, out, observer);
    if (out.emitted.empty()) return;
    const size_t k = static_cast<size_t>((e.fromSun ? 0 : EmissionImportance::N) + e.cell);
    ++out.emitted[k];
    if (out.surface.size() + out.volume.size() > before) ++out.stored[k];
}

void PhotonTracer::walk(Ray ray, Spec w, RandomStream& rng, ChunkResult& out, PhotonObserver* observer) const {
    // The copies still to walk: one list per thread, kept from photon to photon (a list per photon
    // allocated and freed once for every photon that split).
    static thread_local Pending pending;
    pending.clear();
    State first;
    first.ray = ray, first.w = w;
    walkFrom(first, rng, out, observer, pending);
    while (!pending.empty()) {
        const State s = pending.back();
        pending.pop_back();
        walkFrom(s, rng, out, observer, pending);
    }
}

void PhotonTracer::walkFrom(State s, RandomStream& rng, ChunkResult& out, PhotonObserver* observer,
                            Pending& pending) const {
    for (;;) {
        SurfaceHit h;
        bool hit;
        const Medium& md = scene_.media()[static_cast<size_t>(s.medium)];
        if (md.scattering()) {
            // The free flight first, then the geometry only up to it (Scene::flightToSurface).
            const double uBand = rng.uniform(), uDist = rng.uniform();
            const FreeFlight ff = scene_.flightToSurface(s.ray, s.medium, g_, uBand, uDist, &h, &hit);
            if (observer)
                observer->flight(s.ray, ff.scattered ? ff.t : hit ? h.t : ir::kInfinity, s.medium, s.w, true,
                                 s.scattered());
            s.w *= ff.weight;
            if (ff.scattered) {
                if (!scatter(s, ff, rng, out, observer, pending)) return;
                continue;
            }
            if (s.w.isBlack()) return;
        } else if (md.attenuating()) {
            hit = scene_.geometry().intersect(s.ray, &h);
            if (!hit) return;
            if (observer) observer->flight(s.ray, h.t, s.medium, s.w, false, s.scattered());
            s.w *= md.transmittance(s.ray, h.t, g_);
        } else {
            hit = scene_.geometry().intersect(s.ray, &h);
            if (observer) observer->flight(s.ray, hit ? h.t : ir::kInfinity, s.medium, s.w, false, s.scattered());
        }
        if (!hit) return;
        if (scene_.isPeriodicWall(h)) {
            const auto next = step_.wrap(h, s.ray.d, &s.wraps);
            if (!next) {
                static StatCounter& lost = statCounter("photons lost at periodic walls");
                lost.add();
                return;
            }
            s.ray = *next;
            continue;
        }
        const BxDF bxdf = scene_.bxdf(h, g_);
        if (bxdf.isDelta() || bxdf.isGlossy()) {
            // Interfaces, smooth or rough: one direction sampled from the BxDF in importance mode,
            // weighted by f |cos| / pdf (1 for the smooth one; for the rough one the fraction of its
            // weight a single-scattering microfacet model keeps).
            const Interaction it = step_.atInterface(s.ray, h, bxdf, SunChain{}, &s.specular, 0, rng, nullptr);
            if (it.kind != Interaction::Kind::Continued) return;
            s.w *= it.out[0].weight;
            s.medium = it.out[0].medium;
            s.ray = it.out[0].ray;
            s.from.reset();
            continue;
        }
        InteractionStep::requireDiffuse(bxdf);
        if (!reflectDiffuse(s, h, rng, out, observer)) return;
    }
}

double DepthImportance::at(double height) const {
    if (z.empty()) return 1.0;
    if (height >= z.front()) return std::exp(logI.front());
    if (height <= z.back()) return std::exp(logI.back() - std::min(fallBelow * (z.back() - height), kMaxFall));
    // z descending: the first point at or below `height`.
    const size_t k = static_cast<size_t>(std::upper_bound(z.begin(), z.end(), height, std::greater<double>()) - z.begin());
    const double t = (z[k - 1] - height) / (z[k - 1] - z[k]);
    return std::exp(logI[k - 1] + t * (logI[k] - logI[k - 1]));
}

DepthImportance DepthImportance::fromProfile(std::vector<std::pair<double, double>> profile, double exponent,
                                             double maxImportance, bool fallBelowDeepest) {
    profile.erase(std::remove_if(profile.begin(), profile.end(),
                                 [](const auto& p) { return !(p.second > 0) || !std::isfinite(p.second) || !std::isfinite(p.first); }),
                  profile.end());
    std::sort(profile.begin(), profile.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    profile.erase(std::unique(profile.begin(), profile.end(), [](const auto& a, const auto& b) { return a.first == b.first; }),
                  profile.end());
    DepthImportance d;
    if (profile.size() < 2) return d;
    const double top = profile.front().second, lo = std::log(1e-2), hi = std::log(maxImportance);
    for (const auto& [z, e] : profile) {
        d.z.push_back(z);
        d.logI.push_back(std::clamp(exponent * std::log(top / e), lo, hi));
    }
    const size_t n = profile.size();
    if (fallBelowDeepest && profile[n - 2].first > profile[n - 1].first)
        d.fallBelow = std::max(0.0, std::log(profile[n - 2].second / profile[n - 1].second) /
                                        (profile[n - 2].first - profile[n - 1].first));
    return d;
}

ObservedPhotons::ObservedPhotons(const Scene& scene, BandGroup g, const PhotonPassSettings& settings)
    : settings_(settings) {
    settings_.surfaceTarget = settings_.volumeTarget = 0;
    settings_.effectiveScattering = false;  // every collision turns the photon (PhotonObserver::flight's `from`)
    settings_.surfaceMaterial.assign(scene.materials().size(), false);
    settings_.volumeMedium.assign(scene.media().size(), false);
    tracer_ = std::make_unique<PhotonTracer>(scene, g, settings_);
}
ObservedPhotons::~ObservedPhotons() = default;
const PhotonSource& ObservedPhotons::source() const { return tracer_->source(); }
void ObservedPhotons::trace(uint64_t index, PhotonObserver& observer) const {
    ChunkResult none;
    tracer_->trace(index, none, nullptr, &observer);
}

PhotonSource PhotonSource::of(const Scene& scene, BandGroup g) {
    PhotonSource s;
    const ir::Domain& d = scene.domain();
    s.x0 = d.x0;
    s.y0 = d.y0;
    s.lx = d.x1 - d.x0;
    s.ly = d.y1 - d.y0;
    s.area = s.lx * s.ly;
    const BBox3 b = scene.geometry().bounds();
    s.z = (b.empty() ? 0.0 : b.hi.z) + 1e-3 * std::max(1.0, b.empty() ? 1.0 : b.hi.z - b.lo.z);
    s.zLow = b.empty() ? 0.0 : b.lo.z;
    s.sunFlux = Spec(g.count);
    s.skyFlux = Spec(g.count);
    const SunSource& sun = scene.sun();
    const double cz = sun.direction.z;
    double sumSun = 0, sumSky = 0;
    for (int i = 0; i < g.count; ++i) {
        if (sun.enabled && cz > 0) s.sunFlux[i] = sun.irradiance[g.begin + i] * cz * s.area;
        s.skyFlux[i] = kPi * scene.sky().radiance[g.begin + i] * s.area;
        sumSun += s.sunFlux[i];
        sumSky += s.skyFlux[i];
    }
    s.pSun = sumSun + sumSky > 0 ? sumSun / (sumSun + sumSky) : 0;
    s.meanFlux = (sumSun + sumSky) / g.count;
    return s;
}

EmissionImportance EmissionImportance::fromPilot(const std::vector<uint64_t>& emitted,
                                                 const std::vector<uint64_t>& stored) {
    EmissionImportance imp;
    for (int s = 0; s < 2; ++s) {
        // u_c: the share of the cell's pilot photons that stored, shrunk toward the source's mean
        // share by kPrior photons' worth (so that cells equally useful, ~64 pilot photons each, do
        // not get weights that differ by their binomial noise).
        constexpr double kPrior = 16;
        std::vector<double> u(N, 0.0);
        uint64_t em = 0, st = 0;
        for (int c = 0; c < N; ++c) em += emitted[s * N + c], st += stored[s * N + c];
        const double mean = em > 0 ? static_cast<double>(st) / static_cast<double>(em) : 1.0;
        double sum = 0;
        for (int c = 0; c < N; ++c) {
            u[c] = (static_cast<double>(stored[s * N + c]) + kPrior * mean) /
                   (static_cast<double>(emitted[s * N + c]) + kPrior);
            sum += u[c];
        }
        // The importance density, worth it only if it stores at least kMinGain times as often per
        // photon as the uniform one (sum_c p_c u_c against the mean u); else uniform, weight 1.
        std::vector<double> p(N, 1.0 / N);
        double gain = 0;
        if (sum > 0)
            for (int c = 0; c < N; ++c) p[c] = 0.9 * u[c] / sum + 0.1 / N, gain += p[c] * u[c];
        imp.active[s] = sum > 0 && gain / (sum / N) >= kMinGain;
        if (!imp.active[s]) p.assign(N, 1.0 / N);
        imp.cdf[s].resize(N);
        imp.weight[s].resize(N);
        double acc = 0;
        for (int c = 0; c < N; ++c) {
            imp.weight[s][c] = (1.0 / N) / p[c];
            acc += p[c];
            imp.cdf[s][c] = acc;
        }
        for (double& v : imp.cdf[s]) v /= acc;  // exactly 1 at the end
    }
    return imp;
}

EmittedPhoton emitPhoton(const Scene& scene, const PhotonSource& src, RandomStream& rng,
                         const EmissionImportance* importance) {
    const SunSource& sun = scene.sun();
    EmittedPhoton e;
    e.fromSun = rng.uniform() < src.pSun;
    double ux = rng.uniform(), uy = rng.uniform();
    const double u1 = rng.uniform(), u2 = rng.uniform();
    constexpr int K = EmissionImportance::kCells;
    double weight = 1;
    if (importance) {
        // The cell from ux through the cell probabilities; ux's place within its step, and uy,
        // place the photon uniformly inside the cell.
        const std::vector<double>& cdf = importance->cdf[e.fromSun ? 0 : 1];
        const int c = static_cast<int>(std::min<size_t>(std::upper_bound(cdf.begin(), cdf.end(), ux) - cdf.begin(),
                                                        cdf.size() - 1));
        const double lo = c > 0 ? cdf[static_cast<size_t>(c - 1)] : 0.0, hi = cdf[static_cast<size_t>(c)];
        const double f = hi > lo ? std::clamp((ux - lo) / (hi - lo), 0.0, std::nextafter(1.0, 0.0)) : 0.5;
        ux = (c % K + f) / K;
        uy = (c / K + uy) / K;
        weight = importance->weight[e.fromSun ? 0 : 1][static_cast<size_t>(c)];
        e.cell = c;
    } else {
        e.cell = std::min(K - 1, static_cast<int>(uy * K)) * K + std::min(K - 1, static_cast<int>(ux * K));
    }
    Ray& ray = e.ray;
    ray.o = {src.x0 + ux * src.lx, src.y0 + uy * src.ly, src.z};
    if (e.fromSun) ray.d = -sun.sampleDirection(u1, u2);
    else ray.d = -sampleCosineHemisphere(u1, u2);
    // The sources light an infinite horizontal plane, and the domain stands for one period of
    // it: the air above the scene is periodic too. A photon that would leave the domain's plan
    // view before its first hit continues from the opposite side (up to 256 times; only
    // grazing sky photons need more), so it lands inside, wherever it started and however
    // grazing the light. (Moving the origin by whole periods instead, from where the ray
    // would land, misjudges rays that miss the scene outside the domain: they were lost
    // under the scene, 0.104 m / L of the sun's photons for a 60 degree sun 0.06 m above a
    // flat sea, 5% of a 2 m domain.) Periodic domains are exactly this; in bounded ones the
    // scene around the landing point stands in for the scene outside the domain.
    for (int k = 0; k < 256 && ray.d.z < 0; ++k) {
        SurfaceHit first;
        const double tHit = scene.geometry().intersect(ray, &first) ? first.t : (src.zLow - ray.o.z) / ray.d.z;
        double tExit = ir::kInfinity;
        int axis = -1;
        auto exitAt = [&](double o, double d, double lo, double len, int ax) {
            if (d == 0) return;
            const double t = ((d > 0 ? lo + len : lo) - o) / d;
            if (t < tExit) tExit = t, axis = ax;
        };
        exitAt(ray.o.x, ray.d.x, src.x0, src.lx, 0);
        exitAt(ray.o.y, ray.d.y, src.y0, src.ly, 1);
        if (axis < 0 || tHit <= tExit) break;
        Point3 p = ray.at(tExit);
        if (axis == 0) p.x = ray.d.x > 0 ? src.x0 : src.x0 + src.lx;
        else p.y = ray.d.y > 0 ? src.y0 : src.y0 + src.ly;
        ray.o = p;
    }
    // Relative power: Phi_source,b / (P(source) Phi_mean).
    e.power = (e.fromSun ? src.sunFlux * (1.0 / src.pSun) : src.skyFlux * (1.0 / (1.0 - src.pSun))) *
              (weight / src.meanFlux);
    return e;
}

namespace {

// Fills the maps of one pass to their targets. Chunks of kChunk photons are traced in waves: the
// first has one chunk per thread; later ones as many as the stored rate so far says the open maps
// still need (rounded up to whole rounds of the threads, at most 8 rounds), so a small target does
// not trace a wave it then discards. The maps depend only on the chunks appended in order, not on
// the waves.
class MapFiller {
public:
    MapFiller(const PhotonTracer& tracer, BandGroup g, const PhotonPassSettings& st, PhotonMaps& maps)
        : tracer_(tracer), g_(g), st_(st), maps_(maps), closedS_(st.surfaceTarget == 0), closedV_(st.volumeTarget == 0),
          maxEmitted_(st.maxEmitted > 0 ? st.maxEmitted
                                        : std::max<uint64_t>(10'000'000, 1000 * std::max(st.surfaceTarget, st.volumeTarget))),
          // A round: a chunk for every thread of every rank.
          perRound_(static_cast<uint64_t>(std::max(2, st.threads > 0 ? st.threads : tbb::info::default_concurrency())) *
                    static_cast<uint64_t>(ranks().size())) {
        // The maps' final size is known to within a chunk: reserving it makes appending one copy.
        // (Capped by the memory budget's check of the targets, render/estimator.cpp.)
        auto reserve = [](PhotonMap& m, uint64_t target) {
            if (target > 0)
                m.reserve(static_cast<size_t>(std::min<uint64_t>(target + target / 16 + 4 * kChunk, uint64_t{1} << 34)));
        };
        reserve(maps.surface, st.surfaceTarget);
        reserve(maps.volume, st.volumeTarget);
    }
    bool done() const { return (closedS_ && closedV_) || chunk0_ * kChunk >= maxEmitted_; }
    bool full() const { return closedS_ && closedV_; }
    bool closedSurface() const { return closedS_; }
    bool closedVolume() const { return closedV_; }
    // Traces the next wave and appends its chunks in order until the maps are full.
    void wave(tbb::task_arena& arena) {
        const uint64_t n = waveSize();
        // Chunk buffers are reused from wave to wave (no fresh pages, no regrowth once they have
        // seen a chunk's worth).
        if (results_.size() < n) {
            const size_t old = results_.size();
            results_.resize(n);
            for (size_t k = old; k < n; ++k) {
                results_[k].surface = PhotonMap(g_.count, true);
                results_[k].volume = PhotonMap(g_.count, false);
            }
        }
        const bool pilot = st_.importance && chunk0_ == 0;
        for (uint64_t k = 0; k < n; ++k) {
            results_[k].surface.clear(), results_[k].volume.clear();
            results_[k].emitted.assign(pilot ? 2 * EmissionImportance::N : 0, 0);
            results_[k].stored.assign(pilot ? 2 * EmissionImportance::N : 0, 0);
        }
        const EmissionImportance* imp = importanceUsed() ? &importance_ : nullptr;
        // The ranks of a run share the wave's chunks, and every rank gets every chunk's photons.
        distributeItems(
            n, 0, ShareWith::AllRanks,
            [&](uint64_t c0, uint64_t c1) {
                arena.execute([&] {
                    tbb::parallel_for(tbb::blocked_range<uint64_t>(c0, c1, 1), [&](const tbb::blocked_range<uint64_t>& rr) {
                        for (uint64_t c = rr.begin(); c != rr.end(); ++c) {
                            const uint64_t first = (chunk0_ + c) * kChunk;
                            for (uint64_t k = 0; k < kChunk; ++k) tracer_.trace(first + k, results_[c], imp);
                            flushRayStats();
                        }
                    });
                });
            },
            [&](uint64_t c, ByteWriter& w) {
                results_[c].surface.pack(w), results_[c].volume.pack(w);
                w.putArray(results_[c].emitted.data(), results_[c].emitted.size());
                w.putArray(results_[c].stored.data(), results_[c].stored.size());
            },
            [&](uint64_t c, ByteReader& r) {
                results_[c].surface.unpack(r), results_[c].volume.unpack(r);
                r.getArray(results_[c].emitted), r.getArray(results_[c].stored);
            });
        // The pilot's photons only teach the emission density: their stores are dropped, so every
        // stored photon comes from that one density (the pilot's uniform photons would carry up to
        // 1 / (0.9 N u_c / sum u) times the flux of the others and dominate the noise).
        // When the pilot finds nothing to gain, its photons were emitted as every later one will
        // be: they are kept, and the maps are those of uniform emission, chunk for chunk.
        if (pilot) learnImportance(n);
        if (pilot && importanceUsed()) pilotChunks_ = n;
        else append(n);
        chunk0_ += n;
    }
    bool importanceUsed() const { return importance_.active[0] || importance_.active[1]; }

private:
    // The pilot of importance emission: a fixed number of chunks (the same for any thread count).
    static constexpr uint64_t kPilotChunks = 4;
    void learnImportance(uint64_t n) {
        std::vector<uint64_t> emitted(2 * EmissionImportance::N, 0), stored(emitted.size(), 0);
        for (uint64_t c = 0; c < n; ++c)
            for (size_t k = 0; k < emitted.size(); ++k)
                emitted[k] += results_[c].emitted[k], stored[k] += results_[c].stored[k];
        importance_ = EmissionImportance::fromPilot(emitted, stored);
    }
    uint64_t waveSize() const {
        const uint64_t cap = (maxEmitted_ + kChunk - 1) / kChunk;
        if (chunk0_ == 0) return std::min(st_.importance ? kPilotChunks : perRound_, cap);
        const uint64_t kept = chunk0_ - pilotChunks_;  // chunks appended so far
        const uint64_t left = (maxEmitted_ - chunk0_ * kChunk + kChunk - 1) / kChunk;
        if (kept == 0) return std::min(perRound_, left);
        double need = 0;
        auto still = [&](bool closed, uint64_t have, uint64_t target) {
            if (closed) return;
            const double perChunk = static_cast<double>(have) / static_cast<double>(kept);
            need = std::max(need, perChunk > 0 ? static_cast<double>(target - have) / perChunk : 1e18);
        };
        still(closedS_, maps_.surface.size(), st_.surfaceTarget);
        still(closedV_, maps_.volume.size(), st_.volumeTarget);
        const double rounds = std::ceil(std::min(need * 1.05 + 1, 1e12) / static_cast<double>(perRound_));
        // Never more chunks than the emission cap leaves (done() stops the waves before it is reached).
        return std::min(perRound_ * static_cast<uint64_t>(std::clamp(rounds, 1.0, 8.0)), left);
    }
    void append(uint64_t n) {
        for (uint64_t c = 0; c < n && !full(); ++c) {
            const uint64_t emittedAfter = (chunk0_ - pilotChunks_ + c + 1) * kChunk;  // the pilot not counted
            if (!closedS_) {
                maps_.surface.append(results_[c].surface);
                if (maps_.surface.size() >= st_.surfaceTarget) closedS_ = true, maps_.emittedSurface = emittedAfter;
            }
            if (!closedV_) {
                maps_.volume.append(results_[c].volume);
                if (maps_.volume.size() >= st_.volumeTarget) closedV_ = true, maps_.emittedVolume = emittedAfter;
            }
            maps_.emitted = emittedAfter;
            if (emittedAfter >= maxEmitted_) break;
        }
    }

    const PhotonTracer& tracer_;
    BandGroup g_;
    const PhotonPassSettings& st_;
    PhotonMaps& maps_;
    bool closedS_, closedV_;
    uint64_t maxEmitted_, perRound_;
    uint64_t chunk0_ = 0;
    std::vector<ChunkResult> results_;
    EmissionImportance importance_;  // empty until the pilot is done
    uint64_t pilotChunks_ = 0;
};

}  // namespace

PhotonMaps tracePhotons(const Scene& scene, BandGroup g, const PhotonPassSettings& st) {
    const auto t0 = std::chrono::steady_clock::now();
    PhotonMaps maps;
    maps.surface = PhotonMap(g.count, true);
    maps.volume = PhotonMap(g.count, false);
    const PhotonTracer tracer(scene, g, st);
    const PhotonSource& src = tracer.source();
    const bool wantS = st.surfaceTarget > 0, wantV = st.volumeTarget > 0;
    if ((!wantS && !wantV) || src.meanFlux <= 0) return maps;
    std::unique_ptr<Progress> progress;
    const uint64_t goal = std::max(st.surfaceTarget, st.volumeTarget);
    if (st.progress) progress = std::make_unique<Progress>("photons", goal, "photons");
    MapFiller filler(tracer, g, st, maps);
    tbb::task_arena arena(st.threads > 0 ? st.threads : tbb::task_arena::automatic);
    while (!filler.done()) {
        filler.wave(arena);
        if (progress) {
            const uint64_t done = std::min(goal, std::min(wantS ? maps.surface.size() : goal, wantV ? maps.volume.size() : goal));
            if (done > progress->done()) progress->advance(done - progress->done());
        }
    }
    if (progress) progress->finish();
    // A map the cap left open holds what the emitted photons stored.
    if (!filler.closedSurface()) maps.emittedSurface = maps.emitted;
    if (!filler.closedVolume()) maps.emittedVolume = maps.emitted;
    if (!filler.full())
        log::warn("photon pass: {} photons emitted (the cap) before the maps were full: surface {} of {}, volume {} of "
                  "{} stored; the maps hold what was stored",
                  maps.emitted, maps.surface.size(), st.surfaceTarget, maps.volume.size(), st.volumeTarget);
    // Flux per photon: the total source flux over the photons emitted while filling each map.
    auto scale = [&](PhotonMap& m, uint64_t emitted, double radius) {
        m.fluxScale.assign(g.count, emitted > 0 ? src.meanFlux / static_cast<double>(emitted) : 0.0);
        m.build(radius);
    };
    scale(maps.surface, maps.emittedSurface, st.surfaceRadius);
    scale(maps.volume, maps.emittedVolume, st.volumeRadius);
    statCounter("photons emitted").add(static_cast<int64_t>(maps.emitted));
    statCounter("photons stored (surface)").add(static_cast<int64_t>(maps.surface.size()));
    statCounter("photons stored (volume)").add(static_cast<int64_t>(maps.volume.size()));
    maps.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    log::info("photon pass: {} photons emitted{}, {} stored ({} surface, {} volume): {:.1f} % of the emitted, in "
              "{:.2f} s",
              maps.emitted, filler.importanceUsed() ? " (importance emission)" : "", maps.surface.size() + maps.volume.size(),
              maps.surface.size(), maps.volume.size(),
              maps.emitted > 0 ? 100.0 * static_cast<double>(maps.surface.size() + maps.volume.size()) /
                                     static_cast<double>(maps.emitted)
                               : 0.0,
              maps.seconds);
    return maps;
}

namespace {

constexpr uint64_t kDepthPilotPass = 1ull << 45, kDepthPilotStageStride = 1ull << 44;

// (z, Eo up to a constant) per depth bin of the volume map of the first medium that keeps one.
std::vector<std::pair<double, double>> volumeDepthProfile(const Scene& scene, BandGroup g, const PhotonPassSettings& st,
                                                         const PhotonMap& vm) {
    constexpr int kBins = 64;
    constexpr double kMinPhotons = 32;
    size_t medium = 0;
    while (medium < st.volumeMedium.size() && !st.volumeMedium[medium]) ++medium;
    if (medium >= st.volumeMedium.size() || vm.size() == 0) return {};
    const Medium& md = scene.media()[medium];
    double zLo = ir::kInfinity, zHi = -ir::kInfinity;
    for (size_t i = 0; i < vm.size(); ++i) zLo = std::min(zLo, vm.position(i).z), zHi = std::max(zHi, vm.position(i).z);
    const double width = (zHi - zLo) / kBins;
    if (!(width > 0)) return {};
    std::vector<double> sum(kBins, 0.0), count(kBins, 0.0);
    for (size_t i = 0; i < vm.size(); ++i) {
        const double z = vm.position(i).z;
        const MediumLayer& l = md.layers()[static_cast<size_t>(md.layerAt(z))];
        const int k = std::min(kBins - 1, static_cast<int>((zHi - z) / width));
        const double b = st.effectiveScattering ? l.cEff[g.begin] - l.a[g.begin] : l.b[g.begin];
        if (!(b > 0)) continue;
        sum[k] += vm.power(i, 0) / b, count[k] += 1;
    }
    std::vector<std::pair<double, double>> profile;
    for (int k = 0; k < kBins; ++k)
        if (count[k] >= kMinPhotons) profile.emplace_back(zHi - (k + 0.5) * width, sum[k]);
    return profile;
}

}  // namespace

DepthImportance volumeDepthImportance(const Scene& scene, BandGroup g, const PhotonPassSettings& st) {
    PhotonPassSettings pilot = st;
    pilot.surfaceTarget = 0;
    pilot.volumeTarget = std::max<uint64_t>(st.volumeTarget / 32, 8192);
    pilot.progress = false;
    pilot.depthImportance = {};
    DepthImportance d;
    for (uint64_t stage = 0; stage < 2; ++stage) {
        pilot.pass = st.pass + kDepthPilotPass + stage * kDepthPilotStageStride;
        const PhotonMaps maps = tracePhotons(scene, g, pilot);
        DepthImportance next = DepthImportance::fromProfile(volumeDepthProfile(scene, g, pilot, maps.volume));
        if (next.empty()) break;
        d = std::move(next);
        pilot.depthImportance = d;
    }
    if (!d.empty())
        log::info("photon pass: split by depth, importance {:.3g} at {:.2f} m to {:.3g} at {:.2f} m (pilot)",
                  std::exp(d.logI.front()), d.z.front(), std::exp(d.logI.back()), d.z.back());
    return d;
}

}  // namespace littoral::render
