#include "render/estimator.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <set>
#include <type_traits>

#include <fmt/format.h>

#include "core/error.h"
#include "core/log.h"
#include "core/probe_quantities.h"
#include "core/render_budget.h"
#include "core/resource_limits.h"
#include "core/suggest.h"
#include "core/units.h"
#include "render/photon_pass.h"
#include "render/probes.h"
#include "render/sampling.h"

#include <unistd.h>

namespace littoral::render {

std::unique_ptr<Estimator> makeDirsigEstimator(const Scene&, const RenderConfig&, BandGroup, const PhotonMaps*, int);
std::unique_ptr<Estimator> makePathEstimator(const Scene&, const RenderConfig&, BandGroup);

// ---------------------------------------------------------------------------------------------
// Render settings: the ones the shared logic below reads (each estimator's descriptor composes
// them), the registration list, and makeRenderConfig.

ParamSpec maxBouncesSetting(double defaultValue) {
    return {"max_bounces", "", ParamType::Integer, defaultValue, 0, 100000, "", "scattering and diffuse vertices per path"};
}
ParamSpec maxSpecularDepthSetting(double defaultValue) {
    return {"max_specular_depth", "", ParamType::Integer, defaultValue, 0, 100000, "", "specular interface events per path"};
}
ParamSpec probeSamplesSetting() {
    return {"probe_samples", "", ParamType::Integer, 4096, 2, 1 << 30, "", "sample paths per probe quantity"};
}
ParamSpec probeBatchesSetting() {
    return {"probe_batches", "", ParamType::Integer, 16, 2, 4096, "", "independent batches for the probes' standard errors"};
}
// Up to 100 m: a longer step would take one in-scatter estimate over more water than any scene
// holds (the range scene files have always had; scene.json allowed 1e4 until both read this one).
ParamSpec marchStepSetting() {
    return {"march_step_m", "", ParamType::Real, 0.1, 1e-4, 100, "m",
            "step of the in-scatter (sun and photon-map) estimates along rays in water"};
}

// The estimators' descriptors, and the probe quantities they evaluate (render/probes.cpp).
void registerEstimatorKinds() {
    static std::once_flag once;
    std::call_once(once, [] {
        KindRegistry<KindInfo>& r = estimatorKindsForRegistration();
        r.add(dirsigEstimatorKind());
        r.add(pathEstimatorKind());
        for (const std::string& name : allNames<ir::Estimator>())
            if (!r.find(name)) throw InternalError("estimator '" + name + "' has no descriptor");
        registerProbeQuantityKinds(probeQuantityKindsForRegistration());
    });
}

namespace {

// Reads the optional render settings the chosen estimator declares, with their defaults and
// ranges, remembering which were read.
class SettingsReader {
public:
    SettingsReader(const ir::RenderSettings& s, const KindInfo& estimator) : s_(s), estimator_(estimator) {}

    template <class T> T get(std::string_view key) {
        const ParamSpec* spec = estimator_.param(key);
        if (!spec) throw InternalError(fmt::format("the {} estimator reads '{}' without declaring it", estimator_.name, key));
        read_.insert(std::string(key));
        const ParamValue* v = s_.settings.find(key);
        if (!v && !spec->defaultValue) throw InternalError(fmt::format("render setting '{}' has no default", key));
        const ParamValue value = v ? *v : spec->defaultParamValue();
        if (v) check(*spec, value);
        if constexpr (std::is_same_v<T, bool>) return std::get<bool>(value);
        else if constexpr (std::is_floating_point_v<T>) return numberOf(value);
        else return static_cast<T>(std::get<int64_t>(value));
    }
    bool isSet(std::string_view key) const { return s_.settings.has(key); }

