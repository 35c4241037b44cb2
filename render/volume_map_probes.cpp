#include "render/volume_map_probes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/log.h"
#include "render/forward_tally.h"
#include "render/photon_pass.h"

namespace littoral::render {

namespace {

enum Tally { kEd, kEu, kEod, kEou, kTallies };
constexpr std::array<const char*, kTallies> kNames = {"Ed", "Eu", "Eod", "Eou"};

// One probe's slab: its centre, half-thickness and medium, and (per band, per tally) the sums of
// x = Phi g / b_s and of x^2 over the records in it.
struct Slab {
    int probe;
    double z, h;
    int medium;
    std::vector<std::array<double, kTallies>> s0, s1;  // [band][tally]
};

// The slab half-thickness for a probe at z in medium md between the scene's horizontal faces
// (0 where it would reach no further than the radius).
double slabHalfThickness(const Medium& md, const std::vector<double>& faces, double z, double radius) {
    double h = kSlabRadii * radius;
    for (double f : faces) h = std::min(h, std::abs(f - z));
    for (const MediumLayer& l : md.layers())
        for (double b : {l.zTop, l.zBottom})
            if (std::isfinite(b)) h = std::min(h, std::abs(b - z));
    return h >= radius ? h : 0.0;
}

// The slabs of every probe quantity this answers (quantities in `asked`).
std::vector<Slab> slabsOf(const Scene& scene, const RenderConfig& cfg, const std::vector<double>& faces,
                          std::vector<std::vector<int>>* asked) {
    std::vector<Slab> slabs;
    const auto& probes = scene.ir().probes;
    for (size_t i = 0; i < probes.size(); ++i) {
        const ir::Probe& p = probes[i];
        const int m = scene.mediumIndex(p.medium, fmt::format("probe '{}' medium", p.name));
        if (m <= 0 || static_cast<size_t>(m - 1) >= cfg.mediumPM.size() || !cfg.mediumPM[static_cast<size_t>(m - 1)])
            continue;
        const Medium& md = scene.media()[static_cast<size_t>(m)];
        if (!md.scattering()) continue;
        std::vector<int> tallies;
        for (const std::string& q : p.quantities)
            for (int t = 0; t < kTallies; ++t)
                if (q == kNames[static_cast<size_t>(t)]) tallies.push_back(t);
        const double h = slabHalfThickness(md, faces, p.position.z, cfg.volumeRadius);
        if (tallies.empty() || h <= 0) continue;
        slabs.push_back({static_cast<int>(i), p.position.z, h, m, {}, {}});
        asked->push_back(tallies);
    }
    return slabs;
}

// Adds the volume map's records to the slabs' sums (bands of group g; s0 sized to every band).
void addRecords(const Scene& scene, const RenderConfig& cfg, const PhotonMap& vm, BandGroup g, std::vector<Slab>* slabs) {
    for (size_t i = 0; i < vm.size(); ++i) {
        const double z = vm.position(i).z;
        for (Slab& s : *slabs) {
            if (!(std::abs(z - s.z) <= s.h)) continue;
            const Medium& md = scene.media()[static_cast<size_t>(s.medium)];
            const MediumLayer& l = md.layers()[static_cast<size_t>(md.layerAt(z))];
            const double mu = vm.direction(i).z;
            for (int b = 0; b < g.count; ++b) {
                const int band = g.begin + b;
                const double bs = cfg.effectiveScattering ? l.cEff[band] - l.a[band] : l.b[band];
                if (!(bs > 0)) continue;
                const double x = static_cast<double>(vm.power(i, b)) * vm.fluxScale[b] / bs;
                std::array<double, kTallies> gx{};
                if (mu < 0) gx[kEd] = -mu * x, gx[kEod] = x;
                if (mu > 0) gx[kEu] = mu * x, gx[kEou] = x;
                for (int t = 0; t < kTallies; ++t) s.s0[band][t] += gx[t], s.s1[band][t] += gx[t] * gx[t];
            }
        }
    }
}

// The slabs of the run's probes with their sums over the volume maps of `maps` (one per band
// group, nullptr where a group has none); *asked receives each slab's tallies. Empty, with a
// warning, when no probe value qualifies.
std::vector<Slab> slabSums(const Scene& scene, const RenderConfig& cfg, const std::vector<const PhotonMap*>& maps,
                           const std::vector<BandGroup>& groups, std::vector<std::vector<int>>* asked) {
    std::vector<double> faces;
    if (cfg.estimator != ir::Estimator::Dirsig || !cfg.probeCollisions || cfg.passes < 2 || cfg.volumePhotons == 0 ||
        !horizontalFacePlanes(scene.ir(), &faces))
        return {};
    std::vector<Slab> slabs = slabsOf(scene, cfg, faces, asked);
    const int nb = scene.bandCount();
    for (Slab& s : slabs) s.s0.assign(nb, {}), s.s1.assign(nb, {});
    for (size_t gi = 0; gi < maps.size(); ++gi)
        if (maps[gi]) addRecords(scene, cfg, *maps[gi], groups[gi], &slabs);
    return slabs;
}

// The pilot's map: a quarter of a pass's volume photons (and no surface map), on random streams of
// its own, split by depth as the passes are.
constexpr uint64_t kCollisionPilotStream = 1ull << 47;
constexpr uint64_t kCollisionPilotShare = 4;

}  // namespace

CollisionPlan planCollisions(const Scene& scene, int threads) {
    CollisionPlan plan;
    const RenderConfig cfg = makeRenderConfig(scene.ir());
    const std::vector<BandGroup> groups = bandGroups(scene);
    std::vector<std::vector<int>> asked;
    std::vector<double> faces;
    if (cfg.estimator != ir::Estimator::Dirsig || !cfg.probeCollisions || cfg.passes < 2 || cfg.volumePhotons == 0 ||
        !horizontalFacePlanes(scene.ir(), &faces))
        return plan;
    if (slabsOf(scene, cfg, faces, &asked).empty()) {
        // Set, but nothing for it to do: said once, not silently ignored.
        log::warnOnce("render.photons.probe_collisions is set, but no probe value can be answered from the volume "
                      "map's collisions (Ed, Eu, Eod or Eou of a probe in water that keeps a volume map, at least one "
                      "volume search radius from a horizontal face or layer boundary): every probe value is gathered");
        return plan;
    }
    asked.clear();
    std::vector<PhotonMaps> pilots;
    pilots.reserve(groups.size());
    std::vector<const PhotonMap*> maps;
    for (const BandGroup& g : groups) {
        RenderConfig c = cfg;
        c.surfacePhotons = 0;
        c.volumePhotons = std::max<uint64_t>(1000, cfg.volumePhotons / kCollisionPilotShare);
        PhotonPassSettings ps = photonPassSettings(scene, c, g, 1, threads, false, 0);
        ps.pass = kCollisionPilotStream + static_cast<uint64_t>(g.begin);
        pilots.push_back(tracePhotons(scene, g, ps));
        maps.push_back(&pilots.back().volume);
    }
    const std::vector<Slab> slabs = slabSums(scene, cfg, maps, groups, &asked);
    const double share = static_cast<double>(std::max<uint64_t>(1000, cfg.volumePhotons / kCollisionPilotShare)) /
                         static_cast<double>(cfg.volumePhotons);
    const auto& probes = scene.ir().probes;
    int chosen = 0, total = 0;
    for (size_t k = 0; k < slabs.size(); ++k) {
        const Slab& s = slabs[k];
        for (int t : asked[k]) {
            // The predicted relative error of one pass: the records' own spread, scaled from the
            // pilot's photons to a pass's, and by kRecordCorrelation for the records one photon's
            // walk leaves in the slab (worst band).
            double se = 0;
            for (size_t b = 0; b < s.s0.size(); ++b) {
                const double m = s.s0[b][static_cast<size_t>(t)];
                se = std::max(se, m > 0 ? kRecordCorrelation * std::sqrt(s.s1[b][static_cast<size_t>(t)] * share) / m
                                        : std::numeric_limits<double>::infinity());
            }
            const bool use = se <= kCollisionTrustedSe;
            ++total;
            if (use) plan.values.insert({s.probe, kNames[static_cast<size_t>(t)]}), ++chosen;
            log::debug("probe {} {}: {} (the pilot predicts {:.2g} % a pass from the collisions in its slab of +-{:.3g} m)",
                       probes[static_cast<size_t>(s.probe)].name, kNames[static_cast<size_t>(t)],
                       use ? "collisions" : "gather", 100 * se, s.h);
        }
    }
    log::info("probe methods: the volume map's collisions answer {} of the {} probe values they could, the gather the "
              "rest (the reasons: --verbose; the methods: probes.csv)", chosen, total);
    return plan;
}

ProbeAnswers volumeMapCollisions(const Scene& scene, const EstimatorSet& estimators, const CollisionPlan& plan) {
    ProbeAnswers answers;
    const RenderConfig& cfg = estimators.config();
    std::vector<const PhotonMap*> maps;
    for (size_t gi = 0; gi < estimators.size(); ++gi) {
        const PhotonMaps* m = estimators.photonMaps(gi);
        maps.push_back(m ? &m->volume : nullptr);
    }
    std::vector<std::vector<int>> asked;
    const std::vector<Slab> slabs = plan.values.empty() ? std::vector<Slab>{} : slabSums(scene, cfg, maps, estimators.groups(), &asked);
    int64_t records = 0;
    for (const PhotonMap* m : maps)
        if (m) records = std::max(records, static_cast<int64_t>(m->size()));
    const int nb = scene.bandCount();
    const ir::Domain& d = scene.domain();
    const double area = (d.x1 - d.x0) * (d.y1 - d.y0);
    for (size_t k = 0; k < slabs.size(); ++k) {
        const Slab& s = slabs[k];
        const ir::Probe& p = scene.ir().probes[static_cast<size_t>(s.probe)];
        for (int t : asked[k]) {
            if (!plan.values.count({s.probe, kNames[static_cast<size_t>(t)]})) continue;
            ProbeValue v;
            v.probe = p.name;
            v.quantity = kNames[static_cast<size_t>(t)];
            v.units = "W m^-2 um^-1";
            v.position = p.position;
            v.medium = p.medium;
            v.mean.assign(nb, 0.0);
            v.stderr_.assign(nb, 0.0);  // the passes' spread replaces it (render_job.cpp)
            for (int b = 0; b < nb; ++b) v.mean[b] = s.s0[b][t] / (2 * s.h * area);
            v.samples = records;
            v.batches = cfg.passes;
            v.method = "collisions";
            const std::string q = v.quantity;  // not v's own: v is moved into the call
            answers.set(s.probe, q, std::move(v));
        }
    }
    return answers;
}

}  // namespace littoral::render
