#pragma once
// Sun connections: every way a path vertex is joined to the solar disc, in one place that every
// estimator composes (the dirsig and path estimators and the probes).
//
//  * next-event estimation of the sun at a point in air (a shadow ray), in water under smooth
//    interfaces (the refracted sun through the facet actually above) and under a rough interface
//    (the interface's transmission lobe, weighted by the facet hit): SunConnection::sample/along;
//  * the sun at a glossy (rough interface) hit, combined with BSDF sampling by multiple
//    importance sampling: SunConnection::atGlossyHit;
//  * the environment seen by a ray that escapes (sky, and the disc when the path's SunChain says
//    no earlier estimate covered it): SunConnection::environment.
// The SunChain rules below say which estimate covers which chain of interface events, so that no
// light is counted twice.
#include <memory>
#include <optional>
#include <vector>

#include "core/frame.h"
#include "core/rng.h"
#include "render/facet_beams.h"
#include "render/scene.h"
#include "render/spectral.h"

namespace littoral::render {

// Statistics counter (core/stats.h): sun estimates of the straight-path mode that reached the sky
// through a dielectric object or a wave crest without refraction (runRenderJob warns with the count).
inline constexpr const char* kStraightPathSun = "sun estimates: straight-path crossings of dielectric objects or crests";

// How a glossy (rough interface) hit gets the sun: next-event estimation and BSDF sampling
// combined by the power heuristic (the default), or one alone (for tests: all three agree).
enum class GlossySun { Mis, NeeOnly, BsdfOnly };

// Which interface events since the last scattering vertex (diffuse hit, medium collision or probe)
// a ray has gone through: the sun estimate at that vertex covers some chains of events, and a ray
// reaching the solar disc along one of those does not count it again.
//
// Each vertex's estimate covers chains with no reflection, a fixed number of rough transmissions
// (one for the rough-interface strategy, else none) and a range [coverMin, coverMax] of smooth
// ones (SunConnection::chainAfterVertex sets them):
//  * a shadow ray in air covers 0 smooth transmissions; in the straight-path mode (the dirsig
//    estimator: dielectric objects and wave crests crossed straight, docs/rendering.md) any number;
//  * a vertex in a denser medium lit through facet beams (render/facet_beams.h) covers 1 up to the
//    beams' maxOrder() (1 without dielectric objects, else the chains' length), entering from the
//    air only at the last (intoSky == 1), except single refractions whose leg from the vertex is
//    within FacetBeams::kMinSlope of the horizontal (not in the grid): those, a reflection (total
//    internal reflection under a steep facet), a longer chain or a re-entry are left to the rays
//    that sample the BSDF and the phase function, which count the disc when they reach it;
//  * under flat water without objects (the straight path through the facet above) exactly 1, any
//    number in the straight-path mode;
//  * the rough-interface strategy (SunConnection::sample in water under a rough interface) one
//    rough transmission and no smooth one (any number in the straight-path mode).
// No wall counts as an event. A glossy (rough interface) hit estimates the sun itself for the side
// of the surface where air is (SunConnection::atGlossyHit); the ray it samples toward that side then
// counts the disc with the MIS weight of BSDF sampling if it reaches it directly, and fully after
// any further event (afterGlossy).
struct SunChain {
    static constexpr int kAny = 1 << 30;
    bool fromSensor = true;  // no scattering vertex before (or a glossy sun estimate): the disc counts
    bool reflected = false;
    int transmissions = 0;       // smooth interfaces
    int roughTransmissions = 0;  // rough interfaces
    int intoSky = 0;             // transmissions into a sky medium (the air), smooth or rough
    bool roughSun = false;       // the vertex's sun estimate was the rough-interface strategy
    int coverMin = 0, coverMax = kAny;  // smooth transmissions the vertex's estimate covers
    bool oneSkyEntry = false;    // ... only if the chain entered the air once (facet beams)
    bool firstLegFlat = false;   // the ray's first leg rose less steeply than FacetBeams::kMinSlope
    double glossyPdf = 0;        // > 0: left a glossy hit whose sun estimate covered the direct disc
    bool noEstimate = false;     // the vertex made no sun estimate (setInWaterSunEstimates(false))
    bool countsSun() const {
        if (fromSensor || reflected || noEstimate) return true;
        const bool covered = roughTransmissions == (roughSun ? 1 : 0) && transmissions >= coverMin &&
                             transmissions <= coverMax &&
                             (!oneSkyEntry || (intoSky <= 1 && !(transmissions == 1 && firstLegFlat)));
        return !covered;
    }
    static SunChain afterVertex(bool rough, int coverMin, int coverMax, bool oneSkyEntry) {
        SunChain c;
        c.fromSensor = false;
        c.roughSun = rough;
        c.coverMin = coverMin, c.coverMax = coverMax, c.oneSkyEntry = oneSkyEntry;
        return c;
    }
    static SunChain afterGlossy(double bsdfPdf) {
        SunChain c;
        c.glossyPdf = bsdfPdf;
        return c;
    }
    // Any surface hit ends the direct flight from a glossy vertex.
    void hitSurface() { glossyPdf = 0; }
    // The chain after an interface event that reflected or transmitted (smooth or rough) the ray
    // arriving with direction z-component legZ, into a sky medium or not.
    void record(bool transmitted, bool rough, bool toSky, double legZ) {
        if (!reflected && transmissions == 0 && roughTransmissions == 0) firstLegFlat = legZ < FacetBeams::kMinSlope;
        if (!transmitted) reflected = true;
        else if (rough) ++roughTransmissions;
        else ++transmissions;
        if (transmitted && toSky) ++intoSky;
    }
};

// The solar beam at a point, as one sample of a sun estimate: the radiance L arriving at the
// point along toSun and the density `pdf` (per unit solid angle of toSun) with which the estimate
// chose that direction, so that E = L / pdf is the estimate of the irradiance on a plane normal to
// toSun. For a direct or singly refracted disc L = E_beam / Omega (uniform over the disc of solid
// angle Omega as seen from the point) and pdf = 1 / Omega; through a rough interface toSun is drawn
// from its transmission lobe (see SunConnection::sample) and L is the radiance estimate for one
// point of the disc.
struct SunBeam {
    Spec E;          // L / pdf, per band
    Spec L;          // radiance along toSun, per band
    Vec3 toSun;      // unit, from the point toward the sun (or the facet that sends it), in the point's medium
    double pdf = 0;  // sr^-1
    bool valid = false;
};

class SunConnection {
public:
    // effectiveExtinction[m]: transmittance in medium m uses the effective extinction a + b (1 - f)
    // (the dissertation's effective scattering coefficient: scattering into the 0.01 sr forward cone
    // counts as unscattered); empty = no medium does. The dirsig estimator sets it for MediumPM
    // media when render.photons.effective_scattering is set, so that the direct sun, the camera
    // rays and the volume map (which then stores no forward-cone events) agree.
    // straightPath: shadow rays from the air cross dielectric objects and wave crests along the
    // straight-path model (the dirsig estimator, after the dissertation); otherwise every estimate
    // follows real refractions only, and anything else is left to sampling (the path estimator).
    SunConnection(const Scene& scene, BandGroup group, GlossySun glossy, std::vector<bool> effectiveExtinction = {},
                  bool straightPath = false);

