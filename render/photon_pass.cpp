#include "render/photon_pass.h"

#include <algorithm>
#include <chrono>
#include <cmath>

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
#include "render/sampling.h"

namespace littoral::render {

namespace {

constexpr uint64_t kPhotonPassBase = 1ull << 50;  // random-stream passes of the photon pass
constexpr uint64_t kChunk = 16384;                // photons per chunk

struct Source {
    double area = 0;
    double x0 = 0, y0 = 0, lx = 0, ly = 0, z = 0;
    double zLow = 0;  // the scene's lowest point
    Spec sunFlux, skyFlux;  // per band, W um^-1
    double pSun = 0;        // probability of emitting from the sun
    double meanFlux = 0;    // band-averaged total flux
};

Source makeSource(const Scene& scene, BandGroup g) {
    Source s;
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

struct ChunkResult {
    PhotonMap surface, volume;
};

}  // namespace

PhotonMaps tracePhotons(const Scene& scene, BandGroup g, const PhotonPassSettings& st) {
    const auto t0 = std::chrono::steady_clock::now();
    PhotonMaps maps;
    maps.surface = PhotonMap(g.count, true);
    maps.volume = PhotonMap(g.count, false);
    const Source src = makeSource(scene, g);
    const bool wantS = st.surfaceTarget > 0, wantV = st.volumeTarget > 0;
    if ((!wantS && !wantV) || src.meanFlux <= 0) return maps;
    const uint64_t maxEmitted =
        st.maxEmitted > 0 ? st.maxEmitted : std::max<uint64_t>(10'000'000, 1000 * std::max(st.surfaceTarget, st.volumeTarget));
    const double cosCone = 1.0 - kEffectiveConeSr / (2.0 * kPi);
    const SunSource& sun = scene.sun();

    // One photon: trace it and append what it stores to `out`.
    auto tracePhoton = [&](uint64_t index, ChunkResult& out) {
        RandomStream rng(st.seed, kPhotonPassBase + st.pass, index);
        const bool fromSun = rng.uniform() < src.pSun;
        const double ux = rng.uniform(), uy = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
        Ray ray;
        ray.o = {src.x0 + ux * src.lx, src.y0 + uy * src.ly, src.z};
        if (fromSun) ray.d = -sun.sampleDirection(u1, u2);
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
            const double tHit =
                scene.geometry().intersect(ray, &first) ? first.t : (src.zLow - ray.o.z) / ray.d.z;
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
        Spec w = (fromSun ? src.sunFlux * (1.0 / src.pSun) : src.skyFlux * (1.0 / (1.0 - src.pSun))) * (1.0 / src.meanFlux);
        int medium = 0, events = 0, specular = 0, wraps = 0;
        auto roulette = [&]() {
            const double q = std::min(1.0, w.maxValue());
            if (rng.uniform() >= q || !(q > 0)) return false;
            w *= 1.0 / q;
            return true;
        };
        for (;;) {
            SurfaceHit h;
            bool hit;
            const Medium& md = scene.media()[medium];
            if (md.scattering()) {
                // The free flight first, then the geometry only up to it (Scene::flightToSurface).
                const double uBand = rng.uniform(), uDist = rng.uniform();
                const FreeFlight ff = scene.flightToSurface(ray, medium, g, uBand, uDist, &h, &hit);
                w *= ff.weight;
                if (ff.scattered) {
                    if (w.isBlack() || ++events > st.maxBounces) return;
                    const Point3 x = ray.at(ff.t);
                    Spec pw;
                    const Vec3 wi = md.samplePhase(ff.layer, g, ray.d, rng, &pw);
                    const bool forward = st.effectiveScattering && dot(wi, ray.d) > cosCone;
                    if (!forward && st.volumeMedium[medium]) out.volume.add(x, ray.d, Vec3{0, 0, 1}, w);
                    if (!forward) {
                        w *= pw;
                        ray = Ray{x, wi};
                    } else {
                        ray = Ray{x, ray.d};
                    }
                    if (!roulette()) return;
                    continue;
                }
                if (w.isBlack()) return;
            } else if (md.attenuating()) {
                hit = scene.geometry().intersect(ray, &h);
                if (!hit) return;
                w *= md.transmittance(ray, h.t, g);
            } else {
                hit = scene.geometry().intersect(ray, &h);
            }
            if (!hit) return;
            const MaterialData& m = scene.material(h);
            if (m.isPeriodicWall()) {
                const auto next = scene.wrapRay(h, ray.d);
                if (!next) {
                    static StatCounter& lost = statCounter("photons lost at periodic walls");
                    lost.add();
                    return;
                }
                if (++wraps > Scene::kMaxWraps) return;
                ray = *next;
                continue;
            }
            const BxDF bxdf = scene.bxdf(h, g);
            if (bxdf.isDelta() || bxdf.isGlossy()) {
                // Interfaces, smooth or rough: one direction sampled from the BxDF in importance
                // mode, weighted by f |cos| / pdf (1 for the smooth one; for the rough one the
                // fraction of its weight a single-scattering microfacet model keeps).
                if (++specular > 1000) return;
                const Frame frame = scene.shadingFrame(h);
                const Vec3 wo = frame.toLocal(-ray.d);
                const double uc = rng.uniform(), v1 = rng.uniform(), v2 = rng.uniform();
                if (std::abs(wo.z) < 1e-12) {
                    ray = spawnRay(h.p, h.ng, ray.d);
                    medium = scene.nearMedium(h);
                    continue;
                }
                const auto s = bxdf.sample(wo, uc, Vec2{v1, v2}, TransportMode::Importance);
                if (!s || s->pdf <= 0) return;
                w *= s->f * std::abs(s->wi.z) / s->pdf;
                medium = s->isTransmission() ? scene.farMedium(h) : scene.nearMedium(h);
                ray = spawnRay(h.p, h.ng, frame.toWorld(s->wi));
                continue;
            }
            const Spec rho = scene.albedo(h, g);
            const Normal3 n = h.front ? h.ng : -h.ng;
            if (st.surfaceMaterial[scene.materialIndex(h)]) out.surface.add(h.p, ray.d, n, w);
            if (rho.isBlack() || ++events > st.maxBounces) return;
            w *= rho;
            if (!roulette()) return;
            const Frame frame = Frame::fromNormal(n);
            const double v1 = rng.uniform(), v2 = rng.uniform();
            ray = spawnRay(h.p, h.ng, normalize(frame.toWorld(sampleCosineHemisphere(v1, v2))));
        }
    };

    const int threads = st.threads > 0 ? st.threads : tbb::info::default_concurrency();
    // Chunks are traced in waves: the first has one chunk per thread; later ones as many as the
    // stored rate so far says the open maps still need (rounded up to whole rounds of the
    // threads, at most 8 rounds), so a small target does not trace a wave it then discards. The
    // maps depend only on the chunks appended in order, not on the waves.
    const uint64_t perRound = static_cast<uint64_t>(std::max(2, threads));
    std::unique_ptr<Progress> progress;
    const uint64_t goal = std::max(st.surfaceTarget, st.volumeTarget);
    if (st.progress) progress = std::make_unique<Progress>("photons", goal, "photons");
    bool closedS = !wantS, closedV = !wantV;
    uint64_t chunk0 = 0;
    std::vector<ChunkResult> results;
    // The maps' final size is known to within a chunk: reserving it makes appending one copy.
    // (Capped by the memory budget's check of the targets, render/estimator.cpp.)
    if (wantS) maps.surface.reserve(static_cast<size_t>(std::min<uint64_t>(st.surfaceTarget + st.surfaceTarget / 16 + 4 * kChunk, uint64_t{1} << 34)));
    if (wantV) maps.volume.reserve(static_cast<size_t>(std::min<uint64_t>(st.volumeTarget + st.volumeTarget / 16 + 4 * kChunk, uint64_t{1} << 34)));
    tbb::task_arena arena(st.threads > 0 ? st.threads : tbb::task_arena::automatic);
    while (!(closedS && closedV) && chunk0 * kChunk < maxEmitted) {
        uint64_t wave = perRound;
        if (chunk0 > 0) {
            double need = 0;
            auto still = [&](bool closed, uint64_t have, uint64_t target) {
                if (closed) return;
                const double perChunk = static_cast<double>(have) / static_cast<double>(chunk0);
                need = std::max(need, perChunk > 0 ? static_cast<double>(target - have) / perChunk : 1e18);
            };
            still(closedS, maps.surface.size(), st.surfaceTarget);
            still(closedV, maps.volume.size(), st.volumeTarget);
            const double rounds = std::ceil(std::min(need * 1.05 + 1, 1e12) / static_cast<double>(perRound));
            wave = perRound * static_cast<uint64_t>(std::clamp(rounds, 1.0, 8.0));
        }
        // Chunk buffers are reused from wave to wave (no fresh pages, no regrowth once they have
        // seen a chunk's worth), and the maps are reserved for their targets plus a chunk.
        if (results.size() < wave) {
            const size_t old = results.size();
            results.resize(wave);
            for (size_t k = old; k < wave; ++k) {
                results[k].surface = PhotonMap(g.count, true);
                results[k].volume = PhotonMap(g.count, false);
            }
        }
        for (uint64_t k = 0; k < wave; ++k) results[k].surface.clear(), results[k].volume.clear();
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<uint64_t>(0, wave, 1), [&](const tbb::blocked_range<uint64_t>& rr) {
                for (uint64_t c = rr.begin(); c != rr.end(); ++c) {
                    const uint64_t first = (chunk0 + c) * kChunk;
                    for (uint64_t k = 0; k < kChunk; ++k) tracePhoton(first + k, results[c]);
                    flushRayStats();
                }
            });
        });
        for (uint64_t c = 0; c < wave && !(closedS && closedV); ++c) {
            const uint64_t emittedAfter = (chunk0 + c + 1) * kChunk;
            if (!closedS) {
                maps.surface.append(results[c].surface);
                if (maps.surface.size() >= st.surfaceTarget) closedS = true, maps.emittedSurface = emittedAfter;
            }
            if (!closedV) {
                maps.volume.append(results[c].volume);
                if (maps.volume.size() >= st.volumeTarget) closedV = true, maps.emittedVolume = emittedAfter;
            }
            maps.emitted = emittedAfter;
            if (emittedAfter >= maxEmitted) break;
        }
        chunk0 += wave;
        if (progress) {
            const uint64_t done = std::min(goal, std::min(wantS ? maps.surface.size() : goal, wantV ? maps.volume.size() : goal));
            if (done > progress->done()) progress->advance(done - progress->done());
        }
    }
    if (progress) progress->finish();
    if (!closedS) maps.emittedSurface = maps.emitted;
    if (!closedV) maps.emittedVolume = maps.emitted;
    if ((!closedS || !closedV))
        log::warn("photon pass: {} photons emitted (the cap) before the maps were full: surface {} of {}, volume {} of "
                  "{} stored; the maps hold what was stored",
                  maps.emitted, maps.surface.size(), st.surfaceTarget, maps.volume.size(), st.volumeTarget);
    // Flux per photon: the total source flux over the photons emitted while filling each map.
    auto scale = [&](PhotonMap& m, uint64_t emitted) {
        m.fluxScale.assign(g.count, emitted > 0 ? src.meanFlux / static_cast<double>(emitted) : 0.0);
        m.build(st.cellSize);
    };
    scale(maps.surface, maps.emittedSurface);
    scale(maps.volume, maps.emittedVolume);
    statCounter("photons emitted").add(static_cast<int64_t>(maps.emitted));
    statCounter("photons stored (surface)").add(static_cast<int64_t>(maps.surface.size()));
    statCounter("photons stored (volume)").add(static_cast<int64_t>(maps.volume.size()));
    maps.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    log::debug("photon pass: {} emitted, {} surface and {} volume photons stored in {:.2f} s", maps.emitted,
               maps.surface.size(), maps.volume.size(), maps.seconds);
    return maps;
}

}  // namespace littoral::render
