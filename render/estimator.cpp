#include "render/estimator.h"
#include "render/forward_tally.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <set>
#include <type_traits>

#include <fmt/format.h>

#include "core/error.h"
#include "core/log.h"
#include "core/material_kinds.h"
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
// The path estimator's forward irradiance tallies (render/forward_tally.h).
ParamSpec probePhotonsSetting() {
    return {"probe_photons", "", ParamType::Integer, 1e6, 0, 1e12, "",
            "photons traced from the sun and sky for the forward tallies of Ed, Eu, Eod, Eou and Lu at probes in "
            "scattering water of a horizontally invariant scene, where a pilot chooses forward or backward per "
            "quantity (docs/rendering.md); 0 = backward paths only"};
}
// Up to 100 m: a longer step would take one in-scatter estimate over more water than any scene
// holds (the range scene files have always had; scene.json allowed 1e4 until both read this one).
ParamSpec marchStepSetting() {
    return {"march_step_m", "", ParamType::Real, 0.1, 1e-4, 100, "m",
            "step of the in-scatter (sun and photon-map) estimates along rays in water"};
}

// Per-pixel convergence (render/renderer.cpp): 0 = every pixel takes samples_per_pixel.
ParamSpec targetRelativeErrorSetting() {
    return {"target_relative_error", "", ParamType::Real, 0, 0, 1, "",
            "per-pixel target relative standard error: a pilot of samples_per_pixel decides each pixel's "
            "samples, up to max_samples_per_pixel; 0 = off"};
}
ParamSpec maxSamplesPerPixelSetting() {
    return {"max_samples_per_pixel", "", ParamType::Integer, 1024, 4, 1 << 20, "",
            "the most samples a pixel takes under target_relative_error"};
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

// The dirsig estimator's default gather step along rays through a medium-pm medium, in volume
// search radii (march_step_m unset).
constexpr double kGatherStepRadii = 20;

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
    // Photon paths: render.max_specular_depth when it is set (the estimator read it already), else 1000.
    c->photonMaxSpecularDepth = r.isSet("max_specular_depth") ? c->maxSpecularDepth : 1000;
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

// A search radius must fit in the scene: a disc wider than the domain's smaller side reaches past
// every surface (or water) it averages, and the boundary compensation, which measures the covered
// share of the disc, cannot resolve a share far below 1/4 (the share at a corner of a surface that
// spans the domain when r equals the smaller side): the estimate would fall as 1/r^2.
void checkRadiusFitsDomain(const ir::SceneIR& ir, SettingsReader& r, const char* key, double radius) {
    const ir::Domain& d = ir.domain;
    const double side = std::min(d.x1 - d.x0, d.y1 - d.y0);
    if (radius <= side) return;
    r.fail(key, fmt::format("{}{:g} m is wider than the scene: a search radius may be at most the domain's smaller side, "
                            "{:g} m (domain x [{:g}, {:g}], y [{:g}, {:g}] m), or the search disc reaches past the "
                            "surfaces it averages and the estimate falls as 1/r^2",
                            r.isSet(key) ? "" : "the default ", radius, side, d.x0, d.x1, d.y0, d.y1));
}

// Whether some layer of `m` scatters in some band.
bool scatters(const ir::Medium& m, const std::vector<Band>& bands) {
    for (const ir::Layer& l : m.layers)
        for (const ir::Scatterer& sc : l.scatterers)
            for (double b : sc.scattering.bandAverages(bands, "scattering of medium '" + m.name + "'"))
                if (b > 0) return true;
    return false;
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
        if (!ir.media[i].solver && scatters(ir.media[i], ir.render.bands))
            log::warn("medium '{}' scatters but names no solver: the dirsig estimator counts its scattering as loss "
                      "(Beer-Lambert with c = a + b) and renders none of its in-scattered light; give it solver "
                      "medium-pm (the volume photon map), or solver attenuation to keep the loss deliberately",
                      ir.media[i].name);
    }
    if (surfacePM >= 0) {
        if (!r.isSet("surface_photons"))
            materialError(ir.materials[surfacePM], static_cast<size_t>(surfacePM),
                          "the surface-pm solver needs the surface photon map: set render.photons.surface");
        c->surfacePhotons = r.get<uint64_t>("surface_photons");
        c->surfaceRadius = r.get<double>("surface_search_radius_m");
        checkRadiusFitsDomain(ir, r, "surface_search_radius_m", c->surfaceRadius);
    }
    if (mediumPM >= 0) {
        c->volumePhotons = r.get<uint64_t>("volume_photons");
        c->volumeRadius = r.get<double>("volume_search_radius_m");
        checkRadiusFitsDomain(ir, r, "volume_search_radius_m", c->volumeRadius);
        // Each gather step is one grid query, whose cells reach r plus half a cell diagonal beyond
        // the step at either end: a step of 20 radii keeps those ends to a few per cent of the
        // photons tested (a step of 4 radii tested 5.2 photons per one within r, 20 radii 3.9:
        // docs/performance.md).
        c->marchStep = r.isSet("march_step_m") ? r.get<double>("march_step_m")
                                               : std::clamp(kGatherStepRadii * c->volumeRadius, 1e-4, 100.0);
        c->effectiveScattering = r.get<bool>("effective_scattering");
        c->depthSplitting = r.get<bool>("photon_depth_splitting");
        c->probeCollisions = r.get<bool>("probe_collisions");
    }
    if (c->usesPhotons()) {
        readPhotonPasses(ir.render, r, c);
        c->photonImportance = r.get<bool>("photon_importance");
    }
    if (c->probeCollisions) {
        // Its standard error is the passes' spread, and its slab spans the domain (volume_map_probes.h).
        if (c->passes < 2)
            r.fail("probe_collisions", "needs at least 2 progressive passes (render.progressive.passes): the standard "
                                       "error of a collision estimate is the spread of the passes' maps");
        if (const std::string why = horizontalInvarianceProblem(ir); !why.empty())
            r.fail("probe_collisions", fmt::format("applies only to a horizontally invariant scene (docs/rendering.md, "
                                                   "\"Forward probe tallies\"), and here {}", why));
    }
    return surfacePM < 0 && mediumPM < 0 ? "photon maps (photons, search_radius_m, march_step_m, progressive) are read "
                                           "only when a material uses solver surface-pm or the water uses solver medium-pm"
                                         : "";
}

