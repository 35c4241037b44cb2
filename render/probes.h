#pragma once
// Point radiometers (the Scene IR's probes): plane irradiances Ed and Eu, scalar irradiances Eod
// and Eou, and nadir-viewing upwelling radiance Lu at a point, by integrating traced radiance.
//
//   Ed  = Int_{up}   L(w) |cos theta| dw   cosine-weighted stratified sampling: Ed = pi <L>
//   Eu  = Int_{down} L(w) |cos theta| dw   (the same toward the lower hemisphere)
//   Eod = Int_{up}   L(w) dw              uniform stratified sampling: Eod = 2 pi <L>
//   Eou = Int_{down} L(w) dw
//   Lu  = L arriving from straight below (the radiance a nadir-looking sensor reads)
// L(w) is the radiance arriving at the probe from direction w, estimated by the render's
// estimator (a backward, adjoint estimate: paths start at the probe; the probe casts no shadow).
// The sun's direct beam is added by next-event estimation (E_sun cos theta_s for Ed, E_sun for
// Eod, refracted through the interface above in water) instead of waiting for a sample to land
// in the 6.7e-5 sr disc; the sampled rays then carry only the rest (Estimator::LiIndirect).
//
// Standard errors come from independent batches: the `probe_samples` paths are split into
// `probe_batches` batches of equal size, each stratified on its own over the hemisphere, and the
// standard error is the standard deviation of the batch means divided by sqrt(batches). Batch
// means are independent, so this is honest whatever the stratification does to single samples
// (s / sqrt(N) over stratified samples would overstate the error, over correlated ones understate
// it). Results are identical for any thread count.
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "core/kinds.h"
#include "core/scene_ir.h"
#include "render/estimator.h"
#include "render/renderer.h"
#include "render/scene.h"

namespace littoral::render {

struct ProbeValue {
    std::string probe, quantity;
    std::string units;                // W m^-2 um^-1 (irradiances) or W m^-2 sr^-1 um^-1 (Lu)
    Point3 position;                  // the probe's position, m
    std::string medium;               // the medium it reads in ("air" or a medium name)
    std::vector<double> mean, stderr_;  // per render band
    int64_t samples = 0;                // sample paths, or photons for the forward tallies
    int batches = 0;
    // "backward" (paths from the probe, or the photon maps' gather along them), "forward"
    // (render/forward_tally.h) or "collisions" (render/volume_map_probes.h)
    std::string method = "backward";
};

// Probe values answered before any backward path is traced, by (index into ir.probes, quantity):
// the path estimator's forward tallies (render/forward_tally.h) and the dirsig estimator's
// collision estimates from the volume photon map (render/volume_map_probes.h).
class ProbeAnswers {
public:
    // The value of quantity `q` of probe `index`, or nullptr.
    const ProbeValue* find(int index, const std::string& q) const;
    // The (probe index, quantity) pairs answered, in order.
    std::vector<std::pair<int, std::string>> answered() const;
    bool empty() const { return values_.empty(); }
    void set(int index, const std::string& q, ProbeValue v) { values_[{index, q}] = std::move(v); }

private:
    std::map<std::pair<int, std::string>, ProbeValue> values_;
};

// The checks evaluateProbe makes before sampling: the probe's medium exists, the probe is not
// inside an opaque object, and its samples form render.probe_batches batches. InputError.
void checkProbe(const Scene& scene, const RenderConfig& cfg, const ir::Probe& probe);

// Evaluates every quantity of one probe. InputError for an unknown quantity, an unknown medium or
// a probe inside a closed opaque object.
// With `answers`, the quantities it holds are taken from it (the forward tallies, the volume map's
// collisions).
std::vector<ProbeValue> evaluateProbe(const Scene& scene, const EstimatorSet& estimators, const ir::Probe& probe,
                                      int probeIndex, const RenderOptions& opts = {},
                                      const ProbeAnswers* answers = nullptr);
// Every probe of the scene, in order: the forward tallies (path) or the volume map's collisions
// (dirsig) where they apply, backward paths for the rest.
struct CollisionPlan;
// `collisions`: the values the volume map's collisions answer (planCollisions,
// render/volume_map_probes.h), computed once per run; none when nullptr.
std::vector<ProbeValue> evaluateProbes(const Scene& scene, const EstimatorSet& estimators, const RenderOptions& opts = {},
                                       const CollisionPlan* collisions = nullptr);
// Convenience: builds the estimators of `scene` for this one call.
std::vector<ProbeValue> evaluateProbe(const Scene& scene, const ir::Probe& probe, int probeIndex,
                                      const RenderOptions& opts = {});

// The mean of B independent batch means and its standard error (their spread / sqrt(B)), per
// band of g, into v->mean / v->stderr_ (sized to every render band). chunkSums holds B x
// chunksPerBatch sums in batch order; each batch mean is its chunks' sum over perBatch. With
// `denominators` (Rrs): each batch's value is the ratio of its sums.
void batchStatistics(const std::vector<Spec>& chunkSums, int B, int chunksPerBatch, double perBatch, BandGroup g,
                     ProbeValue* v, const std::vector<Spec>* denominators = nullptr);

// Warns once (naming the worst) when probe values' standard errors exceed half of their values:
// a rare path carries most of such a value (docs/rendering.md, Known limits). Returns how many.
int warnAboutUncertainProbes(const std::vector<ProbeValue>& values, const std::vector<Band>& bands);

// Adds the probe quantities' descriptors (name, doc; probes.cpp) to `registry`; called by
// registerEstimatorKinds(), so that the scene-file parser reads the same names.
void registerProbeQuantityKinds(KindRegistry<KindInfo>& registry);

// CSV (one row per probe, quantity and band) and JSON renderings of probe results.
std::string probesCsv(const std::vector<ProbeValue>& values, const std::vector<Band>& bands);
std::string probesJson(const std::vector<ProbeValue>& values, const std::vector<Band>& bands);
// The diffuse attenuation K_d between consecutive Ed probes that lie one below the other (a
// vertical profile); "" if there are none. docs/outputs.md, "Probes".
std::string kdCsv(const std::vector<ProbeValue>& values, const std::vector<Band>& bands);

}  // namespace littoral::render
