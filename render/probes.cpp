#include "render/probes.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <tuple>
#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/error.h"
#include "core/frame.h"
#include "core/kinds.h"
#include "core/log.h"
#include "core/probe_quantities.h"
#include "core/progress.h"
#include "core/rng.h"
#include "core/units.h"
#include "render/distributed.h"
#include "render/forward_tally.h"
#include "render/volume_map_probes.h"
#include "render/sampling.h"

namespace littoral::render {

namespace {

enum class Quantity { Ed, Eu, Eod, Eou, Lu, Lw, Rrs };

// The quantities a probe measures: one descriptor each (name, doc line; no parameters), in the
// order messages list them. registerEstimatorKinds() registers them for the scene-file parser.
struct QuantityKind {
    KindInfo info;
    Quantity quantity;
};
const KindInfo& kindInfo(const QuantityKind& k) { return k.info; }

const KindRegistry<QuantityKind>& quantityKinds() {
    static const KindRegistry<QuantityKind> registry = [] {
        KindRegistry<QuantityKind> r("probe quantity");
        r.add({{"probe quantity", "Ed", "downwelling plane irradiance, W m^-2 um^-1", {}}, Quantity::Ed});
        r.add({{"probe quantity", "Eu", "upwelling plane irradiance, W m^-2 um^-1", {}}, Quantity::Eu});
        r.add({{"probe quantity", "Eod", "downwelling scalar irradiance, W m^-2 um^-1", {}}, Quantity::Eod});
        r.add({{"probe quantity", "Eou", "upwelling scalar irradiance, W m^-2 um^-1", {}}, Quantity::Eou});
        r.add({{"probe quantity", "Lu", "nadir-viewing upwelling radiance, W m^-2 sr^-1 um^-1", {}}, Quantity::Lu});
        r.add({{"probe quantity", "Lw",
                "water-leaving part of Lu for a probe in the air above the sea (docs/rendering.md), W m^-2 sr^-1 um^-1",
                {}},
               Quantity::Lw});
        r.add({{"probe quantity", "Rrs",
                "remote-sensing reflectance Lw / Ed(0+) at the sea point below a probe in the air, sr^-1", {}},
               Quantity::Rrs});
        return r;
    }();
    return registry;
}

Quantity parseQuantity(const std::string& q, const std::string& who) { return quantityKinds().get(q, who).quantity; }

// Pass numbers for probe random streams, far from pixel-sample passes; progressive pass p adds
// (p - 1) 2^24, so that every pass draws its own directions and paths (see renderer.cpp).
constexpr uint64_t kProbePassBase = 1ull << 40;
constexpr uint64_t kProbeProgressiveStride = 1ull << 24;

// One quantity of one probe for one band group: draws its samples.
struct ProbeSampler {
    const Estimator& est;
    BandGroup g;
    Quantity q;
    const Medium& md;
    int layer, medium;
    Point3 position;
    Normal3 n;
    Frame frame;
    std::optional<Vec3> sunDir;  // set: the downwelling quantity mixes in sampling around the refracted sun

    bool up() const { return q == Quantity::Ed || q == Quantity::Eod; }

    bool waterLeaving() const { return q == Quantity::Lw || q == Quantity::Rrs; }

    // One sample, for the stratified point u of the quantity's hemisphere. Lw and Rrs: the
    // water-leaving part of the nadir ray's radiance, and in *ed0 the Ed(0+) of its sea point.
    Spec sample(const Vec2& u, RandomStream& rng, Spec* ed0 = nullptr) const {
        if (waterLeaving()) {
            Ray ray;
            ray.o = position;
            ray.d = {0, 0, -1};
            const RadianceParts p = est.LiParts(ray, medium, rng);
            if (ed0) *ed0 = p.ed0;
            return p.waterLeaving;
        }
        if (sunDir) return sampleMixed(u, rng);
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
        ray.o = position;
        ray.d = normalize(frame.toWorld(w));
        if (!up()) return est.Li(ray, medium, rng) * weight;
        // Diffuse light by sampling, the direct beam by next-event estimation.
        Spec L = est.LiIndirect(ray, medium, rng) * weight;
        L += est.sun().direct(position, n, medium, q == Quantity::Eod, rng);
        return L;
    }