    // Every setting that is set must be one some estimator declares (else unknown, with a did you
    // mean) and must have been read.
    void finish(const std::string& hint) const {
        const std::vector<const ParamSpec*> all = allRenderSettings();
        std::vector<std::string> names, readable;
        for (const ParamSpec* p : all) names.push_back(p->name);
        for (const auto& [key, value] : s_.settings)
            if (std::find(names.begin(), names.end(), key) == names.end()) {
                std::string m = fmt::format("unknown setting (allowed: {})", joinList(names));
                const std::string near = closestMatch(key, names);
                if (!near.empty()) m += fmt::format("; did you mean '{}'?", near);
                fail(key, m);
            }
        for (const ParamSpec* p : all)
            if (read_.count(p->name)) readable.push_back(p->sceneName());
        for (const ParamSpec* p : all)
            if (s_.settings.has(p->name) && !read_.count(p->name))
                fail(p->name, fmt::format("is set, but the '{}' estimator does not read it{} (it reads: {})", estimator_.name,
                                          hint.empty() ? "" : "; " + hint, joinList(readable)));
    }

    // InputError at the scene-file location of the setting when known, else naming scene.json's key.
    [[noreturn]] void fail(std::string_view irKey, const std::string& msg) const {
        for (const ParamSpec* p : allRenderSettings()) {
            if (p->name != irKey) continue;
            const auto it = s_.locations.find(p->sceneName());
            if (it != s_.locations.end()) throw InputError(it->second, fmt::format("render.{}: {}", p->sceneName(), msg));
        }
        throw InputError(fmt::format("render.{}: {}", irKey, msg));
    }

private:
    void check(const ParamSpec& spec, const ParamValue& v) const {
        const bool typeOk = spec.type == ParamType::Boolean  ? std::holds_alternative<bool>(v)
                            : spec.type == ParamType::Integer ? std::holds_alternative<int64_t>(v)
                                                              : !std::holds_alternative<bool>(v);
        if (!typeOk)
            fail(spec.name, fmt::format("expected {}, found {}",
                                        spec.type == ParamType::Boolean   ? "true or false"
                                        : spec.type == ParamType::Integer ? "an integer"
                                                                          : "a number",
                                        formatValue(v)));
        if (!spec.inRange(numberOf(v)))
            fail(spec.name, fmt::format("{} is out of range; allowed {}", formatValue(v), spec.rangeText()));
    }

