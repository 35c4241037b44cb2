// The kind descriptors against everything that reads them: for every registered kind of every
// family (phase functions, estimators, probe quantities, material types, sensor types, medium
// models, water presets and wave models), each documented parameter is accepted by the scene-file
// parser at its default and at both ends of its range, refused just outside with a located error
// naming the range, round-trips through the Scene IR, and is range-checked by the renderer's
// factory alike; unknown names get a did-you-mean; docs/scene-format.md lists exactly the
// registered parameters with their ranges.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/kinds.h"
#include "core/material_kinds.h"
#include "core/phase_functions.h"
#include "core/probe_quantities.h"
#include "core/scene_ir.h"
#include "core/sensor_types.h"
#include "core/suggest.h"
#include "render/camera.h"
#include "render/estimator.h"
#include "render/estimator_settings.h"
#include "scenegen/scene_file.h"
#include "scenegen/water_constituents.h"
#include "scenegen/yaml_reader.h"
#include "scenegen/surface_section.h"
#include "surfaces/wave_kinds.h"

using namespace littoral;
using namespace littoral::scenegen;
namespace fs = std::filesystem;

namespace {

// The values to try for a parameter: its default and the ends of its range (accepted), and just
// outside each end (refused). Booleans have no outside.
struct Trial {
    std::string text;
    ParamValue value;
};
std::vector<Trial> insideValues(const ParamSpec& p) {
    std::vector<Trial> v;
    if (p.type == ParamType::Boolean) return {{"true", true}, {"false", false}};
    auto add = [&](double x) {
        if (p.type == ParamType::Integer) v.push_back({fmt::format("{}", static_cast<long long>(x)), static_cast<int64_t>(x)});
        else v.push_back({fmt::format("{}", x), x});
    };
    if (p.defaultValue) add(*p.defaultValue);
    add(p.loOpen ? p.lo + 1e-6 * std::max(1.0, p.hi - p.lo) : p.lo);  // an open end: just inside
    add(p.hi);
    return v;
}
std::vector<std::string> outsideTexts(const ParamSpec& p) {
    if (p.type == ParamType::Boolean) return {"2"};
    if (p.type == ParamType::Integer)
        return {fmt::format("{}", static_cast<long long>(p.lo) - 1), fmt::format("{}", static_cast<long long>(p.hi) + 1)};
    const double d = 1e-6 * std::max(1.0, p.hi - p.lo);
    return {fmt::format("{}", p.loOpen ? p.lo : p.lo - d), fmt::format("{}", p.hi + d)};
}

scenegen::SceneSpec parse(const std::string& text) {
    return scenegen::parseScene(scenegen::YamlNode::loadString(text, "kinds.yaml"), "kinds.yaml");
}

// The message of the InputError parsing `text` throws ("" if none), with its location.
std::string parseError(const std::string& text, SourceLoc* where = nullptr) {
    try {
        (void)parse(text);
    } catch (const InputError& e) {
        if (where) *where = e.where();
        return e.message();
    }
    return "";
}

std::string phaseScene(const std::string& phase) {
    return "scene: {name: kinds}\nrender: {estimator: path}\nwater:\n  optics:\n    scattering_per_m: 0.1\n"
           "    phase: " +
           phase + "\n";
}

std::string phaseText(const PhaseKind& k, const std::string& param, const std::string& value) {
    std::string s = "{type: " + k.info.name;
    for (const ParamSpec& p : k.info.params) {
        if (p.name == param) s += ", " + p.name + ": " + value;
        else if (!p.defaultValue) s += ", " + p.name + ": " + fmt::format("{}", p.lo);
    }
    return s + "}";
}

ir::SceneIR irOf(const scenegen::SceneSpec& spec) {
    ir::SceneIR ir;
    scenegen::applyCommonSections(spec, &ir);
    return ir;
}

// Writes, reads and writes again: byte-identical text, and the IR read back.
ir::SceneIR roundTrip(const ir::SceneIR& ir) {
    const std::string text = ir::toJsonText(ir);
    ir::SceneIR back = ir::fromJsonText(text, "scene.json");
    EXPECT_EQ(ir::toJsonText(back), text);
    return back;
}

}  // namespace

TEST(KindDescriptors, PhaseFunctionParametersMatchTheParserAndTheIr) {
    ASSERT_FALSE(phaseFunctionKinds().empty());
    for (const PhaseKind& k : phaseFunctionKinds().kinds()) {
        SCOPED_TRACE(k.info.name);
        EXPECT_EQ(k.info.family, "phase function");
        EXPECT_FALSE(k.info.doc.empty());
        // Every kind parses with only its required parameters, and builds.
        {
            const auto spec = parse(phaseScene(phaseText(k, "", "")));
            const ir::PhaseFunction& ph = spec.waterOptics.iops.scatterers.at(0).phase;
            EXPECT_EQ(ph.type, k.info.name);
            EXPECT_EQ(ph.params.size(), k.info.params.size());  // defaults filled in
            const ir::SceneIR back = roundTrip(irOf(spec));
            EXPECT_EQ(back.media.at(0).layers.at(0).scatterers.at(0).phase, ph);
            EXPECT_NO_THROW(makePhaseFunction(ph.type, ph.params, "test"));
        }
        for (const ParamSpec& p : k.info.params) {
            SCOPED_TRACE(p.name);
            EXPECT_FALSE(p.doc.empty());
            for (const Trial& t : insideValues(p)) {
                const auto spec = parse(phaseScene(phaseText(k, p.name, t.text)));
                const ir::PhaseFunction& ph = spec.waterOptics.iops.scatterers.at(0).phase;
                ASSERT_NE(ph.params.find(p.name), nullptr);
                EXPECT_EQ(numberOf(*ph.params.find(p.name)), numberOf(t.value)) << t.text;
                const ir::SceneIR back = roundTrip(irOf(spec));
                EXPECT_EQ(back.media.at(0).layers.at(0).scatterers.at(0).phase, ph) << t.text;
            }
            for (const std::string& out : outsideTexts(p)) {
                SourceLoc where;
                const std::string msg = parseError(phaseScene(phaseText(k, p.name, out)), &where);
                EXPECT_NE(msg.find("out of range; allowed " + p.rangeText()), std::string::npos) << out << ": " << msg;
                EXPECT_EQ(where.file, "kinds.yaml");
                EXPECT_EQ(where.line, 6) << msg;
                // The renderer's factory (a hand-edited IR) checks the same range.
                ParamValues given;
                given.set(p.name, std::stod(out));
                for (const ParamSpec& q : k.info.params)
                    if (q.name != p.name && !q.defaultValue) given.set(q.name, q.lo);
                try {
                    (void)makePhaseFunction(k.info.name, given, "media[0]");
                    ADD_FAILURE() << "the factory accepted " << out;
                } catch (const InputError& e) {
                    EXPECT_NE(std::string(e.what()).find("allowed " + p.rangeText()), std::string::npos) << e.what();
                }
            }
            if (!p.defaultValue) {
                const std::string msg = parseError(phaseScene("{type: " + k.info.name + "}"));
                EXPECT_NE(msg.find(p.name), std::string::npos) << msg;
            }
        }
    }
}

