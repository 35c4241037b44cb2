// Render throughput against the bare Embree kernel, side by side in one run.
//
//   BM_RenderFull/threads:N  a full render (Fresnel water box over a Classic checkerboard ground,
//                            uniform sky + sun, 32 sky samples per diffuse hit) of a 256 x 256
//                            image; rays/s counts every ray the renderer casts (closest-hit and
//                            shadow rays), taken from the "rays cast" and "shadow rays" counters.
//   BM_EmbreeRawMix/threads:N  exactly the rays one frame of the render casts (recorded with
//                            render::setThreadRayLog on a 1-thread render): its closest-hit
//                            queries replayed with bare rtcIntersect1 and its shadow queries with
//                            bare rtcOccluded1, same BVH, no hit reconstruction, no shading. This is
//                            the denominator the renderer is judged against (issue 8: >= 0.5).
//   BM_EmbreeRaw/threads:N   for reference, the same BVH and the primary (pixel-centre) rays only,
//                            with bare rtcIntersect1 (coherent rays, faster than the render's mix).
// At exit the ratios render rays/s / raw rays/s are printed per thread count.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <map>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/frame.h"
#include "core/log.h"
#include "core/rng.h"
#include "core/progress.h"
#include "core/stats.h"
#include "core/units.h"
#include "render/camera.h"
#include "render/renderer.h"
#include "render/sampling.h"

namespace {

using namespace littoral;
using M = ir::Material;

TriMesh boxMesh(const Point3& lo, const Point3& hi, bool floor) {
    TriMesh m;
    for (int i = 0; i < 8; ++i)
        m.positions.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
    const uint32_t q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (int f = floor ? 0 : 1; f < 6; ++f) {
        m.triangles.push_back({q[f][0], q[f][1], q[f][2]});
        m.triangles.push_back({q[f][0], q[f][2], q[f][3]});
    }
    // Outward orientation (counter-clockwise seen from outside): flip faces facing the centre.
    const Point3 c = (lo + hi) * 0.5;
    for (auto& t : m.triangles) {
        const Vec3 a = m.positions[t[0]], b = m.positions[t[1]], d = m.positions[t[2]];
        if (dot(cross(b - a, d - a), (a + b + d) * (1.0 / 3.0) - c) < 0) std::swap(t[1], t[2]);
    }
    return m;
}

TriMesh checkerGround(double half, int n) {
    TriMesh m;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) m.positions.push_back({-half + 2 * half * i / n, -half + 2 * half * j / n, 0});
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
            m.triangles.push_back({a, b, c});
            m.triangles.push_back({a, c, d});
            m.faceMaterial.push_back((i + j) % 2);
            m.faceMaterial.push_back((i + j) % 2);
        }
    return m;
}

const ir::SceneIR& benchScene() {
    static const ir::SceneIR s = [] {
        ir::SceneIR s;
        s.name = "bench";
        s.render.bands = {Band{0.4, 0.6}};
        s.render.settings.set("hemisphere_samples", 32);
        s.sun.enabled = true;
        s.sun.zenith = deg2rad(30);
        s.sun.irradiance = Spectrum::constant(0.5);
        s.sky.radiance = Spectrum::constant(0.5 / kPi);
        s.media.push_back(ir::Medium::homogeneous("water", 1.34, Spectrum::constant(0.05), Spectrum::constant(0.09)));
        M water;
        water.name = "water";
        water.type = M::Type::Dielectric;
        water.solver = M::Solver::Fresnel;
        M white;
        white.name = "white";
        white.reflectance = Spectrum::constant(0.8);
        M dark = white;
        dark.name = "dark";
        dark.reflectance = Spectrum::constant(0.1);
        s.materials = {water, white, dark};
        ir::Mesh g;
        g.name = "ground";
        g.materials = {"dark", "white"};
        g.data = checkerGround(6, 40);
        ir::Mesh b;
        b.name = "waterbox";
        b.materials = {"water"};
        b.inside = "water";
        b.data = boxMesh({-2, -2, 0}, {2, 2, 3}, false);
        s.meshes = {g, b};
        ir::Sensor cam;
        cam.name = "nadir";
        cam.position = {0.1, 0.05, 12};
        cam.forward = {0, 0, -1};
        cam.up = {0, 1, 0};
        cam.width = cam.height = 256;
        cam.focalLength = 0.02;
        cam.pixelPitch = 4e-5;
        s.sensors = {cam};
        return s;
    }();
    return s;
}