// The dirsig solver of each material: the one it names, if its type's descriptor allows it
// (core/material_kinds.h), or its type's default.
void readDirsigSolvers(const ir::SceneIR& ir, RenderConfig* c) {
    for (size_t i = 0; i < ir.materials.size(); ++i) {
        const ir::Material& m = ir.materials[i];
        const MaterialKind& kind = materialKind(m.type);
        ir::Material::Solver solver = kind.defaultSolver;
        if (m.solver) {
            solver = *m.solver;
            if (kind.namedSolvers.empty())
                materialError(m, i, fmt::format("a {} material takes no solver ({}); remove solver '{}'", kind.info.name,
                                                kind.noSolverWhy, nameOf(solver)));
            if (std::find(kind.namedSolvers.begin(), kind.namedSolvers.end(), solver) == kind.namedSolvers.end())
                materialError(m, i, fmt::format("solver {} cannot evaluate a {} material (allowed: {})", nameOf(solver),
                                                kind.info.name, joinList(kind.solverNames())));
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
    c->probePhotons = static_cast<uint64_t>(r.get<int64_t>("probe_photons"));
    if (c->probePhotons > 0 && c->probePhotons < static_cast<uint64_t>(c->probeBatches))
        r.fail("probe_photons", fmt::format("{} photons cannot form render.probe_batches = {} batches", c->probePhotons,
                                            c->probeBatches));
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

namespace {

// render.target_relative_error and its cap: the pilot (each sensor's samples_per_pixel) needs 4
// samples at least to estimate a variance, and the cap must allow more than the pilot; the cap
// alone would do nothing, and is refused.
void readPixelConvergence(const ir::SceneIR& ir, SettingsReader& r, RenderConfig* c) {
    c->targetRelativeError = r.get<double>("target_relative_error");
    c->maxSamplesPerPixel = r.get<int>("max_samples_per_pixel");
    if (c->targetRelativeError <= 0) {
        if (r.isSet("max_samples_per_pixel"))
            r.fail("max_samples_per_pixel", "caps the samples of render.target_relative_error, which is not set; set "
                                            "both, or remove max_samples_per_pixel");
        return;
    }
    for (const ir::Sensor& s : ir.sensors) {
        if (s.samplesPerPixel < 4)
            r.fail("target_relative_error", fmt::format("needs samples_per_pixel >= 4 on every sensor, the pilot that "
                                                        "estimates each pixel's variance; sensor '{}' has {}",
                                                        s.name, s.samplesPerPixel));
        if (s.samplesPerPixel >= c->maxSamplesPerPixel)
            r.fail("target_relative_error", fmt::format("sensor '{}' has samples_per_pixel {}, not below "
                                                        "render.max_samples_per_pixel {}: no pixel could take more",
                                                        s.name, s.samplesPerPixel, c->maxSamplesPerPixel));
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
    readPixelConvergence(ir, r, &c);
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

Estimator::Estimator(const Scene& scene, const RenderConfig& config, BandGroup group,
                     std::vector<bool> effectiveExtinction)
    : scene_(scene), config_(config), group_(group),
      sun_(scene, group, config.glossySun, std::move(effectiveExtinction), config.estimator == ir::Estimator::Dirsig) {
    LITTORAL_CHECK(group.count >= 1 && group.count <= kMaxGroupBands);
    LITTORAL_CHECK(group.begin >= 0 && group.begin + group.count <= scene.bandCount());
    LITTORAL_CHECK_EQ(config.solvers.size(), scene.materials().size());
}

std::unique_ptr<Estimator> Estimator::create(const Scene& scene, const RenderConfig& config, BandGroup group,
                                             const PhotonMaps* maps, int pass) {
    switch (config.estimator) {
        case ir::Estimator::Dirsig: return makeDirsigEstimator(scene, config, group, maps, pass);
        case ir::Estimator::Path: return makePathEstimator(scene, config, group);
    }
    throw InternalError("unknown estimator");
}

PhotonPassSettings photonPassSettings(const Scene& scene, const RenderConfig& config, BandGroup g, int pass, int threads,
                                      bool progress, uint64_t maxPhotonsEmitted) {
    PhotonPassSettings ps;
    ps.surfaceTarget = config.surfacePhotons;
    ps.volumeTarget = config.volumePhotons;
    ps.maxBounces = config.photonMaxBounces;
    ps.maxSpecularDepth = config.photonMaxSpecularDepth;
    ps.effectiveScattering = config.effectiveScattering;
    ps.importance = config.photonImportance;
    ps.seed = scene.ir().render.seed;
    ps.pass = static_cast<uint64_t>(pass) * 64 + static_cast<uint64_t>(g.begin);
    ps.surfaceRadius = config.radiusAt(config.surfaceRadius, pass);
    ps.volumeRadius = config.radiusAt(config.volumeRadius, pass);
    ps.threads = threads;
    ps.progress = progress;
    ps.maxEmitted = maxPhotonsEmitted;
    ps.volumeMedium.assign(scene.media().size(), false);
    for (size_t m = 0; m < config.mediumPM.size(); ++m) ps.volumeMedium[m + 1] = config.mediumPM[m];
    for (size_t m = 0; m < config.solvers.size(); ++m)
        ps.surfaceMaterial.push_back(config.solvers[m] == ir::Material::Solver::SurfacePM);
    if (config.depthSplitting && ps.volumeTarget > 0) ps.depthImportance = volumeDepthImportance(scene, g, ps);
    return ps;
}

EstimatorSet::EstimatorSet(const Scene& scene, int pass, int threads, bool progress, uint64_t maxPhotonsEmitted)
    : config_(makeRenderConfig(scene.ir())), groups_(bandGroups(scene)), pass_(pass) {
    for (const BandGroup& g : groups_) {
        const PhotonMaps* maps = nullptr;
        if (config_.usesPhotons()) {
            const PhotonPassSettings ps = photonPassSettings(scene, config_, g, pass, threads, progress, maxPhotonsEmitted);
            maps_.push_back(std::make_unique<PhotonMaps>(tracePhotons(scene, g, ps)));
            maps = maps_.back().get();
        }
        estimators_.push_back(Estimator::create(scene, config_, g, maps, pass));
    }
}

EstimatorSet::~EstimatorSet() = default;

}  // namespace littoral::render
