#pragma once
// The Estimator interface: radiance along a ray, for sensors and probes alike.
//
// An estimator is chosen per render (`render.estimator`) and built once per band group by
// Estimator::create, then shared by every sensor and probe of the render:
//   dirsig  the dissertation's per-material radiometry solvers (Table 10.4): Classic and Generic for
//           diffuse materials, Fresnel for interfaces; media attenuate by Beer–Lambert with c = a + b
//           (dirsig_estimator.cpp);
//   path    an unbiased volumetric path tracer: free-flight sampling, phase-function sampling,
//           next-event estimation toward the sun and Russian roulette (path_estimator.cpp).
// Adding an estimator is one file (with its descriptor at the end, render/estimator_settings.h)
// plus one line in the factory, in registerEstimatorKinds() and in the Estimator name table.
//
// Settings: makeRenderConfig() reads every render setting the chosen estimator uses (with the
// default and allowed range its descriptor declares) and refuses, with an InputError naming it,
// any setting that no estimator declares (with a did-you-mean), any that is set but that the
// estimator does not read, and any material solver the estimator does not honour.
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/rng.h"
#include "core/scene_ir.h"
#include "render/estimator_settings.h"
#include "render/interaction.h"
#include "render/scene.h"
#include "render/spectral.h"
#include "render/sun_connection.h"

