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

double photonMapBytes(const PhotonPassSettings& s, int bands) {
    // Records, the grid (one 4-byte bucket start per photon, rounded up to a power of two: at most
    // 2x), and one chunk of overshoot per map.
    auto one = [&](uint64_t target, bool normals) {
        if (target == 0) return 0.0;
        const double n = static_cast<double>(target + kChunk * 8);
        return n * static_cast<double>(PhotonMap::bytesPerPhoton(bands, normals)) + 2.0 * n * 4.0;
    };
    return one(s.surfaceTarget, true) + one(s.volumeTarget, false);
}

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
        // The sources light an infinite horizontal plane; the domain receives the part of it whose
        // first landing point lies inside. A photon whose first hit (or, if it hits nothing, its
        // crossing of the scene's lowest level) falls outside is moved by whole domain periods so
        // that it falls inside: uniform emission over one period of an infinite plane, so every
        // point of the domain sees the whole sky and sun, however close to the domain's edge and
        // however grazing the light (periodic domains are exactly this; elsewhere the scene around
        // the first landing point stands in for the scene outside the domain).
        for (int tries = 0; tries < 3 && ray.d.z < 0; ++tries) {
            SurfaceHit first;
            const Point3 c = scene.geometry().intersect(ray, &first) ? first.p : ray.at((src.zLow - ray.o.z) / ray.d.z);
            const double kx = std::floor((c.x - src.x0) / src.lx), ky = std::floor((c.y - src.y0) / src.ly);
            if (kx == 0 && ky == 0) break;
            ray.o.x -= kx * src.lx;
            ray.o.y -= ky * src.ly;
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
            const bool hit = scene.geometry().intersect(ray, &h);
            const Medium& md = scene.media()[medium];
            if (md.scattering()) {
                const double uBand = rng.uniform(), uDist = rng.uniform();
                const FreeFlight ff = md.sampleFreeFlight(ray, hit ? h.t : ir::kInfinity, g, uBand, uDist);
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
                if (!hit) return;
                w *= md.transmittance(ray, h.t, g);
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
    const uint64_t wave = static_cast<uint64_t>(std::max(8, threads * 8));
    std::unique_ptr<Progress> progress;
    const uint64_t goal = std::max(st.surfaceTarget, st.volumeTarget);
    if (st.progress) progress = std::make_unique<Progress>("photons", goal, "photons");
    bool closedS = !wantS, closedV = !wantV;
    uint64_t chunk0 = 0;
    tbb::task_arena arena(st.threads > 0 ? st.threads : tbb::task_arena::automatic);
    while (!(closedS && closedV) && chunk0 * kChunk < maxEmitted) {
        std::vector<ChunkResult> results(wave);
        for (auto& r : results) {
            r.surface = PhotonMap(g.count, true);
            r.volume = PhotonMap(g.count, false);
        }
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