TEST(KindDescriptors, UnknownPhaseFunctionGetsADidYouMean) {
    const std::string msg = parseError(phaseScene("{type: henyey-greenstien, g: 0.5}"));
    EXPECT_NE(msg.find("did you mean 'henyey-greenstein'"), std::string::npos) << msg;
    // A parameter of another kind names the kind it belongs to.
    EXPECT_NE(parseError(phaseScene("{type: isotropic, g: 0.5}")).find("only used by the henyey-greenstein"),
              std::string::npos);
    // The IR reader and the factory give the same did-you-mean.
    auto spec = parse(phaseScene("{type: petzold}"));
    std::string text = ir::toJsonText(irOf(spec));
    text.replace(text.find("\"petzold\""), 9, "\"petzld\"");
    try {
        (void)ir::fromJsonText(text, "scene.json");
        ADD_FAILURE();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("did you mean 'petzold'"), std::string::npos) << e.what();
    }
    try {
        (void)makePhaseFunction("rayleight", {}, "x");
        ADD_FAILURE();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("did you mean 'rayleigh'"), std::string::npos) << e.what();
    }
}

namespace {

std::string renderScene(const std::string& estimator, const std::string& sceneKey, const std::string& value) {
    std::string r = "scene: {name: kinds}\nrender:\n  estimator: " + estimator + "\n";
    const size_t dot = sceneKey.find('.');
    if (dot == std::string::npos) r += "  " + sceneKey + ": " + value + "\n";
    else r += "  " + sceneKey.substr(0, dot) + ":\n    " + sceneKey.substr(dot + 1) + ": " + value + "\n";
    return r;
}

// An IR in which the estimator reads every setting it declares: for dirsig, a surface-pm material
// and a medium-pm medium with both photon counts set.
ir::SceneIR readingEverything(const KindInfo& estimator) {
    ir::SceneIR s;
    s.render.estimator = *parseName<ir::Estimator>(estimator.name);
    if (estimator.name == "dirsig") {
        ir::Material m;
        m.name = "sand";
        m.solver = ir::Material::Solver::SurfacePM;
        s.materials.push_back(m);
        ir::Medium w = ir::Medium::homogeneous("water", 1.34, Spectrum::constant(0.1), Spectrum::constant(0.1));
        w.solver = ir::Medium::Solver::MediumPM;
        s.media.push_back(w);
        s.render.settings.set("surface_photons", 1000);
        s.render.settings.set("volume_photons", 1000);
    }
    return s;
}

}  // namespace

TEST(KindDescriptors, EstimatorSettingsMatchTheParserTheIrAndMakeRenderConfig) {
    render::registerEstimatorKinds();
    ASSERT_EQ(estimatorKinds().names(), allNames<ir::Estimator>());
    for (const KindInfo& k : estimatorKinds().kinds()) {
        SCOPED_TRACE(k.name);
        EXPECT_FALSE(k.doc.empty());
        EXPECT_NO_THROW(render::makeRenderConfig(readingEverything(k)));
        for (const ParamSpec& p : k.params) {
            SCOPED_TRACE(p.sceneName());
            EXPECT_FALSE(p.doc.empty());
            // One range per setting: every estimator that declares it declares the same one.
            for (const ParamSpec* q : allRenderSettings())
                if (q->name == p.name) {
                    EXPECT_EQ(q->rangeText(), p.rangeText());
                }
            for (const Trial& t : insideValues(p)) {
                const auto spec = parse(renderScene(k.name, p.sceneName(), t.text));
                const ParamValue* v = spec.render.settings.settings.find(p.name);
                ASSERT_NE(v, nullptr) << t.text;
                EXPECT_EQ(*v, t.value) << t.text;
                EXPECT_EQ(spec.render.settings.locations.count(p.sceneName()), 1u);
                const ir::SceneIR back = roundTrip(irOf(spec));
                ASSERT_NE(back.render.settings.find(p.name), nullptr);
                EXPECT_EQ(numberOf(*back.render.settings.find(p.name)), numberOf(t.value));
            }
            for (const std::string& out : outsideTexts(p)) {
                SourceLoc where;
                const std::string msg = parseError(renderScene(k.name, p.sceneName(), out), &where);
                if (p.type == ParamType::Boolean) EXPECT_NE(msg.find("expected true or false"), std::string::npos) << msg;
                else EXPECT_NE(msg.find("out of range; allowed " + p.rangeText()), std::string::npos) << out << ": " << msg;
                EXPECT_EQ(where.line, p.sceneName().find('.') == std::string::npos ? 4 : 5) << msg;
                if (p.type == ParamType::Boolean) continue;
                // makeRenderConfig refuses the same value in a hand-edited IR.
                ir::SceneIR s = readingEverything(k);
                if (p.type == ParamType::Integer) s.render.settings.set(p.name, std::stoll(out));
                else s.render.settings.set(p.name, std::stod(out));
                try {
                    (void)render::makeRenderConfig(s);
                    ADD_FAILURE() << "makeRenderConfig accepted " << out;
                } catch (const InputError& e) {
                    EXPECT_NE(std::string(e.what()).find("render." + p.name + ": " + out + " is out of range; allowed " +
                                                         p.rangeText()),
                              std::string::npos)
                        << e.what();
                }
            }
        }
    }
}