    const ir::RenderSettings& s_;
    const KindInfo& estimator_;
    std::set<std::string> read_;
};

[[noreturn]] void materialError(const ir::Material& m, size_t i, const std::string& msg) {
    if (!m.origin.file.empty()) throw InputError(m.origin, fmt::format("material '{}': {}", m.name, msg));
    throw InputError(fmt::format("materials[{}] '{}': {}", i, m.name, msg));
}

[[noreturn]] void mediumError(const ir::Medium& m, size_t i, const std::string& msg) {
    if (!m.origin.file.empty()) throw InputError(m.origin, fmt::format("medium '{}': {}", m.name, msg));
    throw InputError(fmt::format("media[{}] '{}': {}", i, m.name, msg));
}

// The progressive passes, and the maps of the largest band group against the memory budget (the
// same estimate check-scene uses, core/render_budget.h).
void readPhotonPasses(const ir::RenderSettings& s, SettingsReader& r, RenderConfig* c) {
    c->photonMaxBounces = r.get<int>("photon_max_bounces");
    c->passes = r.get<int>("progressive_passes");
    c->alpha = r.get<double>("progressive_alpha");
    static_assert(kMaxGroupBands == kPhotonGroupBandsMax);
    const double sb = photonBytesEach(true, s.bands.size()), vb = photonBytesEach(false, s.bands.size());
    const double need = static_cast<double>(c->surfacePhotons) * sb + static_cast<double>(c->volumePhotons) * vb;
    const double budget = static_cast<double>(memoryBudget());
    if (need > budget)
        r.fail(static_cast<double>(c->volumePhotons) * vb > static_cast<double>(c->surfacePhotons) * sb ? "volume_photons"
                                                                                                     : "surface_photons",
               fmt::format("{} surface and {} volume photons need {} ({:.0f} and {:.0f} bytes each with the search grid "
                           "and its build buffers), more than the memory budget of {} (--max-memory)",
                           c->surfacePhotons, c->volumePhotons, formatBytes(need), sb, vb, formatBytes(budget)));
}

// The photon maps: read only when some material or medium uses a photon-map solver. Returns the
// hint for settings set but not read.
std::string readDirsigPhotonSettings(const ir::SceneIR& ir, SettingsReader& r, RenderConfig* c) {
    int surfacePM = -1, mediumPM = -1;
    for (size_t i = 0; i < ir.materials.size(); ++i)
        if (ir.materials[i].solver == ir::Material::Solver::SurfacePM && surfacePM < 0) surfacePM = static_cast<int>(i);
    for (size_t i = 0; i < ir.media.size(); ++i) {
        c->mediumPM.push_back(ir.media[i].solver == ir::Medium::Solver::MediumPM);
        if (c->mediumPM.back() && mediumPM < 0) mediumPM = static_cast<int>(i);
    }
    if (surfacePM >= 0) {
        if (!r.isSet("surface_photons"))
            materialError(ir.materials[surfacePM], static_cast<size_t>(surfacePM),
                          "the surface-pm solver needs the surface photon map: set render.photons.surface");
        c->surfacePhotons = r.get<uint64_t>("surface_photons");
        c->surfaceRadius = r.get<double>("surface_search_radius_m");
    }
    if (mediumPM >= 0) {
        if (!r.isSet("volume_photons"))
            mediumError(ir.media[mediumPM], static_cast<size_t>(mediumPM),
                        "the medium-pm solver needs the volume photon map: set render.photons.volume");
        c->volumePhotons = r.get<uint64_t>("volume_photons");
        c->volumeRadius = r.get<double>("volume_search_radius_m");
        c->marchStep = r.get<double>("march_step_m");
        c->effectiveScattering = r.get<bool>("effective_scattering");
    }
    if (c->usesPhotons()) readPhotonPasses(ir.render, r, c);
    return surfacePM < 0 && mediumPM < 0 ? "photon maps (photons, search_radius_m, march_step_m, progressive) are read "
                                           "only when a material uses solver surface-pm or the water uses solver medium-pm"
                                         : "";
}

// The dirsig solver of each material: the one it names, or the default for its type.
void readDirsigSolvers(const ir::SceneIR& ir, RenderConfig* c) {
    using S = ir::Material::Solver;
    using T = ir::Material::Type;
    for (size_t i = 0; i < ir.materials.size(); ++i) {
        const ir::Material& m = ir.materials[i];
        const bool diffuse = m.type == T::Lambertian || m.type == T::Textured;
        const bool interface = m.type == T::Dielectric || m.type == T::RoughDielectric;
        S solver = interface ? S::Fresnel : S::Classic;
        if (m.solver) {
            solver = *m.solver;
            if (!diffuse && !interface)
                materialError(m, i, fmt::format("a {} material has no radiometry solver; remove solver '{}'",
                                                nameOf(m.type), nameOf(solver)));
            if (diffuse && solver == S::Fresnel)
                materialError(m, i, "solver fresnel cannot evaluate a diffuse material (use classic, generic or surface-pm)");
            if (interface && solver != S::Fresnel && solver != S::Generic)
                materialError(m, i, fmt::format("an interface needs the fresnel (or generic) solver, not {}", nameOf(solver)));
        }
        c->solvers.push_back(solver);
    }
}

void readDirsigSettings(const ir::SceneIR& ir, SettingsReader& r, RenderConfig* c) {
    c->maxBounces = r.get<int>("max_bounces");
    c->maxSpecularDepth = r.get<int>("max_specular_depth");
    c->hemisphereSamples = r.get<int>("hemisphere_samples");
    r.finish(readDirsigPhotonSettings(ir, r, c));
    readDirsigSolvers(ir, c);
}

void readPathSettings(const ir::SceneIR& ir, SettingsReader& r, RenderConfig* c) {
    c->maxBounces = r.get<int>("max_bounces");
    c->maxSpecularDepth = r.get<int>("max_specular_depth");
    c->marchStep = r.get<double>("march_step_m");
    r.finish("");
    for (size_t i = 0; i < ir.materials.size(); ++i) {
        const ir::Material& m = ir.materials[i];
        if (m.solver)
            materialError(m, i, fmt::format("the path estimator does not use per-material solvers; remove solver '{}' or "
                                            "choose estimator: dirsig",
                                            nameOf(*m.solver)));
        c->solvers.push_back(ir::Material::Solver::Generic);
    }
    for (size_t i = 0; i < ir.media.size(); ++i) {
        if (ir.media[i].solver)
            mediumError(ir.media[i], i, fmt::format("the path estimator does not use medium solvers; remove solver '{}' or "
                                                    "choose estimator: dirsig",
                                                    nameOf(*ir.media[i].solver)));
        c->mediumPM.push_back(false);
    }
}

}  // namespace

RenderConfig makeRenderConfig(const ir::SceneIR& ir) {
    registerEstimatorKinds();
    const ir::RenderSettings& s = ir.render;
    RenderConfig c;
    c.estimator = s.estimator;
    SettingsReader r(s, estimatorKinds().get(nameOf(s.estimator), "render.estimator"));
    c.probeSamples = r.get<int>("probe_samples");
    c.probeBatches = r.get<int>("probe_batches");
    if (c.probeBatches > c.probeSamples)
        r.fail("probe_batches", fmt::format("{} batches cannot be formed from {} probe samples", c.probeBatches,
                                            c.probeSamples));
    switch (s.estimator) {
        case ir::Estimator::Dirsig: readDirsigSettings(ir, r, &c); break;
        case ir::Estimator::Path: readPathSettings(ir, r, &c); break;
    }
    return c;
}

std::vector<BandGroup> bandGroups(const Scene& scene) {
    std::vector<BandGroup> groups;
    const int nb = scene.bandCount();
    auto sameIndex = [&](int a, int b) {
        for (const Medium& m : scene.media())
            if (m.n(a) != m.n(b)) return false;
        return true;
    };
    int b = 0;
    while (b < nb) {
        BandGroup g{b, 1};
        while (b + g.count < nb && g.count < kMaxGroupBands && sameIndex(b, b + g.count)) ++g.count;
        groups.push_back(g);
        b += g.count;
    }
    return groups;
}

Estimator::Estimator(const Scene& scene, const RenderConfig& config, BandGroup group)
    : scene_(scene), config_(config), group_(group) {
    LITTORAL_CHECK(group.count >= 1 && group.count <= kMaxGroupBands);
    LITTORAL_CHECK(group.begin >= 0 && group.begin + group.count <= scene.bandCount());
    skyRadiance_ = bandValues(scene.sky().radiance);
    LITTORAL_CHECK_EQ(config.solvers.size(), scene.materials().size());
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
            if (k < 0 || !scene.materials()[static_cast<size_t>(k)].isRough()) continue;
            roughSunMaterial_[static_cast<size_t>(in)] = k;
            roughProto_[static_cast<size_t>(in)] =
                scene.roughBxdf(k, outside.n(group.begin), scene.media()[static_cast<size_t>(in)].n(group.begin));
            roughFrame_[static_cast<size_t>(in)] =
                Frame::fromNormalAndTangent(Vec3{0, 0, 1}, scene.materials()[static_cast<size_t>(k)].downwind);
            break;
        }
    }
}

