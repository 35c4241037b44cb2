#include "render/renderer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <set>
#include <string>
#include <utility>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/error.h"
#include "core/log.h"
#include "core/progress.h"
#include "core/rng.h"
#include "render/estimator.h"
#include "render/sampling.h"
#include "render/distributed.h"
#include "render/tile_checkpoint.h"

namespace littoral::render {

namespace {

// A pixel's sums of the water-leaving parts over its samples (Ed(0+) over those that met the sea).
struct PartSums {
    Spec waterLeaving, skyReflected, glint, other, ed0;
    int seaSamples = 0;
    explicit PartSums(int n) : waterLeaving(n), skyReflected(n), glint(n), other(n), ed0(n) {}
    void add(const RadianceParts& p) {
        waterLeaving += p.waterLeaving;
        skyReflected += p.skyReflected;
        glint += p.glint;
        other += p.other;
        if (p.sea) {
            ed0 += p.ed0;
            ++seaSamples;
        }
    }
};

struct Tiling {
    int width, height, size, nx, ny;
    Tiling(int w, int h, int s) : width(w), height(h), size(std::max(1, s)) {
        nx = (w + size - 1) / size;
        ny = (h + size - 1) / size;
    }
    size_t count() const { return static_cast<size_t>(nx) * ny; }
    template <class F> void forEachPixel(size_t tile, F&& f) const {
        const int tx = static_cast<int>(tile % nx), ty = static_cast<int>(tile / nx);
        const int x0 = tx * size, y0 = ty * size;
        const int x1 = std::min(width, x0 + size), y1 = std::min(height, y0 + size);
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) f(x, y);
    }
};

// Calls f(value) for every value of the image's films in `tile` and the bands of g (for moving
// tiles between ranks).
template <class F>
void forTileValues(SensorImage& img, const Tiling& tiling, size_t tile, int nb, BandGroup g, F&& f) {
    for (Film* film : img.films())
        tiling.forEachPixel(tile, [&](int x, int y) {
            float* p = film->pixels.data() + (static_cast<size_t>(y) * tiling.width + x) * nb + g.begin;
            for (int b = 0; b < g.count; ++b) f(p[b]);
        });
}

// Runs body(tile) for tiles [begin, end) (all of them by default) on the render's threads.
template <class F>
void runTiles(const RenderOptions& opts, const Tiling& tiling, Progress* progress, F&& body, size_t begin = 0,
              size_t end = SIZE_MAX) {
    tbb::task_arena arena(opts.threads > 0 ? opts.threads : tbb::task_arena::automatic);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<size_t>(begin, std::min(end, tiling.count()), 1), [&](const tbb::blocked_range<size_t>& r) {
            for (size_t t = r.begin(); t != r.end(); ++t) {
                body(t);
                flushRayStats();
                if (progress) progress->advance();
            }
        });
    });
}

// Follows a pixel-centre ray through specular interfaces (refracting where possible, reflecting
// under TIR) to the first opaque surface; returns its depth below z = 0 (0 above), NaN if none,
// and sets *surface to its material index (left at -1 if none).
float truthDepth(const Scene& scene, Ray ray, int maxEvents, int32_t* surface, SurfaceHit* opaque) {
    SurfaceHit h;
    for (int e = 0; e <= maxEvents; ++e) {
        if (!scene.geometry().intersect(ray, &h)) return std::numeric_limits<float>::quiet_NaN();
        const MaterialData& m = scene.material(h);
        if (m.isPeriodicWall()) {
            const auto next = scene.wrapRay(h, ray.d);
            if (!next) return std::numeric_limits<float>::quiet_NaN();
            ray = *next;
            continue;
        }
        if (m.isOpaque()) {
            *surface = scene.materialIndex(h);
            *opaque = h;
            return static_cast<float>(h.p.z < 0 ? -h.p.z : 0.0);
        }
        const double nO = scene.media()[scene.nearMedium(h)].n(0);
        const double nT = scene.media()[scene.farMedium(h)].n(0);
        const Normal3 n = h.front ? h.ng : -h.ng;
        Vec3 wt;
        if (refract(-ray.d, n, nO / nT, &wt)) {
            ray = spawnRay(h.p, h.ng, normalize(wt));
        } else {
            ray = spawnRay(h.p, h.ng, normalize(reflect(-ray.d, n)));
        }
    }
    return std::numeric_limits<float>::quiet_NaN();
}

}  // namespace