TEST(KindDescriptors, UnknownRenderSettingGetsADidYouMean) {
    render::registerEstimatorKinds();
    const std::string a = parseError("scene: {name: kinds}\nrender: {march_step: 0.1}\n");
    EXPECT_NE(a.find("did you mean 'march_step_m'"), std::string::npos) << a;
    const std::string b = parseError("scene: {name: kinds}\nrender: {photons: {surfac: 10}}\n");
    EXPECT_NE(b.find("did you mean 'surface'"), std::string::npos) << b;
    ir::SceneIR s;
    s.render.settings.set("probe_sample", 100);
    try {
        (void)render::makeRenderConfig(s);
        ADD_FAILURE();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("did you mean 'probe_samples'"), std::string::npos) << e.what();
    }
}

namespace {

// The rows of the table after "<!-- descriptor table: FAMILY -->" in docs/scene-format.md, each
// split into its cells (backticks removed).
std::vector<std::vector<std::string>> docsTable(const std::string& family) {
    std::ifstream in(fs::path(LITTORAL_SOURCE_DIR) / "docs" / "scene-format.md");
    std::string line;
    bool inside = false;
    std::vector<std::vector<std::string>> rows;
    while (std::getline(in, line)) {
        if (line == "<!-- descriptor table: " + family + " -->") {
            inside = true;
            continue;
        }
        if (!inside) continue;
        if (line.rfind("|", 0) != 0) break;
        std::vector<std::string> cells;
        size_t pos = 1;
        for (size_t bar; (bar = line.find('|', pos)) != std::string::npos; pos = bar + 1) {
            std::string c = line.substr(pos, bar - pos);
            std::erase(c, '`');
            while (!c.empty() && c.front() == ' ') c.erase(0, 1);
            while (!c.empty() && c.back() == ' ') c.pop_back();
            cells.push_back(c);
        }
        if (cells.size() >= 3 && cells[0] != "type" && cells[0] != "key" && cells[0] != "quantity" &&
            cells[0].rfind("---", 0) != 0)
            rows.push_back(cells);
    }
    return rows;
}

}  // namespace

TEST(KindDescriptors, DocsListExactlyTheRegisteredParameters) {
    // Phase functions: one row per parameter (or one row "—" for a kind without any), with the
    // descriptor's range.
    std::set<std::pair<std::string, std::string>> documented, registered;
    for (const auto& row : docsTable("phase function")) {
        documented.insert({row[0], row[1]});
        if (row[1] == "—") continue;
        const PhaseKind* k = phaseFunctionKinds().find(row[0]);
        ASSERT_NE(k, nullptr) << row[0];
        const ParamSpec* p = k->info.param(row[1]);
        ASSERT_NE(p, nullptr) << row[0] << " " << row[1];
        EXPECT_EQ(row[3], p->rangeText()) << row[0] << " " << row[1];
        EXPECT_EQ(row[2] == "required", !p->defaultValue) << row[0] << " " << row[1];
    }
    for (const PhaseKind& k : phaseFunctionKinds().kinds()) {
        if (k.info.params.empty()) registered.insert({k.info.name, "—"});
        for (const ParamSpec& p : k.info.params) registered.insert({k.info.name, p.name});
    }
    EXPECT_EQ(documented, registered);

    // Estimator settings: one row per scene-file key, with the one range.
    render::registerEstimatorKinds();
    std::set<std::string> keys, declared;
    for (const auto& row : docsTable("estimator")) {
        keys.insert(row[0]);
        for (const ParamSpec* p : allRenderSettings())
            if (p->sceneName() == row[0]) {
                EXPECT_EQ(row[3], p->rangeText()) << row[0];
            }
    }
    for (const ParamSpec* p : allRenderSettings()) declared.insert(p->sceneName());
    EXPECT_EQ(keys, declared);

    // Probe quantities: one row each.
    std::vector<std::string> quantities;
    for (const auto& row : docsTable("probe quantity")) quantities.push_back(row[0]);
    EXPECT_EQ(quantities, probeQuantityKinds().names());
}

// ---- wave models -------------------------------------------------------------------------------

namespace {

using surfaces::WaveKind;

// A small, coarse water.surface section of model `k` (parsed only, never generated): `key: value`
// on line 5, then the model's required parameters at a middle value.
std::string waveScene(const WaveKind& k, const std::string& key = "", const std::string& value = "") {
    std::string s = "scene: {name: kinds}\nwater:\n  surface:\n    model: " + k.info.name + "\n";
    if (!key.empty()) s += "    " + key + ": " + value + "\n";
    for (const ParamSpec& p : k.info.params)
        if (p.name != key && !p.defaultValue) s += "    " + p.name + ": 5\n";  // wind: 5 m/s suits every model
    return s + "    size: 20\n    spacing: 0.5\n    triangles: 0\n";
}

scenegen::YamlNode surfaceNode(const std::string& text) {
    return scenegen::YamlNode::loadString(text, "kinds.yaml")["water"]["surface"];
}

// The InputError message of the full parser (keys and the checks that combine them), "" if none.
std::string surfaceError(const std::string& text, SourceLoc* where = nullptr) {
    try {
        (void)scenegen::parseWaterSurface(surfaceNode(text));
    } catch (const InputError& e) {
        if (where) *where = e.where();
        return e.message();
    }
    return "";
}

// What the descriptor makes of its defaults with `key` set to `value`.
surfaces::WaveParams fromDescriptor(const WaveKind& k, const std::string& key, const ParamValue& value) {
    ParamValues v;
    for (const ParamSpec& p : k.info.params) v.set(p.name, p.name == key ? value : ParamValue(5.0));
    for (const ParamSpec& p : k.info.params)
        if (p.name != key && p.defaultValue) v.set(p.name, p.defaultParamValue());
    std::vector<std::string> choices;
    for (const auto& c : k.choices) choices.push_back(c.defaultValue);
    surfaces::WaveParams w;
    w.model = k.model;
    k.apply(v, choices, w);
    return w;
}

void expectSameModelFields(const surfaces::WaveParams& a, const surfaces::WaveParams& b) {
    EXPECT_EQ(a.model, b.model);
    EXPECT_EQ(a.windSpeed, b.windSpeed);
    EXPECT_EQ(a.windDirection, b.windDirection);
    EXPECT_EQ(a.seed, b.seed);
    EXPECT_EQ(a.sea, b.sea);
    EXPECT_EQ(a.fetch, b.fetch);
    EXPECT_EQ(a.gamma, b.gamma);
    EXPECT_EQ(a.amplitude, b.amplitude);
    EXPECT_EQ(a.wavelength, b.wavelength);
    EXPECT_EQ(a.phase, b.phase);
    EXPECT_EQ(a.time, b.time);
    EXPECT_EQ(a.depth, b.depth);
}

}  // namespace