namespace littoral::render {

// Statistics counters (core/stats.h) of the path estimator: paths started at a camera or probe,
// and paths that reached render.max_bounces with weight left (their radiance beyond is lost;
// runRenderJob warns with the fraction).
inline constexpr const char* kPathsTraced = "path estimator: paths traced";
inline constexpr const char* kPathsCut = "path estimator: paths cut at render.max_bounces";

// render.photons.volume when unset: the volume map of a medium-pm water (which a scene file's
// scattering water is by default under dirsig). 20 B + 2 B per band each: 24 MB at 2 bands.
inline constexpr double kDefaultVolumePhotons = 1e6;

// The render settings, resolved (defaults applied, ranges checked) for the chosen estimator.
struct RenderConfig {
    ir::Estimator estimator = ir::Estimator::Dirsig;
    int maxBounces = 8;          // dirsig: diffuse vertices per path (GRS semantics); path: scattering + diffuse vertices
    int maxSpecularDepth = 16;   // interface events per path
    int hemisphereSamples = 64;  // dirsig: rays at the first diffuse vertex
    int probeSamples = 4096;     // sample paths per probe quantity
    int probeBatches = 16;       // independent batches (standard errors from their spread)
    uint64_t probePhotons = 0;   // path: photons of the forward irradiance tallies (render/forward_tally.h); 0 = off
    double marchStep = 0.1;      // path: spacing of sun estimates; dirsig MediumPM: gather step along rays (m)
    // Per-pixel convergence: > 0, each pixel takes the samples its pilot (samples_per_pixel) says it
    // needs for this relative standard error, up to maxSamplesPerPixel (render/renderer.cpp).
    double targetRelativeError = 0;
    int maxSamplesPerPixel = 0;
    // Per material (index as in the IR): the dirsig solver that evaluates it.
    std::vector<ir::Material::Solver> solvers;
    // Photon maps (dirsig with SurfacePM materials or MediumPM media).
    std::vector<bool> mediumPM;  // per IR medium
    uint64_t surfacePhotons = 0, volumePhotons = 0;
    double surfaceRadius = 0.4, volumeRadius = 0.4;  // m, first pass
    int photonMaxBounces = 200;
    // Interface events per photon path: render.max_specular_depth when it is set, else 1000 (photon
    // paths are not split, so a long specular chain costs no more than its length).
    int photonMaxSpecularDepth = 1000;
    bool effectiveScattering = false;
    bool photonImportance = true;  // render.photons.importance
    bool depthSplitting = false;   // render.photons.depth_splitting (volume map)
    // render.photons.probe_collisions: the irradiances of probes in a horizontally invariant scene
    // from the volume map's collisions (render/volume_map_probes.h) instead of its gather.
    bool probeCollisions = false;
    int passes = 1;             // progressive passes
    double alpha = 2.0 / 3.0;   // radius reduction per pass (Knaus & Zwicker 2011)
    bool usesPhotons() const { return surfacePhotons > 0 || volumePhotons > 0; }
    // Search radius of pass p (1-based): r_p^2 = r_1^2 p^(alpha - 1), for the 2-D kernels of both
    // estimates (the surface disc and the beam's cross-section).
    // How a glossy (rough interface) hit gets the sun (render/sun_connection.h).
    using GlossySun = render::GlossySun;
    GlossySun glossySun = GlossySun::Mis;
    double radiusAt(double r1, int pass) const { return r1 * std::pow(static_cast<double>(pass), 0.5 * (alpha - 1.0)); }
};

// Resolves and checks the render settings of a Scene IR (no geometry needed, so `littoral
// check-scene` runs it too). InputError for an out-of-range value, a setting the estimator does
// not read, or a material solver it cannot honour; errors carry the scene-file location when the
// IR came from a scene file (RenderSettings::locations), else name scene.json's key.
RenderConfig makeRenderConfig(const ir::SceneIR& ir);

// Groups consecutive render bands into band groups (see BandGroup).
std::vector<BandGroup> bandGroups(const Scene& scene);

struct PhotonMaps;
struct PhotonPassSettings;

// The radiance of a sensor ray in the air split by where it first meets the sea surface (the
// interface between the air and the water medium; render/water_products.cpp):
//   waterLeaving  the light transmitted up through that surface point (Lw as the sensor sees it:
//                 T_f L / n^2 of the radiance just under it, everything the water and seabed send);
//   glint         the solar beam reflected once there: the rough interface's sun estimate and the
//                 solar disc met directly by the reflected ray;
//   skyReflected  everything else reflected there (the sky, and whatever the reflected ray meets);
//   other         rays whose first surface is not the sea (land, objects, the sky seen directly).
// The four add up to Estimator::Li's radiance for the same ray and random numbers.
// ed0: the downwelling plane irradiance Ed(0+) on a horizontal plane at the sea point (sun and
// sky, shadowed by everything but the sea surface itself; W m^-2 um^-1), meaningful when `sea`.
struct RadianceParts {
    Spec waterLeaving, skyReflected, glint, other, ed0;
    bool sea = false;
    explicit RadianceParts(int bands = 0)
        : waterLeaving(bands), skyReflected(bands), glint(bands), other(bands), ed0(bands) {}
    Spec total() const { return waterLeaving + skyReflected + glint + other; }
};

// The water medium of the products: the one named "water" (a scene file's), else the first after
// the air; -1 if the scene has none.
int waterMediumIndex(const Scene& scene);
// Is h on the sea surface (an interface between the air and that medium)?
bool isSeaSurface(const Scene& scene, const SurfaceHit& h);
// Does a ray straight down from p, through periodic walls, first meet the sea surface from the air?
bool seaBelow(const Scene& scene, const Point3& p);

class Estimator {
public:
    // `effectiveExtinction` (per medium, or empty): see SunConnection.
    Estimator(const Scene& scene, const RenderConfig& config, BandGroup group,
              std::vector<bool> effectiveExtinction = {});
    virtual ~Estimator() = default;
    Estimator(const Estimator&) = delete;
    Estimator& operator=(const Estimator&) = delete;

    // `maps` (the photon maps of this group and pass, or null) and `pass` (1-based) are used by the
    // dirsig estimator's SurfacePM and MediumPM solvers.
    static std::unique_ptr<Estimator> create(const Scene& scene, const RenderConfig& config, BandGroup group,
                                             const PhotonMaps* maps = nullptr, int pass = 1);

