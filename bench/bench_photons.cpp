// Photon-map benchmarks (issue 9), measured side by side in one run:
//
//  1. Throughput of the photon pass (render/photon_pass.cpp) on real geometry against a
//     speed-of-light loop written here: photons in homogeneous water with the same IOPs and phase
//     function, no geometry, no interfaces, the same record store (PhotonMap::add per chunk, the
//     chunks appended into one map, its grid built) and the same random streams, on the same threads. The real scene is a periodic 20 x 20 m domain of flat
//     water 30 m deep over a black floor (walls, Fresnel surface, sun at 30 deg), the IOPs of the
//     dissertation's "low" water at 0.5 um scaled to b/c = 0.9, HG g = 0.88. Reported: photons
//     emitted and scattering events stored per second, and their ratios.
//  2. Scaling of the map from 1 M to 100 M photons at a fixed density (uniform in a box whose
//     volume grows with N, 3000 photons per m^3, the dissertation's coastal density): build time
//     (per photon and against N log N), query time of a fixed-radius sphere (0.4 m, ~800 photons)
//     and of a beam segment, bytes per photon and peak RSS. Each size runs in its own process
//     (fork) so that its peak RSS is its own.
//
// Usage: bench_photons [--quick] [--throughput] [--scaling-only] [--sizes N1,N2,...] [--threads N]
// (--scaling-only skips part 1; --sizes sets part 2's photon counts, default 1 M to 100 M.)
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/log.h"
#include "core/phase_functions.h"
#include "core/progress.h"
#include "core/rng.h"
#include "render/photon_map.h"
#include "render/estimator_settings.h"
#include "render/photon_pass.h"
#include "render/scene.h"
#include "scenegen/assemble.h"

namespace fs = std::filesystem;
using namespace littoral;
using namespace littoral::render;

