// A water layer's phase function, evaluated as the renderer and the forward tallies evaluate it
// (render::LayerPhase, one lookup by the top bits of t = 1 - cos), against the table's own
// evaluation (TabulatedPhase::evalOneMinusCos: 4096 bins uniform in sin(psi / 2), then a
// bisection), side by side in one run: Petzold's table, one band, one thread, at two mixes of
// angles. "sampled": t of directions drawn from Petzold's phase function itself (most within a
// few degrees: what a photon's next direction and the sun's forward peak ask); "uniform": t uniform
// in [0, 2) (a beam query's photons seen from arbitrary view directions). BM_SampleTable times the
// table's sampling (1 - cos from a uniform number).
// Run: build/bin/bench_phase
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "render/medium.h"

using namespace littoral;

namespace {

const std::vector<double>& angles(bool sampled) {
    static std::vector<double> s, u;
    std::vector<double>& v = sampled ? s : u;
    if (v.empty()) {
        const PhaseFunction petzold = PhaseFunction::petzold();
        std::mt19937_64 gen(1);
        std::uniform_real_distribution<double> U(0.0, 1.0);
        for (int i = 0; i < (1 << 20); ++i) {
            if (sampled) {
                const Vec3 d = petzold.sample(Vec3{0, 0, 1}, U(gen), U(gen), U(gen), nullptr);
                v.push_back(std::max(1.0 - d.z, 1e-12));
            } else {
                v.push_back(2.0 * U(gen));
            }
        }
    }
    return v;
}

void BM_LayerPhase(benchmark::State& st) {
    const render::LayerPhase layer({PhaseFunction::petzold()}, {{1.0}});
    const std::vector<double>& t = angles(st.range(0) == 1);
    double sum = 0, p;
    for (auto _ : st) {
        for (double x : t) {
            layer.eval(x, 0, 1, &p);
            sum += p;
        }
    }
    benchmark::DoNotOptimize(sum);
    st.SetItemsProcessed(static_cast<int64_t>(st.iterations()) * static_cast<int64_t>(t.size()));
    st.SetLabel(st.range(0) == 1 ? "sampled" : "uniform");
}

void BM_TableItself(benchmark::State& st) {
    const auto table = petzoldAverageParticleTable();
    const std::vector<double>& t = angles(st.range(0) == 1);
    double sum = 0;
    for (auto _ : st)
        for (double x : t) sum += table->evalOneMinusCos(x);
    benchmark::DoNotOptimize(sum);
    st.SetItemsProcessed(static_cast<int64_t>(st.iterations()) * static_cast<int64_t>(t.size()));
    st.SetLabel(st.range(0) == 1 ? "sampled" : "uniform");
}

// Drawing 1 - cos from the table (TabulatedPhase::sampleOneMinusCos, an exact inversion of its
// piecewise-linear density): what every collision of a photon or a path in Petzold water asks.
void BM_SampleTable(benchmark::State& st) {
    const auto table = petzoldAverageParticleTable();
    std::vector<double> u(1 << 20);
    std::mt19937_64 gen(2);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    for (double& x : u) x = U(gen);
    double sum = 0;
    for (auto _ : st)
        for (double x : u) sum += table->sampleOneMinusCos(x);
    benchmark::DoNotOptimize(sum);
    st.SetItemsProcessed(static_cast<int64_t>(st.iterations()) * static_cast<int64_t>(u.size()));
}

}  // namespace

BENCHMARK(BM_LayerPhase)->Arg(1)->Arg(0);
BENCHMARK(BM_TableItself)->Arg(1)->Arg(0);
BENCHMARK(BM_SampleTable);
BENCHMARK_MAIN();
