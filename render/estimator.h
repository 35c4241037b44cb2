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
#include "render/scene.h"
#include "render/spectral.h"

namespace littoral::render {

// The render settings, resolved (defaults applied, ranges checked) for the chosen estimator.
struct RenderConfig {
    ir::Estimator estimator = ir::Estimator::Dirsig;
    int maxBounces = 8;          // dirsig: diffuse vertices per path (GRS semantics); path: scattering + diffuse vertices
    int maxSpecularDepth = 16;   // interface events per path
    int hemisphereSamples = 64;  // dirsig: rays at the first diffuse vertex
    int probeSamples = 4096;     // sample paths per probe quantity
    int probeBatches = 16;       // independent batches (standard errors from their spread)
    double marchStep = 0.1;      // path: spacing of sun estimates; dirsig MediumPM: gather step along rays (m)
    // Per material (index as in the IR): the dirsig solver that evaluates it.
    std::vector<ir::Material::Solver> solvers;
    // Photon maps (dirsig with SurfacePM materials or MediumPM media).
    std::vector<bool> mediumPM;  // per IR medium
    uint64_t surfacePhotons = 0, volumePhotons = 0;
    double surfaceRadius = 0.4, volumeRadius = 0.4;  // m, first pass
    int photonMaxBounces = 200;
    bool effectiveScattering = false;
    int passes = 1;             // progressive passes
    double alpha = 2.0 / 3.0;   // radius reduction per pass (Knaus & Zwicker 2011)
    bool usesPhotons() const { return surfacePhotons > 0 || volumePhotons > 0; }
    // Search radius of pass p (1-based): r_p^2 = r_1^2 p^(alpha - 1), for the 2-D kernels of both
    // estimates (the surface disc and the beam's cross-section).
    // How a glossy (rough interface) hit gets the sun: next-event estimation and BSDF sampling
    // combined by the power heuristic (the default), or one alone (for tests: all three agree).
    enum class GlossySun { Mis, NeeOnly, BsdfOnly };
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

// Which interface events since the last scattering vertex (diffuse hit, medium collision or probe)
// a ray has gone through: the sun estimate at that vertex covers some chains of events, and a ray
// reaching the solar disc along one of those does not count it again.
//
// A vertex in air (a shadow ray) or in water under smooth interfaces (the refracted sun) covers
// chains with no reflection and no rough event, through any number of smooth interfaces (its own
// medium's surface, refracted, and dielectric objects, crossed by the straight-path model); a vertex
// in water under a rough interface (Estimator::sunBeam's rough strategy) covers chains with no
// reflection and exactly one rough transmission. A glossy (rough interface) hit estimates the sun itself for
// the side of the surface where air is (Estimator::glossySun); the ray it samples toward that
// side then counts the disc with the MIS weight of BSDF sampling if it reaches it directly, and
// fully after any further event (afterGlossy).
struct SunChain {
    bool fromSensor = true;  // no scattering vertex before (or a glossy sun estimate): the disc counts
    bool reflected = false;
    int transmissions = 0;       // smooth interfaces
    int roughTransmissions = 0;  // rough interfaces
    bool roughSun = false;       // the vertex's sun estimate was the rough-interface strategy
    double glossyPdf = 0;        // > 0: left a glossy hit whose sun estimate covered the direct disc
    bool countsSun() const {
        if (fromSensor || reflected) return true;
        // Smooth transmissions are covered in any number: the sun estimate refracts at the medium's
        // surface and crosses dielectric objects along the straight-path model.
        const bool covered = roughSun ? roughTransmissions == 1 : roughTransmissions == 0;
        return !covered;
    }
    static SunChain afterVertex(bool rough = false) {
        SunChain c;
        c.fromSensor = false;
        c.roughSun = rough;
        return c;
    }
    static SunChain afterGlossy(double bsdfPdf) {
        SunChain c;
        c.glossyPdf = bsdfPdf;
        return c;
    }
    // Any surface hit ends the direct flight from a glossy vertex.
    void hitSurface() { glossyPdf = 0; }
};

struct PhotonMaps;

class Estimator {
public:
    Estimator(const Scene& scene, const RenderConfig& config, BandGroup group);
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
    // single refraction (the part directSun() below estimates): probes add that part separately.
    virtual Spec LiIndirect(const Ray& ray, int medium, RandomStream& rng) const = 0;