namespace {
// Calls f(hit) for the first hit of a ray from p along each of the six axis directions that hits.
template <class F> void forEachAxisHit(const Scene& scene, const Point3& p, F&& f) {
    static const Vec3 dirs[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const Vec3& d : dirs) {
        Ray r;
        r.o = p;
        r.d = d;
        SurfaceHit h;
        if (scene.geometry().intersect(r, &h) && !f(h)) return;
    }
}
}  // namespace

void checkPositionInRange(const Point3& p, const std::string& who) {
    for (double c : {p.x, p.y, p.z})
        if (!(std::abs(c) <= kMaxPositionM))
            throw InputError(fmt::format("{}: position ({}, {}, {}) lies beyond {:g} m from the origin; positions must be "
                                         "finite and within {:g} m in each coordinate (rays from farther away lose "
                                         "their precision in single-precision ray tracing)",
                                         who, p.x, p.y, p.z, kMaxPositionM, kMaxPositionM));
}

void checkNotInsideOpaque(const Scene& scene, const Point3& p, const std::string& who) {
    forEachAxisHit(scene, p, [&](const SurfaceHit& h) {
        const MaterialData& m = scene.material(h);
        // A closed mesh that encloses a medium (a water volume, even with black floor faces) is
        // not an opaque object; one with air inside and an opaque face seen from behind is.
        if (!h.front && m.isOpaque() && scene.meshClosed(h.mesh) && scene.insideMedium(h.mesh) == 0)
            throw InputError(fmt::format("{}: position ({}, {}, {}) is inside the closed opaque mesh '{}' (material "
                                         "'{}'): the camera would see only the inside of the object",
                                         who, p.x, p.y, p.z, scene.ir().meshes[h.mesh].name, m.name));
        return true;
    });
}

// Refuses a medium the camera or probe declares that disagrees with the interfaces around it (e.g.
// a camera inside a water volume declared in air: its first segment would not be attenuated, and
// a probe in air declared in water would attenuate and refract what it reads). Says nothing when
// the surroundings are ambiguous (the six axis rays see different media).
std::string mediumName(const Scene& scene, int m) {
    const std::string& n = scene.media()[static_cast<size_t>(m)].name();
    return n.empty() ? "air" : n;
}

void checkDeclaredMedium(const Scene& scene, const Point3& p, int declared, const std::string& who) {
    int seen = -1, votes = 0;
    bool ambiguous = false;
    forEachAxisHit(scene, p, [&](const SurfaceHit& h) {
        if (!(scene.bxdfFlags(h) & kTransmission)) return true;
        const int m = h.front ? scene.outsideMedium(h.mesh) : scene.insideMedium(h.mesh);
        if (seen >= 0 && m != seen) return !(ambiguous = true);  // ambiguous surroundings: say nothing
        seen = m;
        ++votes;
        return true;
    });
    if (!ambiguous && votes > 0 && seen != declared)
        throw InputError(fmt::format("{}: declared in medium '{}', but the interfaces around its position ({}, {}, {}) "
                                     "put it in '{}' (a scene file's medium: auto chooses by the water level)",
                                     who, mediumName(scene, declared), p.x, p.y, p.z, mediumName(scene, seen)));
}

void checkClearOfSurfaces(const Scene& scene, const Point3& p, const std::string& who) {
    forEachAxisHit(scene, p, [&](const SurfaceHit& h) {
        const MaterialData& m = scene.material(h);
        if (!m.isOpaque() || h.t >= kSurfaceClearance) return true;
        throw InputError(fmt::format("{}: position ({}, {}, {}) lies {:.3g} m from the surface of mesh '{}' (material "
                                     "'{}'), closer than {} m: its rays would start on the surface and one side would "
                                     "read nothing; move it off the surface",
                                     who, p.x, p.y, p.z, h.t, scene.ir().meshes[h.mesh].name, m.name, kSurfaceClearance));
    });
}

