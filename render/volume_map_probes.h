#pragma once
// The irradiance probes (and Lu, over a black bottom: volume_map_probes.cpp, addLu) of a
// horizontally invariant scene answered from the volume photon map's collisions (the dirsig
// estimator; render.photons.probe_collisions, off by default; docs/rendering.md, "Probes from the
// volume map's collisions").
//
// The volume map records a photon at each scattering event it stores, with its power and its
// direction before the event, at the rate b_s L(x, w) per unit volume and solid angle (b_s the
// scattering coefficient that stores: b, or b (1 - f) with effective scattering). Over a volume V,
//   (1 / V) sum_i Phi_i g(d_i) / b_s(x_i)   estimates   the mean over V of Int L(w) g(w) dw,
// which is Eod for g = 1 on downward directions, Ed for g = |mu| there, and Eou and Eu upward. It is
// the collision estimator of transport theory: no phase function and no search radius enter it, so
// it has none of the gather's heavy tail in forward-peaked water (a few upward photons near a view
// direction carrying Eou).
//
// In a horizontally invariant scene (forward_tally.h) the light depends on depth alone, so V is the
// slab |z - z_p| <= h across the domain (area A), V = 2 h A, and the estimate is the slab's mean of
// the profile: E(z_p) (1 + h^2 / 6 E''/E) to second order (E''/E = K^2 for a profile falling as
// e^(-K z): 0.2 % at K = 0.23 m^-1 and h = 0.5 m; none for a linear one, as near a black bottom),
// the kernel bias every photon-map estimate has at its radius.
//   h = min(kSlabRadii x the first pass's volume search radius, the distance from the probe to the
//       nearest horizontal face and to the nearest boundary between its medium's layers, and the
//       thickness that keeps the bias within kSlabBias (below));
// where that is below one search radius, the probe keeps the gather along directions.
//
// Each value's standard error is the spread of the progressive passes (each traces its own map), so
// this applies only to runs of at least two passes; the records of one photon's walk are
// correlated, and within one map there is no batch to see it.
//
// The records in a slab number about 2 h b_s A Eo per unit of the photons' flux, so the estimate
// needs water that scatters: in clear water (b_s of a few 0.01 m^-1) the gather, which sums the
// records along metres of each view ray, does better; a pilot chooses (below). Off by default: the
// slab's kernel bias, held to kSlabBias, is still larger than the gather's at its radius.
#include <map>
#include <string>
#include <utility>

#include "render/estimator.h"
#include "render/probes.h"
#include "render/scene.h"

namespace littoral::render {

// Slab half-thickness, in first-pass volume search radii (0.5 m at the columns' 0.1 m).
inline constexpr double kSlabRadii = 5.0;

// Which values the collisions answer. A pilot map (a quarter of a pass's volume photons or one
// chunk of photons, on random streams of its own, so the choice does not depend on the passes it
// chooses for) predicts each value's relative error in one pass from the spread of its records'
// contributions x_i:
//   se = kRecordCorrelation sqrt(sum x_i^2) / sum x_i,  scaled by sqrt(the pilot's records / a pass's);
// the collisions answer where that is at most kCollisionTrustedSe, the gather elsewhere. The
// records of one photon's walk are correlated (and depth splitting's copies share a history), so
// the records' spread understates a pass's: kRecordCorrelation is the ratio measured on the
// stratified column and problem 2 (docs/rendering.md). The gather's error in a pass was 1-10 % on
// the columns measured (4.0 % for the stratified column's Eou at 5 m, where the collisions had
// 4.6 %), and the gather takes most of a run's time while the collisions cost almost nothing, so
// they answer where their error in a pass is 6 % or less (1.9 % over 10 passes).
inline constexpr double kRecordCorrelation = 1.15;
inline constexpr double kCollisionTrustedSe = 0.06;

// The kernel bias a slab may have, (k h)^2 / 6 for a profile e^(k z): where the pilot's records
// (their mean offset from the probe, k h^2 / 3) put it higher, the slab is thinned to meet it, and
// where that leaves less than one search radius the value is gathered. A linear profile (near a
// black bottom) has none, but reads as one of k = E' / E: the thinning errs on the safe side.
inline constexpr double kSlabBias = 0.005;

struct CollisionPlan {
    std::map<std::pair<int, std::string>, double> values;  // (probe index, quantity) -> slab half-thickness
};

// The plan of a run (above): empty unless the estimator is dirsig with
// render.photons.probe_collisions, at least two progressive passes and a horizontally invariant
// scene. The same for every pass, thread count and rank (the pilot's streams are its own).
CollisionPlan planCollisions(const Scene& scene, int threads);

// The values of Ed, Eu, Eod, Eou and Lu in `plan`, from `estimators`' volume maps.
ProbeAnswers volumeMapCollisions(const Scene& scene, const EstimatorSet& estimators, const CollisionPlan& plan);

}  // namespace littoral::render
