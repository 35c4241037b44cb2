#include "render/volume_map_probes.h"

#include <algorithm>
#include <array>
#include <cmath>
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

// One probe's slab: its centre, half-thickness and medium, and (per band, per tally) the sum of
// Phi g / b_s over the records in it.
struct Slab {
    int probe;
    double z, h;
    int medium;
    std::vector<std::array<double, kTallies>> s0;  // [band][tally]
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
        slabs.push_back({static_cast<int>(i), p.position.z, h, m, {}});
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
                for (int t = 0; t < kTallies; ++t) s.s0[band][t] += gx[t];
            }
        }
    }
}

}  // namespace

ProbeAnswers volumeMapCollisions(const Scene& scene, const EstimatorSet& estimators) {
    ProbeAnswers answers;
    const RenderConfig& cfg = estimators.config();
    std::vector<double> faces;
    if (cfg.estimator != ir::Estimator::Dirsig || !cfg.probeCollisions || cfg.passes < 2 || cfg.volumePhotons == 0 ||
        !horizontalFacePlanes(scene.ir(), &faces))
        return answers;
    std::vector<std::vector<int>> asked;
    std::vector<Slab> slabs = slabsOf(scene, cfg, faces, &asked);
    if (slabs.empty()) {
        // Set, but nothing for it to do: said once, not silently ignored.
        log::warnOnce("render.photons.probe_collisions is set, but no probe value can be answered from the volume "
                      "map's collisions (Ed, Eu, Eod or Eou of a probe in water that keeps a volume map, at least one "
                      "volume search radius from a horizontal face or layer boundary): every probe value is gathered");
        return answers;
    }
    const int nb = scene.bandCount();
    for (Slab& s : slabs) s.s0.assign(nb, {});
    int64_t records = 0;
    for (size_t gi = 0; gi < estimators.size(); ++gi) {
        const PhotonMaps* maps = estimators.photonMaps(gi);
        if (!maps) continue;
        addRecords(scene, cfg, maps->volume, estimators.groups()[gi], &slabs);
        records = std::max(records, static_cast<int64_t>(maps->volume.size()));
    }
    const ir::Domain& d = scene.domain();
    const double area = (d.x1 - d.x0) * (d.y1 - d.y0);
    for (size_t k = 0; k < slabs.size(); ++k) {
        const Slab& s = slabs[k];
        const ir::Probe& p = scene.ir().probes[static_cast<size_t>(s.probe)];
        for (int t : asked[k]) {
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