std::unique_ptr<Estimator> Estimator::create(const Scene& scene, const RenderConfig& config, BandGroup group,
                                             const PhotonMaps* maps, int pass) {
    switch (config.estimator) {
        case ir::Estimator::Dirsig: return makeDirsigEstimator(scene, config, group, maps, pass);
        case ir::Estimator::Path: return makePathEstimator(scene, config, group);
    }
    throw InternalError("unknown estimator");
}

EstimatorSet::EstimatorSet(const Scene& scene, int pass, int threads, bool progress)
    : config_(makeRenderConfig(scene.ir())), groups_(bandGroups(scene)), pass_(pass) {
    for (const BandGroup& g : groups_) {
        const PhotonMaps* maps = nullptr;
        if (config_.usesPhotons()) {
            PhotonPassSettings ps;
            ps.surfaceTarget = config_.surfacePhotons;
            ps.volumeTarget = config_.volumePhotons;
            ps.maxBounces = config_.photonMaxBounces;
            ps.effectiveScattering = config_.effectiveScattering;
            ps.seed = scene.ir().render.seed;
            ps.pass = static_cast<uint64_t>(pass) * 64 + static_cast<uint64_t>(g.begin);
            ps.cellSize = std::max(config_.radiusAt(config_.surfaceRadius, pass), config_.radiusAt(config_.volumeRadius, pass));
            ps.threads = threads;
            ps.progress = progress;
            ps.volumeMedium.assign(scene.media().size(), false);
            for (size_t m = 0; m < config_.mediumPM.size(); ++m) ps.volumeMedium[m + 1] = config_.mediumPM[m];
            for (size_t m = 0; m < config_.solvers.size(); ++m)
                ps.surfaceMaterial.push_back(config_.solvers[m] == ir::Material::Solver::SurfacePM);
            maps_.push_back(std::make_unique<PhotonMaps>(tracePhotons(scene, g, ps)));
            maps = maps_.back().get();
        }
        estimators_.push_back(Estimator::create(scene, config_, g, maps, pass));
    }
}

