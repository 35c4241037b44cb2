#include "render/estimator.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>

#include "core/error.h"
#include "core/log.h"
#include "core/render_budget.h"
#include "core/resource_limits.h"
#include "core/suggest.h"
#include "core/units.h"
#include "render/photon_pass.h"
#include "render/sampling.h"

#include <unistd.h>

namespace littoral::render {

std::unique_ptr<Estimator> makeDirsigEstimator(const Scene&, const RenderConfig&, BandGroup, const PhotonMaps*, int);
std::unique_ptr<Estimator> makePathEstimator(const Scene&, const RenderConfig&, BandGroup);

namespace {

// Reads optional render settings with their defaults and ranges, remembering which were read.
class SettingsReader {
public:
    explicit SettingsReader(const ir::RenderSettings& s) : s_(s) {}

    template <class T>
    T get(const std::optional<T>& v, const char* irKey, T def, T lo, T hi, const char* unit = "") {
        read_.insert(irKey);
        if (!v) return def;
        if (!(*v >= lo && *v <= hi))
            fail(irKey, fmt::format("{} is out of range; allowed [{}, {}]{}{}", *v, lo, hi, *unit ? " " : "", unit));
        return *v;
    }

    // Every setting that is set but was not read is an error naming it.
    void finish(std::string_view estimator, const std::string& hint) const {
        std::vector<std::string> readable;
        for (const auto& k : ir::renderSettingKeys())
            if (read_.count(k.irKey)) readable.push_back(k.sceneKey);
        for (const auto& k : ir::renderSettingKeys())
            if (k.isSet(s_) && !read_.count(k.irKey))
                fail(k.irKey, fmt::format("is set, but the '{}' estimator does not read it{} (it reads: {})", estimator,
                                          hint.empty() ? "" : "; " + hint, joinList(readable)));
    }