    // Radiance arriving at ray.o from direction -ray.d (unit), per band of the group, for a ray
    // that starts in `medium` (a sensor ray: the solar disc counts wherever a path reaches it).
    virtual Spec Li(const Ray& ray, int medium, RandomStream& rng) const = 0;
    // The same radiance without the direct solar beam that reaches ray.o unscattered along a
    // single refraction (the part sun().direct() estimates): probes add that part separately.
    virtual Spec LiIndirect(const Ray& ray, int medium, RandomStream& rng) const = 0;

    // Li(ray, medium) split into its water-leaving parts (RadianceParts), for a sensor in the air
    // (medium 0; InternalError otherwise).
    RadianceParts LiParts(const Ray& ray, int medium, RandomStream& rng) const;

    // The sun connections of this estimator's band group (next-event estimation through flat,
    // rough and faceted interfaces, the sky and disc seen by escaping rays).
    const SunConnection& sun() const { return sun_; }

    const Scene& scene() const { return scene_; }
    const RenderConfig& config() const { return config_; }
    BandGroup group() const { return group_; }
    int bandCount() const { return group_.count; }

protected:
    Spec bandValues(const std::vector<double>& v) const { return sun_.bandValues(v); }
    // For LiParts: the interaction step of this estimator's radiance paths, and the radiance along
    // a continuation that leaves a sensor path's first interface event, times its weight, as Li
    // would follow it (`split`: one of the two lobes of a split event; `splits` deterministic
    // splits left, `specular` interface events and `wraps` wall crossings so far, `startNormal`
    // the surface it leaves).
    virtual const InteractionStep& interactionStep() const = 0;
    // From *ray in the air to its first surface that is not a periodic wall, wrapping as Li does
    // (*wraps counts the wraps; *T takes the air's transmittance, if it attenuates, up to the hit).
    // False if the ray escapes; true with *h a periodic wall if a wrap fails.
    bool walkWalls(Ray* ray, SurfaceHit* h, int* wraps, Spec* T) const;
    virtual Spec continuePath(const Continuation& c, bool split, int splits, int specular, int wraps,
                              const Normal3& startNormal, RandomStream& rng) const = 0;

    const Scene& scene_;
    const RenderConfig& config_;
    BandGroup group_;
    SunConnection sun_;
};

// The photon pass of band group g's maps in progressive pass `pass` (1-based): the render's
// photon settings, random streams keyed by the pass and the group, the pass's radii, and the
// depth splitting's pilot when render.photons.depth_splitting is set.
PhotonPassSettings photonPassSettings(const Scene& scene, const RenderConfig& config, BandGroup g, int pass, int threads,
                                      bool progress, uint64_t maxPhotonsEmitted);

// The estimators of one render: the resolved settings and one estimator per band group, built once
// and shared by every sensor and probe.
class EstimatorSet {
public:
    // For progressive photon mapping, pass p (1-based) traces its own photon maps (random streams
    // keyed by the pass) with the pass's radii. maxPhotonsEmitted caps the photons a photon pass
    // emits while filling its maps (0: PhotonPassSettings' default, render/photon_pass.h).
    explicit EstimatorSet(const Scene& scene, int pass = 1, int threads = 0, bool progress = false,
                          uint64_t maxPhotonsEmitted = 0);
    ~EstimatorSet();
    const RenderConfig& config() const { return config_; }
    const std::vector<BandGroup>& groups() const { return groups_; }
    const Estimator& forGroup(size_t i) const { return *estimators_[i]; }
    // The photon maps of band group i (nullptr when the estimator uses none).
    const PhotonMaps* photonMaps(size_t i) const { return i < maps_.size() ? maps_[i].get() : nullptr; }
    size_t size() const { return estimators_.size(); }
    int pass() const { return pass_; }

private:
    RenderConfig config_;
    std::vector<BandGroup> groups_;
    std::vector<std::unique_ptr<PhotonMaps>> maps_;
    std::vector<std::unique_ptr<Estimator>> estimators_;
    int pass_ = 1;
};


}  // namespace littoral::render
