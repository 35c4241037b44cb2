#pragma once
// The photon pass (dissertation Ch. 3, 6, 9; seed-ch08-09.md §2.1): light paths traced from the
// sun and the sky into the scene, their scattering events in water stored in the volume map and
// their hits on diffuse surfaces in the surface map.
//
//  * Emission: photons start on a horizontal rectangle over the scene's domain (just above every
//    surface), from the sun (direction uniform over the disc) or the sky (cosine-weighted over the
//    upper hemisphere), the source chosen in proportion to its band-summed flux: sun
//    E_sun cos(theta_s) A, sky pi L_sky A (A the rectangle's area). Each photon starts with the
//    relative power Phi_source,b / (P(source) Phi_mean), about 1. The rectangle stands for one
//    period of an infinite plane: a photon whose first landing point falls outside the domain is
//    moved by whole periods to land inside, so grazing light reaches the domain's edges too.
//  * Transport: BxDFs through their sample() in importance mode (the smooth Fresnel interface:
//    reflection or refraction by Fresnel probability, no n^2 scaling), media by free-flight
//    sampling and phase sampling, diffuse surfaces by cosine sampling. Absorption is Russian
//    roulette that keeps the power per band near its start (survival with the largest band's
//    albedo): every stored photon carries about the same flux, as in DIRSIG (equal-flux photons
//    give the smallest variance). Periodic walls wrap photons like rays.
//  * Storage: scattering events in a medium whose solver is MediumPM go into the volume map
//    (position, direction of travel before the event, power); hits on diffuse materials whose
//    solver is SurfacePM go into the surface map (position, direction of travel, surface normal on
//    the side hit, power). With `effective_scattering` (DIRSIG's effective scattering
//    coefficient, Ch. 6.4.7 / 9) events that deflect the photon by less than the cone of 0.01 sr
//    count as unscattered: not stored, direction kept.
//  * Flux per photon (DIRSIG's rule): each map closes when it holds its target count; its flux
//    per photon is the total source flux over the number of photons emitted until then.
//  * Importance emission (`render.photons.importance`, on by default): a pilot of the first 4
//    chunks (65 536 photons, emitted uniformly; their stores are dropped and they are not counted
//    as emitted) counts, per source and per cell of a 32 x 32 grid over the domain's plan view, the
//    photons that stored anything. The rest start in cell c with probability
//    p_c = 0.9 u_c / sum u + 0.1 / N (u_c: the share of c's pilot photons that stored, shrunk toward
//    the source's mean by 16 photons' worth; N cells), and carry the weight (1 / N) / p_c, at most
//    10 (for a source whose pilot predicts at least 1.1 times the uniform stores per photon; else
//    it stays uniform, and if both do, the pilot's photons are kept): each photon is still an
//    unbiased estimate of what a uniform one gives, so the maps' estimates are unchanged, while
//    photons aimed at dry land and Classic materials, which store nothing, become rarer. The
//    defensive tenth keeps every cell reachable (light from land that is reflected into the
//    water is still found).
//  * Determinism: photon k draws all its numbers from RandomStream(seed, pass, k); photons are
//    traced in chunks of fixed size whose results are appended in chunk order, and maps close at
//    chunk boundaries, so the maps are identical for any thread count.
#include <array>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "core/rng.h"
#include "render/medium.h"
#include "render/photon_map.h"
#include "render/scene.h"