// Every parameter of every wave model: the default and both ends of its range are read by the
// scene-file parser as the descriptor gives them (ends that a check combining keys refuses, such as
// a wind too weak for any allowed spacing to resolve, are read by readWaterSurfaceKeys, the parser's
// first half); just outside is refused at the key with the range.
TEST(KindDescriptors, WaveModelParametersMatchTheSurfaceParser) {
    const auto& kinds = surfaces::waveModelKinds();
    ASSERT_EQ(kinds.names(), surfaces::waveModelNames());
    for (const WaveKind& k : kinds.kinds()) {
        SCOPED_TRACE(k.info.name);
        EXPECT_EQ(k.info.family, "wave model");
        EXPECT_FALSE(k.info.doc.empty());
        EXPECT_EQ(&surfaces::waveKind(k.model), &k);
        // The defaults (and the required keys at 5) pass every check.
        EXPECT_EQ(surfaceError(waveScene(k)), "");
        expectSameModelFields(scenegen::parseWaterSurface(surfaceNode(waveScene(k))), fromDescriptor(k, "", 0.0));
        for (const ParamSpec& p : k.info.params) {
            SCOPED_TRACE(p.name);
            EXPECT_FALSE(p.doc.empty());
            EXPECT_NE(p.type, ParamType::Boolean);
            for (const Trial& t : insideValues(p)) {
                const surfaces::WaveParams w = scenegen::readWaterSurfaceKeys(surfaceNode(waveScene(k, p.name, t.text)));
                expectSameModelFields(w, fromDescriptor(k, p.name, t.value));
            }
            const auto& own = k.rangeCheckedByValidation;
            const bool ownWords = std::find(own.begin(), own.end(), p.name) != own.end();
            for (const std::string& out : outsideTexts(p)) {
                SourceLoc where;
                const std::string msg = surfaceError(waveScene(k, p.name, out), &where);
                const std::string range = ownWords ? fmt::format("allowed {} to {} {}", p.lo, p.hi, p.unit)
                                                   : "out of range; allowed " + p.rangeText();
                EXPECT_NE(msg.find(range), std::string::npos) << out << ": " << msg;
                EXPECT_NE(msg.find("water.surface." + p.name), std::string::npos) << msg;
                EXPECT_EQ(where.file, "kinds.yaml");
                EXPECT_EQ(where.line, 5) << msg;
            }
        }
        for (const auto& c : k.choices) {
            SCOPED_TRACE(c.key);
            EXPECT_NE(std::find(c.allowed.begin(), c.allowed.end(), c.defaultValue), c.allowed.end());
            for (const std::string& v : c.allowed) EXPECT_EQ(surfaceError(waveScene(k, c.key, v)), "") << v;
            const std::string msg = surfaceError(waveScene(k, c.key, c.allowed.back() + "x"));
            EXPECT_NE(msg.find("did you mean '" + c.allowed.back() + "'"), std::string::npos) << msg;
        }
    }
}

TEST(KindDescriptors, WaveModelKeysOfOtherModelsAndUnknownModels) {
    const auto& kinds = surfaces::waveModelKinds();
    // A key of another model is refused at the key, naming the models that take it.
    for (const std::string& key : surfaces::waveModelKeys()) {
        const std::string users = surfaces::waveModelsTaking(key);
        ASSERT_FALSE(users.empty()) << key;
        for (const WaveKind& k : kinds.kinds()) {
            if (k.takes(key)) continue;
            SourceLoc where;
            const std::string msg = surfaceError(waveScene(k, key, key == "sea" ? "clean" : "1"), &where);
            EXPECT_NE(msg.find(fmt::format("water.surface.{}: does not apply to model {}; it is used by: {}", key,
                                           k.info.name, users)),
                      std::string::npos)
                << msg;
            EXPECT_EQ(where.line, 5) << msg;
        }
    }
    EXPECT_EQ(surfaces::waveModelsTaking("gamma"), "jonswap");
    // An unknown model gets a did-you-mean, at the model's line.
    SourceLoc where;
    const std::string msg = surfaceError("water:\n  surface:\n    model: jonswop\n    wind_speed: 5\n", &where);
    EXPECT_NE(msg.find("did you mean 'jonswap'"), std::string::npos) << msg;
    EXPECT_EQ(where.line, 3) << msg;
    try {
        (void)kinds.get("elfouhali", "water.surface.model");
        ADD_FAILURE();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("did you mean 'elfouhaily'"), std::string::npos) << e.what();
    }
}

