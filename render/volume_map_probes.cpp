#include "render/volume_map_probes.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/log.h"
#include "core/units.h"
#include "render/forward_tally.h"
#include "render/photon_pass.h"

namespace littoral::render {

namespace {

const Vec3 kUp{0, 0, 1};

// One value's slab: its probe and tally, centre, half-thickness and medium, and per band the sums
// of x = Phi g / b_s, of x^2 and of x (z - z_p) over the records in it. For Lu the "slab" is the
// water below the probe down to the surface its nadir ray meets (h: the distance to it), and x is
// the record's in-scatter toward the probe (addRecords).
struct Slab {
    int probe, tally;
    double z, h;
    int medium;
    std::vector<double> s0, s1, sz;  // [band]
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

// The distance from p straight down to a black surface (infinite if the ray meets nothing), or 0
// where it meets another kind: the Lu of a probe above a surface that reflects or transmits light
// needs that surface's radiance, which the gather's view ray brings (render/dirsig_estimator.cpp).
double blackBelow(const Scene& scene, const Point3& p) {
    SurfaceHit h;
    if (!scene.geometry().intersect(Ray{p, Vec3{0, 0, -1}}, &h)) return ir::kInfinity;
    const auto idx = static_cast<size_t>(scene.materialIndex(h));
    return idx < scene.ir().materials.size() && scene.ir().materials[idx].type == ir::Material::Type::Black ? h.t : 0.0;
}

// The slab of every probe value this could answer, at its largest half-thickness.
std::vector<Slab> candidateSlabs(const Scene& scene, const RenderConfig& cfg, const std::vector<double>& faces) {
    std::vector<Slab> slabs;
    const auto& probes = scene.ir().probes;
    for (size_t i = 0; i < probes.size(); ++i) {
        const ir::Probe& p = probes[i];
        const int m = scene.mediumIndex(p.medium, fmt::format("probe '{}' medium", p.name));
        if (m <= 0 || static_cast<size_t>(m - 1) >= cfg.mediumPM.size() || !cfg.mediumPM[static_cast<size_t>(m - 1)])
            continue;
        const Medium& md = scene.media()[static_cast<size_t>(m)];
        if (!md.scattering()) continue;
        const double h = slabHalfThickness(md, faces, p.position.z, cfg.volumeRadius);
        for (const std::string& q : p.quantities) {
            const int t = tallyOf(q);
            if (t == kLu) {
                // A forward-peaked phase function is bounded only once effective scattering cuts its
                // cone out: Petzold's own peak gives the sum an infinite variance (docs/rendering.md).
                const double below = !md.forwardPeaked() || cfg.effectiveScattering ? blackBelow(scene, p.position) : 0;
                if (below > 0)
                    slabs.push_back({static_cast<int>(i), t, p.position.z, below, m, {}, {}, {}});
            } else if (t >= 0 && h > 0) {
                slabs.push_back({static_cast<int>(i), t, p.position.z, h, m, {}, {}, {}});
            }
        }
    }
    return slabs;
}

// Adds record i's in-scatter toward a probe above it to Lu's sums: in a horizontally invariant
// scene the in-scatter J(z, up) per unit length is (1 / A) sum_i Phi_i p(d_i -> up) delta(z - z_i),
// and Lu(z_p) = Int J(z) T(z_p - z) dz over the water below, down to the black surface: each
// record below adds Phi_i p(d_i -> up) T / A (the gather's disc kernel 1 / (pi r^2) per unit length,
// spread over the whole plane). With effective scattering, as in the gather, the phase function
// is the part outside the 0.01 sr cone (over 1 - f), a record whose cone holds the view direction
// is unscattered light, and T is the effective transmittance.
void addLu(const Scene& scene, const RenderConfig& cfg, const PhotonMap& vm, BandGroup g, size_t i, Slab* s) {
    const double z = vm.position(i).z;
    if (!(z < s->z && s->z - z < s->h)) return;
    const Vec3 dir = vm.direction(i);
    const bool eff = cfg.effectiveScattering;
    if (eff && dir.z > 1.0 - kEffectiveConeSr / (2.0 * kPi)) return;
    const Medium& md = scene.media()[static_cast<size_t>(s->medium)];
    const Spec T = md.transmittance(Ray{Point3{0, 0, s->z}, Vec3{0, 0, -1}}, s->z - z, g, eff);
    if (T.maxValue() < 6e-6) return;
    const int layer = md.layerAt(z);
    const Spec p = md.phase(layer, g, dir, kUp);
    for (int b = 0; b < g.count; ++b) {
        const size_t band = static_cast<size_t>(g.begin + b);
        const double cone = eff ? md.layers()[static_cast<size_t>(layer)].outsideCone[band] : 1.0;
        const double x = T[b] * p[b] * cone * static_cast<double>(vm.power(i, b)) * vm.fluxScale[b];
        s->s0[band] += x, s->s1[band] += x * x;
    }
}

// Adds the volume map's records to the slabs' sums (bands of group g).
void addRecords(const Scene& scene, const RenderConfig& cfg, const PhotonMap& vm, BandGroup g, std::vector<Slab>* slabs) {
    for (size_t i = 0; i < vm.size(); ++i) {
        const double z = vm.position(i).z;
        for (Slab& s : *slabs) {
            if (s.tally == kLu) {
                addLu(scene, cfg, vm, g, i, &s);
                continue;
            }
            if (!(std::abs(z - s.z) <= s.h)) continue;
            const double mu = vm.direction(i).z;
            const bool down = s.tally == kEd || s.tally == kEod;
            if (down ? !(mu < 0) : !(mu > 0)) continue;
            const double gmu = s.tally == kEd || s.tally == kEu ? std::abs(mu) : 1.0;
            const Medium& md = scene.media()[static_cast<size_t>(s.medium)];
            const MediumLayer& l = md.layers()[static_cast<size_t>(md.layerAt(z))];
            for (int b = 0; b < g.count; ++b) {
                const size_t band = static_cast<size_t>(g.begin + b);
                const double bs = cfg.effectiveScattering ? l.cEff[band] - l.a[band] : l.b[band];
                if (!(bs > 0)) continue;
                const double x = gmu * static_cast<double>(vm.power(i, b)) * vm.fluxScale[b] / bs;
                s.s0[band] += x, s.s1[band] += x * x, s.sz[band] += x * (z - s.z);
            }
        }
    }
}

// `slabs` with their sums over the volume maps of `maps` (one per band group, nullptr where a
// group has none).
void sumSlabs(const Scene& scene, const RenderConfig& cfg, const std::vector<const PhotonMap*>& maps,
              const std::vector<BandGroup>& groups, std::vector<Slab>* slabs) {
    const size_t nb = static_cast<size_t>(scene.bandCount());
    for (Slab& s : *slabs) s.s0.assign(nb, 0.0), s.s1.assign(nb, 0.0), s.sz.assign(nb, 0.0);
    for (size_t gi = 0; gi < maps.size(); ++gi)
        if (maps[gi]) addRecords(scene, cfg, *maps[gi], groups[gi], slabs);
}

// The pilot's map: a quarter of a pass's volume photons, or a whole chunk of photons where that is
// more (and no surface map), on random streams of its own, split by depth as the passes are.
constexpr uint64_t kCollisionPilotStream = 1ull << 47;
constexpr uint64_t kCollisionPilotShare = 4;

// The pilot's volume maps, one per band group.
std::vector<PhotonMaps> pilotMaps(const Scene& scene, const RenderConfig& cfg, const std::vector<BandGroup>& groups,
                                  int threads) {
    std::vector<PhotonMaps> pilots;
    for (const BandGroup& g : groups) {
        RenderConfig c = cfg;
        c.surfacePhotons = 0;
        c.volumePhotons = std::max<uint64_t>(1000, cfg.volumePhotons / kCollisionPilotShare);
        PhotonPassSettings ps = photonPassSettings(scene, c, g, 1, threads, false, 0);
        ps.pass = kCollisionPilotStream + static_cast<uint64_t>(g.begin);
        pilots.push_back(tracePhotons(scene, g, ps));
    }
    return pilots;
}

// One value's choice from its pilot slab `s` (share: the pilot's photons over a pass's): the
// half-thickness that keeps the estimated kernel bias within kSlabBias, and the predicted relative
// error of one pass at it (above; infinite where the half-thickness falls below `radius` or no
// record reached the slab). *why receives the figures, for the log.
std::pair<double, double> choose(const Slab& s, double share, double radius, std::string* why) {
    double k = 0, se = 0;
    for (size_t b = 0; b < s.s0.size(); ++b) {
        if (!(s.s0[b] > 0)) return {0.0, std::numeric_limits<double>::infinity()};
        // The records' mean offset from the probe is k h^2 / 3 for a profile e^(k (z - z_p)).
        k = std::max(k, std::abs(3 * s.sz[b] / s.s0[b]) / (s.h * s.h));
        se = std::max(se, kRecordCorrelation * std::sqrt(s.s1[b] * share) / s.s0[b]);
    }
    if (s.tally == kLu) {  // no slab: every record below
        *why = fmt::format("the pilot predicts {:.2g} % a pass from the in-scatter of every record below", 100 * se);
        return {s.h, se};
    }
    const double h = k * s.h * k * s.h / 6 > kSlabBias ? std::sqrt(6 * kSlabBias) / k : s.h;
    // The records in a slab are about proportional to its thickness.
    se = h >= radius ? se * std::sqrt(s.h / h) : std::numeric_limits<double>::infinity();
    *why = fmt::format("the pilot predicts {:.2g} % a pass from the collisions in its slab of +-{:.3g} m; the profile "
                       "changes as e^({:.2g} m^-1 z) there",
                       100 * se, h, k);
    return {h, se};
}

}  // namespace

CollisionPlan planCollisions(const Scene& scene, int threads) {
    CollisionPlan plan;
    const RenderConfig cfg = makeRenderConfig(scene.ir());
    std::vector<double> faces;
    if (cfg.estimator != ir::Estimator::Dirsig || !cfg.probeCollisions || cfg.passes < 2 || cfg.volumePhotons == 0 ||
        !horizontalFacePlanes(scene.ir(), &faces))
        return plan;
    std::vector<Slab> slabs = candidateSlabs(scene, cfg, faces);
    if (slabs.empty()) {
        // Set, but nothing for it to do: said once, not silently ignored.
        log::warnOnce("render.photons.probe_collisions is set, but no probe value can be answered from the volume "
                      "map's collisions (Ed, Eu, Eod or Eou of a probe in water that keeps a volume map, at least one "
                      "volume search radius from a horizontal face or layer boundary; Lu where the probe's nadir ray "
                      "meets a black surface or nothing, in forward-peaked water only with effective scattering): "
                      "every probe value is gathered");
        return plan;
    }
    const std::vector<BandGroup> groups = bandGroups(scene);
    const std::vector<PhotonMaps> pilots = pilotMaps(scene, cfg, groups, threads);
    std::vector<const PhotonMap*> maps;
    for (const PhotonMaps& m : pilots) maps.push_back(&m.volume);
    sumSlabs(scene, cfg, maps, groups, &slabs);
    // The pilot's records over a pass's. Maps fill by whole chunks of photons, so a pass stores its
    // target rounded up to a chunk's records (at the pilot's records per photon), and the pilot's
    // smaller target may fill a chunk as large as the pass's.
    double share = 1.0;
    for (const PhotonMaps& m : pilots) {
        if (m.volume.size() == 0 || m.emittedVolume == 0) continue;
        const double perChunk = static_cast<double>(m.volume.size()) / static_cast<double>(m.emittedVolume) *
                                static_cast<double>(kPhotonChunk);
        const double pass = std::ceil(static_cast<double>(cfg.volumePhotons) / perChunk) * perChunk;
        share = std::min(share, static_cast<double>(m.volume.size()) / std::max(pass, 1.0));
    }
    for (const Slab& s : slabs) {
        std::string why;
        const auto [h, se] = choose(s, share, cfg.volumeRadius, &why);
        // Lu: always, where it applies. Its estimate is the gather's along the nadir line with the disc
        // kernel spread over the whole plane (addLu), so it sums every record the gather would and
        // about A / (pi r^2) times as many besides, with the same weights: never noisier.
        const bool use = s.tally == kLu ? std::isfinite(se) : se <= kCollisionTrustedSe;
        const std::string q = kTallyNames[static_cast<size_t>(s.tally)];
        if (use) plan.values[{s.probe, q}] = h;
        log::debug("probe {} {}: {} ({})", scene.ir().probes[static_cast<size_t>(s.probe)].name, q,
                   use ? "collisions" : "gather", why);
    }
    log::info("probe methods: the volume map's collisions answer {} of the {} probe values they could, the gather the "
              "rest (the reasons: --verbose; the methods: probes.csv)",
              plan.values.size(), slabs.size());
    return plan;
}

ProbeAnswers volumeMapCollisions(const Scene& scene, const EstimatorSet& estimators, const CollisionPlan& plan) {
    ProbeAnswers answers;
    if (plan.values.empty()) return answers;
    const RenderConfig& cfg = estimators.config();
    const auto& probes = scene.ir().probes;
    std::vector<Slab> slabs;
    for (const auto& [key, h] : plan.values) {
        const ir::Probe& p = probes[static_cast<size_t>(key.first)];
        const int m = scene.mediumIndex(p.medium, fmt::format("probe '{}' medium", p.name));
        slabs.push_back({key.first, tallyOf(key.second), p.position.z, h, m, {}, {}, {}});
    }
    std::vector<const PhotonMap*> maps;
    int64_t records = 0;
    for (size_t gi = 0; gi < estimators.size(); ++gi) {
        const PhotonMaps* m = estimators.photonMaps(gi);
        maps.push_back(m ? &m->volume : nullptr);
        if (m) records = std::max(records, static_cast<int64_t>(m->volume.size()));
    }
    sumSlabs(scene, cfg, maps, estimators.groups(), &slabs);
    const ir::Domain& d = scene.domain();
    const double area = (d.x1 - d.x0) * (d.y1 - d.y0);
    for (const Slab& s : slabs) {
        const ir::Probe& p = probes[static_cast<size_t>(s.probe)];
        ProbeValue v;
        v.probe = p.name;
        v.quantity = kTallyNames[static_cast<size_t>(s.tally)];
        v.units = s.tally == kLu ? "W m^-2 sr^-1 um^-1" : "W m^-2 um^-1";
        v.position = p.position;
        v.medium = p.medium;
        v.mean.resize(s.s0.size());
        const double volume = s.tally == kLu ? area : 2 * s.h * area;  // Lu: per unit depth (addLu)
        for (size_t b = 0; b < s.s0.size(); ++b) v.mean[b] = s.s0[b] / volume;
        v.stderr_.assign(s.s0.size(), 0.0);  // the passes' spread replaces it (render_job.cpp)
        v.samples = records;
        v.batches = cfg.passes;
        v.method = "collisions";
        const std::string q = v.quantity;  // not v's own: v is moved into the call
        answers.set(s.probe, q, std::move(v));
    }
    return answers;
}

}  // namespace littoral::render