const render::Scene& scene() {
    static const render::Scene sc(benchScene(), ".");
    return sc;
}

std::map<int, double> gRender, gRaw, gRawSecondary, gRawMix;  // best rays/s per thread count

// The rays of one frame of the render, recorded once.
const render::RayLog& recordedMix() {
    static const render::RayLog log = [] {
        render::RayLog l;
        render::RenderOptions o;
        o.threads = 1;
        o.progress = false;
        render::setThreadRayLog(&l);
        auto img = render::renderSensor(scene(), benchScene().sensors[0], o);
        render::setThreadRayLog(nullptr);
        benchmark::DoNotOptimize(img.film.pixels.data());
        return l;
    }();
    return log;
}

void BM_EmbreeRawMix(benchmark::State& state) {
    const int threads = static_cast<int>(state.range(0));
    const render::RayLog& mix = recordedMix();
    const auto& geo = scene().geometry();
    tbb::task_arena arena(threads);
    int64_t total = 0;
    const size_t nc = mix.closest.size(), no = mix.occlusion.size();
    for (auto _ : state) {
        std::atomic<uint64_t> hits{0};
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<size_t>(0, nc + no, 4096), [&](const tbb::blocked_range<size_t>& r) {
                for (size_t i = r.begin(); i < r.end();) {
                    if (i < nc) {
                        const size_t e = std::min(r.end(), nc);
                        hits += geo.rawIntersectCount(mix.closest.data() + i, e - i);
                        i = e;
                    } else {
                        hits += geo.rawOccludedCount(mix.occlusion.data() + (i - nc), r.end() - i);
                        i = r.end();
                    }
                }
            });
        });
        benchmark::DoNotOptimize(hits.load());
        total += static_cast<int64_t>(nc + no);
    }
    state.counters["rays/s"] = benchmark::Counter(static_cast<double>(total), benchmark::Counter::kIsRate);
    state.counters["closest"] = static_cast<double>(nc);
    state.counters["occlusion"] = static_cast<double>(no);
}

void BM_RenderFull(benchmark::State& state) {
    const int threads = static_cast<int>(state.range(0));
    render::RenderOptions o;
    o.threads = threads;
    o.progress = false;
    int64_t rays = 0;
    for (auto _ : state) {
        const int64_t before = statCounter("rays cast").value + statCounter("shadow rays").value;
        auto img = render::renderSensor(scene(), benchScene().sensors[0], o);
        benchmark::DoNotOptimize(img.film.pixels.data());
        rays += statCounter("rays cast").value + statCounter("shadow rays").value - before;
    }
    state.counters["rays/s"] = benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kIsRate);
    state.counters["rays/frame"] = static_cast<double>(rays) / state.iterations();
}

void BM_EmbreeRaw(benchmark::State& state) {
    const int threads = static_cast<int>(state.range(0));
    const render::Camera cam(benchScene().sensors[0]);
    std::vector<Ray> rays;
    for (int y = 0; y < cam.height(); ++y)
        for (int x = 0; x < cam.width(); ++x) rays.push_back(cam.generateRay(x + 0.5, y + 0.5));
    const auto& geo = scene().geometry();
    tbb::task_arena arena(threads);
    int64_t total = 0;
    for (auto _ : state) {
        std::atomic<uint64_t> hits{0};
        arena.execute([&] {
            // Tiles of 256 rays (one image row), as the renderer's tiles.
            tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
                hits += geo.rawIntersectCount(rays.data() + r.begin(), r.size());
            });
        });
        benchmark::DoNotOptimize(hits.load());
        total += static_cast<int64_t>(rays.size());
    }
    state.counters["rays/s"] = benchmark::Counter(static_cast<double>(total), benchmark::Counter::kIsRate);
}