// docs/scene-format.md lists every wave model's parameters and choices, with the descriptor's
// default and range, and nothing else.
TEST(KindDescriptors, DocsListExactlyTheRegisteredWaveModelParameters) {
    std::set<std::pair<std::string, std::string>> documented, registered;
    for (const auto& row : docsTable("wave model")) {
        if (row[0] == "model") continue;  // the header
        ASSERT_GE(row.size(), 5u);
        documented.insert({row[0], row[1]});
        if (row[1] == "—") continue;
        const WaveKind* k = surfaces::waveModelKinds().find(row[0]);
        ASSERT_NE(k, nullptr) << row[0];
        if (const auto* c = k->choice(row[1])) {
            EXPECT_EQ(row[2], c->defaultValue) << row[0] << " " << row[1];
            EXPECT_EQ(row[3], joinList(c->allowed)) << row[0] << " " << row[1];
            continue;
        }
        const ParamSpec* p = k->info.param(row[1]);
        ASSERT_NE(p, nullptr) << row[0] << " " << row[1];
        EXPECT_EQ(row[3], p->rangeText()) << row[0] << " " << row[1];
        EXPECT_EQ(row[2], p->defaultValue ? formatValue(p->defaultParamValue()) : "required") << row[0] << " " << row[1];
    }
    for (const WaveKind& k : surfaces::waveModelKinds().kinds()) {
        if (k.info.params.empty() && k.choices.empty()) registered.insert({k.info.name, "—"});
        for (const ParamSpec& p : k.info.params) registered.insert({k.info.name, p.name});
        for (const auto& c : k.choices) registered.insert({k.info.name, c.key});
    }
    EXPECT_EQ(documented, registered);
}

TEST(KindDescriptors, ProbeQuantitiesMatchTheParserAndTheRenderer) {
    render::registerEstimatorKinds();
    ASSERT_FALSE(probeQuantityKinds().empty());
    for (const KindInfo& k : probeQuantityKinds().kinds()) {
        SCOPED_TRACE(k.name);
        EXPECT_EQ(k.family, "probe quantity");
        EXPECT_FALSE(k.doc.empty());
        EXPECT_TRUE(k.params.empty());
        const auto spec = parse("scene: {name: kinds}\nprobes:\n  - {name: p, position: [0, 0, 1], quantities: [" + k.name +
                                "]}\n");
        const ir::SceneIR back = roundTrip(irOf(spec));
        EXPECT_EQ(back.probes.at(0).quantities, std::vector<std::string>{k.name});
    }
    const std::string msg =
        parseError("scene: {name: kinds}\nprobes:\n  - {name: p, position: [0, 0, 1], quantities: [Eud]}\n");
    EXPECT_NE(msg.find("did you mean"), std::string::npos) << msg;
}

// ---- material types ---------------------------------------------------------------------------