EstimatorSet::~EstimatorSet() = default;

Spec Estimator::bandValues(const std::vector<double>& v) const {
    Spec s(group_.count);
    for (int i = 0; i < group_.count; ++i) s[i] = v[group_.begin + i];
    return s;
}

Spec Estimator::environment(const Vec3& d, bool withSun) const {
    Spec L = d.z > 0 ? skyRadiance_ : Spec(group_.count);
    const SunSource& sun = scene_.sun();
    if (withSun && sun.inDisc(d)) {
        // Uniform disc radiance L_sun = E_sun / Omega_sun (exact cone solid angle).
        for (int i = 0; i < group_.count; ++i) L[i] += sun.irradiance[group_.begin + i] / sun.solidAngle;
    }
    return L;
}

double Estimator::misSunWeight(double bsdfPdf) const {
    switch (config_.glossySun) {
        case RenderConfig::GlossySun::NeeOnly: return 0.0;
        case RenderConfig::GlossySun::BsdfOnly: return 1.0;  // (no estimate was made: glossyPdf is never set)
        case RenderConfig::GlossySun::Mis: break;
    }
    // Power heuristic (Veach 1997, eq. 9.13, beta = 2) against the disc's uniform density 1/Omega.
    const double pl = 1.0 / scene_.sun().solidAngle;
    return bsdfPdf * bsdfPdf / (bsdfPdf * bsdfPdf + pl * pl);
}

Spec Estimator::environment(const Vec3& d, const SunChain& chain) const {
    Spec L = environment(d, false);
    const SunSource& sun = scene_.sun();
    if (!chain.countsSun() || !sun.inDisc(d)) return L;
    const double w = chain.glossyPdf > 0 ? misSunWeight(chain.glossyPdf) : 1.0;
    if (w <= 0) return L;
    for (int i = 0; i < group_.count; ++i) L[i] += w * sun.irradiance[group_.begin + i] / sun.solidAngle;
    return L;
}

SunChain Estimator::chainAfterVertex(int medium) const { return SunChain::afterVertex(roughSun(medium)); }

bool Estimator::skyMedium(int m) const {
    const Medium& md = scene_.media()[static_cast<size_t>(m)];
    return md.n(group_.begin) == 1.0 && !md.attenuating();
}

namespace {
// Fresnel transmittance of a crossing that keeps the direction (the straight-path model of
// dielectric objects, docs/rendering.md): the path's direction is taken as the one on the side of
// the lower index, so the crossing never reflects totally; 1 between equal indices.
double straightCrossing(double cosAngle, double n1, double n2) {
    if (n1 == n2) return 1.0;
    return 1.0 - fresnelDielectric(std::abs(cosAngle), std::min(n1, n2), std::max(n1, n2));
}
constexpr int kMaxStraightCrossings = 64;
}  // namespace