    [[noreturn]] void fail(const char* irKey, const std::string& msg) const {
        for (const auto& k : ir::renderSettingKeys()) {
            if (std::string_view(k.irKey) != irKey) continue;
            const auto it = s_.locations.find(k.sceneKey);
            if (it != s_.locations.end()) throw InputError(it->second, fmt::format("render.{}: {}", k.sceneKey, msg));
        }
        throw InputError(fmt::format("render.{}: {}", irKey, msg));
    }

private:
    const ir::RenderSettings& s_;
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


}  // namespace

RenderConfig makeRenderConfig(const ir::SceneIR& ir) {
    const ir::RenderSettings& s = ir.render;
    RenderConfig c;
    c.estimator = s.estimator;
    SettingsReader r(s);
    c.probeSamples = r.get(s.probeSamples, "probe_samples", 4096, 2, 1 << 30);
    c.probeBatches = r.get(s.probeBatches, "probe_batches", 16, 2, 4096);
    if (c.probeBatches > c.probeSamples)
        r.fail("probe_batches", fmt::format("{} batches cannot be formed from {} probe samples", c.probeBatches,
                                            c.probeSamples));
    using S = ir::Material::Solver;
    using T = ir::Material::Type;
    switch (s.estimator) {
        case ir::Estimator::Dirsig: {
            c.maxBounces = r.get(s.maxBounces, "max_bounces", 8, 0, 100000);
            c.maxSpecularDepth = r.get(s.maxSpecularDepth, "max_specular_depth", 16, 0, 100000);
            c.hemisphereSamples = r.get(s.hemisphereSamples, "hemisphere_samples", 64, 1, 1 << 20);
            // Photon maps: read only when some material or medium uses a photon-map solver.
            int surfacePM = -1, mediumPM = -1;
            for (size_t i = 0; i < ir.materials.size(); ++i)
                if (ir.materials[i].solver == S::SurfacePM && surfacePM < 0) surfacePM = static_cast<int>(i);
            for (size_t i = 0; i < ir.media.size(); ++i) {
                c.mediumPM.push_back(ir.media[i].solver == ir::Medium::Solver::MediumPM);
                if (c.mediumPM.back() && mediumPM < 0) mediumPM = static_cast<int>(i);
            }
            if (surfacePM >= 0) {
                if (!s.surfacePhotons)
                    materialError(ir.materials[surfacePM], static_cast<size_t>(surfacePM),
                                  "the surface-pm solver needs the surface photon map: set render.photons.surface");
                c.surfacePhotons = r.get(s.surfacePhotons, "surface_photons", uint64_t{0}, uint64_t{1}, uint64_t{10'000'000'000});
                c.surfaceRadius = r.get(s.surfaceSearchRadius, "surface_search_radius_m", 0.4, 1e-4, 100.0, "m");
            }
            if (mediumPM >= 0) {
                if (!s.volumePhotons)
                    mediumError(ir.media[mediumPM], static_cast<size_t>(mediumPM),
                                "the medium-pm solver needs the volume photon map: set render.photons.volume");
                c.volumePhotons = r.get(s.volumePhotons, "volume_photons", uint64_t{0}, uint64_t{1}, uint64_t{10'000'000'000});
                c.volumeRadius = r.get(s.volumeSearchRadius, "volume_search_radius_m", 0.4, 1e-4, 100.0, "m");
                c.marchStep = r.get(s.marchStep, "march_step_m", 0.1, 1e-4, 1e4, "m");
                c.effectiveScattering = r.get(s.effectiveScattering, "effective_scattering", false, false, true);
            }
            if (c.usesPhotons()) {
                c.photonMaxBounces = r.get(s.photonMaxBounces, "photon_max_bounces", 200, 1, 100000);
                c.photonMaxSpecularDepth = s.maxSpecularDepth.value_or(1000);
                c.passes = r.get(s.progressivePasses, "progressive_passes", 1, 1, 100000);
                c.alpha = r.get(s.progressiveAlpha, "progressive_alpha", 2.0 / 3.0, 0.05, 0.99);
                // The maps of the largest band group must fit in the memory budget (the same
                // estimate check-scene uses, core/render_budget.h).
                static_assert(kMaxGroupBands == kPhotonGroupBandsMax);
                const double sb = photonBytesEach(true, s.bands.size()), vb = photonBytesEach(false, s.bands.size());
                const double need = static_cast<double>(c.surfacePhotons) * sb + static_cast<double>(c.volumePhotons) * vb;
                const double budget = static_cast<double>(memoryBudget());
                if (need > budget)
                    r.fail(static_cast<double>(c.volumePhotons) * vb > static_cast<double>(c.surfacePhotons) * sb
                               ? "volume_photons"
                               : "surface_photons",
                           fmt::format("{} surface and {} volume photons need {} ({:.0f} and {:.0f} bytes each with "
                                       "the search grid and its build buffers), more than the memory budget of {} "
                                       "(--max-memory)",
                                       c.surfacePhotons, c.volumePhotons, formatBytes(need), sb, vb,
                                       formatBytes(budget)));
            }
            r.finish("dirsig", surfacePM < 0 && mediumPM < 0
                                   ? "photon maps (photons, search_radius_m, march_step_m, progressive) are read only "
                                     "when a material uses solver surface-pm or the water uses solver medium-pm"
                                   : "");
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
                        materialError(m, i, "solver fresnel cannot evaluate a diffuse material (use classic, generic "
                                            "or surface-pm)");
                    if (interface && solver != S::Fresnel && solver != S::Generic)
                        materialError(m, i, fmt::format("an interface needs the fresnel (or generic) solver, not {}",
                                                        nameOf(solver)));
                }
                c.solvers.push_back(solver);
            }
            break;
        }
        case ir::Estimator::Path: {
            // Limits far above what Russian roulette lets a path reach: they only stop a path that
            // would otherwise never end (light trapped without loss), so they do not bias results.
            c.maxBounces = r.get(s.maxBounces, "max_bounces", 1000, 0, 100000);
            c.maxSpecularDepth = r.get(s.maxSpecularDepth, "max_specular_depth", 1000, 0, 100000);
            c.marchStep = r.get(s.marchStep, "march_step_m", 0.1, 1e-4, 1e4, "m");
            r.finish("path", "");
            for (size_t i = 0; i < ir.materials.size(); ++i) {
                const ir::Material& m = ir.materials[i];
                if (m.solver)
                    materialError(m, i, fmt::format("the path estimator does not use per-material solvers; remove "
                                                    "solver '{}' or choose estimator: dirsig",
                                                    nameOf(*m.solver)));
                c.solvers.push_back(S::Generic);
            }
            for (size_t i = 0; i < ir.media.size(); ++i) {
                if (ir.media[i].solver)
                    mediumError(ir.media[i], i, fmt::format("the path estimator does not use medium solvers; remove "
                                                            "solver '{}' or choose estimator: dirsig",
                                                            nameOf(*ir.media[i].solver)));
                c.mediumPM.push_back(false);
            }
            break;
        }
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
      sun_(scene, group, config.glossySun, std::move(effectiveExtinction)) {
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

EstimatorSet::EstimatorSet(const Scene& scene, int pass, int threads, bool progress)
    : config_(makeRenderConfig(scene.ir())), groups_(bandGroups(scene)), pass_(pass) {
    for (const BandGroup& g : groups_) {
        const PhotonMaps* maps = nullptr;
        if (config_.usesPhotons()) {
            PhotonPassSettings ps;
            ps.surfaceTarget = config_.surfacePhotons;
            ps.volumeTarget = config_.volumePhotons;
            ps.maxBounces = config_.photonMaxBounces;
            ps.maxSpecularDepth = config_.photonMaxSpecularDepth;
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

}  // namespace littoral::render