    // The direct solar beam at the point p (inside `medium`, not on a surface) on a plane with
    // normal n (E_sun cos, or E_sun for scalar irradiance), by next-event estimation: a shadow ray
    // in air, the refracted sun through the interface above in water (see SunBeam).
    Spec directSun(const Point3& p, const Normal3& n, int medium, bool scalar, RandomStream& rng) const;

    // Direction toward the centre of the solar disc as seen from inside `medium` through a
    // horizontal interface (Snell, Eq. 4.1); nullopt without a sun. A guide for importance
    // sampling (e.g. probe directions near the forward-scattering peak), not a visibility claim.
    std::optional<Vec3> refractedSunDirection(int medium) const;

    const Scene& scene() const { return scene_; }
    const RenderConfig& config() const { return config_; }
    BandGroup group() const { return group_; }
    int bandCount() const { return group_.count; }

protected:
    // The solar beam at a point, as one sample of a sun estimate: the radiance L arriving at the
    // point along toSun and the density `pdf` (per unit solid angle of toSun) with which the
    // estimate chose that direction, so that E = L / pdf is the estimate of the irradiance on a
    // plane normal to toSun. For a direct or singly refracted disc L = E_beam / Omega (uniform over
    // the disc of solid angle Omega as seen from the point) and pdf = 1 / Omega; through a rough
    // interface toSun is drawn from its transmission lobe (see sunBeam) and L is the radiance
    // estimate for one point of the disc.
    struct SunBeam {
        Spec E;                 // L / pdf, per band
        Spec L;                 // radiance along toSun, per band
        Vec3 toSun;             // unit, from the point toward the sun (or the facet that sends it), in the point's medium
        double pdf = 0;         // sr^-1
        bool valid = false;
    };
    // The sun seen from p along the in-medium direction `dir` (the pdf is that of the sunBeam
    // strategy for this direction). In air: a shadow ray along dir, valid inside the solar disc.
    // In a denser medium under a smooth interface: traced (through periodic walls) to the interface
    // above, refracted through the facet hit, valid if it leaves inside the solar disc and reaches
    // the sky unoccluded. In a medium bounded by a rough interface (roughSun(medium)): the point of
    // the disc given by uDisc, its light transmitted toward p by the rough BTDF of the facet hit.
    SunBeam sunAlong(const Point3& p, const Normal3& ng, const Vec3& dir, int medium, const Vec2& uDisc) const;
    // Next-event estimate of the sun at p (offset off the surface with normal ng, or ng = 0 for a
    // point inside a medium). If `facing` is not zero, directions with dot(toSun, facing) <= 0 are
    // rejected before any ray is cast. It draws two numbers from rng whatever the geometry (four in a
    // medium bounded by a rough interface, so the stream layout depends only on the medium):
    //  * in air: a shadow ray toward a uniformly sampled point of the disc (through dielectric
    //    objects along the straight-path model: skyTransmittance);
    //  * in a denser medium: the in-medium direction that a horizontal interface refracts toward
    //    that point is traced to the interface actually above (straight through submerged
    //    dielectric objects; a floating object's dry face stands for a horizontal water surface),
    //    refracted through the facet hit
    //    (Snell, Fresnel T_f), and counted if it leaves inside the disc and reaches the sky
    //    unoccluded, with the medium's transmittance along the leg and the solid-angle compression
    //    cos(theta_air)/cos(theta_medium);
    //  * in a medium under a rough interface: the direction toward the surface is drawn from the
    //    interface's transmission lobe for light from the sampled disc point (the rough BxDF of a
    //    horizontal surface, RoughDielectricBxDF::sampleTransmission), traced to the interface, and
    //    weighted by the BTDF of the facet actually hit: E = E_sun f_t(toward p, toward sun)
    //    |cos theta_sun| / pdf.
    // Which chains such an estimate covers is recorded by chainAfterVertex(medium) (SunChain).
    SunBeam sunBeam(const Point3& p, const Normal3& ng, const Vec3& facing, int medium, RandomStream& rng) const;

    // Whether transmittance in `medium` uses the effective extinction a + b (1 - f) (the
    // dissertation's effective scattering coefficient: scattering into the 0.01 sr forward cone
    // counts as unscattered). The dirsig estimator says yes for MediumPM media when
    // render.photons.effective_scattering is set, so that the direct sun, the camera rays and the
    // volume map (which then stores no forward-cone events) agree.
    virtual bool effectiveExtinction(int /*medium*/) const { return false; }

