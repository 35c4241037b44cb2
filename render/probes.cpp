#include "render/probes.h"

#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/error.h"
#include "core/frame.h"
#include "core/rng.h"
#include "core/units.h"
#include "render/integrator.h"
#include "render/sampling.h"

namespace littoral::render {

namespace {

enum class Quantity { Ed, Eu, Eod, Eou, Lu };

Quantity parseQuantity(const std::string& q, const std::string& who) {
    if (q == "Ed") return Quantity::Ed;
    if (q == "Eu") return Quantity::Eu;
    if (q == "Eod") return Quantity::Eod;
    if (q == "Eou") return Quantity::Eou;
    if (q == "Lu") return Quantity::Lu;
    throw InputError(fmt::format("{}: unknown quantity '{}' (allowed: Ed, Eu, Eod, Eou, Lu)", who, q));
}

// Pass numbers for probe random streams, far from pixel-sample passes.
constexpr uint64_t kProbePassBase = 1ull << 40;

}  // namespace

std::vector<ProbeValue> evaluateProbe(const Scene& scene, const ir::Probe& probe, int probeIndex,
                                      const RenderOptions& opts) {
    const std::string who = fmt::format("probe '{}'", probe.name);
    const int medium = scene.mediumIndex(probe.medium, who + " medium");
    checkNotInsideOpaque(scene, probe.position, who);
    const int N = scene.ir().render.probeSamples;
    if (N < 2) throw InputError(fmt::format("render.probeSamples {} must be at least 2", N));
    const int nb = scene.bandCount();
    const StratifiedLayout layout(N);
    std::vector<ProbeValue> out;
    for (size_t qi = 0; qi < probe.quantities.size(); ++qi) {
        const Quantity q = parseQuantity(probe.quantities[qi], who);
        ProbeValue v;
        v.probe = probe.name;
        v.quantity = probe.quantities[qi];
        v.units = q == Quantity::Lu ? "W m^-2 sr^-1 um^-1" : "W m^-2 um^-1";
        v.mean.assign(nb, 0.0);
        v.stderr_.assign(nb, 0.0);
        const bool up = q == Quantity::Ed || q == Quantity::Eod;
        const Normal3 n{0, 0, up ? 1.0 : -1.0};
        const Frame frame = Frame::fromNormal(n);
        for (const BandGroup& g : bandGroups(scene)) {
            const Integrator integrator(scene, g);
            std::vector<Spec> samples(N);
            tbb::task_arena arena(opts.threads > 0 ? opts.threads : tbb::task_arena::automatic);
            arena.execute([&] {
                tbb::parallel_for(tbb::blocked_range<int>(0, N, 64), [&](const tbb::blocked_range<int>& r) {
                    for (int k = r.begin(); k != r.end(); ++k) {
                        RandomStream rng(scene.ir().render.seed, kProbePassBase + probeIndex * 16 + qi, k);
                        const Vec2 u = layout.point(k, rng.uniform(), rng.uniform());
                        Vec3 w;
                        double weight;
                        switch (q) {
                            case Quantity::Ed:
                            case Quantity::Eu:
                                w = sampleCosineHemisphere(u.x, u.y);
                                weight = kPi;  // Int L cos dw = pi <L> under pdf cos/pi
                                break;
                            case Quantity::Eod:
                            case Quantity::Eou:
                                w = sampleUniformHemisphere(u.x, u.y);
                                weight = 2.0 * kPi;  // Int L dw = 2 pi <L> under pdf 1/(2 pi)
                                break;
                            case Quantity::Lu:
                            default:
                                w = {0, 0, 1};
                                weight = 1.0;
                                break;
                        }
                        Ray ray;
                        ray.o = probe.position;
                        ray.d = normalize(frame.toWorld(w));
                        PathState st;
                        st.medium = medium;
                        st.splits = 1;
                        st.fromSensor = q == Quantity::Lu;  // Ed/Eod add the sun by sunIrradiance
                        Spec L = integrator.Li(ray, st, rng) * weight;
                        // Direct sun by a shadow ray (plane: E cos; scalar: E).
                        if (q == Quantity::Ed || q == Quantity::Eod) {
                            L += integrator.sunIrradiance(probe.position, n, n, medium, rng, q == Quantity::Eod);
                        }
                        samples[k] = L;
                    }
                    flushRayStats();
                });
            });
            for (int b = 0; b < g.count; ++b) {
                double sum = 0, sum2 = 0;
                for (const Spec& s : samples) {
                    sum += s[b];
                    sum2 += s[b] * s[b];
                }
                const double mean = sum / N;
                const double var = std::max(0.0, (sum2 - N * mean * mean) / (N - 1));
                v.mean[g.begin + b] = mean;
                v.stderr_[g.begin + b] = std::sqrt(var / N);
            }
        }
        out.push_back(std::move(v));
    }
    return out;
}

std::string probesCsv(const std::vector<ProbeValue>& values, const std::vector<Band>& bands) {
    std::string s = "probe,quantity,band_lo_um,band_hi_um,value,stderr,units\n";
    for (const ProbeValue& v : values)
        for (size_t b = 0; b < bands.size(); ++b)
            s += fmt::format("{},{},{},{},{:.9g},{:.9g},{}\n", v.probe, v.quantity, bands[b].lo, bands[b].hi,
                             v.mean[b], v.stderr_[b], v.units);
    return s;
}

std::string probesJson(const std::vector<ProbeValue>& values, const std::vector<Band>& bands) {
    nlohmann::json j;
    j["bands"] = nlohmann::json::array();
    for (const Band& b : bands) j["bands"].push_back({{"lo_um", b.lo}, {"hi_um", b.hi}});
    j["probes"] = nlohmann::json::array();
    for (const ProbeValue& v : values)
        j["probes"].push_back(
            {{"probe", v.probe}, {"quantity", v.quantity}, {"units", v.units}, {"value", v.mean}, {"stderr", v.stderr_}});
    return j.dump(2) + "\n";
}

}  // namespace littoral::render