namespace {
// A hit on a vertical face at the domain's edge: a side wall of the water volume or of the seabed
// (what a real site would continue past), seen directly or through the water.
bool onDomainWall(const ir::Domain& d, const SurfaceHit& h) {
    if (std::abs(h.ng.z) > 0.1) return false;
    const double tol = 1e-6 * std::max({1.0, d.x1 - d.x0, d.y1 - d.y0});
    return std::abs(h.p.x - d.x0) < tol || std::abs(h.p.x - d.x1) < tol || std::abs(h.p.y - d.y0) < tol ||
           std::abs(h.p.y - d.y1) < tol;
}

// Pixels that see past the scene: a warning (the image is still what the scene holds), once per
// sensor and only when at least one pixel in 10,000 is affected.
void warnIfViewLeavesDomain(const ir::Domain& d, const std::string& who, int64_t past, int64_t walls, int64_t pixels) {
    if (pixels <= 0 || static_cast<double>(past + walls) < 1e-4 * static_cast<double>(pixels)) return;
    static std::mutex m;
    static std::set<std::string> warned;  // renderTruth runs before and during rendering: say it once
    {
        std::lock_guard<std::mutex> lock(m);
        if (!warned.insert(who).second) return;
    }
    const double pct = 100.0 / static_cast<double>(pixels);
    log::warn("{}: {:.3g} % of the pixels see past the scene's domain (x [{:g}, {:g}], y [{:g}, {:g}] m): {:.3g} % look "
              "down past its edge at nothing and {:.3g} % meet its side walls; they show no scene there (narrow the "
              "view, move the sensor, or enlarge the domain)",
              who, pct * static_cast<double>(past + walls), d.x0, d.x1, d.y0, d.y1, pct * static_cast<double>(past),
              pct * static_cast<double>(walls));
}
}  // namespace

TruthImages renderTruth(const Scene& scene, const ir::Sensor& sensor, const RenderOptions& opts) {
    const Camera cam(sensor);
    const std::string who = fmt::format("sensor '{}'", sensor.name);
    checkPositionInRange(sensor.position, who);
    const int medium = scene.mediumIndex(sensor.medium, who + " medium");
    if (sensor.type == ir::Sensor::Type::Pinhole) {
        checkNotInsideOpaque(scene, sensor.position, who);
        checkDeclaredMedium(scene, sensor.position, medium, who);
    }
    if (sensor.waterProducts) checkWaterProducts(scene, sensor, medium);
    TruthImages truth(cam.width(), cam.height());
    const Tiling tiling(cam.width(), cam.height(), opts.tileSize);
    std::atomic<int64_t> hits{0};
    // The truth images follow at most render.max_specular_depth interface events (16 unless set,
    // whichever estimator renders the radiance).
    const ParamValue* depth = scene.ir().render.settings.find("max_specular_depth");
    const int maxEvents = depth ? static_cast<int>(numberOf(*depth)) : 16;
    std::atomic<int64_t> pastDomain{0}, onWalls{0};
    runTiles(opts, tiling, nullptr, [&](size_t tile) {
        int64_t local = 0, past = 0, walls = 0;
        tiling.forEachPixel(tile, [&](int x, int y) {
            const Ray ray = cam.generateRay(x + 0.5, y + 0.5);
            SurfaceHit h;
            const size_t i = truth.index(x, y);
            if (!scene.geometry().intersect(ray, &h)) {
                past += ray.d.z < 0 ? 1 : 0;  // looking down at nothing: beyond the scene's ground
                return;
            }
            ++local;
            truth.materialId[i] = scene.materialIndex(h);
            truth.range[i] = static_cast<float>(h.t);
            SurfaceHit opaque;
            truth.hitDepth[i] = truthDepth(scene, ray, maxEvents, &truth.surfaceId[i], &opaque);
            const bool wall = onDomainWall(scene.ir().domain, h) ||
                              (truth.surfaceId[i] >= 0 && onDomainWall(scene.ir().domain, opaque));
            walls += wall ? 1 : 0;
        });
        hits += local;
        pastDomain += past;
        onWalls += walls;
    });
    if (hits.load() == 0)
        throw InputError(fmt::format("{}: empty view: none of the {} x {} pixel rays meets any geometry (check "
                                     "position, forward and the field of view)",
                                     who, cam.width(), cam.height()));
    warnIfViewLeavesDomain(scene.ir().domain, who, pastDomain.load(), onWalls.load(),
                           static_cast<int64_t>(cam.width()) * cam.height());
    return truth;
}

std::vector<Film*> SensorImage::films() {
    std::vector<Film*> f{&film};
    if (products)
        for (Film* p : {&products->waterLeaving, &products->skyReflected, &products->glint, &products->other, &products->ed0})
            f.push_back(p);
    if (standardError) f.push_back(&*standardError);
    return f;
}

size_t filmCount(const ir::Sensor& s) { return 1 + (s.waterProducts ? 5 : 0) + (s.samplesPerPixel >= 2 ? 1 : 0); }

std::vector<const Film*> SensorImage::films() const {
    std::vector<const Film*> f;
    for (Film* p : const_cast<SensorImage*>(this)->films()) f.push_back(p);
    return f;
}

