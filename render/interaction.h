#pragma once
// The interaction step: what a path does where it meets a surface, one function for every transport
// loop (the dirsig and path estimators' camera and probe paths, the photon pass's photons).
//
//  * a periodic side wall wraps the ray to the opposite wall (Scene::wrapRay), medium unchanged;
//  * an interface (a BxDF flagged specular or glossy) is crossed or reflected: the tangent case,
//    deterministic two-lobe splitting of smooth interfaces, one lobe sampled otherwise, the sun's
//    next-event estimate at glossy hits (radiance paths), the medium switch and the SunChain
//    update;
//  * a diffuse BxDF is a scattering vertex that each loop evaluates its own way (sun and sky
//    estimates, hemisphere sampling, photon storage); any other BxDF is an internal error, so a
//    new kind of BxDF cannot render silently as something else.
// Transport decides by the BxDF's flags, never by the material's type.
#include <optional>

#include "core/frame.h"
#include "core/rng.h"
#include "render/scene.h"
#include "render/spectral.h"
#include "render/sun_connection.h"

namespace littoral::render {

// A ray leaving an interaction: where it goes, in which medium, with which sun chain, and the
// event's weight f |cos| / pdf (1 for a wrap and the tangent case).
struct Continuation {
    Ray ray;
    int medium = 0;
    SunChain chain;
    double weight = 1.0;
};

// The outcome of an interface event.
struct Interaction {
    enum class Kind {
        Ended,      // the path ends here (specular depth exhausted, or no lobe could be sampled)
        Continued,  // one continuation: out[0]
        Split,      // both lobes of a smooth interface: out[0] reflected, out[1] transmitted
    };
    Kind kind = Kind::Ended;
    Continuation out[2];  // Split: a lobe with weight 0 (e.g. no transmission under TIR) is skipped
};

// When an interface event draws its three random numbers (uc, u1, u2). Each loop keeps the stream
// layout it was validated with:
//  * path and photon loops draw them at every non-tangent event, split or not (the layout of a path
//    then depends only on its event count);
//  * the dirsig estimator draws them only for a sampled lobe, so that its deterministic splits
//    consume none, and its smooth interfaces draw them in the order (u1, u2, uc).
struct InterfaceDraws {
    bool whenSplitting = true;
    bool deltaUcLast = false;
};

class InteractionStep {
public:
    // `sun`: the sun connections used at glossy hits (radiance paths); null for photon paths.
    // `maxSpecular`: interface events allowed per path.
    InteractionStep(const Scene& scene, BandGroup group, TransportMode mode, const SunConnection* sun, int maxSpecular,
                    InterfaceDraws draws);

    // A periodic wall at h: the ray continuing from the opposite wall along d, or nullopt if the
    // wrap fails (the hit is not on a domain edge) or the path has wrapped Scene::kMaxWraps times
    // (*wraps counts the wraps of the path).
    std::optional<Ray> wrap(const SurfaceHit& h, const Vec3& d, int* wraps) const;
    // Does a transmission at h enter a sky medium (the air; SunChain::intoSky)?
    bool intoSky(const SurfaceHit& h) const;

    // The event at an interface h (bxdf = Scene::bxdf(h), specular or glossy) reached along ray with
    // sun chain `chain` (already past SunChain::hitSurface). *specular counts the path's interface
    // events; the first `splits` > 0 smooth events of a radiance path may split into both lobes.
    // At a glossy hit of a radiance path, *sun receives the sun's next-event estimate toward the
    // viewer (radiance, to be weighted by the path's throughput); it is not touched otherwise (one
    // interface event per ray of a frame: the outcome is kept small).
    Interaction atInterface(const Ray& ray, const SurfaceHit& h, const BxDF& bxdf, const SunChain& chain,
                            int* specular, int splits, RandomStream& rng, Spec* sun) const;

    // InternalError unless bxdf is diffuse: the callers' scattering-vertex code handles only those.
    static void requireDiffuse(const BxDF& bxdf);

private:
    struct Numbers {
        double uc = 0;
        Vec2 u;
    };
    static Numbers draw(RandomStream& rng, bool ucLast);
    // One lobe sampled with the numbers n; neeSide as returned by SunConnection::atGlossyHit.
    Interaction sampled(const SurfaceHit& h, const Frame& frame, const BxDF& bxdf, const Vec3& wo,
                        const SunChain& chain, int neeSide, const Numbers& n) const;
    Interaction split(const SurfaceHit& h, const Frame& frame, const Vec3& wo, const BSDFSample& r, const BSDFSample& t,
                      bool canTransmit, const SunChain& chain) const;

    const Scene& scene_;
    BandGroup group_;
    TransportMode mode_;
    const SunConnection* sun_;
    int maxSpecular_;
    InterfaceDraws draws_;
};

}  // namespace littoral::render