// The renderer's rays are mostly incoherent hemisphere samples, which Embree traverses more
// slowly than coherent primary rays. For reference: bare rtcIntersect1 on 8 cosine-distributed
// rays leaving each pixel's primary hit point (the Classic solver's sky rays), same BVH.
void BM_EmbreeRawSecondary(benchmark::State& state) {
    const int threads = static_cast<int>(state.range(0));
    const render::Camera cam(benchScene().sensors[0]);
    const auto& geo = scene().geometry();
    std::vector<Ray> rays;
    for (int y = 0; y < cam.height(); ++y)
        for (int x = 0; x < cam.width(); ++x) {
            render::SurfaceHit h;
            if (!geo.intersect(cam.generateRay(x + 0.5, y + 0.5), &h)) continue;
            const Vec3 n = h.front ? h.ng : -h.ng;
            const Frame f = Frame::fromNormal(n);
            RandomStream rng(7, 0, static_cast<uint64_t>(y) * cam.width() + x);
            for (int k = 0; k < 8; ++k)
                rays.push_back(render::spawnRay(
                    h.p, h.ng, normalize(f.toWorld(render::sampleCosineHemisphere(rng.uniform(), rng.uniform())))));
        }
    tbb::task_arena arena(threads);
    int64_t total = 0;
    for (auto _ : state) {
        std::atomic<uint64_t> hits{0};
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 2048), [&](const tbb::blocked_range<size_t>& r) {
                hits += geo.rawIntersectCount(rays.data() + r.begin(), r.size());
            });
        });
        benchmark::DoNotOptimize(hits.load());
        total += static_cast<int64_t>(rays.size());
    }
    state.counters["rays/s"] = benchmark::Counter(static_cast<double>(total), benchmark::Counter::kIsRate);
}

BENCHMARK(BM_RenderFull)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_EmbreeRawMix)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_EmbreeRaw)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_EmbreeRawSecondary)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// Collects rays/s per run to print the ratio at the end.
class RatioReporter : public benchmark::ConsoleReporter {
public:
    void ReportRuns(const std::vector<Run>& runs) override {
        for (const Run& r : runs) {
            auto it = r.counters.find("rays/s");
            if (it == r.counters.end()) continue;
            const std::string name = r.benchmark_name();
            const auto pos = name.find("threads:");
            if (pos == std::string::npos) continue;
            const int threads = std::atoi(name.c_str() + pos + 8);
            auto& table = name.find("RenderFull") != std::string::npos   ? gRender
                          : name.find("Secondary") != std::string::npos ? gRawSecondary
                          : name.find("RawMix") != std::string::npos    ? gRawMix
                                                                         : gRaw;
            table[threads] = std::max(table[threads], static_cast<double>(it->second));
        }
        ConsoleReporter::ReportRuns(runs);
    }
};

}  // namespace

int main(int argc, char** argv) {
    littoral::Progress::setEnabled(false);
    benchmark::Initialize(&argc, argv);
    RatioReporter reporter;
    benchmark::RunSpecifiedBenchmarks(&reporter);
    for (const auto& [threads, raw] : gRaw) {
        if (!gRender.count(threads)) continue;
        if (gRawMix.count(threads))
            std::printf("threads %d: render %.3g rays/s, bare Embree on the same ray mix %.3g rays/s: RATIO %.3f\n",
                        threads, gRender[threads], gRawMix[threads], gRender[threads] / gRawMix[threads]);
        std::printf("threads %d: render %.3g rays/s, raw rtcIntersect1 on the primary rays %.3g rays/s, ratio %.3f",
                    threads, gRender[threads], raw, gRender[threads] / raw);
        if (gRawSecondary.count(threads))
            std::printf("; raw on hemisphere rays %.3g rays/s, ratio %.3f", gRawSecondary[threads],
                        gRender[threads] / gRawSecondary[threads]);
        std::printf("\n");
    }
    benchmark::Shutdown();
    return 0;
}