void checkWaterProducts(const Scene& scene, const ir::Sensor& sensor, int medium) {
    if (medium != 0)
        throw InputError(fmt::format("sensor '{}': water_products needs a sensor in the air (it is in medium '{}'): the "
                                     "products split what reaches a sensor above the sea surface",
                                     sensor.name, mediumName(scene, medium)));
    if (waterMediumIndex(scene) < 0)
        throw InputError(fmt::format("sensor '{}': water_products needs a water medium (the scene has none): the "
                                     "products split the radiance where it meets the sea surface",
                                     sensor.name));
}

SensorImage renderSensor(const Scene& scene, const ir::Sensor& sensor, const RenderOptions& opts) {
    const EstimatorSet estimators(scene);
    return renderSensor(scene, estimators, sensor, opts);
}

namespace {

// One pixel's sums over n samples: the radiance, its square (for the standard error) and, with
// water products, the parts.
struct PixelSamples {
    Spec sum, sum2;
    PartSums parts;
    explicit PixelSamples(int nb) : sum(nb), sum2(nb), parts(nb) {}
};

// Samples pixels with one band group's estimator. Sample s of a pixel uses the random stream
// firstStream + s of that pixel; n > 1 samples are stratified over the pixel's area.
struct PixelSampler {
    const Camera& cam;
    const Estimator& estimator;
    int medium;
    uint64_t seed;
    bool withParts;
    int bands;

    PixelSamples operator()(int x, int y, uint64_t firstStream, int n) const {
        PixelSamples ps(bands);
        const StratifiedLayout layout(n);
        const uint64_t pixel = static_cast<uint64_t>(y) * cam.width() + x;
        for (int s = 0; s < n; ++s) {
            RandomStream rng(seed, firstStream + static_cast<uint64_t>(s), pixel);
            Vec2 u{0.5, 0.5};  // one sample: the pixel centre (as the thesis' comparators)
            const double j1 = rng.uniform(), j2 = rng.uniform();
            if (n > 1) u = layout.point(s, j1, j2);
            const Ray ray = cam.generateRay(x + u.x, y + u.y);
            Spec v;
            if (withParts) {
                const RadianceParts p = estimator.LiParts(ray, medium, rng);
                ps.parts.add(p);
                v = p.total();
            } else {
                v = estimator.Li(ray, medium, rng);
            }
            ps.sum += v;
            ps.sum2 += v * v;
        }
        return ps;
    }
};

// The pilot samples of render.target_relative_error come from streams of their own (far above any
// pixel's final samples), so that the number of final samples depends on nothing they contain:
// the final mean stays unbiased (docs/rendering.md, "Per-pixel convergence").
constexpr uint64_t kPilotStreamBase = uint64_t{1} << 62;

// The samples a pixel needs for relative standard error `target` in every band, from a pilot of
// n0 samples: sigma^2 / (target mean)^2, at most cap; the cap where a band's pilot mean is 0 but its
// samples vary.
double samplesForTarget(const PixelSamples& pilot, int n0, double target, int cap) {
    double need = 0;
    for (int b = 0; b < pilot.sum.n; ++b) {
        const double mean = pilot.sum[b] / n0;
        const double var = std::max(0.0, (pilot.sum2[b] - n0 * mean * mean) / (n0 - 1));
        if (var <= 0) continue;
        if (mean <= 0) return cap;
        need = std::max(need, var / (target * target * mean * mean));
    }
    return std::min<double>(need, cap);
}

// Every pixel's samples under render.target_relative_error. A small pilot underestimates the
// variance of heavy-tailed radiance (a glint through a facet that few of its samples catch), so a
// pixel takes the larger of its own need and the mean need of its 3 x 3 neighbourhood, whose
// pilots together are nine times larger; within [n0, cap]. The pilots use streams of their own
// (kPilotStreamBase), so the count depends on nothing the final samples contain.
template <class Sampler>
std::vector<int> adaptiveSampleCounts(const RenderOptions& opts, const Tiling& tiling, const Sampler& sampler,
                                      uint64_t firstPilot, int n0, double target, int cap) {
    const int w = tiling.width, h = tiling.height;
    std::vector<double> need(static_cast<size_t>(w) * h);
    // The pilot's tiles are shared by the ranks; every rank gets every pixel's need (the counts
    // below look at the neighbours).
    auto needOfTile = [&](size_t tile, auto&& f) {
        tiling.forEachPixel(tile, [&](int x, int y) { f(need[static_cast<size_t>(y) * w + x]); });
    };
    distributeItems(
        tiling.count(), 0, ShareWith::AllRanks,
        [&](uint64_t b, uint64_t e) {
            runTiles(opts, tiling, nullptr, [&](size_t tile) {
                tiling.forEachPixel(tile, [&](int x, int y) {
                    need[static_cast<size_t>(y) * w + x] = samplesForTarget(sampler(x, y, firstPilot, n0), n0, target, cap);
                });
            }, b, e);
        },
        [&](uint64_t t, ByteWriter& wr) { needOfTile(t, [&](double& v) { wr.put(v); }); },
        [&](uint64_t t, ByteReader& rd) { needOfTile(t, [&](double& v) { v = rd.get<double>(); }); });
    std::vector<int> n(need.size());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double sum = 0;
            int count = 0;
            for (int j = std::max(0, y - 1); j <= std::min(h - 1, y + 1); ++j)
                for (int i = std::max(0, x - 1); i <= std::min(w - 1, x + 1); ++i) sum += need[static_cast<size_t>(j) * w + i], ++count;
            const double k = std::max(need[static_cast<size_t>(y) * w + x], sum / count);
            n[static_cast<size_t>(y) * w + x] = static_cast<int>(std::clamp(std::ceil(k), static_cast<double>(n0), static_cast<double>(cap)));
        }
    return n;
}