namespace {

std::string lobeText(uint8_t f) {
    std::vector<std::string> v;
    if (f & kReflection) v.push_back("reflection");
    if (f & kTransmission) v.push_back("transmission");
    if (f & kDiffuse) v.push_back("diffuse");
    if (f & kSpecular) v.push_back("specular");
    if (f & kGlossy) v.push_back("glossy");
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
    return s.empty() ? "—" : s;
}

// The IR text of one material of `kind`, every key it needs present, `key` set to `value` (JSON).
std::string materialIr(const MaterialKind& kind, const std::string& key, const std::string& value) {
    ir::SceneIR s;
    ir::Material m;
    m.name = "m";
    m.type = kind.type;
    m.windSpeed = 5;
    if (kind.hasReflectance) m.reflectance = Spectrum::constant(0.5);
    m.texture = "t.tif";
    m.classMaterials = {"m"};
    s.materials.push_back(m);
    if (key.empty()) return ir::toJsonText(s);
    nlohmann::ordered_json j = nlohmann::ordered_json::parse(ir::toJsonText(s));
    if (!key.empty()) j["materials"][0][key] = nlohmann::ordered_json::parse(value);
    return j.dump(2);
}

std::string irError(const std::string& text) {
    try {
        (void)ir::fromJsonText(text, "scene.json");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

namespace {

// A pinhole or orthographic sensor with `param: value` on line 9 (`param` left out when `value` is
// ""), then the type's other required parameters (at the low end of their ranges).
std::string sensorScene(const SensorKind& k, const std::string& param, const std::string& value) {
    std::string s = "scene: {name: kinds}\nsensors:\n  - name: cam\n    type: " + k.info.name +
                    "\n    position: [0, 0, 10]\n    direction: [0, 0, -1]\n    width: 4\n    height: 3\n";
    if (!param.empty() && !value.empty()) s += "    " + param + ": " + value + "\n";
    for (const ParamSpec& p : k.info.params)
        if (p.sceneName() != param && !p.defaultValue) s += "    " + p.sceneName() + ": " + fmt::format("{}", p.lo) + "\n";
    return s;
}

}  // namespace

TEST(KindDescriptors, EveryMaterialTypeHasOneDescriptorAndTheDocsListThem) {
    // Every enumerator of ir::Material::Type is registered once, and the docs' table lists the
    // registered types with their lobes, solvers and doc line.
    std::set<std::string> names;
    for (const auto& e : EnumNames<ir::Material::Type>::table) {
        const MaterialKind& k = materialKind(e.value);
        EXPECT_EQ(k.info.name, e.name);
        EXPECT_EQ(k.info.family, "material type");
        names.insert(k.info.name);
    }
    EXPECT_EQ(names.size(), materialKinds().kinds().size());
    std::vector<std::string> documented;
    for (const auto& row : docsTable("material type")) {
        ASSERT_EQ(row.size(), 6u);
        const MaterialKind* k = materialKinds().find(row[0]);
        ASSERT_NE(k, nullptr) << row[0];
        documented.push_back(row[0]);
        EXPECT_EQ(row[1], k->inSceneFiles ? "yes" : "no") << row[0];
        EXPECT_EQ(row[2], lobeText(k->lobes)) << row[0];
        EXPECT_EQ(row[3], std::string(nameOf(k->defaultSolver))) << row[0];
        EXPECT_EQ(row[4], k->namedSolvers.empty() ? "—" : joinList(k->solverNames())) << row[0];
        EXPECT_EQ(row[5], k->info.doc) << row[0];
    }
    EXPECT_EQ(documented, materialKinds().names());
    // The key table: exactly the keys each type uses, numbers with the descriptor's range.
    std::set<std::pair<std::string, std::string>> keys, registered;
    for (const auto& row : docsTable("material type key")) {
        keys.insert({row[0], row[1]});
        const MaterialKind* k = materialKinds().find(row[0]);
        ASSERT_NE(k, nullptr) << row[0];
        if (const ParamSpec* p = k->info.param(row[1])) {
            EXPECT_EQ(row[3], p->rangeText()) << row[0] << " " << row[1];
            EXPECT_EQ(row[2], p->defaultValue ? formatValue(p->defaultParamValue()) : "required") << row[1];
        }
    }
    for (const MaterialKind& k : materialKinds().kinds()) {
        if (k.hasReflectance) registered.insert({k.info.name, "reflectance"});
        for (const ParamSpec& p : k.info.params) registered.insert({k.info.name, p.name});
        for (const std::string& key : k.irKeys) registered.insert({k.info.name, key});
    }
    EXPECT_EQ(keys, registered);
    // The scene file's type list is the descriptors' (the materials table's allowed values).
    EXPECT_EQ(sceneMaterialTypeNames(), (std::vector<std::string>{"lambertian", "dielectric", "black"}));
}

TEST(KindDescriptors, MaterialTypeNumbersMatchTheIrReader) {
    for (const MaterialKind& k : materialKinds().kinds()) {
        SCOPED_TRACE(k.info.name);
        // The complete material round-trips byte-identically.
        const std::string text = materialIr(k, "", "");
        ASSERT_EQ(irError(text), "") << text;
        EXPECT_EQ(ir::toJsonText(ir::fromJsonText(text, "scene.json")), text);
        for (const ParamSpec& p : k.info.params) {
            SCOPED_TRACE(p.name);
            for (const Trial& t : insideValues(p)) {
                const std::string e = irError(materialIr(k, p.name, t.text));
                EXPECT_EQ(e, "") << t.text;
                if (!e.empty()) continue;
                const ir::Material m = ir::fromJsonText(materialIr(k, p.name, t.text), "scene.json").materials[0];
                const double got = p.name == "wind_speed_mps"     ? m.windSpeed
                                   : p.name == "wind_azimuth_rad" ? m.windAzimuth
                                                                  : (m.gramCharlier ? 1.0 : 0.0);
                EXPECT_EQ(got, numberOf(t.value));
            }
            for (const std::string& out : outsideTexts(p)) {
                const std::string e = irError(materialIr(k, p.name, out));
                EXPECT_NE(e.find("materials[0]." + p.name), std::string::npos) << e;
                if (p.type != ParamType::Boolean) {
                    EXPECT_NE(e.find(p.rangeText()), std::string::npos) << e;
                }
            }
        }
    }
    // A key of another type is refused, naming the types that use it.
    const std::string e = irError(materialIr(materialKind(ir::Material::Type::Lambertian), "wind_speed_mps", "5"));
    EXPECT_NE(e.find("materials[0].wind_speed_mps: a lambertian material does not use this key; it belongs to: "
                     "rough-dielectric"),
              std::string::npos)
        << e;
    // A reflectance on a type without one is refused.
    const std::string r = irError(materialIr(materialKind(ir::Material::Type::Dielectric), "reflectance", "0.3"));
    EXPECT_NE(r.find("materials[0].reflectance: a dielectric material has no reflectance"), std::string::npos) << r;
    // An unknown type gets a did-you-mean.
    const std::string u = irError(materialIr(materialKind(ir::Material::Type::Lambertian), "type", "\"lambertain\""));
    EXPECT_NE(u.find("did you mean 'lambertian'"), std::string::npos) << u;
}

TEST(KindDescriptors, MaterialSceneKeysAndSolversMatchTheParser) {
    const std::string base = "scene: {name: kinds}\nmaterials:\n  - {name: m, type: ";
    for (const std::string& type : sceneMaterialTypeNames()) {
        SCOPED_TRACE(type);
        const MaterialKind& k = *materialKinds().find(type);
        // Every scene key of another type is refused at the key, naming the types that take it.
        for (const std::string& other : sceneMaterialTypeNames())
            for (const std::string& key : materialKinds().find(other)->sceneKeys) {
                if (k.takesSceneKey(key)) continue;
                SourceLoc at;
                const std::string e = parseError(base + type + ", " + key + ": 1.2}\n", &at);
                EXPECT_FALSE(e.empty()) << key;
                EXPECT_EQ(at.line, 3) << key << ": " << e;
                if (key != "solver" && key != "reflectance") {
                    EXPECT_NE(e.find(sceneTypesWithKey(key)), std::string::npos) << e;
                }
            }
    }
    // The solvers a lambertian may name are exactly its descriptor's, and every interface refuses
    // a solver in the IR too (`generic` on an interface changes nothing).
    for (const auto& e : EnumNames<ir::Material::Solver>::table) {
        const std::string err = parseError(base + "lambertian, reflectance: 0.2, solver: " + std::string(e.name) + "}\n");
        const auto& ok = materialKind(ir::Material::Type::Lambertian).namedSolvers;
        EXPECT_EQ(err.empty(), std::find(ok.begin(), ok.end(), e.value) != ok.end()) << e.name << ": " << err;
    }
    for (ir::Material::Type t : {ir::Material::Type::Dielectric, ir::Material::Type::RoughDielectric}) {
        ir::SceneIR s = ir::fromJsonText(materialIr(materialKind(t), "solver", "\"generic\""), "scene.json");
        try {
            (void)render::makeRenderConfig(s);
            ADD_FAILURE() << nameOf(t);
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("solver generic cannot evaluate a"), std::string::npos) << e.what();
        }
    }
}

TEST(KindDescriptors, SensorTypeParametersMatchTheParserTheIrAndTheCamera) {
    ASSERT_EQ(sensorTypeKinds().names(), allNames<ir::Sensor::Type>());
    for (const SensorKind& k : sensorTypeKinds().kinds()) {
        SCOPED_TRACE(k.info.name);
        EXPECT_EQ(k.info.family, "sensor type");
        EXPECT_FALSE(k.info.doc.empty());
        ASSERT_EQ(k.fields.size(), k.info.params.size());
        for (size_t i = 0; i < k.info.params.size(); ++i) {
            const ParamSpec& p = k.info.params[i];
            const SensorField& f = k.fields[i];
            SCOPED_TRACE(p.sceneName());
            EXPECT_FALSE(p.doc.empty());
            for (const Trial& t : insideValues(p)) {
                const auto spec = parse(sensorScene(k, p.sceneName(), t.text));
                const double irValue = numberOf(t.value) * f.irScale;  // the scene file's unit -> m
                EXPECT_EQ(spec.sensors.at(0).optics.number(p.name), irValue) << t.text;
                const ir::SceneIR ir = irOf(spec);
                EXPECT_EQ(ir.sensors.at(0).type, k.type);
                EXPECT_EQ(ir.sensors.at(0).*f.field, irValue) << t.text;
                EXPECT_NE(ir::toJsonText(ir).find("\"" + p.name + "\""), std::string::npos);
                const ir::SceneIR back = roundTrip(ir);
                EXPECT_EQ(back.sensors.at(0).*f.field, irValue) << t.text;
                // The type's camera factory builds it.
                EXPECT_NO_THROW(render::Camera{back.sensors.at(0)}) << t.text;
            }
            for (const std::string& out : outsideTexts(p)) {
                SourceLoc where;
                const std::string msg = parseError(sensorScene(k, p.sceneName(), out), &where);
                EXPECT_NE(msg.find("out of range; allowed " + p.rangeText()), std::string::npos) << out << ": " << msg;
                EXPECT_EQ(where.file, "kinds.yaml");
                EXPECT_EQ(where.line, 9) << msg;
            }
            if (!p.defaultValue) {
                const std::string msg = parseError(sensorScene(k, p.sceneName(), ""));
                EXPECT_NE(msg.find(p.sceneName()), std::string::npos) << msg;
            }
        }
        // A parameter of another type is refused, naming the type that uses it.
        for (const SensorKind& other : sensorTypeKinds().kinds())
            for (const ParamSpec& q : other.info.params) {
                if (k.info.paramBySceneKey(q.sceneName())) continue;
                SourceLoc where;
                const std::string msg = parseError(sensorScene(k, q.sceneName(), fmt::format("{}", q.lo)), &where);
                EXPECT_NE(msg.find("'" + q.sceneName() + "' is only used by the " + other.info.name + " sensor type"),
                          std::string::npos)
                    << msg;
                EXPECT_EQ(where.line, 9) << msg;
                // A frame sensor (a placement that makes a pinhole) takes none of them.
                const std::string frame = parseError(
                    "scene: {name: kinds}\nsensors:\n  - {name: cam, type: frame, elevation_deg: 90, azimuth_deg: 0, "
                    "range_m: 10, gsd_m: 0.1, width: 4, height: 3, " +
                    q.sceneName() + ": 1}\n");
                EXPECT_NE(frame.find("not used by a frame sensor"), std::string::npos) << frame;
            }
    }
}

TEST(KindDescriptors, UnknownSensorTypeGetsADidYouMean) {
    const std::string msg = parseError(
        "scene: {name: kinds}\nsensors:\n  - {name: cam, type: orthographc, position: [0, 0, 1], direction: [0, 0, -1], "
        "pixel_size_m: 1, width: 4, height: 3}\n");
    EXPECT_NE(msg.find("did you mean 'orthographic'"), std::string::npos) << msg;
    // The IR reader gives the same did-you-mean.
    const SensorKind& pinhole = *sensorTypeKinds().find("pinhole");
    std::string text = ir::toJsonText(irOf(parse(sensorScene(pinhole, "", ""))));
    text.replace(text.find("\"pinhole\""), 9, "\"pinhol\"");
    try {
        (void)ir::fromJsonText(text, "scene.json");
        ADD_FAILURE();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("did you mean 'pinhole'"), std::string::npos) << e.what();
    }
}

TEST(KindDescriptors, IrSensorKeysOfAnotherTypeAreRefused) {
    // A hand-edited pinhole with the orthographic pixel_size_m: it would do nothing, so the IR
    // reader refuses it at its key, naming the type it belongs to.
    const SensorKind& pinhole = *sensorTypeKinds().find("pinhole");
    nlohmann::ordered_json j = nlohmann::ordered_json::parse(ir::toJsonText(irOf(parse(sensorScene(pinhole, "", "")))));
    j["sensors"][0]["pixel_size_m"] = 0.1;
    try {
        (void)ir::fromJsonText(j.dump(2), "scene.json");
        ADD_FAILURE();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("sensors[0].pixel_size_m: a pinhole sensor does not use this key; it "
                                             "belongs to the orthographic sensor type"),
                  std::string::npos)
            << e.what();
    }
}

