#include "render/sun_connection.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <tuple>

#include "core/error.h"
#include "core/stats.h"
#include "core/units.h"
#include "render/sampling.h"

namespace littoral::render {

namespace {
// Fresnel transmittance of a crossing that keeps the direction (the straight-path model of
// dielectric objects, docs/rendering.md): the path's direction is taken as the one on the side of
// the lower index, so the crossing never reflects totally; 1 between equal indices.
double straightCrossing(double cosAngle, double n1, double n2) {
    if (n1 == n2) return 1.0;
    return 1.0 - fresnelDielectric(std::abs(cosAngle), std::min(n1, n2), std::max(n1, n2));
}
constexpr int kMaxStraightCrossings = 64;
std::atomic<bool> gInWaterSunEstimates{true};  // setInWaterSunEstimates
}  // namespace

void setInWaterSunEstimates(bool on) { gInWaterSunEstimates.store(on); }

SunConnection::SunConnection(const Scene& scene, BandGroup group, GlossySun glossy, std::vector<bool> effective,
                             bool straightPath)
    : scene_(scene), group_(group), glossy_(glossy), effective_(std::move(effective)),
      inWater_(gInWaterSunEstimates.load()), straight_(straightPath) {
    LITTORAL_CHECK(effective_.empty() || effective_.size() == scene.media().size());
    for (const Medium& md : scene.media()) sky_.push_back(md.n(group.begin) == 1.0 && !md.attenuating());
    skyRadiance_ = bandValues(scene.sky().radiance);
    // A medium under a rough interface: the inside medium of a mesh that uses a rough material, whose
    // outside is a non-attenuating medium (the air the sun shines through). Its sun estimates use
    // the first such interface's lobe for sampling (the facet actually hit weights them).
    const size_t nm = scene.media().size();
    roughSunMaterial_.assign(nm, -1);
    roughProto_.assign(nm, std::nullopt);
    roughFrame_.assign(nm, Frame{});
    const auto& meshes = scene.ir().meshes;
    for (size_t mi = 0; mi < meshes.size(); ++mi) {
        const int in = scene.insideMedium(static_cast<int>(mi)), out = scene.outsideMedium(static_cast<int>(mi));
        if (in == out || roughSunMaterial_[static_cast<size_t>(in)] >= 0) continue;
        const Medium& outside = scene.media()[static_cast<size_t>(out)];
        if (outside.attenuating()) continue;
        for (const std::string& name : meshes[mi].materials) {
            int k = -1;
            for (size_t j = 0; j < scene.materials().size(); ++j)
                if (scene.materials()[j].name == name) k = static_cast<int>(j);
            if (k < 0 || !(scene.materials()[static_cast<size_t>(k)].bxdfFlags() & kGlossy)) continue;
            roughSunMaterial_[static_cast<size_t>(in)] = k;
            roughProto_[static_cast<size_t>(in)] =
                scene.roughBxdf(k, outside.n(group.begin), scene.media()[static_cast<size_t>(in)].n(group.begin));
            roughFrame_[static_cast<size_t>(in)] =
                Frame::fromNormalAndTangent(Vec3{0, 0, 1}, scene.materials()[static_cast<size_t>(k)].downwind);
            break;
        }
    }
    // Facet beams into every denser medium that is not under a rough interface.
    beams_.resize(nm);
    const std::vector<bool> sky(sky_.begin(), sky_.end());
    std::vector<double> index(nm);
    for (size_t m = 0; m < nm; ++m) index[m] = scene.media()[m].n(group.begin);
    const SunSource& sun = scene.sun();
    for (size_t m = 0; m < nm && sun.enabled; ++m) {
        if (sky[m] || roughSunMaterial_[m] >= 0) continue;
        auto b = std::make_unique<FacetBeams>(scene, static_cast<int>(m), index, sky, sun.direction, sun.halfAngle);
        // Under flat water without objects every beam is the straight path's (docs/rendering.md):
        // one ray, not a lookup and two (the Mobley columns' path estimate took 10 times as long
        // through the beams).
        if (!b->empty() && (b->hasObjects() || !b->allHorizontal())) beams_[m] = std::move(b);
    }
}

SunChain SunConnection::chainAfterVertex(int medium) const {
    const bool rough = roughAbove(medium);
    const FacetBeams* fb = beamsInto(medium);
    SunChain c;
    if (rough) c = SunChain::afterVertex(true, 0, straight_ ? SunChain::kAny : 0, false);
    else if (fb) c = SunChain::afterVertex(false, 1, fb->maxOrder(), true);
    else if (skyMedium(medium)) c = SunChain::afterVertex(false, 0, straight_ ? SunChain::kAny : 0, false);
    else c = SunChain::afterVertex(false, straight_ ? 0 : 1, straight_ ? SunChain::kAny : 1, false);
    c.noEstimate = !estimatesIn(medium);
    return c;
}

Spec SunConnection::bandValues(const std::vector<double>& v) const {
    Spec s(group_.count);
    for (int i = 0; i < group_.count; ++i) s[i] = v[group_.begin + i];
    return s;
}

Spec SunConnection::transmittance(const Ray& ray, double t, int medium) const {
    return scene_.media()[static_cast<size_t>(medium)].transmittance(ray, t, group_, effectiveExtinction(medium));
}

SunBeam SunConnection::none() const {
    SunBeam b;
    b.E = b.L = Spec(group_.count);
    return b;
}

Spec SunConnection::environment(const Vec3& d, bool withSun) const {
    Spec L = d.z > 0 ? skyRadiance_ : Spec(group_.count);
    const SunSource& sun = scene_.sun();
    if (withSun && sun.inDisc(d)) {
        // Uniform disc radiance L_sun = E_sun / Omega_sun (exact cone solid angle).
        for (int i = 0; i < group_.count; ++i) L[i] += sun.irradiance[group_.begin + i] / sun.solidAngle;
    }
    return L;
}

double SunConnection::misSunWeight(double bsdfPdf) const {
    switch (glossy_) {
        case GlossySun::NeeOnly: return 0.0;
        case GlossySun::BsdfOnly: return 1.0;  // (no estimate was made: glossyPdf is never set)
        case GlossySun::Mis: break;
    }
    // Power heuristic (Veach 1997, eq. 9.13, beta = 2) against the disc's uniform density 1/Omega.
    const double pl = 1.0 / scene_.sun().solidAngle;
    return bsdfPdf * bsdfPdf / (bsdfPdf * bsdfPdf + pl * pl);
}

Spec SunConnection::environment(const Vec3& d, const SunChain& chain) const {
    Spec L = environment(d, false);
    const SunSource& sun = scene_.sun();
    if (!sun.inDisc(d) || !chain.countsSun()) return L;  // the disc test first: it rarely passes
    const double w = chain.glossyPdf > 0 ? misSunWeight(chain.glossyPdf) : 1.0;
    if (w <= 0) return L;
    for (int i = 0; i < group_.count; ++i) L[i] += w * sun.irradiance[group_.begin + i] / sun.solidAngle;
    return L;
}

SunConnection::Walk SunConnection::straightWalk(Ray r, int m, bool stopAtSky, Spec* T, SurfaceHit* h, int* near,
                                                int* crossed) const {
    for (int k = 0, wraps = 0; k < kMaxStraightCrossings;) {
        if (crossed) *crossed = k;
        const Medium& md = scene_.media()[static_cast<size_t>(m)];
        if (!scene_.geometry().intersect(r, h)) return md.attenuating() ? Walk::Blocked : Walk::Escaped;
        if (md.attenuating()) *T *= transmittance(r, h->t, m);
        if (scene_.isPeriodicWall(*h)) {
            const auto next = scene_.wrapRay(*h, r.d);
            if (!next || ++wraps > Scene::kMaxWraps) return Walk::Blocked;
            r = *next;
            continue;
        }
        // Opaque surfaces block the sun.
        const uint8_t flags = scene_.bxdfFlags(*h);
        if (!(flags & kTransmission)) return Walk::Blocked;
        const int far = scene_.farMedium(*h);
        if (stopAtSky) {
            if (scene_.nearMedium(*h) != m) return Walk::Blocked;
            if (skyMedium(far)) {
                *near = m;
                return Walk::AtSky;
            }
        }
        // Rough interfaces block the straight path too (light through them is sampled), and so
        // does every interface unless the straight-path model is in force.
        if ((flags & kGlossy) || !straight_) return Walk::Blocked;
        *T *= straightCrossing(dot(r.d, h->ng),
                               scene_.media()[static_cast<size_t>(scene_.nearMedium(*h))].n(group_.begin),
                               scene_.media()[static_cast<size_t>(far)].n(group_.begin));
        m = far;
        r = spawnRay(h->p, h->ng, r.d);
        ++k;
    }
    return Walk::Blocked;
}

bool SunConnection::skyTransmittance(const Ray& ray, int medium, Spec* T) const {
    *T = Spec(group_.count, 1.0);
    if (!scene_.geometry().occluded(ray)) return true;  // the common case: nothing in the way
    SurfaceHit h;
    int near = -1;
    int crossed = 0;
    if (straightWalk(ray, medium, false, T, &h, &near, &crossed) != Walk::Escaped) return false;
    if (crossed > 0) {
        static StatCounter& straight = statCounter(kStraightPathSun);
        straight.add();
    }
    return true;
}

bool SunConnection::traceToSky(const Point3& p, const Normal3& ng, const Vec3& dir, int medium, SurfaceHit* h,
                               int* near, Spec* atten) const {
    *atten = Spec(group_.count, 1.0);
    return straightWalk(spawnRay(p, ng, dir), medium, true, atten, h, near) == Walk::AtSky;
}

SunBeam SunConnection::roughAlong(const Point3& p, const Normal3& ng, const Vec3& dir, int medium, const Vec3& ws,
                                  double pdf) const {
    SunBeam beam = none();
    SurfaceHit h;
    Spec atten;
    int near = -1;
    if (!traceToSky(p, ng, dir, medium, &h, &near, &atten)) return beam;
    // A smooth facet refracts the disc into a set of measure zero; only the medium's own rough
    // surface sends this light.
    if (!(scene_.bxdfFlags(h) & kGlossy) || near != medium) return beam;
    const Frame frame = scene_.shadingFrame(h);
    const BxDF bxdf = scene_.bxdf(h, group_);
    const Vec3 wo = frame.toLocal(-dir), wi = frame.toLocal(ws);
    // Radiance mode: the light arrives from ws and leaves toward p (the n^2 law included).
    const double f = bxdf.f(wo, wi, TransportMode::Radiance);
    if (!(f > 0)) return beam;
    Spec sky;
    if (!skyTransmittance(spawnRay(h.p, h.ng, ws), scene_.farMedium(h), &sky)) return beam;
    // One point of the disc sampled with density 1/Omega_sun: radiance f L_sun |cos| / (1/Omega)
    // = f E_sun |cos theta_i| at the point (and the transmittances on the way).
    const SunSource& sun = scene_.sun();
    const double g = f * std::abs(wi.z);
    for (int i = 0; i < group_.count; ++i) beam.L[i] = sun.irradiance[group_.begin + i] * g * atten[i] * sky[i];
    beam.toSun = dir;
    beam.pdf = pdf;
    if (pdf > 0) beam.E = beam.L * (1.0 / pdf);
    beam.valid = true;
    return beam;
}

SunBeam SunConnection::along(const Point3& p, const Normal3& ng, const Vec3& dir, int medium,
                             const Vec2& uDisc) const {
    SunBeam beam = none();
    const SunSource& sun = scene_.sun();
    if (!sun.enabled || !estimatesIn(medium)) return beam;
    if (skyMedium(medium)) {
        // In air: a straight shadow ray (through dielectric objects with their transmittance).
        if (!sun.inDisc(dir)) return beam;
        Spec T;
        if (!skyTransmittance(spawnRay(p, ng, dir), medium, &T)) return beam;
        beam.E = bandValues(sun.irradiance) * T;
        beam.L = beam.E * (1.0 / sun.solidAngle);
        beam.toSun = dir;
        beam.pdf = 1.0 / sun.solidAngle;
        beam.valid = true;
        return beam;
    }
    if (roughAbove(medium)) {
        // The disc point uDisc, and the density with which sample() would have chosen dir for it.
        const Vec3 ws = sun.sampleDirection(uDisc.x, uDisc.y);
        const Frame& F = roughFrame_[static_cast<size_t>(medium)];
        const double pdf = roughProto_[static_cast<size_t>(medium)]->pdfTransmission(F.toLocal(ws), F.toLocal(-dir));
        return roughAlong(p, ng, dir, medium, ws, pdf);
    }
    if (const FacetBeams* fb = beamsInto(medium)) {
        // Traced to the facet above; the beams that contain p for the disc direction it sends light
        // from give the density with which sample() picks this one.
        // The probability with which sample() would pick this beam among those that contain p for
        // the disc direction it leaves toward. If no indexed beam does (a single refraction closer
        // to the horizontal than kMinSlope), the light is not covered (SunChain): none.
        Vec3 out;
        double w = 0;
        int refractions = 0;
        SunBeam b = beamAlong(p, ng, dir, medium, -1, 1, &out, &w, &refractions);
        if (!b.valid) return b;
        // A single refraction flatter than the grid indexes is left to sampling (SunChain), even
        // where other beams contain p for the same disc direction.
        if (refractions == 1 && dir.z < FacetBeams::kMinSlope) return none();
        double total = 0;
        fb->forEachContaining(p, out, [&](int f, const Vec3&, double) { total += fb->weight(f, out); });
        if (!(total > 0)) return none();
        b.pdf *= std::min(1.0, w / total);
        b.E = b.L * (1.0 / b.pdf);
        return b;
    }
    return smoothAlong(p, ng, dir, medium);
}

int SunConnection::firstSurface(Ray r, int m, SurfaceHit* h, Spec* atten) const {
    *atten = Spec(group_.count, 1.0);
    const bool attenuating = scene_.media()[static_cast<size_t>(m)].attenuating();
    for (int wraps = 0;;) {
        if (!scene_.geometry().intersect(r, h)) return 0;
        if (attenuating) *atten *= transmittance(r, h->t, m);
        if (!scene_.isPeriodicWall(*h)) return 1;
        const auto next = scene_.wrapRay(*h, r.d);
        if (!next || ++wraps > Scene::kMaxWraps) return -1;
        r = *next;
    }
}

SunBeam SunConnection::beamAlong(const Point3& p, const Normal3& ng, const Vec3& dir, int medium, int beam,
                                 double pick, Vec3* outAir, double* weight, int* refractions) const {
    const FacetBeams& fb = *beamsInto(medium);
    std::array<BeamFace, FacetBeams::kMaxChainOrder> faces;
    const int nFaces = beam >= 0 ? fb.faces(beam, &faces) : 0;
    const SunSource& sun = scene_.sun();
    Spec atten(group_.count, 1.0);
    double geom = 1, solidAngle = sun.solidAngle;
    Ray r = spawnRay(p, ng, dir);
    Vec3 d = dir, out;
    for (int k = 0, m = medium;; ++k) {
        SurfaceHit h;
        Spec a;
        if (k >= fb.maxOrder() || firstSurface(r, m, &h, &a) != 1) return none();
        atten *= a;
        if (beam >= 0) {
            const BeamFace& f = faces[static_cast<size_t>(k)];
            if (k >= nFaces || h.mesh != f.mesh || h.instance != f.instance || h.face != f.face) return none();  // in its shadow
        }
        const MaterialData& mat = scene_.material(h);
        const int farM = scene_.farMedium(h);
        if (!mat.isInterface() || mat.isRough() || scene_.nearMedium(h) != m) return none();
        const double nNear = scene_.media()[static_cast<size_t>(m)].n(group_.begin);
        const double nFar = scene_.media()[static_cast<size_t>(farM)].n(group_.begin);
        const Normal3 nf = h.front ? h.ng : -h.ng;  // face normal on the near side
        const double cosW = std::abs(dot(d, nf));
        if (!refract(-d, nf, nNear / nFar, &out)) return none();  // total internal reflection at this face
        out = normalize(out);
        const double cosA = std::abs(dot(out, nf));
        // Each refraction: Fresnel T and the face's area seen from the far side over the beam's
        // cross section (cosA / cosW), and the solid angle compressed by nFar^2 cosA / (nNear^2 cosW)
        // (etendue).
        geom *= (1.0 - fresnelDielectric(cosW, nNear, nFar)) * cosA / cosW;
        solidAngle = solidAngle * (nFar * nFar) * cosA / (nNear * nNear * cosW);
        if (!skyMedium(farM)) {
            r = spawnRay(h.p, h.ng, out), m = farM, d = out;
            continue;
        }
        if (beam >= 0 && k + 1 != nFaces) return none();
        // sample() chose dir so that it leaves toward its disc point; along()'s dir must find the disc.
        if (beam < 0 && !sun.inDisc(out)) return none();
        // The air above the face must be clear: light through anything else is another chain.
        SurfaceHit above;
        Spec unused;
        if (firstSurface(spawnRay(h.p, h.ng, out), farM, &above, &unused) != 0) return none();
        if (refractions) *refractions = k + 1;
        break;
    }
    if (outAir) *outAir = out;
    if (weight) *weight = geom;
    SunBeam result = none();
    for (int i = 0; i < group_.count; ++i) result.L[i] = sun.irradiance[group_.begin + i] * geom * atten[i] / solidAngle;
    result.toSun = dir;
    result.pdf = pick / solidAngle;
    if (result.pdf > 0) result.E = result.L * (1.0 / result.pdf);
    result.valid = true;
    return result;
}

SunBeam SunConnection::beamSample(const Point3& p, const Normal3& ng, const Vec3& facing, int medium, const Vec3& ws,
                                  double uPick) const {
    const FacetBeams& fb = *beamsInto(medium);
    // One of the beams, with probability proportional to its weight (its irradiance before
    // attenuation and shadowing, FacetBeams::weight): the estimate is divided by that probability
    // (beamAlong). They are kept as they are found; only where more than kKept overlap (a strong
    // caustic) is the lookup repeated to reach the one picked.
    constexpr int kKept = 16;
    struct Kept {
        int beam;
        Vec3 d;
        double w;
    };
    std::array<Kept, kKept> kept;
    double total = 0;
    const int beams = fb.forEachContaining(p, ws, [&, n = 0](int f, const Vec3& df, double) mutable {
        const double w = fb.weight(f, ws);
        total += w;
        if (n < kKept) kept[static_cast<size_t>(n++)] = {f, df, w};
    });
    if (beams == 0 || !(total > 0)) return none();
    const double target = uPick * total;
    double acc = 0;
    Kept pick{-1, Vec3{0, 0, 0}, 0};
    for (int k = 0; k < std::min(beams, kKept) && pick.beam < 0; ++k) {
        const Kept& c = kept[static_cast<size_t>(k)];
        acc += c.w;
        if (c.w > 0 && (target < acc || k + 1 == beams)) pick = c;
    }
    if (pick.beam < 0) {
        acc = 0;
        Kept last{-1, Vec3{0, 0, 0}, 0};
        fb.forEachContaining(p, ws, [&](int f, const Vec3& df, double) {
            if (pick.beam >= 0) return;
            const double w = fb.weight(f, ws);
            acc += w;
            if (w > 0) last = {f, df, w};
            if (w > 0 && target < acc) pick = last;
        });
        if (pick.beam < 0) pick = last;  // (rounding: target at the very end)
    }
    if (pick.beam < 0) return none();
    const bool checkFacing = facing.x != 0 || facing.y != 0 || facing.z != 0;
    if (checkFacing && dot(-pick.d, facing) <= 0) return none();
    return beamAlong(p, ng, -pick.d, medium, pick.beam, pick.w / total);
}

SunBeam SunConnection::smoothAlong(const Point3& p, const Normal3& ng, const Vec3& dir, int medium) const {
    // In a denser medium without objects: follow dir up, through periodic walls, to the interface
    // with the air above.
    SunBeam beam = none();
    const SunSource& sun = scene_.sun();
    const double nm = scene_.media()[static_cast<size_t>(medium)].n(group_.begin);
    SurfaceHit h;
    Spec atten;
    int near = -1;
    if (!traceToSky(p, ng, dir, medium, &h, &near, &atten)) return beam;
    if (scene_.bxdfFlags(h) & kGlossy) return beam;  // (only with roughAbove(medium), handled by along())
    const int farM = scene_.farMedium(h);
    const double nFar = scene_.media()[static_cast<size_t>(farM)].n(group_.begin);
    const Normal3 nf = h.front ? h.ng : -h.ng;  // facet normal on the medium side
    // The medium's own surface (without objects, the only interface above): refracted through the
    // facet hit (Snell, Eq. 4.1; Fresnel T_f).
    if (near != medium) return beam;
    const double cosW = std::abs(dot(dir, nf));
    Vec3 out;
    if (!refract(-dir, nf, nm / nFar, &out)) return beam;  // TIR at this facet
    out = normalize(out);
    const double cosA = std::abs(dot(out, nf));
    const double T = 1.0 - fresnelDielectric(cosW, nm, nFar);
    if (!sun.inDisc(out)) return beam;  // the facet sends it elsewhere
    Spec sky;
    if (!skyTransmittance(spawnRay(h.p, h.ng, out), farM, &sky)) return beam;
    // Radiance in the medium T (nm/nFar)^2 L_sun over a solid angle compressed by
    // (nFar/nm)^2 cos(theta_far)/cos(theta_medium) (etendue n^2 cos dOmega is conserved): beam
    // irradiance E_sun T cosA / cosW.
    const double geom = T * cosA / cosW;
    for (int i = 0; i < group_.count; ++i) beam.E[i] = sun.irradiance[group_.begin + i] * geom * atten[i] * sky[i];
    const double solidAngle = sun.solidAngle * sqr(nFar / nm) * cosA / cosW;
    beam.L = beam.E * (1.0 / solidAngle);
    beam.toSun = dir;
    beam.pdf = 1.0 / solidAngle;
    beam.valid = true;
    return beam;
}

SunBeam SunConnection::sample(const Point3& p, const Normal3& ng, const Vec3& facing, int medium,
                              RandomStream& rng) const {
    const SunSource& sun = scene_.sun();
    // Draw the numbers unconditionally so the random stream layout does not depend on geometry
    // (keeps neighbouring pixels' streams aligned).
    const double u1 = rng.uniform(), u2 = rng.uniform();
    const bool rough = roughAbove(medium);
    const FacetBeams* beams = beamsInto(medium);
    double v1 = 0, v2 = 0;
    if (rough) v1 = rng.uniform(), v2 = rng.uniform();
    if (!sun.enabled || !estimatesIn(medium)) return none();
    const Vec3 ws = sun.sampleDirection(u1, u2);  // uniform over the disc, pdf 1 / Omega_sun
    // Which of the beams that contain p: from u1's low 27 bits (the disc point uses its high bits),
    // so that the stream layout stays that of the flat-surface estimate (two numbers).
    if (beams) return beamSample(p, ng, facing, medium, ws, u1 * 0x1.0p26 - std::floor(u1 * 0x1.0p26));
    const bool checkFacing = facing.x != 0 || facing.y != 0 || facing.z != 0;
    if (rough) {
        // The transmission lobe of a horizontal rough surface lit from ws (light travels from ws
        // into the medium; RoughDielectricBxDF::sampleTransmission): dir points back up along it.
        const Frame& F = roughFrame_[static_cast<size_t>(medium)];
        const RoughDielectricBxDF& proto = *roughProto_[static_cast<size_t>(medium)];
        const Vec3 wsl = F.toLocal(ws);
        const auto wi = proto.sampleTransmission(wsl, Vec2{v1, v2});
        if (!wi) return none();
        const double pdf = proto.pdfTransmission(wsl, *wi);
        const Vec3 dir = normalize(-F.toWorld(*wi));
        if (checkFacing && dot(dir, facing) <= 0) return none();
        return roughAlong(p, ng, dir, medium, ws, pdf);
    }
    const double nm = scene_.media()[static_cast<size_t>(medium)].n(group_.begin);
    Vec3 dir = ws;
    if (!skyMedium(medium)) {
        // The direction in the medium that a horizontal interface refracts toward ws (Snell,
        // Eq. 4.1, air index 1); the facet actually hit decides (along()).
        Vec3 wt;
        if (!refract(ws, Vec3{0, 0, 1}, 1.0 / nm, &wt)) return none();
        dir = normalize(-wt);
    }
    if (checkFacing && dot(dir, facing) <= 0) return none();
    return along(p, ng, dir, medium, Vec2{u1, u2});
}

Spec SunConnection::atGlossyHit(const SurfaceHit& h, const Frame& frame, const BxDF& bxdf, const Vec3& wo,
                                const SunChain& chain, RandomStream& rng, int* neeSide) const {
    Spec L(group_.count);
    *neeSide = 0;
    const double u1 = rng.uniform(), u2 = rng.uniform();  // drawn always (stream layout)
    const SunSource& sun = scene_.sun();
    if (!sun.enabled || glossy_ == GlossySun::BsdfOnly) return L;
    // The side of the surface where the sun is reached by a straight shadow ray: the one whose
    // medium is a sky medium (index 1, nothing attenuates).
    const int out = scene_.outsideMedium(h.mesh), in = scene_.insideMedium(h.mesh);
    const int side = skyMedium(out) ? +1 : skyMedium(in) ? -1 : 0;
    if (side == 0) return L;
    // Would the event that connects wo to that side (reflection if wo is on it, else a rough
    // transmission) leave a chain whose disc counts? If not, an earlier vertex's estimate covers it.
    SunChain after = chain;
    after.record((wo.z > 0) != (side > 0), true, true, 1.0);  // a transmission toward the air side
    if (!after.countsSun()) return L;
    *neeSide = side;
    const Vec3 ws = sun.sampleDirection(u1, u2);
    const Vec3 wi = frame.toLocal(ws);
    if (wi.z * side <= 0) return L;  // the sun is below this face
    const double f = bxdf.f(wo, wi, TransportMode::Radiance);
    if (!(f > 0)) return L;
    const double pl = 1.0 / sun.solidAngle;
    double w = 1.0;
    if (glossy_ == GlossySun::Mis) {
        const double pb = bxdf.pdf(wo, wi, TransportMode::Radiance);
        w = pl * pl / (pl * pl + pb * pb);  // power heuristic
    }
    Spec sky;
    if (!skyTransmittance(spawnRay(h.p, h.ng, ws), side > 0 ? out : in, &sky)) return L;
    // f L_sun |cos| / pdf_light, pdf_light = 1 / Omega: f E_sun |cos theta_i|.
    const double g = w * f * std::abs(wi.z);
    for (int i = 0; i < group_.count; ++i) L[i] = sun.irradiance[group_.begin + i] * g * sky[i];
    return L;
}

SunChain SunConnection::chainAfterGlossy(const SunChain& chain, const BSDFSample& s, int neeSide, bool toSky,
                                         double legZ) const {
    if (neeSide != 0 && (s.wi.z > 0) == (neeSide > 0)) return SunChain::afterGlossy(s.pdf);
    SunChain c = chain;
    c.glossyPdf = 0;
    c.record(s.isTransmission(), true, toSky, legZ);
    return c;
}

std::optional<Vec3> SunConnection::refractedDirection(int medium) const {
    const SunSource& sun = scene_.sun();
    if (!sun.enabled) return std::nullopt;
    const double nm = scene_.media()[static_cast<size_t>(medium)].n(group_.begin);
    if (nm == 1.0) return sun.direction;
    Vec3 wt;
    if (!refract(sun.direction, Vec3{0, 0, 1}, 1.0 / nm, &wt)) return std::nullopt;
    return normalize(-wt);
}

Spec SunConnection::direct(const Point3& p, const Normal3& n, int medium, bool scalar, RandomStream& rng) const {
    const FacetBeams* fb = beamsInto(medium);
    if (fb && estimatesIn(medium)) {
        // Every beam that contains p, summed (not one picked): the probe's direct sun is then free
        // of noise but for the disc direction. The numbers sample() would draw, in its order.
        const double u1 = rng.uniform(), u2 = rng.uniform();
        Spec E(group_.count);
        if (!scene_.sun().enabled) return E;
        const Vec3 ws = scene_.sun().sampleDirection(u1, u2);
        fb->forEachContaining(p, ws, [&](int f, const Vec3& d, double) {
            const SunBeam b = beamAlong(p, Normal3{0, 0, 0}, -d, medium, f, 1.0);
            const double c = b.valid ? dot(b.toSun, n) : 0.0;
            if (c > 0) E += b.E * (scalar ? 1.0 : c);
        });
        return E;
    }
    // A probe is a point inside a medium, not on a surface: its rays start exactly at p.
    const SunBeam b = sample(p, Normal3{0, 0, 0}, n, medium, rng);
    if (!b.valid) return Spec(group_.count);
    const double c = dot(b.toSun, n);
    if (c <= 0) return Spec(group_.count);
    return b.E * (scalar ? 1.0 : c);
}

}  // namespace littoral::render