    // Technique 0: the quantity's own (cosine or uniform) hemisphere; technique 1: the phase
    // function around the refracted sun; combined by the balance heuristic.
    Spec sampleMixed(const Vec2& u, RandomStream& rng) const {
        const bool plane = q == Quantity::Ed;
        const double ut = rng.uniform(), u0 = rng.uniform(), u3 = rng.uniform();
        Vec3 w, wl;
        if (ut < 0.5) {
            wl = plane ? sampleCosineHemisphere(u.x, u.y) : sampleUniformHemisphere(u.x, u.y);
            w = frame.toWorld(wl);
        } else {
            w = md.sampleAround(layer, g, *sunDir, u0, u.x, u.y, u3);
            wl = frame.toLocal(w);
        }
        const double cosT = wl.z;
        Spec L(g.count);
        if (cosT > 0) {
            const double p0 = plane ? cosT * kInvPi : 1.0 / (2.0 * kPi);
            const double p1 = md.pdfAround(layer, g, *sunDir, w);
            const double f = plane ? cosT : 1.0;  // Ed weights by cos, Eod not
            Ray ray;
            ray.o = position;
            ray.d = normalize(w);
            L = est.LiIndirect(ray, medium, rng) * (f / (0.5 * p0 + 0.5 * p1));
        }
        L += est.sun().direct(position, n, medium, q == Quantity::Eod, rng);
        return L;
    }
};

// A probe value to be filled band group by band group.
ProbeValue emptyValue(const std::string& probe, const std::string& quantity, Quantity q, int bands, int samples,
                      int batches) {
    ProbeValue v;
    v.probe = probe;
    v.quantity = quantity;
    v.units = q == Quantity::Lu || q == Quantity::Lw ? "W m^-2 sr^-1 um^-1"
              : q == Quantity::Rrs                   ? "sr^-1"
                                                     : "W m^-2 um^-1";
    v.mean.assign(bands, 0.0);
    v.stderr_.assign(bands, 0.0);
    v.samples = samples;
    v.batches = batches;
    return v;
}

// How a probe quantity's samples are cut: B batches of perBatch samples, each in chunks of at most
// `chunk` samples, drawn from streams (seed, stream, sample index).
struct ProbeChunks {
    int B, chunksPerBatch, perBatch, chunk;
    const StratifiedLayout& layout;
    uint64_t seed, stream;
};

// The sample sums of every chunk (and, with `withEd`, the sums of Ed(0+) for Rrs). Each chunk is
// summed by one task, so the sums do not depend on the thread count; the chunks are shared by the
// ranks of a run, and each chunk's sums reach every rank.
void sumProbeChunks(const ProbeSampler& sampler, const ProbeChunks& plan, BandGroup g, bool withEd,
                    const RenderOptions& opts, Progress* progress, std::vector<Spec>* chunkSums,
                    std::vector<Spec>* edSums) {
    chunkSums->assign(static_cast<size_t>(plan.B) * plan.chunksPerBatch, Spec(g.count));
    edSums->assign(withEd ? chunkSums->size() : 0, Spec(g.count));
    tbb::task_arena arena(opts.threads > 0 ? opts.threads : tbb::task_arena::automatic);
    auto sumChunk = [&](size_t c) {
        const int batch = static_cast<int>(c / plan.chunksPerBatch);
        const int k0 = static_cast<int>(c % plan.chunksPerBatch) * plan.chunk;
        const int k1 = std::min(plan.perBatch, k0 + plan.chunk);
        Spec sum(g.count), ed(g.count), ed0(g.count);
        for (int k = k0; k < k1; ++k) {
            RandomStream rng(plan.seed, plan.stream, static_cast<uint64_t>(batch) * plan.perBatch + k);
            const Vec2 u = plan.layout.point(k, rng.uniform(), rng.uniform());
            sum += sampler.sample(u, rng, &ed0);
            ed += ed0;
        }
        (*chunkSums)[c] = sum;
        if (withEd) (*edSums)[c] = ed;
        flushRayStats();
        if (progress) progress->advance();
    };
    auto chunkValues = [&](uint64_t c, auto&& f) {
        for (int b = 0; b < g.count; ++b) f((*chunkSums)[c][b]);
        if (withEd)
            for (int b = 0; b < g.count; ++b) f((*edSums)[c][b]);
    };
    distributeItems(
        chunkSums->size(), 0, ShareWith::AllRanks,
        [&](uint64_t c0, uint64_t c1) {
            arena.execute([&] {
                tbb::parallel_for(tbb::blocked_range<size_t>(c0, c1, 1), [&](const tbb::blocked_range<size_t>& r) {
                    for (size_t c = r.begin(); c != r.end(); ++c) sumChunk(c);
                });
            });
        },
        [&](uint64_t c, ByteWriter& w) { chunkValues(c, [&](double& x) { w.put(x); }); },
        [&](uint64_t c, ByteReader& r) { chunkValues(c, [&](double& x) { x = r.get<double>(); }); });
}

}  // namespace

void batchStatistics(const std::vector<Spec>& chunkSums, int B, int chunksPerBatch, double perBatch, BandGroup g,
                     ProbeValue* v, const std::vector<Spec>* denominators) {
    for (int b = 0; b < g.count; ++b) {
        double sum = 0, sum2 = 0;
        for (int batch = 0; batch < B; ++batch) {
            double s = 0, d = 0;
            for (int c = 0; c < chunksPerBatch; ++c) {
                const size_t k = static_cast<size_t>(batch) * chunksPerBatch + c;
                s += chunkSums[k][b];
                if (denominators) d += (*denominators)[k][b];
            }
            const double m = denominators ? (d > 0 ? s / d : 0.0) : s / perBatch;
            sum += m;
            sum2 += m * m;
        }
        const double mean = sum / B;
        const double var = std::max(0.0, (sum2 - B * mean * mean) / (B - 1));
        v->mean[g.begin + b] = mean;
        v->stderr_[g.begin + b] = std::sqrt(var / B);
    }
}

void registerProbeQuantityKinds(KindRegistry<KindInfo>& registry) {
    for (const QuantityKind& k : quantityKinds().kinds()) registry.add(k.info);
}

void checkProbe(const Scene& scene, const RenderConfig& cfg, const ir::Probe& probe) {
    const std::string who = fmt::format("probe '{}'", probe.name);
    checkPositionInRange(probe.position, who);
    const int medium = scene.mediumIndex(probe.medium, who + " medium");
    checkNotInsideOpaque(scene, probe.position, who);
    checkClearOfSurfaces(scene, probe.position, who);
    checkDeclaredMedium(scene, probe.position, medium, who);
    for (const std::string& q : probe.quantities) {
        const Quantity k = parseQuantity(q, who);
        if ((k == Quantity::Lw || k == Quantity::Rrs) && (medium != 0 || !seaBelow(scene, probe.position)))
            throw InputError(fmt::format("{}: quantity {} needs a probe in the air with the sea surface straight below it "
                                         "(it splits the nadir radiance where it meets the sea)",
                                         who, q));
    }
    const int B = cfg.probeBatches;
    const int N = probe.samples.value_or(cfg.probeSamples);
    if (N < B)
        throw InputError(fmt::format("{}: {} samples cannot form {} batches (render.probe_batches: set samples to at "
                                     "least {} or lower probe_batches)",
                                     who, N, B, B));
}

namespace {

// Streams of the method-choice pilot's backward paths: within each progressive pass, above every
// probe's own (probe index x 16 + quantity < 2^23).
constexpr uint64_t kProbePilotOffset = 1ull << 23;

// One quantity (index qi) of one probe by backward paths: N samples in render.probe_batches
// batches, drawn from the streams at streamBase.
ProbeValue backwardValue(const Scene& scene, const EstimatorSet& estimators, const ir::Probe& probe, int probeIndex,
                         size_t qi, int N, uint64_t streamBase, const RenderOptions& opts, Progress* progress,
                         int batches = 0) {
    const std::string who = fmt::format("probe '{}'", probe.name);
    const int medium = scene.mediumIndex(probe.medium, who + " medium");
    const int B = batches > 0 ? batches : estimators.config().probeBatches;
    const int perBatch = N / B;  // a remainder of fewer than B samples is not drawn
    // Work is cut into chunks of at most kChunk samples inside each batch (sumProbeChunks); the
    // chunk sums are added in a fixed order, so the result does not depend on the thread count.
    constexpr int kChunk = 1024;
    const int chunksPerBatch = (perBatch + kChunk - 1) / kChunk;
    const StratifiedLayout layout(perBatch);
    const Quantity q = parseQuantity(probe.quantities[qi], who);
    ProbeValue v = emptyValue(probe.name, probe.quantities[qi], q, scene.bandCount(), perBatch * B, B);
    v.position = probe.position;
    v.medium = probe.medium.empty() ? "air" : probe.medium;
    const bool up = q == Quantity::Ed || q == Quantity::Eod;
    const Normal3 n{0, 0, up ? 1.0 : -1.0};
    const Medium& md = scene.media()[medium];
    for (size_t gi = 0; gi < estimators.size(); ++gi) {
        const Estimator& est = estimators.forGroup(gi);
        const BandGroup g = estimators.groups()[gi];
        // In water with a forward-peaked phase function the sunlit forward-scattering peak around
        // the refracted sun is far brighter than the rest of what a probe sees from below
        // (Petzold: 10^3 times at 0.1 deg); the downwelling quantities then draw half their
        // directions from the phase function around the sun and combine the two strategies by
        // the balance heuristic (one-sample MIS). (For flat phase functions this costs more
        // variance than it saves, measured on Mobley et al.'s problem 1.)
        const ProbeSampler sampler{est, g, q, md, md.layerAt(probe.position.z), medium, probe.position, n,
                                   Frame::fromNormal(n),
                                   up && md.scattering() && md.forwardPeaked() ? est.sun().refractedDirection(medium)
                                                                               : std::nullopt};
        const ProbeChunks plan{B, chunksPerBatch, perBatch, kChunk, layout, scene.ir().render.seed,
                               streamBase + static_cast<uint64_t>(probeIndex) * 16 + qi};
        std::vector<Spec> chunkSums, edSums;
        sumProbeChunks(sampler, plan, g, q == Quantity::Rrs, opts, progress, &chunkSums, &edSums);
        batchStatistics(chunkSums, B, chunksPerBatch, perBatch, g, &v, edSums.empty() ? nullptr : &edSums);
    }
    return v;
}

uint64_t probeStreamBase(const EstimatorSet& estimators) {
    return kProbePassBase + static_cast<uint64_t>(estimators.pass() - 1) * kProbeProgressiveStride;
}

// The squared standard error summed over bands, relative to `ref`'s means (bands where ref is 0
// are left out), scaled from a pilot's sample count to the full one.
double predictedVariance(const ProbeValue& v, const ProbeValue& ref, double pilot, double full) {
    double sum = 0;
    for (size_t b = 0; b < v.mean.size(); ++b) {
        const double m = std::abs(ref.mean[b]) > 0 ? std::abs(ref.mean[b]) : std::abs(v.mean[b]);
        if (m > 0) sum += (v.stderr_[b] / m) * (v.stderr_[b] / m);
    }
    return sum * pilot / full;
}

// Whether some band of v is positive.
bool anyPositive(const ProbeValue& v) {
    return std::any_of(v.mean.begin(), v.mean.end(), [](double m) { return m > 0; });
}
// Whether two independent estimates of one quantity differ by more than 3 combined standard errors
// in some band (a false alarm about once in 370 per band).
bool disagree(const ProbeValue& a, const ProbeValue& b) {
    for (size_t k = 0; k < a.mean.size(); ++k)
        if (std::abs(a.mean[k] - b.mean[k]) > 3 * std::hypot(a.stderr_[k], b.stderr_[k])) return true;
    return false;
}

// The pilots' batches, whatever render.probe_batches is: their standard errors decide the method,
// and from B batches a standard error is itself uncertain by about 1 / sqrt(2 (B - 1)) (16 % at 20
// batches, 9 % at 64), which made close calls go the wrong way.
constexpr int kPilotBatches = 64;
// A forward prediction above 5 % relative se at the full budget means that few photons reach the
// plane, and a few rare arrivals can carry its value: Mobley's problem 1 at albedo 0.2, Eou at
// tau 10 (10^-6 of the light at the surface), was predicted at 6.5 % forward and came out at 26 %.
// Such a cell goes backward unless the pilots disagree (below).
constexpr double kForwardTrustedVariance = 0.05 * 0.05;
// A quarter-size backward pilot that predicts more than this times the forward variance settles the
// method (chooseForward).
constexpr double kClearMargin = 4.0;

// The method of every quantity the forward tallies could answer (docs/rendering.md, "Forward or
// backward: the pilot"): a pilot of 1/16 of each method's budget (backward: 1/64 first, which
// settles the clear cases), on random streams of its own,
// predicts each method's standard error at its full budget (se^2 falls as 1/N); the smaller wins,
// unless a pilot cannot be trusted:
//  - no forward photon reached the probe's plane: backward;
//  - the forward pilot predicts more than 5 % (kForwardTrustedVariance) and the pilots agree:
//    backward;
//  - the two pilots disagree beyond 3 combined standard errors: forward. A crossing or collision
//    adds a bounded weight, so the forward pilot's spread is honest; backward paths in deep or
//    forward-peaked water are heavy-tailed, and a small pilot that has not met their rare large
//    values reports an error far too small (measured: 0.1 % predicted, 36 % at the full budget).
// Returns the (probe, quantity) pairs that go forward; *profile receives the pilot's profile at its
// planes (ForwardTallies::profile; the full run splits its photons by depth with it).
std::set<std::pair<int, std::string>> chooseForward(const Scene& scene, const EstimatorSet& estimators,
                                                    const RenderOptions& opts, std::vector<std::pair<double, double>>* profile) {
    const RenderConfig& cfg = estimators.config();
    std::set<std::pair<int, std::string>> chosen;
    if (cfg.estimator != ir::Estimator::Path || cfg.probePhotons == 0) return chosen;
    // The forward pilot in two stages of 1/32 each: unsplit, for the depth profile; then split by
    // depth with it, as the full run will be, for the prediction (and a better profile for the run).
    ForwardTallyRun pilotRun;
    pilotRun.photons = std::max<uint64_t>(static_cast<uint64_t>(kPilotBatches), cfg.probePhotons / 32);
    pilotRun.pilot = true;
    pilotRun.batches = kPilotBatches;
    RenderOptions quiet = opts;
    quiet.progress = false;
    pilotRun.profile = ForwardTallies(scene, estimators, quiet, pilotRun).profile();
    pilotRun.pilotStage = 1;
    const ForwardTallies pilot(scene, estimators, quiet, pilotRun);
    *profile = pilot.profile();
    const auto& probes = scene.ir().probes;
    for (const auto& [i, q] : pilot.answered()) {
        const ir::Probe& probe = probes[static_cast<size_t>(i)];
        checkProbe(scene, cfg, probe);
        const ProbeValue& f = *pilot.find(i, q);
        const int N = probe.samples.value_or(cfg.probeSamples);
        const size_t qi = static_cast<size_t>(std::find(probe.quantities.begin(), probe.quantities.end(), q) -
                                              probe.quantities.begin());
        const double vf = predictedVariance(f, f, static_cast<double>(f.samples), static_cast<double>(cfg.probePhotons));
        // i by an init-capture: clang before 16 (14 builds the rendered-IR fuzzer) cannot capture a
        // structured binding.
        auto backwardPilot = [&, index = i](int n) {
            const ProbeValue b = backwardValue(scene, estimators, probe, index, qi, std::max(kPilotBatches, n),
                                               probeStreamBase(estimators) + kProbePilotOffset, quiet, nullptr,
                                               kPilotBatches);
            return std::pair{b, predictedVariance(b, f, static_cast<double>(b.samples), static_cast<double>(N))};
        };
        // A quarter-size backward pilot first: a pilot too small to have met the backward paths' rare
        // large values understates their error, never overstates it, so where even it predicts 4 times
        // the forward variance the forward tallies win without the full pilot (problem 2: by 12-60x).
        auto [b, vb] = backwardPilot(N / 64);
        const bool clear = anyPositive(f) && vf <= kForwardTrustedVariance && vb > kClearMargin * vf;
        if (!clear) std::tie(b, vb) = backwardPilot(N / 16);
        bool forward = vf <= vb;
        std::string why = fmt::format("the pilot predicts a relative standard error of {:.2g} % forward, {:.2g} % backward{}",
                                      100 * std::sqrt(vf), 100 * std::sqrt(vb), clear ? " (a quarter-size backward pilot)" : "");
        if (!anyPositive(f)) forward = false, why = "no forward photon reached its plane in the pilot";
        else if (disagree(f, b))
            forward = true, why = "the pilots disagree, and backward paths here are heavy-tailed: " + why;
        else if (vf > kForwardTrustedVariance)
            forward = false, why = "too few forward photons reach its plane for their spread to be trusted: " + why;
        if (forward) chosen.insert({i, q});
        log::debug("probe {} {}: {} ({})", probe.name, q, forward ? "forward" : "backward", why);
    }
    if (!pilot.answered().empty())
        log::info("probe methods: the pilot chose forward tallies for {} and backward paths for {} of the {} probe "
                  "values they could answer (the reasons: --verbose; the methods: probes.csv)",
                  chosen.size(), pilot.answered().size() - chosen.size(), pilot.answered().size());
    return chosen;
}

// A known limit, warned about when it applies (docs/rendering.md, Known limits): backward Lu paths in
// water with a forward-peaked phase function and a high single-scattering albedo are heavy-tailed,
// so a run of 10^4-10^5 paths can read low by more than its reported standard error says (Mobley et
// al.'s problem 2, Petzold at albedo 0.9: 9-13 % low at 2.1-2.5 reported se with 25 000-200 000
// paths). At albedo 0.2 (problem 6) they meet the published values; 0.5 is the threshold between.
// The dirsig estimator's Lu from the volume photon map is heavy-tailed in the same water (it applies
// where the probe's medium is MediumPM). The band-mean albedo at the probe, or 0 where the limit does
// not apply.
double heavyTailedLuAlbedo(const Scene& scene, const RenderConfig& cfg, const ir::Probe& probe) {
    const int medium = scene.mediumIndex(probe.medium, fmt::format("probe '{}' medium", probe.name));
    if (medium <= 0) return 0;
    const size_t pm = static_cast<size_t>(medium - 1);
    if (cfg.estimator == ir::Estimator::Dirsig && (pm >= cfg.mediumPM.size() || !cfg.mediumPM[pm])) return 0;
    const Medium& md = scene.media()[static_cast<size_t>(medium)];
    if (!md.scattering() || !md.forwardPeaked()) return 0;
    const MediumLayer& l = md.layers()[static_cast<size_t>(md.layerAt(probe.position.z))];
    double albedo = 0;
    int n = 0;
    for (size_t b = 0; b < l.c.size(); ++b)
        if (l.c[b] > 0) albedo += l.b[b] / l.c[b], ++n;
    return n > 0 && albedo / n >= 0.5 ? albedo / n : 0;
}

// One warning for the Lu values that came from backward paths (path) or from the volume photon map
// (dirsig) where heavyTailedLuAlbedo applies: `count` of them, the first at `first` (its probe and
// albedo).
void warnAboutHeavyTailedLu(int count, const std::string& first, ir::Estimator estimator) {
    if (count <= 0) return;
    if (estimator == ir::Estimator::Path)
        log::warn("{} Lu value(s) (the first: {}) come from backward paths in water with a forward-peaked phase "
                  "function and a high albedo, which are heavy-tailed: the standard error can understate the error "
                  "(Mobley et al.'s problem 2, albedo 0.9: 9-13 % low at 2.1-2.5 reported standard errors with "
                  "25 000-200 000 paths, within 3 % with 16 times more); raise the probes' samples, or compare with "
                  "`littoral column`",
                  count, first);
    else
        log::warn("{} Lu value(s) (the first: {}) come from the volume photon map in water with a forward-peaked "
                  "phase function and a high albedo: a few upward photons near the view direction carry most of the "
                  "value, and the standard error can understate the error (Mobley et al.'s problem 5 at a search "
                  "radius of 0.1 m: 14-35 % low, at up to 6 reported standard errors); raise "
                  "render.search_radius_m.volume or the photons, or compare with `littoral column`",
                  count, first);
}

}  // namespace

const ProbeValue* ProbeAnswers::find(int index, const std::string& q) const {
    const auto it = values_.find({index, q});
    return it == values_.end() ? nullptr : &it->second;
}

std::vector<std::pair<int, std::string>> ProbeAnswers::answered() const {
    std::vector<std::pair<int, std::string>> keys;
    for (const auto& [key, v] : values_) keys.push_back(key);
    return keys;
}

std::vector<ProbeValue> evaluateProbe(const Scene& scene, const EstimatorSet& estimators, const ir::Probe& probe,
                                      int probeIndex, const RenderOptions& opts, const ProbeAnswers* answers) {
    const RenderConfig& cfg = estimators.config();
    checkProbe(scene, cfg, probe);
    const int B = cfg.probeBatches;
    const int N = probe.samples.value_or(cfg.probeSamples);
    const int chunksPerBatch = (N / B + 1023) / 1024;
    size_t backward = 0;  // the quantities this call traces
    for (const std::string& q : probe.quantities) backward += !(answers && answers->find(probeIndex, q));
    std::unique_ptr<Progress> progress;
    const uint64_t totalChunks = static_cast<uint64_t>(chunksPerBatch) * B * backward * estimators.size();
    if (opts.progress && totalChunks > 64)
        progress = std::make_unique<Progress>(fmt::format("probe {}", probe.name), totalChunks, "chunks");
    std::vector<ProbeValue> out;
    for (size_t qi = 0; qi < probe.quantities.size(); ++qi) {
        if (const ProbeValue* f = answers ? answers->find(probeIndex, probe.quantities[qi]) : nullptr) {
            out.push_back(*f);
            continue;
        }
        out.push_back(
            backwardValue(scene, estimators, probe, probeIndex, qi, N, probeStreamBase(estimators), opts, progress.get()));
    }
    if (progress) progress->finish();
    return out;
}

std::vector<ProbeValue> evaluateProbes(const Scene& scene, const EstimatorSet& estimators, const RenderOptions& opts,
                                       const CollisionPlan* collisions) {
    ForwardTallyRun run;
    run.only = chooseForward(scene, estimators, opts, &run.profile);
    // The path estimator's forward tallies, or the dirsig estimator's volume-map collisions.
    const ProbeAnswers answers = !run.only.empty() ? ProbeAnswers(ForwardTallies(scene, estimators, opts, run))
                                 : collisions      ? volumeMapCollisions(scene, estimators, *collisions)
                                                   : ProbeAnswers();
    std::vector<ProbeValue> out;
    const auto& probes = scene.ir().probes;
    const RenderConfig& cfg = estimators.config();
    const bool warn = estimators.pass() == 1;
    int heavy = 0;  // Lu values answered in a heavy-tailed way (warned about once)
    std::string first;
    for (size_t i = 0; i < probes.size(); ++i) {
        auto v = evaluateProbe(scene, estimators, probes[i], static_cast<int>(i), opts, &answers);
        for (const ProbeValue& pv : v) {
            if (!warn || pv.quantity != "Lu" || pv.method != "backward") continue;
            const double albedo = heavyTailedLuAlbedo(scene, cfg, probes[i]);
            if (albedo > 0 && heavy++ == 0)
                first = fmt::format("probe '{}', in water of single-scattering albedo {:.2f}", pv.probe, albedo);
        }
        out.insert(out.end(), v.begin(), v.end());
    }
    warnAboutHeavyTailedLu(heavy, first, cfg.estimator);
    return out;
}

std::vector<ProbeValue> evaluateProbe(const Scene& scene, const ir::Probe& probe, int probeIndex,
                                      const RenderOptions& opts) {
    const EstimatorSet estimators(scene);
    return evaluateProbe(scene, estimators, probe, probeIndex, opts);
}

std::string probesCsv(const std::vector<ProbeValue>& values, const std::vector<Band>& bands) {
    std::string s = "probe,quantity,band_lo_um,band_hi_um,value,stderr,units,x_m,y_m,z_m,medium,samples,batches,method\n";
    for (const ProbeValue& v : values)
        for (size_t b = 0; b < bands.size(); ++b)
            s += fmt::format("{},{},{},{},{:.9g},{:.9g},{},{:.9g},{:.9g},{:.9g},{},{},{},{}\n", v.probe, v.quantity,
                             bands[b].lo, bands[b].hi, v.mean[b], v.stderr_[b], v.units, v.position.x, v.position.y,
                             v.position.z, v.medium, v.samples, v.batches, v.method);
    return s;
}

std::string probesJson(const std::vector<ProbeValue>& values, const std::vector<Band>& bands) {
    nlohmann::json j;
    j["bands"] = nlohmann::json::array();
    for (const Band& b : bands) j["bands"].push_back({{"lo_um", b.lo}, {"hi_um", b.hi}});
    j["probes"] = nlohmann::json::array();
    for (const ProbeValue& v : values)
        j["probes"].push_back({{"probe", v.probe},
                               {"quantity", v.quantity},
                               {"units", v.units},
                               {"position_m", {v.position.x, v.position.y, v.position.z}},
                               {"medium", v.medium},
                               {"value", v.mean},
                               {"stderr", v.stderr_},
                               {"samples", v.samples},
                               {"batches", v.batches},
                               {"method", v.method}});
    return j.dump(2) + "\n";
}

// K_d between consecutive Ed probes of one vertical run (in the order of `probes`: a vertical `line`
// entry gives one), K_d = ln(Ed_upper / Ed_lower) / (z_upper - z_lower); its standard error from the
// two probes' (independent samples) as sqrt((se_u / Ed_u)^2 + (se_l / Ed_l)^2) / dz. Pairs where
// either Ed is not positive are left out.
std::string kdCsv(const std::vector<ProbeValue>& values, const std::vector<Band>& bands) {
    std::vector<const ProbeValue*> ed;
    for (const ProbeValue& v : values)
        if (v.quantity == "Ed") ed.push_back(&v);
    std::string s;
    for (size_t i = 0; i + 1 < ed.size(); ++i) {
        const ProbeValue& u = *ed[i];
        const ProbeValue& l = *ed[i + 1];
        const double dz = u.position.z - l.position.z;
        if (std::abs(u.position.x - l.position.x) > 1e-9 || std::abs(u.position.y - l.position.y) > 1e-9 || !(dz > 0))
            continue;
        for (size_t b = 0; b < bands.size(); ++b) {
            if (!(u.mean[b] > 0 && l.mean[b] > 0)) continue;
            const double kd = std::log(u.mean[b] / l.mean[b]) / dz;
            const double ru = u.stderr_[b] / u.mean[b], rl = l.stderr_[b] / l.mean[b];
            s += fmt::format("{},{},{:.9g},{:.9g},{:.9g},{:.9g},{},{},{:.9g},{:.9g}\n", u.probe, l.probe, u.position.x,
                             u.position.y, u.position.z, l.position.z, bands[b].lo, bands[b].hi, kd,
                             std::sqrt(ru * ru + rl * rl) / dz);
        }
    }
    if (s.empty()) return "";
    return "upper_probe,lower_probe,x_m,y_m,z_upper_m,z_lower_m,band_lo_um,band_hi_um,kd_per_m,kd_stderr_per_m\n" + s;
}

int warnAboutUncertainProbes(const std::vector<ProbeValue>& values, const std::vector<Band>& bands) {
    constexpr double kRelative = 0.5;
    int count = 0, total = 0;
    double worst = 0;
    std::string worstText;
    for (const ProbeValue& v : values)
        for (size_t b = 0; b < v.mean.size() && b < v.stderr_.size(); ++b) {
            ++total;
            const double m = std::abs(v.mean[b]), se = std::abs(v.stderr_[b]);
            if (!(m > 0) || !(se > kRelative * m)) continue;
            ++count;
            if (se / m <= worst) continue;
            worst = se / m;
            const std::string band =
                b < bands.size() ? fmt::format(" {:g}-{:g} um", bands[b].lo, bands[b].hi) : std::string();
            worstText = fmt::format("{} {}{}: {:.4g} +- {:.4g}", v.probe, v.quantity, band, v.mean[b], v.stderr_[b]);
        }
    if (count > 0)
        log::warn("{} of {} probe value(s) have a standard error above {:.0f} % of the value (worst: {}): a rare light "
                  "path carries most of such a value (for example sunlight that one wave facet reflects into another, "
                  "docs/rendering.md, Known limits); raise render.probe_samples, or compare with the photon maps",
                  count, total, 100 * kRelative, worstText);
    return count;
}

}  // namespace littoral::render