namespace {

// `constituents:` with `param: value` on line 5.
std::string constituentsScene(const std::string& param, const std::string& value) {
    return "scene: {name: kinds}\nwater:\n  optics:\n    constituents:\n      " + param + ": " + value + "\n";
}

// The grid parseIops tabulates constituent spectra on for the default band [0.4, 0.6] um: 5 nm.
std::vector<double> defaultBandGrid() {
    const double lo = 0.4, hi = 0.6;
    std::vector<double> wl;
    for (int i = 0; i <= 40; ++i) wl.push_back(lo + (hi - lo) * i / 40);
    return wl;
}

}  // namespace

TEST(KindDescriptors, ConstituentParametersMatchTheParser) {
    const MediumModelKind* model = mediumModelKinds().find("constituents");
    ASSERT_NE(model, nullptr);
    EXPECT_EQ(model->info.family, "medium model");
    ASSERT_EQ(model->fields.size(), model->info.params.size());
    for (size_t i = 0; i < model->info.params.size(); ++i) {
        const ParamSpec& p = model->info.params[i];
        SCOPED_TRACE(p.name);
        EXPECT_FALSE(p.doc.empty());
        EXPECT_FALSE(p.unit.empty());
        // Omitted, the parameter takes its default.
        WaterComposition defaults;
        EXPECT_EQ(defaults.*model->fields[i], p.defaultValue.value_or(-1));
        for (const Trial& t : insideValues(p)) {
            const auto spec = parse(constituentsScene(p.name, t.text));
            // The value reaches the composition: the IOPs are those computeIops gives for it.
            WaterComposition comp;
            comp.*model->fields[i] = numberOf(t.value);
            const WaterIops w = computeIops(comp, defaultBandGrid());
            const LayerOptics& o = spec.waterOptics.iops;
            EXPECT_EQ(o.preset, "constituents");
            for (double wl : {0.4, 0.47, 0.6}) EXPECT_DOUBLE_EQ(o.absorption.at(wl), w.absorption().at(wl)) << t.text;
            (void)roundTrip(irOf(spec));
        }
        for (const std::string& out : outsideTexts(p)) {
            SourceLoc where;
            const std::string msg = parseError(constituentsScene(p.name, out), &where);
            EXPECT_NE(msg.find("out of range; allowed " + p.rangeText()), std::string::npos) << out << ": " << msg;
            EXPECT_EQ(where.file, "kinds.yaml");
            EXPECT_EQ(where.line, 5) << msg;
        }
    }
    const std::string typo = parseError(constituentsScene("chlorophyl_mg_m3", "1"));
    EXPECT_NE(typo.find("did you mean 'chlorophyll_mg_m3'"), std::string::npos) << typo;
    // One model per node, the message naming the models' keys.
    const std::string two = parseError("scene: {name: kinds}\nwater:\n  optics: {preset: low, constituents: {}}\n");
    EXPECT_NE(two.find("give one of 'preset', 'constituents' or absorption_per_m/scattering_per_m"), std::string::npos)
        << two;
}