namespace littoral::render {

// Splitting by depth (the forward probe tallies' photons, ObservedPhotons; the volume photon map
// with render.photons.depth_splitting, volumeDepthImportance below). I(z) is the importance of a photon at height z: log-linear between the points given, and
// constant beyond the first and the last. At each collision a photon whose largest band power w
// carries v = w I(z) >= 2 is split into n = min(floor(v), maxSplit) copies of power w / n, each
// turned by its own phase-function sample and walked on its own (from the same random stream, in a
// fixed order, so that results stay independent of threads and ranks); and the roulette's window
// becomes rouletteBelow / I(z). A copy is an independent continuation of the same photon, and a
// survivor of the roulette (probability q) carries 1 / q, so every expectation is kept whatever I
// is: the tallies stay unbiased. With I ~ 1 / E(z) (the pilot's irradiance, render/forward_tally.h)
// the photons' number stays near constant with depth, and deep planes are crossed as often as
// shallow ones.
struct DepthImportance {
    std::vector<double> z, logI;  // z descending (the shallowest point first)
    // Below the deepest point, ln I falls by fallBelow per metre (0: constant there; see
    // fromProfile), down to ln I of the deepest point minus kMaxFall.
    double fallBelow = 0;
    static constexpr double kMaxFall = 4.605170185988091;  // ln 100
    bool empty() const { return z.empty(); }
    double at(double height) const;
    // I = (Eo(shallowest) / Eo(z))^exponent, clamped to [1e-2, maxImportance], from (z, Eo) pairs of
    // one medium (points with Eo <= 0 or not finite are left out; fewer than 2 left: empty).
    // With `fallBelowDeepest`, the importance below the deepest point falls as fast as the last two
    // points' Eo does (fallBelow = ln(Eo_last-but-one / Eo_last) / their distance): a photon there
    // reaches the deepest point's plane again only up the same attenuation (a detector's adjoint
    // decays as the light does, at the diffuse attenuation K), so the photons that wander deep
    // below every plane are rouletted instead of walked at full weight.
    static DepthImportance fromProfile(std::vector<std::pair<double, double>> profile, double exponent = 1.0,
                                       double maxImportance = 1e4, bool fallBelowDeepest = false);
};

struct PhotonPassSettings {
    uint64_t surfaceTarget = 0;     // photons to store in the surface map (0: no surface map)
    uint64_t volumeTarget = 0;      // photons to store in the volume map (0: no volume map)
    int maxBounces = 200;           // scattering/diffuse events per photon path
    int maxSpecularDepth = 1000;    // interface events per photon path (render.max_specular_depth when set)
    bool effectiveScattering = false;
    bool importance = true;         // importance emission (above)
    uint64_t seed = 1, pass = 0;
    uint64_t maxEmitted = 0;        // 0: 1000 x the larger target, at least 10^7
    // Russian roulette (absorption) as a weight window: a photon whose largest band power falls
    // below this survives with probability power / rouletteBelow. 1 keeps every stored photon near
    // the same flux (the maps); a lower window lets weighted photons tally longer (ObservedPhotons).
    double rouletteBelow = 1.0;
    DepthImportance depthImportance;  // splitting by depth (above); empty: none
    int maxSplit = 16;                // copies of one collision at the most
    // The search radius each built map's grid is made for (PhotonMap::build): a map whose cells
    // were far larger than its queries' radius would test photons up to a cell's reach from them.
    double surfaceRadius = 0.4, volumeRadius = 0.4;
    int threads = 0;
    bool progress = true;
    std::vector<bool> surfaceMaterial;  // per material: stores surface photons (SurfacePM)
    std::vector<bool> volumeMedium;     // per medium: stores volume photons (MediumPM)
};

// Photons per chunk: a pass traces its photons in chunks and fills its maps with whole chunks, so a
// map holds its target rounded up to a chunk's records.
inline constexpr uint64_t kPhotonChunk = 16384;

struct PhotonMaps {
    PhotonMap surface, volume;
    uint64_t emitted = 0;                            // photons emitted in all
    uint64_t emittedSurface = 0, emittedVolume = 0;  // emitted when each map closed
    double seconds = 0;
};

// Photon emission. The sun and the sky light an infinite horizontal plane just above the scene,
// of which the domain is one period: a photon starts at a uniform point of the domain's plan view
// at height z, from the sun with probability pSun (a direction uniform over the disc) or from the
// sky (cosine-weighted over the upper hemisphere, for a uniform sky), and is moved through the
// periodic air until its first hit lies inside the domain.
struct PhotonSource {
    double area = 0;
    double x0 = 0, y0 = 0, lx = 0, ly = 0, z = 0;
    double zLow = 0;        // the scene's lowest point
    Spec sunFlux, skyFlux;  // per band, W um^-1: E_sun cos(theta_sun) A and pi L_sky A
    double pSun = 0;        // probability of emitting from the sun
    double meanFlux = 0;    // band-averaged total flux
    static PhotonSource of(const Scene& scene, BandGroup g);
};
struct EmittedPhoton {
    Ray ray;
    Spec power;  // per band: Phi_source,b / (P(source) Phi_mean), relative to the mean flux
    bool fromSun = false;
    int cell = 0;  // the EmissionImportance cell it started in (before any periodic move)
};
// Where photons start (see above): per source (0 sun, 1 sky) the cumulative probabilities of the
// kCells x kCells cells (row-major, x fastest) and each cell's weight (1 / N) / p_c.
struct EmissionImportance {
    static constexpr int kCells = 32;
    static constexpr int N = kCells * kCells;
    // Importance is used for a source only when the pilot predicts at least kMinGain times the
    // uniform emission's stores per photon; otherwise that source stays uniform (weight 1).
    static constexpr double kMinGain = 1.1;
    std::array<std::vector<double>, 2> cdf, weight;
    std::array<bool, 2> active{false, false};
    // From the pilot's counts per source and cell: emitted and of those, the ones that stored.
    static EmissionImportance fromPilot(const std::vector<uint64_t>& emitted, const std::vector<uint64_t>& stored);
};
// Draws five numbers from rng; with `importance`, the start cell from its probabilities.
EmittedPhoton emitPhoton(const Scene& scene, const PhotonSource& source, RandomStream& rng,
                         const EmissionImportance* importance = nullptr);

// Told of a photon's path as it is traced (the forward probe tallies, render/forward_tally.h).
class PhotonObserver {
public:
    virtual ~PhotonObserver() = default;
    // The photon flies along ray.o + t ray.d, t in [0, tEnd) (tEnd may be infinite), in `medium`
    // with power w per band at t = 0. `sampled`: the flight's length was drawn by free-flight
    // sampling with a hero band chosen uniformly (Medium::sampleFreeFlight), so at distance t the
    // photon's power is w_b T_b(t) / mean_i T_i(t); otherwise the medium's transmittance
    // attenuates it deterministically, w_b T_b(t). `from`: the collision the flight starts at (told
    // to collision() before it; the flight's direction was drawn by Medium::samplePhase), also when
    // the flight continues such a flight across a periodic wall; nullptr after emission, an
    // interface or a diffuse reflection.
    struct Scattered {
        Vec3 dIn;       // the direction of travel before the collision
        int layer = 0;  // the medium's layer it happened in
        double z = 0;   // its height (a flight continued across a periodic wall starts elsewhere)
    };
    virtual void flight(const Ray& ray, double tEnd, int medium, const Spec& w, bool sampled, const Scattered* from) = 0;
    // A collision at x in a scattering medium's `layer`, of a photon travelling along dIn, with power
    // w per band after the collision's single-scattering albedo (before the phase function turns it).
    virtual void collision(const Point3& x, const Vec3& dIn, int medium, int layer, const Spec& w) {
        (void)x, (void)dIn, (void)medium, (void)layer, (void)w;
    }
    // A diffuse vertex at h, reached from `medium` with power w per band; the surface reflects rho.
    virtual void diffuse(const SurfaceHit& h, int medium, const Spec& rho, const Spec& w) {
        (void)h, (void)medium, (void)rho, (void)w;
    }
    // The photon reached PhotonPassSettings::maxBounces events with power w left and was ended.
    virtual void cut(const Spec& w) { (void)w; }
};

class PhotonTracer;
// Photons traced from the sun and sky one by one, uniformly emitted and storing nothing, each
// path reported to an observer. Photon k draws from RandomStream(seed, photon-pass base + pass, k),
// so any split of the indices gives the same paths.
class ObservedPhotons {
public:
    ObservedPhotons(const Scene& scene, BandGroup g, const PhotonPassSettings& settings);
    ~ObservedPhotons();
    const PhotonSource& source() const;
    void trace(uint64_t index, PhotonObserver& observer) const;

private:
    PhotonPassSettings settings_;
    std::unique_ptr<PhotonTracer> tracer_;
};

// Traces the photons of one band group. Warns if the emission cap is reached before a map is
// full (it then holds what was stored).
PhotonMaps tracePhotons(const Scene& scene, BandGroup group, const PhotonPassSettings& settings);

// Splitting by depth for the volume map (render.photons.depth_splitting): I(z) = Eo(top) / Eo(z)
// of the first medium that keeps a volume map, from a pilot in two stages of volumeTarget / 32
// stored photons each (at least 8192; own random streams): the first unsplit, the second split by
// the first's profile, so that it reaches deeper. Eo(z) per bin of 1/64 of the stored photons' depth
// range: the stored power over the scattering coefficient that stores (b, or b (1 - f) with
// effective scattering) at each photon (bins of fewer than 32 photons are left out; I is constant
// beyond the last). With it the stored photons spread about evenly over depth instead of falling
// with Eo, so deep estimates get photons. Unbiased whatever the pilot finds (DepthImportance).
// Empty if the pilot stores too little to tell.
DepthImportance volumeDepthImportance(const Scene& scene, BandGroup group, const PhotonPassSettings& settings);

// The cone half-angle (cosine) of the effective scattering coefficient: 0.01 sr.
inline constexpr double kEffectiveConeSr = 0.01;

}  // namespace littoral::render
