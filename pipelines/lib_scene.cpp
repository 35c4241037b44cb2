#include "pipelines/lib_scene.h"
#include "pipelines/lib_geo_layers.h"

#include <sys/resource.h>

#include <chrono>

#include <stdlib.h>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/log.h"
#include "core/ranks.h"
#include "core/stats.h"
#include "render/estimator.h"
#include "render/render_job.h"
#include "scenegen/assemble.h"
#include "scenegen/assembly_sections.h"
#include "scenegen/scene_file.h"
#include "scenegen/surface_section.h"
#include "scenegen/synthetic_site.h"

namespace littoral::pipelines {

namespace fs = std::filesystem;

void checkRenderSettings(const scenegen::SceneSpec& spec) {
    ir::SceneIR ir;
    scenegen::applyCommonSections(spec, &ir);
    // Texture classes become materials during assembly; their solvers are checked now too.
    if (spec.textureClasses)
        for (const auto& c : scenegen::parseTextureClasses(*spec.textureClasses).classes) {
            ir::Material m;
            m.name = c.name;
            if (!c.solver.empty()) m.solver = parseName<ir::Material::Solver>(c.solver);
            m.origin = c.loc;
            ir.materials.push_back(m);
        }
    (void)render::makeRenderConfig(ir);
}

namespace {

// A render-time InputError without a location ("probe 'p1': ...", "sensor 'cam': ...",
// "material 'sand': ...") is located at the scene-file entry it names, or at the scene file.
// `orAtFile` false: an error that names none of them is rethrown as it is (an --out problem).
[[noreturn]] void rethrowAtScene(const InputError& e, const scenegen::SceneSpec& spec, const fs::path& sceneFile,
                                 bool orAtFile = true) {
    if (!e.where().file.empty()) throw e;
    const std::string& msg = e.message();
    auto names = [&](const char* what, const std::string& name) {
        return msg.rfind(fmt::format("{} '{}'", what, name), 0) == 0;
    };
    for (const auto& x : spec.sensors)
        if (names("sensor", x.name)) throw InputError(x.loc, msg);
    for (const auto& x : spec.probes)
        if (names("probe", x.name)) throw InputError(x.loc, msg);
    for (const auto& x : spec.materials)
        if (names("material", x.name)) throw InputError(x.loc, msg);
    // Texture classes become materials of their names (a class's mean times its reflectance is
    // checked on the bands by the renderer).
    if (spec.textureClasses)
        for (const auto& c : scenegen::parseTextureClasses(*spec.textureClasses).classes)
            if (names("material", c.name)) throw InputError(c.loc, msg);
    if (!orAtFile) throw e;
    throw InputError(SourceLoc{sceneFile.string()}, msg);
}

// A folder under the system's temporary directory, removed with everything in it when the
// object goes out of scope.
class TemporaryFolder {
public:
    TemporaryFolder() {
        std::string tmpl = (fs::temp_directory_path() / "littoral-check-XXXXXX").string();
        if (!::mkdtemp(tmpl.data())) throw InputError("cannot create a temporary folder under " + fs::temp_directory_path().string());
        path_ = tmpl;
    }
    ~TemporaryFolder() {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    TemporaryFolder(const TemporaryFolder&) = delete;
    TemporaryFolder& operator=(const TemporaryFolder&) = delete;
    const fs::path& path() const { return path_; }

private:
    fs::path path_;
};

}  // namespace

void preflightRender(const scenegen::AssembledScene& built, const scenegen::SceneSpec& spec, const fs::path& sceneFile) {
    const TemporaryFolder tmp;
    if (built.textures) {
        const OutputSetPause scratch;  // not outputs: removed with the folder, whatever happens
        built.textures->writeTextures(tmp.path());
    }
    try {
        render::preflightRenderJob(built.ir, tmp.path(), render::RenderJobOptions{});
    } catch (const InputError& e) {
        rethrowAtScene(e, spec, sceneFile);
    }
}

scenegen::AssembleOptions checkedAssembly(const fs::path& sceneFile) {
    scenegen::AssembleOptions ao;
    ao.beforeWrite = [sceneFile](const scenegen::SceneSpec& spec, const scenegen::AssembledScene& built) {
        preflightRender(built, spec, sceneFile);
    };
    return ao;
}

std::string checkScene(const fs::path& sceneFile) {
    const auto spec = scenegen::loadSceneFile(sceneFile);
    checkRenderSettings(spec);
    // Every check short of rendering: the geometry is built in memory (nothing is written), so the
    // geometric checks run too (objects against the domain and each other, sensors and probes
    // against the ground and the objects, surface coverage, the water volume itself).
    scenegen::AssembleOptions ao;
    const scenegen::AssembledScene built = scenegen::assembleScene(spec, ao);
    if (!built.valid) {
        std::string msg = "the assembled scene failed its validity checks";
        if (built.validity.contains("water") && !built.validity["water"]["valid"].get<bool>())
            for (const auto& r : built.validity["water"]["reasons"]) msg += "\n  water: " + r.get<std::string>();
        throw InputError(SourceLoc{sceneFile.string()}, msg);
    }
    preflightRender(built, spec, sceneFile);
    size_t objects = 0;
    for (const auto& m : built.ir.meshes) objects += m.file.rfind("meshes/object_", 0) == 0 ? 1 : 0;
    std::string s;
    s += fmt::format("  scene '{}': domain [{}, {}] x [{}, {}] m\n", spec.scene.name, spec.scene.x0, spec.scene.x1,
                     spec.scene.y0, spec.scene.y1);
    s += fmt::format("  {} band(s), {} sensor(s), {} probe(s), {} material(s), {} object(s){}{}\n",
                     spec.render.settings.bands.size(), spec.sensors.size(), spec.probes.size(), spec.materials.size(),
                     objects, spec.hasWater ? ", water" : "", spec.bathymetry ? ", bathymetry" : "");
    for (const auto& m : built.ir.meshes)
        s += fmt::format("  mesh {:<20} {:>8} faces{}\n", m.name, m.data.numTriangles(), m.closed ? ", closed" : "");
    return s;
}

void addPreviewOptions(CLI::App* cmd, render::PreviewOptions* preview) {
    cmd->add_option("--gamma", preview->gamma, "PNG preview display gamma (the dissertation's images use 0.65)")
        ->check(CLI::Range(0.05, 5.0))
        ->capture_default_str();
    cmd->add_option("--white", preview->whiteLevel,
                    "PNG preview white level, W m^-2 sr^-1 um^-1 (0 = the 99th percentile of the image)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    cmd->add_option("--blur", preview->blurSigma,
                    "Gaussian sensor blur of the PNG preview, sigma in pixels (0 = none; the dissertation's kernel is 0.636)")
        ->check(CLI::Range(0.0, 50.0))
        ->capture_default_str();
}

std::string resourceSummary() {
    auto millions = [](int64_t n) { return n == 0 ? std::string("0") : fmt::format("{:.3g} M", static_cast<double>(n) * 1e-6); };
    std::string s;
    const int64_t emitted = statCounter("photons emitted").value;
    if (emitted > 0)  // a photon may leave a record at each of its diffuse or volume events
        s += fmt::format(", {} photons emitted ({} surface + {} volume records stored)", millions(emitted),
                         millions(statCounter("photons stored (surface)").value),
                         millions(statCounter("photons stored (volume)").value));
    struct rusage ru {};
    if (getrusage(RUSAGE_SELF, &ru) == 0) s += fmt::format(", peak memory {} MiB", ru.ru_maxrss / 1024);  // KiB on Linux
    return s;
}

namespace {

// The build half of `run`: the scene file read and checked, its IR built (the renderer's own checks
// run on the scene in memory before the IR is written) and published, since the IR is a complete
// output set of its own and the renderer reads its textures from disk (a failed render then leaves
// the IR, never part of it).
struct BuiltForRun {
    scenegen::SceneSpec spec;
    scenegen::AssembledScene built;
};
BuiltForRun buildForRun(const RunOptions& o, const fs::path& irDir) {
    BuiltForRun b{scenegen::loadSceneFile(o.scene), {}};
    checkRenderSettings(b.spec);  // before anything is written
    // A scene may be built for its geometry alone (check-scene and build warn); run has nothing to
    // render, and says so before writing the IR.
    if (b.spec.sensors.empty() && b.spec.probes.empty())
        throw InputError(SourceLoc{o.scene}, "sensors, probes: the scene has neither, so run has nothing to render "
                                             "(build makes its geometry alone)");
    b.built = scenegen::buildScene(o.scene, irDir, checkedAssembly(o.scene));
    publishStagedOutputs();
    return b;
}

render::RenderJobOptions runJobOptions(const RunOptions& o) {
    render::RenderJobOptions jo;
    jo.sensor = o.sensor;
    jo.threads = o.threads;
    jo.progress = o.progress;
    jo.preview = o.preview;
    jo.resume = o.resume;
    jo.enviHeaderLines = [](const ir::SceneIR& ir, const ir::Sensor& s) { return enviGeoHeaderLines(ir, s); };
    return jo;
}

// What `run` prints: the build, the render (`where`: how it ran, e.g. " on 3 MPI ranks") and the
// files written.
std::string runSummary(const RunOptions& o, const fs::path& irDir, const fs::path& out, const render::RenderJobResult& res,
                       double buildSeconds, double renderSeconds, const std::string& where) {
    std::string s = fmt::format("built {} -> {} ({:.1f} s)\n", o.scene, irDir.string(), buildSeconds);
    s += fmt::format("rendered {} sensor(s), {} probe value(s) -> {} ({:.1f} s{}{})\n", res.images.size(), res.probes.size(),
                     out.string(), renderSeconds, where, resourceSummary());
    for (const auto& p : res.written) s += fmt::format("  {}\n", p.string());
    return s;
}

double secondsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// `run` under MPI ranks: rank 0 builds the scene and publishes its IR; then every rank renders the IR
// it reads back, as `render` would. Only rank 0 returns a summary.
std::string runSceneOnRanks(const RunOptions& o, const fs::path& out, const fs::path& irDir) {
    const auto t0 = std::chrono::steady_clock::now();
    // Rank 0 tells the others how its build ended: "" or its error, which every rank then raises,
    // so that bad input ends all of them alike (one message, from rank 0; pipelines/lib_mpi.h).
    auto share = [](const std::string& failure) {
        ByteWriter w;
        w.putArray(failure.data(), failure.size());
        const std::vector<Bytes> all = ranks().allGather(w.bytes());
        ByteReader r(all[0]);
        std::string fromRoot;
        r.getArray(fromRoot);
        return fromRoot;
    };
    if (isRootRank()) {
        try {
            (void)buildForRun(o, irDir);
        } catch (const InputError& e) {
            (void)share(e.where().str().empty() ? e.message() : e.where().str() + ": " + e.message());
            throw;
        }
        (void)share("");
    } else if (const std::string failure = share(""); !failure.empty()) {
        throw InputError(failure);  // rank 0 has printed it
    }
    const double buildSeconds = secondsSince(t0);
    const auto t1 = std::chrono::steady_clock::now();
    const ir::SceneIR ir = ir::readIR(irDir);
    render::RenderJobResult res;
    try {
        res = render::runRenderJob(ir, irDir, out, runJobOptions(o));
    } catch (const InputError& e) {
        render::rethrowAtIrEntry(e, ir, irDir / "scene.json");
    }
    if (!isRootRank()) return "";
    for (const auto& p : writeGeoLayers(ir, res, out)) res.written.push_back(p);
    return runSummary(o, irDir, out, res, buildSeconds, secondsSince(t1), fmt::format(" on {} MPI ranks", ranks().size()));
}

}  // namespace

std::string runScene(const RunOptions& o) {
    const fs::path out(o.out), irDir = out / "ir";
    if (ranks().size() > 1) return runSceneOnRanks(o, out, irDir);
    const auto t0 = std::chrono::steady_clock::now();
    const BuiltForRun b = buildForRun(o, irDir);
    const double buildSeconds = secondsSince(t0);
    const auto t1 = std::chrono::steady_clock::now();
    render::RenderJobResult res;
    try {
        res = render::runRenderJob(b.built.ir, irDir, out, runJobOptions(o));
        for (const auto& p : writeGeoLayers(b.built.ir, res, out)) res.written.push_back(p);
    } catch (const InputError& e) {
        rethrowAtScene(e, b.spec, o.scene, false);
    }
    return runSummary(o, irDir, out, res, buildSeconds, secondsSince(t1), "");
}

std::string runDemo(const DemoOptions& o) {
    const fs::path out(o.out);
    scenegen::SiteOptions so;
    so.seed = o.seed;
    const auto site = scenegen::writeSyntheticSite(out / "site", so);
    publishStagedOutputs();  // the site is read back from disk by the build below
    RunOptions ro;
    ro.scene = site.sceneFile.string();
    ro.out = o.out;
    ro.threads = o.threads;
    ro.progress = o.progress;
    ro.preview = o.preview;
    std::string s = fmt::format("wrote the synthetic coastal site (seed {}) -> {}\n", o.seed, site.sceneFile.string());
    return s + runScene(ro);
}

}  // namespace littoral::pipelines