TEST(KindDescriptors, WaterPresetsParseAndUnknownOnesGetADidYouMean) {
    ASSERT_FALSE(waterPresetKinds().empty());
    EXPECT_EQ(waterPresetNames(), waterPresetKinds().names());
    for (const WaterPresetKind& k : waterPresetKinds().kinds()) {
        SCOPED_TRACE(k.info.name);
        EXPECT_EQ(k.info.family, "water preset");
        EXPECT_TRUE(k.info.params.empty());
        // The doc line says whether the preset includes pure water, and the preset agrees.
        const WaterIops w = k.make();
        EXPECT_EQ(w.name, k.info.name);
        EXPECT_FALSE(w.includesPureWater);
        EXPECT_NE(k.info.doc.find("pure water"), std::string::npos) << k.info.doc;
        const auto spec = parse("scene: {name: kinds}\nwater:\n  optics:\n    preset: " + k.info.name + "\n");
        EXPECT_EQ(spec.waterOptics.iops.preset, k.info.name);
        EXPECT_EQ(roundTrip(irOf(spec)).metadata.at("water.iop_preset"), k.info.name);
    }
    SourceLoc where;
    const std::string msg = parseError("scene: {name: kinds}\nwater:\n  optics:\n    preset: coastl\n", &where);
    EXPECT_NE(msg.find("did you mean 'coastal'"), std::string::npos) << msg;
    EXPECT_EQ(where.line, 4);
}

TEST(KindDescriptors, DocsListExactlyTheSensorTypesAndMediumModels) {
    // Sensor types: one row per parameter, with the scene file's default and range and the IR key.
    std::set<std::pair<std::string, std::string>> documented, registered;
    for (const auto& row : docsTable("sensor type")) {
        ASSERT_GE(row.size(), 6u);
        documented.insert({row[0], row[1]});
        const SensorKind* k = sensorTypeKinds().find(row[0]);
        ASSERT_NE(k, nullptr) << row[0];
        const ParamSpec* p = k->info.paramBySceneKey(row[1]);
        ASSERT_NE(p, nullptr) << row[0] << " " << row[1];
        EXPECT_EQ(row[2] == "required", !p->defaultValue) << row[1];
        EXPECT_EQ(row[3], p->rangeText()) << row[1];
        EXPECT_EQ(row[4], p->name) << row[1];
    }
    for (const SensorKind& k : sensorTypeKinds().kinds())
        for (const ParamSpec& p : k.info.params) registered.insert({k.info.name, p.sceneName()});
    EXPECT_EQ(documented, registered);

    // Medium models: one row each, with the keys that choose it.
    std::vector<std::string> models;
    for (const auto& row : docsTable("medium model")) {
        models.push_back(row[0]);
        const MediumModelKind* m = mediumModelKinds().find(row[0]);
        ASSERT_NE(m, nullptr) << row[0];
        EXPECT_EQ(row[1], joinList(m->sceneKeys)) << row[0];
    }
    EXPECT_EQ(models, mediumModelKinds().names());

    // The constituents model: its parameters with default and range, and the keys that are not
    // numbers (read by the parser itself: the choice of pure water and the phase functions).
    const KindInfo& constituents = mediumModelKinds().find("constituents")->info;
    std::set<std::string> keys, declared = {"pure_water", "pure_water_phase", "particle_phase", "phytoplankton_phase",
                                            "sediment_phase"};
    for (const auto& row : docsTable("medium model constituents")) {
        keys.insert(row[0]);
        if (const ParamSpec* p = constituents.param(row[0])) {
            EXPECT_EQ(row[1], formatValue(p->defaultParamValue())) << row[0];
            EXPECT_EQ(row[2], p->rangeText()) << row[0];
        }
    }
    for (const ParamSpec& p : constituents.params) declared.insert(p.name);
    EXPECT_EQ(keys, declared);

    // Water presets: one row each, in order, with whether it includes pure water and the doc line.
    std::vector<std::string> presets;
    for (const auto& row : docsTable("water preset")) {
        presets.push_back(row[0]);
        const WaterPresetKind* k = waterPresetKinds().find(row[0]);
        ASSERT_NE(k, nullptr) << row[0];
        EXPECT_EQ(row[1], k->pureWater) << row[0];
        EXPECT_FALSE(k->make().includesPureWater) << row[0];  // make() is the source as published
        EXPECT_EQ(row[2], k->info.doc) << row[0];
    }
    EXPECT_EQ(presets, waterPresetKinds().names());
}
