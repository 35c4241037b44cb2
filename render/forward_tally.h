#pragma once
// Forward plane-crossing tallies for the irradiance probes of a horizontally invariant scene
// (docs/rendering.md, "Forward irradiance tallies").
//
// In a scene that does not change along x and y (a periodic domain whose every surface is a
// horizontal plane covering the whole domain with one material, and no instances) the light field
// depends on depth only, so the irradiance at a probe equals its mean over the horizontal plane
// through it. That mean is the flux crossing the plane per unit area: photons traced from the sun
// and sky (render/photon_pass.h, ObservedPhotons, through the same interfaces, roughness, media
// and bottoms as every other estimate) give every probe depth at once,
//   Ed(z)  = Phi / (A N) sum over downward crossings of w,     Eu(z)  = ... upward crossings of w,
//   Eod(z) = Phi / (A N) sum over downward crossings of w / |mu|, Eou(z) = ... upward, w / |mu|,
// with Phi the source flux (band mean), A the domain's area, N the photons emitted, w a photon's
// relative power where it crosses and mu the z component of its direction. Each crossing is an
// unbiased estimate (the expected number of crossings per unit area is the plane irradiance,
// Case & Zweifel's flux-crossing identity), so the tallies are unbiased for the scene they accept.
// A backward estimate at a probe at depth 10 in forward-peaked, high-albedo water must find the
// sunlit forward peak by sampling (heavy tails); a forward photon carries it there by construction.
//
// Standard errors come from render.probe_batches independent batches of photons, as for the
// backward probes. Results do not depend on the thread count or the ranks.
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "render/estimator.h"
#include "render/probes.h"
#include "render/scene.h"

namespace littoral::render {

// "" if the scene is horizontally invariant (above); otherwise why not, naming the element.
std::string horizontalInvarianceProblem(const ir::SceneIR& ir);

// Whether the forward tallies answer quantity `q` of a probe in medium `medium` (a scattering
// medium; Ed, Eu, Eod or Eou).
bool forwardTallyAnswers(const Scene& scene, const std::string& quantity, int medium);

// The forward tallies of every probe quantity they answer. Empty when render.probe_photons is 0,
// the estimator is not `path`, the scene is not horizontally invariant or no probe asks for an
// answered quantity.
class ForwardTallies {
public:
    ForwardTallies() = default;
    ForwardTallies(const Scene& scene, const EstimatorSet& estimators, const RenderOptions& opts);
    bool empty() const { return values_.empty(); }
    // The value of quantity `q` of probe `index` (into ir.probes), or nullptr.
    const ProbeValue* find(int index, const std::string& q) const;
    uint64_t photons() const { return photons_; }

private:
    std::map<std::pair<int, std::string>, ProbeValue> values_;
    uint64_t photons_ = 0;
};

}  // namespace littoral::render