    // The sun seen from p along the in-medium direction `dir` (the pdf is that of sample() for this
    // direction). In air: a shadow ray along dir, valid inside the solar disc. In a denser medium
    // under a smooth interface: traced (through periodic walls) to the interface above, refracted
    // through the facet hit, valid if it leaves inside the solar disc and reaches the sky
    // unoccluded. In a medium bounded by a rough interface (roughAbove(medium)): the point of the
    // disc given by uDisc, its light transmitted toward p by the rough BTDF of the facet hit.
    SunBeam along(const Point3& p, const Normal3& ng, const Vec3& dir, int medium, const Vec2& uDisc) const;
    // Next-event estimate of the sun at p (offset off the surface with normal ng, or ng = 0 for a
    // point inside a medium). If `facing` is not zero, directions with dot(toSun, facing) <= 0 are
    // rejected before any ray is cast. It draws two numbers from rng whatever the geometry (four in a
    // medium bounded by a rough interface, so the stream layout depends only on the medium):
    //  * in air: a shadow ray toward a uniformly sampled point of the disc (in the straight-path
    //    mode through dielectric objects along the straight-path model: skyTransmittance);
    //  * in a denser medium with facet beams (beamsInto: under waves, or holding dielectric
    //    objects): the beams that contain p for that disc point (facets, and chains of refractions
    //    through objects), one of them picked uniformly (from the first number's low bits) and
    //    weighted by their number, traced back through its faces (each the first surface on the
    //    way: else it is shadowed) and on to the sky, which must be clear (beamAlong);
    //  * under flat water without objects: the in-medium direction that a horizontal interface
    //    refracts toward that point is traced to the interface above, refracted through the facet
    //    hit (Snell, Fresnel T_f), and counted if it leaves inside the disc and reaches the sky
    //    unoccluded, with the medium's transmittance along the leg and the solid-angle compression
    //    cos(theta_air)/cos(theta_medium);
    //  * in a medium under a rough interface: the direction toward the surface is drawn from the
    //    interface's transmission lobe for light from the sampled disc point (the rough BxDF of a
    //    horizontal surface, RoughDielectricBxDF::sampleTransmission), traced to the interface, and
    //    weighted by the BTDF of the facet actually hit: E = E_sun f_t(toward p, toward sun)
    //    |cos theta_sun| / pdf.
    // Which chains such an estimate covers is recorded by chainAfterVertex(medium) (SunChain).
    SunBeam sample(const Point3& p, const Normal3& ng, const Vec3& facing, int medium, RandomStream& rng) const;

