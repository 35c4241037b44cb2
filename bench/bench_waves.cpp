// The dissertation's wave surface (Tables 9.5 / 10.2): 1200 x 1200 grid at 0.25 m, seed 500,
// decimated to 30,000 triangles. Synthesis, facetization (presampled lattice + OpenMesh quadric
// decimation) and the statistics are timed separately; BM_WavesEndToEnd is the whole
// generateWaveSurface call. Run: build/bin/bench_waves (add --benchmark_min_time=0.1 for one iteration each).
#include <benchmark/benchmark.h>

#include "core/log.h"
#include "core/progress.h"
#include "surfaces/beaufort.h"
#include "surfaces/facetize.h"
#include "surfaces/surface_stats.h"
#include "surfaces/synthesis.h"
#include "surfaces/wave_surface.h"

using namespace littoral;
using namespace littoral::surfaces;

namespace {
GridSpec dissertationGrid() {
    GridSpec g;
    g.nx = g.ny = 1200;
    g.sizeX = g.sizeY = 300.0;
    g.x0 = g.y0 = -150.0;
    return g;
}
const HeightField& dissertationField(double U) {
    static HeightField f6, f10;
    HeightField& f = U == 6.0 ? f6 : f10;
    if (f.z.empty()) {
        const BeaufortPrediction b = beaufortPrediction(U);
        f = synthesizeGaussian(dissertationGrid(), b.rmsHeight, b.correlationLength, 500);
    }
    return f;
}
}  // namespace

static void BM_Synthesis(benchmark::State& st) {
    const BeaufortPrediction b = beaufortPrediction(static_cast<double>(st.range(0)));
    for (auto _ : st) benchmark::DoNotOptimize(synthesizeGaussian(dissertationGrid(), b.rmsHeight, b.correlationLength, 500));
}
BENCHMARK(BM_Synthesis)->Arg(6)->Arg(10)->Unit(benchmark::kMillisecond);

// Full-resolution triangulation only (no decimation): 2.88 M triangles.
static void BM_Triangulate(benchmark::State& st) {
    const HeightField& f = dissertationField(6.0);
    for (auto _ : st) benchmark::DoNotOptimize(triangulate(f));
}
BENCHMARK(BM_Triangulate)->Unit(benchmark::kMillisecond);

// Facetization and decimation to 30,000 triangles.
static void BM_FacetizeDecimate(benchmark::State& st) {
    const HeightField& f = dissertationField(static_cast<double>(st.range(0)));
    for (auto _ : st) benchmark::DoNotOptimize(facetize(f, 30000));
}
BENCHMARK(BM_FacetizeDecimate)->Arg(6)->Arg(10)->Unit(benchmark::kMillisecond);

// Grid and mesh statistics (two autocorrelation FFTs, mesh rasterisation).
static void BM_Statistics(benchmark::State& st) {
    const HeightField& f = dissertationField(6.0);
    const Facets m = facetize(f, 30000);
    for (auto _ : st) {
        benchmark::DoNotOptimize(measureHeightField(f, 0.0));
        benchmark::DoNotOptimize(measureMesh(m.mesh, f, 0.0));
    }
}
BENCHMARK(BM_Statistics)->Unit(benchmark::kMillisecond);

static void BM_WavesEndToEnd(benchmark::State& st) {
    Progress::setEnabled(false);
    WaveParams p;
    p.windSpeed = static_cast<double>(st.range(0));
    for (auto _ : st) benchmark::DoNotOptimize(generateWaveSurface(p));
}
BENCHMARK(BM_WavesEndToEnd)->Arg(6)->Arg(10)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
