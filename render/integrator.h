#pragma once
// The radiance estimator: recursive ray tracing with per-material radiometry solvers (Table 10.4).
//
//  * Fresnel (Dielectric interfaces): specular reflection and refraction with unpolarised Fresnel
//    weights r_f and T_f = 1 - r_f (Eq. 4.2), Snell directions (Eq. 4.1), total internal
//    reflection, and the n^2 radiance law: radiance arriving from the far side of the interface
//    (index n_t) is seen on the near side (index n_o) scaled by T_f (n_o / n_t)^2. The first
//    `splits` interface events of a camera path trace both lobes (deterministic, noise-free
//    images of smooth water); later events choose one lobe with probability r_f (unbiased).
//  * Classic (diffuse materials): direct sun through a shadow ray (disc sampled uniformly) plus
//    the sky seen over a stratified jittered skydome of mu x phi equal-projected-solid-angle
//    quads, one ray per quad: the fraction of quad rays that reach the sky is the visible sky
//    fraction F of Eq. 6.1 and the surface returns r (E_sun cos theta_s [visible] / pi +
//    F L_sky). Sky rays pass through specular interfaces (Fresnel weights, n^2 law, attenuation)
//    but any opaque surface they meet contributes 0 (no background reflection).
//  * Generic (diffuse materials): the same sun term plus Monte Carlo cosine-weighted sampling of
//    the hemisphere through the BxDF's sample() (pdf cos/pi, so each sample's weight is the
//    reflectance r), independent samples: rays that reach other surfaces recurse, so background
//    reflections are included. The first diffuse vertex of a path shoots `hemisphereSamples` rays, deeper vertices (of either solver) one
//    ray each. At most
//    `maxBounces` diffuse vertices per path (DIRSIG GRS semantics: 0 -> black, 1 -> sky fraction
//    only, 2 -> plus the neighbours' sky fraction, ...).
//  * Every path segment inside a medium is attenuated by Beer–Lambert exp(-c s), c = a + b
//    (Eq. 2.4), through mediumSegment(), the hook where volume in-scatter (ray marching against
//    a volume photon map) plugs in. The current medium is carried along the path: it starts as
//    the sensor's medium and changes when a ray is transmitted through a Dielectric face
//    (front side -> the mesh's inside medium, back side -> outside medium).
//  * Direct sun at a diffuse vertex (sunIrradiance): in air, a shadow ray toward a uniformly
//    sampled point of the disc; in a denser medium, the refracted-sun estimate through the
//    interface above (the in-medium direction that a horizontal surface would refract toward
//    the sampled disc point is traced to the interface, refracted through the facet actually
//    hit, and counted if it leaves inside the disc and reaches the sky unoccluded, with the
//    Fresnel transmittance, Beer–Lambert attenuation and the solid-angle compression
//    cos(theta_air)/cos(theta_water)). The disc is then seen by escaping rays only along chains
//    this estimate does not cover (PathState::sunVisible), so nothing is counted twice.
//
// Known limits (documented in docs/rendering.md): sunlight focused onto a diffuse point by
// tilted facets (caustics under waves) along one refraction is not estimated; the photon pass
// will carry it.
#include <vector>

#include "core/rng.h"
#include "render/embree_scene.h"
#include "render/materials.h"
#include "render/scene.h"
#include "render/spectral.h"

namespace littoral::render {

// Consecutive render bands traced together: at most kMaxGroupBands, and every medium has the same
// refractive index in all of them (so they share ray geometry; dispersion splits groups).
struct BandGroup {
    int begin = 0, count = 0;
};
std::vector<BandGroup> bandGroups(const Scene& scene);

struct PathState {
    int medium = 0;          // index into Scene::media of the medium the ray travels in
    int diffuseDepth = 0;    // diffuse vertices already on the path
    int specularDepth = 0;   // specular interface events already on the path
    int splits = 0;          // remaining deterministic two-lobe Fresnel splits
    // Whether a ray escaping into the solar disc picks up L_sun = E_sun / Omega_sun: always for
    // sensor rays; for rays spawned at a diffuse vertex (or a probe) only when the chain since
    // that vertex is not covered by its sun estimate (sunIrradiance): after a specular
    // reflection or after two or more transmissions.
    bool fromSensor = true;
    bool reflected = false;  // a specular reflection (or TIR) since the last diffuse vertex
    int transmissions = 0;   // refractions since the last diffuse vertex
    bool sunVisible() const { return fromSensor || reflected || transmissions >= 2; }
    bool skyOnly = false;    // Classic sky rays: opaque surfaces contribute 0
};

class Integrator {
public:
    Integrator(const Scene& scene, BandGroup group);

    // Radiance arriving at ray.o from direction -ray.d (ray.d unit), per band of the group.
    Spec Li(const Ray& ray, const PathState& st, RandomStream& rng) const;

    // Radiance leaving the diffuse surface hit `h` toward wo (unit, pointing away from the
    // surface) by the material's solver. `st` is the state of the ray that arrived.
    Spec shadeDiffuse(const SurfaceHit& h, const Vec3& wo, const MaterialData& m, const PathState& st,
                      RandomStream& rng) const;

    // Radiance of the sky (and, if withSun, the solar disc) in direction d, per band.
    Spec environment(const Vec3& d, bool withSun) const;

    // Medium hook: transmittance exp(-c t) along ray.o .. ray.o + t ray.d in `medium`. A volume
    // photon map will add the in-scattered radiance of the segment to *inScatter here.
    Spec mediumSegment(const Ray& ray, double t, int medium, RandomStream& rng, Spec* inScatter) const;

    // Irradiance on a surface with unit normal n at p (in `medium`) from the sun's direct beam,
    // E_sun max(0, cos) if a shadow ray toward a point of the disc escapes (0 in an attenuating
    // medium, where a straight path to the sun cannot exist). scalar = true: the beam's
    // contribution to scalar irradiance, E_sun (no cosine), if the sun is above the plane of n.
    Spec sunIrradiance(const Point3& p, const Normal3& ng, const Normal3& n, int medium, RandomStream& rng,
                       bool scalar = false) const;

    int bandCount() const { return group_.count; }
    const Scene& scene() const { return scene_; }

private:
    Spec shadeInterface(const Ray& ray, const SurfaceHit& h, int mIncident, const PathState& st,
                        RandomStream& rng) const;
    Spec bandValues(const std::vector<double>& v) const;

    const Scene& scene_;
    BandGroup group_;
    int maxBounces_, maxSpecular_, hemisphereSamples_;
};

}  // namespace littoral::render