// What render.target_relative_error did: the mean samples per pixel and, with a warning, the pixels
// that stopped at the cap short of the target (their standard error is in the error image).
void reportAdaptiveSampling(const std::string& sensor, const RenderConfig& cfg, int64_t samples, int64_t capped,
                            int64_t pixels) {
    log::info("sensor '{}': render.target_relative_error {}: {:.1f} samples per pixel on average (a pilot of "
              "samples_per_pixel more each)", sensor, cfg.targetRelativeError, static_cast<double>(samples) / pixels);
    if (capped > 0)
        log::warn("sensor '{}': {} of {} pixels ({:.1f} %) reached render.max_samples_per_pixel = {} before relative "
                  "error {}; their errors are larger (see the _stderr image): raise max_samples_per_pixel",
                  sensor, capped, pixels, 100.0 * capped / pixels, cfg.maxSamplesPerPixel, cfg.targetRelativeError);
}

// The standard error of the mean of n samples with these sums, sqrt(s^2 / n).
double standardError(double sum, double sum2, int n) {
    if (n < 2) return std::numeric_limits<double>::quiet_NaN();
    const double mean = sum / n;
    return std::sqrt(std::max(0.0, (sum2 - n * mean * mean) / (n - 1)) / n);
}

}  // namespace

namespace {

// Writes a pixel's means over its n samples into the films at `at` (its first band of the group):
// the radiance, its standard error and the water-leaving products. A value that is not finite is
// never expected: it is counted (and reported), and 0 is written.
void storePixel(SensorImage& out, const PixelSamples& ps, uint64_t at, int bands, int n, std::atomic<int64_t>& nonFinite) {
    auto store = [&](Film& film, int b, double v) {
        if (!std::isfinite(v)) {
            ++nonFinite;
            v = 0.0;
        }
        film.pixels[at + b] = static_cast<float>(v);
    };
    for (int b = 0; b < bands; ++b) {
        store(out.film, b, ps.sum[b] / n);
        if (out.standardError) store(*out.standardError, b, standardError(ps.sum[b], ps.sum2[b], n));
        if (!out.products) continue;
        WaterProductFilms& f = *out.products;
        const PartSums& p = ps.parts;
        store(f.waterLeaving, b, p.waterLeaving[b] / n);
        store(f.skyReflected, b, p.skyReflected[b] / n);
        store(f.glint, b, p.glint[b] / n);
        store(f.other, b, p.other[b] / n);
        // Ed(0+) over the samples that met the sea; NaN where none did.
        f.ed0.pixels[at + b] = p.seaSamples > 0 ? static_cast<float>(p.ed0[b] / p.seaSamples)
                                                : std::numeric_limits<float>::quiet_NaN();
    }
}

}  // namespace

