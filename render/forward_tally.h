#pragma once
// Forward plane-crossing tallies for the irradiance probes of a horizontally invariant scene
// (docs/rendering.md, "Forward probe tallies").
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
// Two refinements score a crossing's expectation instead, which keeps that: every flight of
// sampled length scores w_b T_b(t) at each plane ahead of it (up to the side walls, where it goes
// on as a new flight), whether or not it gets there; and the upward planes' crossings by the flight
// after a collision are shared, by the balance heuristic, between that flight (drawn from the
// phase function) and a direction drawn at the collision toward grazing and steep upward angles.
// Lu (the radiance travelling straight up) is a collision estimator: every collision below the
// plane adds its scattered power into the upward direction, attenuated to the plane,
//   Lu(z)  = Phi / (A N) [sum over collisions at z' < z of w p(d -> up) T(z', z)
//                         + sum over hits on a Lambertian floor of w rho / pi T(floor, z)],
// with w the power after the collision's albedo and d the photon's direction before it. It applies
// when the nearest face below the probe reflects only diffusely (or absorbs), or there is none.
// A backward estimate at a probe at depth 10 in forward-peaked, high-albedo water must find the
// sunlit forward peak by sampling (heavy tails); a forward photon carries it there by construction.
//
// Standard errors come from render.probe_batches independent batches of photons, as for the
// backward probes. Results do not depend on the thread count or the ranks.
#include <array>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "render/estimator.h"
#include "render/probes.h"
#include "render/scene.h"

namespace littoral::render {

// "" if the scene is horizontally invariant (above); otherwise why not, naming the element.
std::string horizontalInvarianceProblem(const ir::SceneIR& ir);
// The heights of the horizontal faces of a horizontally invariant scene, ascending and distinct
// (false, and nothing written, if the scene is not invariant).
bool horizontalFacePlanes(const ir::SceneIR& ir, std::vector<double>* planes);

// The probe quantities that photons traced forward can answer, by index: the forward tallies'
// (below) and the volume map's collisions' (render/volume_map_probes.h).
enum PhotonTally { kEd, kEu, kEod, kEou, kLu, kTallies };
inline constexpr std::array<const char*, kTallies> kTallyNames = {"Ed", "Eu", "Eod", "Eou", "Lu"};
// The index of quantity q, or -1.
inline int tallyOf(const std::string& q) {
    for (int t = 0; t < kTallies; ++t)
        if (q == kTallyNames[static_cast<size_t>(t)]) return t;
    return -1;
}

// The forward tallies of every probe quantity they answer. Empty when render.probe_photons is 0,
// the estimator is not `path`, the scene is not horizontally invariant or no probe asks for an
// answered quantity.
// What one run of the tallies traces and answers.
struct ForwardTallyRun {
    uint64_t photons = 0;  // 0: render.probe_photons
    int batches = 0;       // 0: render.probe_batches
    bool pilot = false;    // the pilot's own random streams (render/probes.cpp), no progress bar
    int pilotStage = 0;    // the pilot's stage (0 unsplit, 1 split by depth): streams of its own
    // The (probe index, quantity) pairs to answer; empty: every one the tallies answer.
    std::set<std::pair<int, std::string>> only;
    // A pilot's profile (z, E), E the weakest irradiance asked at each plane (profile() below): the
    // photons are split by depth with the importance 1 / E (render/photon_pass.h,
    // DepthImportance); empty (or fewer than two planes with light): no splitting.
    std::vector<std::pair<double, double>> profile;
};

// The answered values: find() and answered() (ProbeAnswers, render/probes.h).
class ForwardTallies : public ProbeAnswers {
public:
    ForwardTallies() = default;
    ForwardTallies(const Scene& scene, const EstimatorSet& estimators, const RenderOptions& opts,
                   const ForwardTallyRun& run = {});
    // At every plane traced (z, E): the weakest band-mean irradiance asked there (Ed, Eu, Eod or
    // Eou; Eod + Eou where only Lu is), what a pilot hands to the full run as
    // ForwardTallyRun::profile.
    const std::vector<std::pair<double, double>>& profile() const { return profile_; }

private:
    std::vector<std::pair<double, double>> profile_;
};

}  // namespace littoral::render