bool Estimator::skyTransmittance(const Ray& ray, int medium, Spec* T) const {
    *T = Spec(group_.count, 1.0);
    if (!scene_.geometry().occluded(ray)) return true;  // the common case: nothing in the way
    Ray r = ray;
    int m = medium;
    for (int k = 0, wraps = 0; k < kMaxStraightCrossings;) {
        SurfaceHit h;
        const Medium& md = scene_.media()[static_cast<size_t>(m)];
        if (!scene_.geometry().intersect(r, &h)) return !md.attenuating();
        if (md.attenuating()) *T *= md.transmittance(r, h.t, group_, effectiveExtinction(m));
        const MaterialData& mat = scene_.material(h);
        if (mat.isPeriodicWall()) {
            const auto next = scene_.wrapRay(h, r.d);
            if (!next || ++wraps > Scene::kMaxWraps) return false;
            r = *next;
            continue;
        }
        // Opaque surfaces block the sun; so do rough interfaces (light through them is sampled).
        if (!mat.isInterface() || mat.isRough()) return false;
        const int far = scene_.farMedium(h);
        *T *= straightCrossing(dot(r.d, h.ng), scene_.media()[static_cast<size_t>(scene_.nearMedium(h))].n(group_.begin),
                               scene_.media()[static_cast<size_t>(far)].n(group_.begin));
        m = far;
        r = spawnRay(h.p, h.ng, r.d);
        ++k;
    }
    return false;
}

bool Estimator::traceToSky(const Point3& p, const Normal3& ng, const Vec3& dir, int medium, SurfaceHit* h,
                           int* near, Spec* atten) const {
    *atten = Spec(group_.count, 1.0);
    Ray r = spawnRay(p, ng, dir);
    int m = medium;
    for (int k = 0, wraps = 0; k < kMaxStraightCrossings;) {
        const Medium& md = scene_.media()[static_cast<size_t>(m)];
        if (!scene_.geometry().intersect(r, h)) return false;
        *atten *= md.transmittance(r, h->t, group_, effectiveExtinction(m));
        const MaterialData& mat = scene_.material(*h);
        if (mat.isPeriodicWall()) {
            const auto next = scene_.wrapRay(*h, dir);
            if (!next || ++wraps > Scene::kMaxWraps) return false;
            r = *next;
            continue;
        }
        if (!mat.isInterface()) return false;
        if (scene_.nearMedium(*h) != m) return false;
        const int far = scene_.farMedium(*h);
        if (skyMedium(far)) {
            *near = m;
            return true;
        }
        // An interface between two dense media (water and a dielectric object): crossed straight.
        if (mat.isRough()) return false;
        *atten *= straightCrossing(dot(dir, h->ng), md.n(group_.begin), scene_.media()[static_cast<size_t>(far)].n(group_.begin));
        m = far;
        r = spawnRay(h->p, h->ng, dir);
        ++k;
    }
    return false;
}