namespace {

double seconds(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double peakRssMiB() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return static_cast<double>(u.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

constexpr double kA = 0.1, kB = 0.9, kG = 0.88;  // m^-1, HG asymmetry

const char* kScene = R"(scene: {name: bench-photons, domain: {x: [-10, 10], y: [-10, 10]}}
sun: {zenith_deg: 30, azimuth_deg: 180, irradiance: 1000}
sky: {radiance: 0}
water:
  horizontal: periodic
  surface: {model: flat}
  optics: {refractive_index: 1.34, absorption_per_m: 0.1, scattering_per_m: 0.9,
           phase: {type: henyey-greenstein, g: 0.88}, solver: medium-pm}
bathymetry: {type: planar_slope, z0_m: -30, spacing_m: 5, material: floor}
materials: [{name: floor, type: black}]
render: {bands: [[0.5, 0.51]], estimator: dirsig, photons: {volume: 1000}, search_radius_m: {volume: 0.4}}
)";

// The speed-of-light loop: chunks of 16384 photons as in the pass, each photon starting at the
// origin heading down, free flights exp(-c s), an event stored per scattering, HG sampling,
// survival by the albedo (equal-flux Russian roulette), until absorbed or 200 events.
struct LoopResult {
    uint64_t photons = 0, events = 0;
    double seconds = 0;       // tracing, storing and building the map
    double traceSeconds = 0;  // tracing with PhotonMap::add only
};
LoopResult speedOfLight(uint64_t photons, int threads) {
    const PhaseFunction hg = PhaseFunction::henyeyGreenstein(kG);
    const double c = kA + kB, albedo = kB / c;
    constexpr uint64_t kChunk = 16384;
    const uint64_t chunks = (photons + kChunk - 1) / kChunk;
    std::vector<PhotonMap> maps(chunks, PhotonMap(1, false));
    std::atomic<uint64_t> events{0};
    const auto t0 = std::chrono::steady_clock::now();
    tbb::task_arena arena(threads);
    arena.execute([&] {
        tbb::parallel_for(uint64_t{0}, chunks, [&](uint64_t k) {
            PhotonMap& m = maps[k];
            uint64_t ev = 0;
            Spec w(1, 1.0);
            for (uint64_t i = k * kChunk; i < std::min(photons, (k + 1) * kChunk); ++i) {
                RandomStream rng(1, 0, i);
                Point3 x{0, 0, 0};
                Vec3 d{0, 0, -1};
                for (int e = 0; e < 200; ++e) {
                    const double s = -std::log(1.0 - rng.uniform()) / c;
                    x = x + d * s;
                    m.add(x, d, Vec3{0, 0, 1}, w);
                    ++ev;
                    const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
                    d = hg.sample(d, u1, u2, u3, nullptr);
                    if (rng.uniform() >= albedo) break;
                }
            }
            events += ev;
        });
    });
    const double traced = seconds(t0);
    // The same store as the pass: the chunks appended in order into one reserved map, then the
    // hash grid built for a 0.4 m radius.
    PhotonMap all(1, false);
    all.reserve(events.load());
    for (const auto& m : maps) all.append(m);
    all.build(0.4);
    return {photons, events.load(), seconds(t0), traced};
}

void throughput(bool quick, int threads) {
    const fs::path dir = fs::temp_directory_path() / "bench_photons";
    fs::create_directories(dir);
    { std::ofstream(dir / "scene.yaml") << kScene; }
    registerEstimatorKinds();  // the scene reader reads their descriptors
    const auto built = scenegen::buildScene(dir / "scene.yaml", dir / "ir");
    const Scene scene(built.ir, dir / "ir");
    const uint64_t target = quick ? 500'000 : 4'000'000;
    PhotonPassSettings ps;
    ps.volumeTarget = target;
    ps.surfaceRadius = ps.volumeRadius = 0.4;
    ps.threads = threads;
    ps.progress = false;
    ps.volumeMedium.assign(scene.media().size(), false);
    for (size_t m = 1; m < scene.media().size(); ++m) ps.volumeMedium[m] = true;
    ps.surfaceMaterial.assign(scene.ir().materials.size(), false);
    BandGroup g{0, 1};
    std::printf("Photon throughput, %d thread(s): water a = %.2f, b = %.2f m^-1, HG g = %.2f\n", threads, kA, kB, kG);
    // Warm-up (page faults of the first chunks), then both measured twice, interleaved.
    speedOfLight(100'000, threads);
    double bestLoopP = 0, bestLoopE = 0, bestPassP = 0, bestPassE = 0, bestTraceP = 0, bestTraceE = 0;
    for (int rep = 0; rep < 2; ++rep) {
        const auto t0 = std::chrono::steady_clock::now();
        const PhotonMaps maps = tracePhotons(scene, g, ps);
        const double tp = seconds(t0);
        const LoopResult l = speedOfLight(maps.emitted, threads);
        bestPassP = std::max(bestPassP, maps.emitted / tp), bestPassE = std::max(bestPassE, maps.volume.size() / tp);
        bestLoopP = std::max(bestLoopP, l.photons / l.seconds), bestLoopE = std::max(bestLoopE, l.events / l.seconds);
        bestTraceP = std::max(bestTraceP, l.photons / l.traceSeconds);
        bestTraceE = std::max(bestTraceE, l.events / l.traceSeconds);
        std::printf("  run %d: pass %llu photons, %zu events stored in %.2f s; loop %llu photons, %llu events in %.2f s\n",
                    rep + 1, static_cast<unsigned long long>(maps.emitted), maps.volume.size(), tp,
                    static_cast<unsigned long long>(l.photons), static_cast<unsigned long long>(l.events), l.seconds);
    }
    std::printf("| | photons/s | events/s |\n|---|---|---|\n");
    std::printf("| speed-of-light loop (no geometry) | %.3g M | %.3g M |\n", bestLoopP / 1e6, bestLoopE / 1e6);
    std::printf("| photon pass, real scene | %.3g M | %.3g M |\n", bestPassP / 1e6, bestPassE / 1e6);
    std::printf("| **ratio** | **%.2f** | **%.2f** |\n", bestPassP / bestLoopP, bestPassE / bestLoopE);
    std::printf("| loop, tracing and PhotonMap::add only (no grid) | %.3g M | %.3g M |\n", bestTraceP / 1e6, bestTraceE / 1e6);
    std::printf("| ratio of the pass to that | %.2f | %.2f |\n\n", bestPassP / bestTraceP, bestPassE / bestTraceE);
}

// One map size, run in a child process; prints one table row.
void scalingRow(uint64_t n, int threads) {
    constexpr double kDensity = 3000, kRadius = 0.4;
    const double side = std::cbrt(static_cast<double>(n) / kDensity);
    PhotonMap map(4, false);
    {
        // Records appended per chunk as the pass does (deterministic, any thread count).
        constexpr uint64_t kChunk = 1 << 20;
        std::vector<PhotonMap> parts((n + kChunk - 1) / kChunk, PhotonMap(4, false));
        tbb::task_arena arena(threads);
        arena.execute([&] {
            tbb::parallel_for(size_t{0}, parts.size(), [&](size_t k) {
                Spec w(4, 1.0);
                for (uint64_t i = k * kChunk; i < std::min(n, (k + 1) * kChunk); ++i) {
                    RandomStream r(7, 0, i);
                    const Point3 p{side * r.uniform(), side * r.uniform(), side * r.uniform()};
                    parts[k].add(p, Vec3{0, 0, -1}, Vec3{0, 0, 1}, w);
                }
            });
        });
        for (const auto& p : parts) map.append(p);
    }
    const auto tb = std::chrono::steady_clock::now();
    map.build(kRadius);
    const double build = seconds(tb);
    // Queries at random interior points (away from the box faces by the radius).
    const int queries = 20000;
    double found = 0;
    const auto tq = std::chrono::steady_clock::now();
    for (int q = 0; q < queries; ++q) {
        RandomStream r(9, 0, q);
        const Point3 c{kRadius + (side - 2 * kRadius) * r.uniform(), kRadius + (side - 2 * kRadius) * r.uniform(),
                       kRadius + (side - 2 * kRadius) * r.uniform()};
        map.forEachInSphere(c, kRadius, [&](size_t i) { found += map.power(i, 0); });
    }
    const double sphere = seconds(tq) / queries;
    // Beam segments of 1 m (a march step) along random directions.
    double foundB = 0;
    const auto tbm = std::chrono::steady_clock::now();
    for (int q = 0; q < queries; ++q) {
        RandomStream r(11, 0, q);
        const Point3 o{1 + (side - 2) * r.uniform(), 1 + (side - 2) * r.uniform(), 1 + (side - 2) * r.uniform()};
        const double z = 2 * r.uniform() - 1, ph = 2 * M_PI * r.uniform(), s = std::sqrt(1 - z * z);
        map.forEachNearSegment(o, Vec3{s * std::cos(ph), s * std::sin(ph), z}, 0, 1, kRadius,
                               [&](size_t i, double) { foundB += map.power(i, 0); });
    }
    const double beam = seconds(tbm) / queries;
    const double nlogn = static_cast<double>(n) * std::log2(static_cast<double>(n));
    std::printf("| %6.0f M | %7.2f s | %6.1f ns | %6.3f ns | %6.1f us (%5.0f) | %6.1f us (%5.0f) | %5.1f | %7.0f MiB |\n",
                n / 1e6, build, 1e9 * build / n, 1e9 * build / nlogn, 1e6 * sphere, found / queries, 1e6 * beam,
                foundB / queries, static_cast<double>(map.memoryBytes()) / n, peakRssMiB());
    std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
    Progress::setEnabled(false);
    log::setLevel(log::Level::Warn);
    bool quick = false, onlyThroughput = false, onlyScaling = false;
    int threads = 2;
    std::vector<uint64_t> chosen;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--quick")) quick = true;
        else if (!std::strcmp(argv[i], "--throughput")) onlyThroughput = true;
        else if (!std::strcmp(argv[i], "--scaling-only")) onlyScaling = true;
        else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) threads = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--sizes") && i + 1 < argc) {
            for (const char* p = argv[++i]; *p;) {
                char* end = nullptr;
                const unsigned long long v = std::strtoull(p, &end, 10);
                if (end == p || v == 0 || (*end && *end != ',')) {
                    std::fprintf(stderr, "--sizes: expected photon counts separated by commas, found '%s'\n", argv[i]);
                    return 1;
                }
                chosen.push_back(v);
                p = *end ? end + 1 : end;
            }
        } else {
            std::fprintf(stderr, "unknown argument '%s' (usage: bench_photons [--quick] [--throughput] [--scaling-only] "
                                 "[--sizes N1,N2,...] [--threads N])\n", argv[i]);
            return 1;
        }
    }
    if (!onlyScaling) throughput(quick, threads);
    if (onlyThroughput) return 0;
    std::printf("Map scaling at 3000 photons/m^3, 4 bands, radius 0.4 m, %d thread(s) for filling and building, "
                "queries on one thread\n",
                threads);
    std::printf("| photons | build | per photon | per N log2 N | sphere query (photons) | 1 m beam query (photons) | "
                "bytes/photon | peak RSS |\n|---|---|---|---|---|---|---|---|\n");
    std::fflush(stdout);
    std::vector<uint64_t> sizes = quick ? std::vector<uint64_t>{1'000'000, 3'000'000}
                                        : std::vector<uint64_t>{1'000'000, 3'000'000, 10'000'000, 30'000'000, 100'000'000};
    if (!chosen.empty()) sizes = chosen;
    for (uint64_t n : sizes) {
        const pid_t pid = fork();
        if (pid == 0) {
            scalingRow(n, threads);
            _exit(0);
        }
        int status = 0;
        waitpid(pid, &status, 0);
    }
    return 0;
}