SensorImage renderSensor(const Scene& scene, const EstimatorSet& estimators, const ir::Sensor& sensor,
                         const RenderOptions& opts) {
    SensorImage out;
    out.sensor = sensor.name;
    out.truth = renderTruth(scene, sensor, opts);  // also validates the camera and the view
    const Camera cam(sensor);
    const int medium = scene.mediumIndex(sensor.medium, fmt::format("sensor '{}' medium", sensor.name));
    out.film = Film(cam.width(), cam.height(), scene.bands());
    if (sensor.waterProducts) out.products = WaterProductFilms{out.film, out.film, out.film, out.film, out.film};
    const int spp = cam.samplesPerPixel();
    if (spp >= 2) out.standardError = out.film;
    LITTORAL_CHECK(out.films().size() == filmCount(sensor));  // the checkpoints are sized by it
    TileCheckpoint* const ck = opts.checkpoint;
    if (ck) ck->restore(opts.checkpointSensor, out.films());  // the tiles a killed run finished
    const int nb = scene.bandCount();
    const Tiling tiling(cam.width(), cam.height(), opts.tileSize);
    const auto& groups = estimators.groups();
    const RenderConfig& cfg = estimators.config();
    const bool adaptive = cfg.targetRelativeError > 0;
    const int cap = adaptive ? cfg.maxSamplesPerPixel : spp;
    // Progressive pass p draws its own samples (streams (p - 1) cap ... ): with the same numbers in
    // every pass, the passes would share their sampling noise and their spread would see only the
    // photon maps' noise.
    const uint64_t pass0 = static_cast<uint64_t>(estimators.pass() - 1);
    const uint64_t firstStream = pass0 * static_cast<uint64_t>(cap), firstPilot = kPilotStreamBase + pass0 * spp;

    std::unique_ptr<Progress> progress;
    if (opts.progress)
        progress = std::make_unique<Progress>(fmt::format("render {}", sensor.name), tiling.count() * groups.size(),
                                              "tiles");
    std::atomic<int64_t> nonFinite{0}, samples{0}, capped{0};
    for (size_t gi = 0; gi < groups.size(); ++gi) {
        const BandGroup g = groups[gi];
        const PixelSampler sampler{cam, estimators.forGroup(gi), medium, scene.ir().render.seed, out.products.has_value(),
                                   g.count};
        std::vector<int> counts;
        if (adaptive) counts = adaptiveSampleCounts(opts, tiling, sampler, firstPilot, spp, cfg.targetRelativeError, cap);
        const size_t nt = tiling.count();
        auto renderTile = [&](size_t tile) {
            if (ck && ck->done(opts.checkpointSensor, gi * nt + tile)) return;  // restored from the checkpoint
            tiling.forEachPixel(tile, [&](int x, int y) {
                const uint64_t pixel = static_cast<uint64_t>(y) * cam.width() + x;
                const int n = adaptive ? counts[pixel] : spp;
                if (adaptive && n >= cap) ++capped;
                samples += n;
                const PixelSamples ps = sampler(x, y, firstStream, n);
                storePixel(out, ps, pixel * nb + g.begin, g.count, n, nonFinite);
            });
        };
        // With a checkpoint, the tiles go in 16 chunks, each saved when it is done. Several ranks
        // share each chunk's tiles, and rank 0 receives them before it saves.
        const size_t chunk = ck ? std::max<size_t>(1, (nt + 15) / 16) : nt;
        for (size_t t0 = 0; t0 < nt; t0 += chunk) {
            const size_t t1 = std::min(nt, t0 + chunk);
            distributeItems(
                t1 - t0, 0, ShareWith::Root,
                [&](uint64_t b, uint64_t e) { runTiles(opts, tiling, progress.get(), renderTile, t0 + b, t0 + e); },
                [&](uint64_t i, ByteWriter& w) { forTileValues(out, tiling, t0 + i, nb, g, [&](float& v) { w.put(v); }); },
                [&](uint64_t i, ByteReader& r) { forTileValues(out, tiling, t0 + i, nb, g, [&](float& v) { v = r.get<float>(); }); });
            if (ck) ck->finished(opts.checkpointSensor, gi * nt + t0, gi * nt + t1, std::as_const(out).films());
        }
    }
    if (ranks().size() > 1) {  // the counts of every rank's tiles, for the reports below
        const std::vector<int64_t> sums = sumOverRanks({nonFinite.load(), samples.load(), capped.load()});
        nonFinite = sums[0], samples = sums[1], capped = sums[2];
    }
    if (progress) progress->finish();
    if (nonFinite.load() > 0)
        log::warn("sensor '{}': {} pixel values were not finite and were set to 0 (please report)", sensor.name,
                  nonFinite.load());
    if (adaptive) reportAdaptiveSampling(sensor.name, cfg, samples.load(), capped.load(),
                                         static_cast<int64_t>(cam.width()) * cam.height() * groups.size());
    return out;
}

}  // namespace littoral::render