    // Is `medium` bounded from above by a rough interface (its sun estimates then sample that
    // interface's transmission lobe)?
    bool roughSun(int medium) const { return roughSunMaterial_[static_cast<size_t>(medium)] >= 0; }

    // Next-event estimation of the sun at a glossy (rough interface) hit h, seen along wo (local
    // frame of bxdf, `frame`): the radiance toward wo of sunlight reaching h along a straight shadow
    // ray on the side of the surface whose medium is air, by the BxDF, weighted against BSDF
    // sampling by the power heuristic (RenderConfig::glossySun chooses MIS or one strategy alone).
    // Skipped when the chain says an earlier vertex's estimate covers the connection. Draws two
    // numbers. Returns in *neeSide the side (+1 outside, -1 inside, 0 none) the estimate covered:
    // a BSDF-sampled direction on that side must carry SunChain::afterGlossy(pdf).
    Spec glossySun(const SurfaceHit& h, const Frame& frame, const BxDF& bxdf, const Vec3& wo, const SunChain& chain,
                   RandomStream& rng, int* neeSide) const;
    // The chain of the ray that leaves a glossy hit along the sampled direction s (local frame):
    // after a next-event estimate on that side, afterGlossy(s.pdf); otherwise `chain` with the event
    // recorded.
    SunChain chainAfterGlossy(const SunChain& chain, const BSDFSample& s, int neeSide) const;

    // Radiance of the sky (and of the solar disc if withSun) seen along direction d.
    Spec environment(const Vec3& d, bool withSun) const;
    // The same for a ray with the given chain: the disc counts if chain.countsSun(), weighted by
    // the multiple-importance weight of BSDF sampling when the ray left a glossy hit whose sun
    // estimate covered it.
    Spec environment(const Vec3& d, const SunChain& chain) const;
    // The SunChain of a ray leaving a scattering vertex in `medium`.
    SunChain chainAfterVertex(int medium) const;

    Spec bandValues(const std::vector<double>& v) const;

    const Scene& scene_;
    const RenderConfig& config_;
    BandGroup group_;
    Spec skyRadiance_;  // the sky's radiance in this group's bands (environment() above the horizon)

private:
    // Is medium m one the sun shines through (index 1, nothing attenuates: the air)?
    bool skyMedium(int m) const;
    // Transmittance toward the sun of a straight ray in a sky medium: 1 if nothing is in the way;
    // through smooth interfaces (dielectric objects, a wave crest) the Fresnel transmittance of a
    // straight crossing at each and Beer–Lambert inside (the straight-path model); false at an
    // opaque surface or a rough interface.
    bool skyTransmittance(const Ray& ray, int medium, Spec* T) const;
    // From p in a dense medium along dir up to the first interface whose far side is a sky medium,
    // through periodic walls and straight through dielectric objects on the way (Fresnel
    // transmittance per crossing, each medium's transmittance): the hit, the medium on its near
    // side and the product; false if the ray meets an opaque surface or nothing first.
    bool traceToSky(const Point3& p, const Normal3& ng, const Vec3& dir, int medium, SurfaceHit* h, int* near,
                    Spec* atten) const;
    // The rough-interface sun of sunAlong/sunBeam: light from the disc direction ws transmitted
    // toward p along -dir by the facet hit; pdf is the density of dir.
    SunBeam roughSunAlong(const Point3& p, const Normal3& ng, const Vec3& dir, int medium, const Vec3& ws,
                          double pdf) const;
    double misSunWeight(double bsdfPdf) const;  // weight of a BSDF-sampled disc hit

    // Per medium: the rough interface material that bounds it from above (-1: none; the medium then
    // sees the sun through smooth interfaces), the horizontal prototype of that interface for
    // sampling, and the frame of the prototype (+z up, x downwind).
    std::vector<int> roughSunMaterial_;
    std::vector<std::optional<RoughDielectricBxDF>> roughProto_;
    std::vector<Frame> roughFrame_;
};

// The estimators of one render: the resolved settings and one estimator per band group, built once
// and shared by every sensor and probe.
class EstimatorSet {
public:
    // For progressive photon mapping, pass p (1-based) traces its own photon maps (random streams
    // keyed by the pass) with the pass's radii.
    explicit EstimatorSet(const Scene& scene, int pass = 1, int threads = 0, bool progress = false);
    ~EstimatorSet();
    const RenderConfig& config() const { return config_; }
    const std::vector<BandGroup>& groups() const { return groups_; }
    const Estimator& forGroup(size_t i) const { return *estimators_[i]; }
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