    // The direct solar beam at the point p (inside `medium`, not on a surface) on a plane with
    // normal n (E_sun cos, or E_sun for scalar irradiance), by next-event estimation: a shadow ray
    // in air, the refracted sun through the interface above in water.
    Spec direct(const Point3& p, const Normal3& n, int medium, bool scalar, RandomStream& rng) const;

    // Direction toward the centre of the solar disc as seen from inside `medium` through a
    // horizontal interface (Snell, Eq. 4.1); nullopt without a sun. A guide for importance
    // sampling (e.g. probe directions near the forward-scattering peak), not a visibility claim.
    std::optional<Vec3> refractedDirection(int medium) const;

    // Next-event estimation of the sun at a glossy (rough interface) hit h, seen along wo (local
    // frame of bxdf, `frame`): the radiance toward wo of sunlight reaching h along a straight shadow
    // ray on the side of the surface whose medium is air, by the BxDF, weighted against BSDF
    // sampling by the power heuristic (GlossySun chooses MIS or one strategy alone). Skipped when
    // the chain says an earlier vertex's estimate covers the connection. Draws two numbers. Returns
    // in *neeSide the side (+1 outside, -1 inside, 0 none) the estimate covered: a BSDF-sampled
    // direction on that side must carry SunChain::afterGlossy(pdf).
    Spec atGlossyHit(const SurfaceHit& h, const Frame& frame, const BxDF& bxdf, const Vec3& wo, const SunChain& chain,
                     RandomStream& rng, int* neeSide) const;
    // The chain of the ray that leaves a glossy hit along the sampled direction s (local frame):
    // after a next-event estimate on that side, afterGlossy(s.pdf); otherwise `chain` with the event
    // recorded (toSky: a transmission into a sky medium; legZ: the arriving ray's direction z).
    SunChain chainAfterGlossy(const SunChain& chain, const BSDFSample& s, int neeSide, bool toSky, double legZ) const;
    // The SunChain of a ray leaving a scattering vertex in `medium`.
    SunChain chainAfterVertex(int medium) const;
    // Is medium m one the sun shines through (index 1, nothing attenuates: the air)? Asked at every
    // interface event (InteractionStep::intoSky), so kept per medium.
    bool skyMedium(int m) const { return sky_[static_cast<size_t>(m)] != 0; }
    // Whether sample(), along() and direct() estimate the sun at points in `medium`: always in the
    // air; in a denser medium unless setInWaterSunEstimates(false) was in force when this connection
    // was made.
    bool estimatesIn(int medium) const { return inWater_ || skyMedium(medium); }
    // The facet beams into `medium` (nullptr: none, or the medium lies under a rough interface or
    // is the air).
    const FacetBeams* beamsInto(int medium) const { return beams_[static_cast<size_t>(medium)].get(); }

    // Radiance of the sky (and of the solar disc if withSun) seen along direction d.
    Spec environment(const Vec3& d, bool withSun) const;
    // The same for a ray with the given chain: the disc counts if chain.countsSun(), weighted by
    // the multiple-importance weight of BSDF sampling when the ray left a glossy hit whose sun
    // estimate covered it.
    Spec environment(const Vec3& d, const SunChain& chain) const;