Estimator::SunBeam Estimator::roughSunAlong(const Point3& p, const Normal3& ng, const Vec3& dir, int medium,
                                            const Vec3& ws, double pdf) const {
    SunBeam beam;
    beam.E = beam.L = Spec(group_.count);
    SurfaceHit h;
    Spec atten;
    int near = -1;
    if (!traceToSky(p, ng, dir, medium, &h, &near, &atten)) return beam;
    // A smooth facet refracts the disc into a set of measure zero; only the medium's own rough
    // surface sends this light.
    if (!scene_.material(h).isRough() || near != medium) return beam;
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

Estimator::SunBeam Estimator::sunAlong(const Point3& p, const Normal3& ng, const Vec3& dir, int medium,
                                       const Vec2& uDisc) const {
    SunBeam beam;
    beam.E = beam.L = Spec(group_.count);
    const SunSource& sun = scene_.sun();
    if (!sun.enabled) return beam;
    const Medium& md = scene_.media()[medium];
    const double nm = md.n(group_.begin);
    if (nm == 1.0 && !md.attenuating()) {
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
    if (roughSun(medium)) {
        // The disc point uDisc, and the density with which sunBeam would have chosen dir for it.
        const Vec3 ws = sun.sampleDirection(uDisc.x, uDisc.y);
        const Frame& F = roughFrame_[static_cast<size_t>(medium)];
        const double pdf = roughProto_[static_cast<size_t>(medium)]->pdfTransmission(F.toLocal(ws), F.toLocal(-dir));
        return roughSunAlong(p, ng, dir, medium, ws, pdf);
    }
    // In a denser medium: follow dir up, through periodic walls and straight through dielectric
    // objects, to the interface with the air above.
    SurfaceHit h;
    Spec atten;
    int near = -1;
    if (!traceToSky(p, ng, dir, medium, &h, &near, &atten)) return beam;
    if (scene_.material(h).isRough()) return beam;  // (only with roughSun(medium), handled above)
    const int farM = scene_.farMedium(h);
    const double nFar = scene_.media()[static_cast<size_t>(farM)].n(group_.begin);
    const Normal3 nf = h.front ? h.ng : -h.ng;  // facet normal on the medium side
    Vec3 out;
    double T, cosA, cosW;
    if (near == medium) {
        // The medium's own surface: refracted through the facet hit (Snell, Eq. 4.1; Fresnel T_f).
        cosW = std::abs(dot(dir, nf));
        if (!refract(-dir, nf, nm / nFar, &out)) return beam;  // TIR at this facet
        out = normalize(out);
        cosA = std::abs(dot(out, nf));
        T = 1.0 - fresnelDielectric(cosW, nm, nFar);
    } else {
        // Leaving a dielectric object into the air (a floating object): the object bends nothing
        // (straight-path model), and the water surface it displaced is taken as horizontal here.
        // The face transmits what light from the air direction `out` would enter it with.
        if (!(dir.z > 0) || !refract(-dir, Vec3{0, 0, -1}, nm / nFar, &out)) return beam;
        out = normalize(out);
        cosW = dir.z;
        cosA = out.z;
        T = 1.0 - fresnelDielectric(std::abs(dot(out, nf)), nFar,
                                    scene_.media()[static_cast<size_t>(near)].n(group_.begin));
    }
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

Estimator::SunBeam Estimator::sunBeam(const Point3& p, const Normal3& ng, const Vec3& facing, int medium,
                                      RandomStream& rng) const {
    SunBeam none;
    none.E = none.L = Spec(group_.count);
    const SunSource& sun = scene_.sun();
    // Draw the numbers unconditionally so the random stream layout does not depend on geometry
    // (keeps neighbouring pixels' streams aligned).
    const double u1 = rng.uniform(), u2 = rng.uniform();
    const bool rough = roughSun(medium);
    double v1 = 0, v2 = 0;
    if (rough) v1 = rng.uniform(), v2 = rng.uniform();
    if (!sun.enabled) return none;
    const Vec3 ws = sun.sampleDirection(u1, u2);  // uniform over the disc, pdf 1 / Omega_sun
    const bool checkFacing = facing.x != 0 || facing.y != 0 || facing.z != 0;
    if (rough) {
        // The transmission lobe of a horizontal rough surface lit from ws (light travels from ws
        // into the medium; RoughDielectricBxDF::sampleTransmission): dir points back up along it.
        const Frame& F = roughFrame_[static_cast<size_t>(medium)];
        const RoughDielectricBxDF& proto = *roughProto_[static_cast<size_t>(medium)];
        const Vec3 wsl = F.toLocal(ws);
        const auto wi = proto.sampleTransmission(wsl, Vec2{v1, v2});
        if (!wi) return none;
        const double pdf = proto.pdfTransmission(wsl, *wi);
        const Vec3 dir = normalize(-F.toWorld(*wi));
        if (checkFacing && dot(dir, facing) <= 0) return none;
        return roughSunAlong(p, ng, dir, medium, ws, pdf);
    }
    const double nm = scene_.media()[medium].n(group_.begin);
    Vec3 dir = ws;
    if (nm != 1.0 || scene_.media()[medium].attenuating()) {
        // The direction in the medium that a horizontal interface refracts toward ws (Snell,
        // Eq. 4.1, air index 1); the facet actually hit decides (sunAlong).
        Vec3 wt;
        if (!refract(ws, Vec3{0, 0, 1}, 1.0 / nm, &wt)) return none;
        dir = normalize(-wt);
    }
    if (checkFacing && dot(dir, facing) <= 0) return none;
    return sunAlong(p, ng, dir, medium, Vec2{u1, u2});
}

Spec Estimator::glossySun(const SurfaceHit& h, const Frame& frame, const BxDF& bxdf, const Vec3& wo,
                          const SunChain& chain, RandomStream& rng, int* neeSide) const {
    Spec L(group_.count);
    *neeSide = 0;
    const double u1 = rng.uniform(), u2 = rng.uniform();  // drawn always (stream layout)
    const SunSource& sun = scene_.sun();
    if (!sun.enabled || config_.glossySun == RenderConfig::GlossySun::BsdfOnly) return L;
    // The side of the surface where the sun is reached by a straight shadow ray: the one whose
    // medium is a sky medium (index 1, nothing attenuates).
    const int out = scene_.outsideMedium(h.mesh), in = scene_.insideMedium(h.mesh);
    const int side = skyMedium(out) ? +1 : skyMedium(in) ? -1 : 0;
    if (side == 0) return L;
    // Would the event that connects wo to that side (reflection if wo is on it, else a rough
    // transmission) leave a chain whose disc counts? If not, an earlier vertex's estimate covers it.
    SunChain after = chain;
    if ((wo.z > 0) == (side > 0)) after.reflected = true;
    else ++after.roughTransmissions;
    if (!after.countsSun()) return L;
    *neeSide = side;
    const Vec3 ws = sun.sampleDirection(u1, u2);
    const Vec3 wi = frame.toLocal(ws);
    if (wi.z * side <= 0) return L;  // the sun is below this face
    const double f = bxdf.f(wo, wi, TransportMode::Radiance);
    if (!(f > 0)) return L;
    const double pl = 1.0 / sun.solidAngle;
    const double w = config_.glossySun == RenderConfig::GlossySun::NeeOnly
                         ? 1.0
                         : [&] {
                               const double pb = bxdf.pdf(wo, wi, TransportMode::Radiance);
                               return pl * pl / (pl * pl + pb * pb);  // power heuristic
                           }();
    Spec sky;
    if (!skyTransmittance(spawnRay(h.p, h.ng, ws), side > 0 ? out : in, &sky)) return L;
    // f L_sun |cos| / pdf_light, pdf_light = 1 / Omega: f E_sun |cos theta_i|.
    const double g = w * f * std::abs(wi.z);
    for (int i = 0; i < group_.count; ++i) L[i] = sun.irradiance[group_.begin + i] * g * sky[i];
    return L;
}

SunChain Estimator::chainAfterGlossy(const SunChain& chain, const BSDFSample& s, int neeSide) const {
    if (neeSide != 0 && (s.wi.z > 0) == (neeSide > 0)) return SunChain::afterGlossy(s.pdf);
    SunChain c = chain;
    c.glossyPdf = 0;
    if (s.isTransmission()) ++c.roughTransmissions;
    else c.reflected = true;
    return c;
}

std::optional<Vec3> Estimator::refractedSunDirection(int medium) const {
    const SunSource& sun = scene_.sun();
    if (!sun.enabled) return std::nullopt;
    const double nm = scene_.media()[medium].n(group_.begin);
    if (nm == 1.0) return sun.direction;
    Vec3 wt;
    if (!refract(sun.direction, Vec3{0, 0, 1}, 1.0 / nm, &wt)) return std::nullopt;
    return normalize(-wt);
}

Spec Estimator::directSun(const Point3& p, const Normal3& n, int medium, bool scalar, RandomStream& rng) const {
    // A probe is a point inside a medium, not on a surface: its rays start exactly at p.
    const SunBeam b = sunBeam(p, Normal3{0, 0, 0}, n, medium, rng);
    if (!b.valid) return Spec(group_.count);
    const double c = dot(b.toSun, n);
    if (c <= 0) return Spec(group_.count);
    return b.E * (scalar ? 1.0 : c);
}

}  // namespace littoral::render