    // Is `medium` bounded from above by a rough interface (its sun estimates then sample that
    // interface's transmission lobe)?
    bool roughAbove(int medium) const { return roughSunMaterial_[static_cast<size_t>(medium)] >= 0; }
    bool effectiveExtinction(int medium) const {
        return !effective_.empty() && effective_[static_cast<size_t>(medium)];
    }
    // The transmittance of `medium` along ray over [0, t], with this connection's extinction rule.
    Spec transmittance(const Ray& ray, double t, int medium) const;
    // Per-band values of a per-render-band table, for this group.
    Spec bandValues(const std::vector<double>& v) const;

private:
    // Transmittance toward the sun of a straight ray from a sky medium: 1 if nothing is in the way;
    // in the straight-path mode through smooth interfaces (dielectric objects, a wave crest) the
    // Fresnel transmittance of a straight crossing at each and Beer–Lambert inside; false at an
    // opaque surface, a rough interface, or (not in that mode) any interface.
    bool skyTransmittance(const Ray& ray, int medium, Spec* T) const;
    // From p in a dense medium along dir up to the first interface whose far side is a sky medium,
    // through periodic walls and (straight-path mode) straight through dielectric objects (Fresnel
    // transmittance per crossing, each medium's transmittance): the hit, the medium on its near
    // side and the product; false if the ray meets an opaque surface or nothing first.
    bool traceToSky(const Point3& p, const Normal3& ng, const Vec3& dir, int medium, SurfaceHit* h, int* near,
                    Spec* atten) const;
    // The walk both of the above take: straight through periodic walls and (straight-path mode)
    // smooth interfaces from `ray` in `medium`, multiplying *T by each medium's transmittance and
    // each straight crossing's Fresnel transmittance, until the ray escapes (returns Escaped),
    // meets something that stops it (Blocked), or, if stopAtSky, reaches an interface whose far
    // side is a sky medium (AtSky, with *h and *near set). *crossed: the interfaces crossed straight.
    enum class Walk { Escaped, Blocked, AtSky };
    Walk straightWalk(Ray ray, int medium, bool stopAtSky, Spec* T, SurfaceHit* h, int* near,
                      int* crossed = nullptr) const;
    // The rough-interface sun of along/sample: light from the disc direction ws transmitted toward
    // p along -dir by the facet hit; pdf is the density of dir.
    SunBeam roughAlong(const Point3& p, const Normal3& ng, const Vec3& dir, int medium, const Vec3& ws,
                       double pdf) const;
    // The smooth-interface sun of along(): dir traced to the interface above and refracted there.
    SunBeam smoothAlong(const Point3& p, const Normal3& ng, const Vec3& dir, int medium) const;
    double misSunWeight(double bsdfPdf) const;  // weight of a BSDF-sampled disc hit
    // The facet-beam sun (sample and along in a medium with beams): from p along dir, through
    // periodic walls only, to the first surface, which must be a smooth interface of `medium`, and
    // refracted there; on through every further smooth face into a dense medium, up to the beams'
    // maxOrder() refractions, until one refracts it into the air, whose light must then come
    // straight from the sky. With `beam` >= 0 the faces crossed must be that beam's, in order (the
    // direction then leaves toward the disc point it was made for); with -1 the direction must
    // leave inside the disc. `pick` is the probability with which the estimate chose this beam
    // among those that contain p for that disc direction (the density is pick / solid angle).
    // *weight: the beam's weight as FacetBeams::weight computes it, from the faces actually crossed;
    // *refractions: their number.
    SunBeam beamAlong(const Point3& p, const Normal3& ng, const Vec3& dir, int medium, int beam, double pick,
                      Vec3* outAir = nullptr, double* weight = nullptr, int* refractions = nullptr) const;
    SunBeam beamSample(const Point3& p, const Normal3& ng, const Vec3& facing, int medium, const Vec3& ws,
                       double uPick) const;
    // Straight along `ray` through periodic walls only: 1 and the first other surface (*h, and the
    // transmittance of `medium` up to it), 0 if the ray escapes, -1 if it wraps without end.
    int firstSurface(Ray ray, int medium, SurfaceHit* h, Spec* atten) const;
    SunBeam none() const;

    const Scene& scene_;
    BandGroup group_;
    std::vector<unsigned char> sky_;  // per medium: skyMedium
    GlossySun glossy_;
    std::vector<bool> effective_;
    Spec skyRadiance_;  // the sky's radiance in this group's bands (environment() above the horizon)
    // Per medium: the rough interface material that bounds it from above (-1: none; the medium then
    // sees the sun through smooth interfaces), the horizontal prototype of that interface for
    // sampling, and the frame of the prototype (+z up, x downwind).
    std::vector<int> roughSunMaterial_;
    std::vector<std::optional<RoughDielectricBxDF>> roughProto_;
    std::vector<Frame> roughFrame_;
    std::vector<std::unique_ptr<FacetBeams>> beams_;  // per medium (see beamsInto)
    bool inWater_ = true;                             // see estimatesIn
    bool straight_ = false;                           // the straight-path mode (constructor)
};

// For benchmarks of the connection's worth (bench/bench_nadir_connection.cpp), not a scene
// setting: with false, SunConnections made afterwards estimate no sun at points in water (or in any
// medium denser than the air). The path estimator then stays unbiased, because the rays it samples
// from those points count the solar disc when they reach it (SunChain::noEstimate), but its noise
// is that of finding a 0.53 deg disc by chance. The dirsig estimator and the probes lose the
// in-water direct sun: use it with the path estimator's images only. Process-wide; default true.
void setInWaterSunEstimates(bool on);

}  // namespace littoral::render
