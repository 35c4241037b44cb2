#include "core/scene_ir.h"

#include "core/material_kinds.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/output_names.h"
#include "core/phase_functions.h"
#include "core/sensor_types.h"
#include "core/suggest.h"
#include "core/units.h"

namespace littoral::ir {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

Vec3 Sun::direction() const {
    const double s = std::sin(zenith);
    return {s * std::cos(azimuth), s * std::sin(azimuth), std::cos(zenith)};
}

const Material* SceneIR::findMaterial(const std::string& n) const {
    for (const auto& m : materials)
        if (m.name == n) return &m;
    return nullptr;
}
const Sensor* SceneIR::findSensor(const std::string& n) const {
    for (const Sensor& x : sensors)
        if (x.name == n) return &x;
    return nullptr;
}

const Medium* SceneIR::findMedium(const std::string& n) const {
    for (const auto& m : media)
        if (m.name == n) return &m;
    return nullptr;
}
const Mesh* SceneIR::findMesh(const std::string& n) const {
    for (const auto& m : meshes)
        if (m.name == n) return &m;
    return nullptr;
}

Medium Medium::homogeneous(std::string name, double n, Spectrum a, Spectrum b, PhaseFunction phase) {
    Medium m;
    m.name = std::move(name);
    m.refractiveIndex = Spectrum::constant(n);
    m.layers[0].absorption = std::move(a);
    if (!(b.isConstant() && b.values()[0] == 0.0)) m.layers[0].scatterers.push_back({"particles", std::move(b), phase});
    return m;
}

std::string checkLayers(const Medium& m) {
    if (m.layers.empty()) return "a medium needs at least one layer";
    if (m.layers.front().zTop != kInfinity) return "the first layer must reach up without limit (z_top_m null)";
    if (m.layers.back().zBottom != -kInfinity) return "the last layer must reach down without limit (z_bottom_m null)";
    for (size_t i = 0; i < m.layers.size(); ++i) {
        const Layer& l = m.layers[i];
        if (!(l.zTop > l.zBottom)) return fmt::format("layer {} is empty or inverted: top {} m, bottom {} m", i, l.zTop, l.zBottom);
        if (i > 0 && m.layers[i - 1].zBottom != l.zTop)
            return fmt::format("layers {} and {} leave a gap or overlap: layer {} ends at z = {} m, layer {} starts at "
                               "z = {} m",
                               i - 1, i, i - 1, m.layers[i - 1].zBottom, i, l.zTop);
    }
    return "";
}

// ---------------------------------------------------------------------------------------------
// Writing

namespace {

std::string nm(auto e) { return std::string(nameOf(e)); }
Json spectrumJson(const Spectrum& s) {
    if (s.isConstant()) return Json(s.values().empty() ? 0.0 : s.values()[0]);
    Json j;
    j["wavelengths_um"] = s.wavelengths();
    j["values"] = s.values();
    return j;
}
Json vecJson(const Vec3& v) { return Json::array({v.x, v.y, v.z}); }
// Infinite layer bounds are written as null (JSON has no infinity).
Json boundJson(double z) { return std::isfinite(z) ? Json(z) : Json(nullptr); }
Json paramJson(const ParamValue& v) {
    if (const auto* i = std::get_if<int64_t>(&v)) return Json(*i);
    if (const auto* d = std::get_if<double>(&v)) return Json(*d);
    return Json(std::get<bool>(v));
}
// A parameter is written when its kind requires it or it differs from its default.
Json phaseJson(const PhaseFunction& p) {
    Json j = {{"type", p.type}};
    const PhaseKind* kind = phaseFunctionKinds().find(p.type);
    for (const auto& [key, value] : p.params) {
        const ParamSpec* spec = kind ? kind->info.param(key) : nullptr;
        if (spec && spec->defaultValue && numberOf(value) == *spec->defaultValue) continue;
        j[key] = paramJson(value);
    }
    return j;
}

}  // namespace

namespace {

Json mediumJson(const Medium& m) {
    Json layers = Json::array();
    for (const auto& l : m.layers) {
        Json sc = Json::array();
        for (const auto& c : l.scatterers)
            sc.push_back({{"name", c.name}, {"scattering_per_m", spectrumJson(c.scattering)}, {"phase", phaseJson(c.phase)}});
        layers.push_back({{"z_top_m", boundJson(l.zTop)},
                          {"z_bottom_m", boundJson(l.zBottom)},
                          {"absorption_per_m", spectrumJson(l.absorption)},
                          {"scatterers", sc}});
    }
    Json mj = {{"name", m.name}, {"refractive_index", spectrumJson(m.refractiveIndex)}, {"layers", layers}};
    if (m.solver) mj["solver"] = nm(*m.solver);
    return mj;
}

// The keys the material's type uses (core/material_kinds.h), in a fixed order.
Json materialJson(const Material& m) {
    const MaterialKind& kind = materialKind(m.type);
    Json mj = {{"name", m.name}, {"type", nm(m.type)}};
    if (m.solver) mj["solver"] = nm(*m.solver);
    mj["reflectance"] = spectrumJson(m.reflectance);
    const Json extent = Json::array({m.textureX0, m.textureY0, m.textureX1, m.textureY1});
    if (kind.uses("texture")) mj["texture"] = {{"file", m.texture}, {"extent_m", extent}};
    if (kind.uses("class_map")) mj["class_map"] = {{"file", m.texture}, {"extent_m", extent}, {"classes", m.classMaterials}};
    if (kind.uses("wind_speed_mps")) mj["wind_speed_mps"] = m.windSpeed;
    if (kind.uses("wind_azimuth_rad")) mj["wind_azimuth_rad"] = m.windAzimuth;
    if (kind.uses("sea")) mj["sea"] = nm(m.sea);
    if (kind.uses("slopes") && m.slopes != CoxMunkSlopes::Anisotropic) mj["slopes"] = nm(m.slopes);
    if (kind.uses("gram_charlier")) mj["gram_charlier"] = m.gramCharlier;
    if (kind.uses("shadowing")) mj["shadowing"] = nm(m.shadowing);
    return mj;
}

Json sensorJson(const Sensor& c) {
    Json cj = {{"name", c.name},
               {"type", nm(c.type)},
               {"position_m", vecJson(c.position)},
               {"forward", vecJson(c.forward)},
               {"up", vecJson(c.up)},
               {"width", c.width},
               {"height", c.height}};
    // The parameters of the sensor's type (core/sensor_types.h), in metres.
    const SensorKind& kind = sensorKind(c.type);
    for (size_t i = 0; i < kind.info.params.size(); ++i) cj[kind.info.params[i].name] = c.*kind.fields[i].field;
    cj["samples_per_pixel"] = c.samplesPerPixel;
    cj["medium"] = c.medium;
    if (c.psf) {
        Json pj = {{"type", c.psf->type}};
        if (c.psf->type == "gaussian") pj["fwhm_px"] = c.psf->fwhmPx;
        else pj["width"] = c.psf->width, pj["height"] = c.psf->height, pj["values"] = c.psf->values;
        cj["psf"] = pj;
    }
    if (c.detector) {
        const SensorDetector& d = *c.detector;
        cj["detector"] = {{"aperture_diameter_m", d.apertureDiameter}, {"integration_time_s", d.integrationTime},
                          {"quantum_efficiency", d.quantumEfficiency}, {"read_noise_e", d.readNoise},
                          {"full_well_e", d.fullWell}, {"bits", d.bits}, {"seed", d.seed}};
    }
    if (c.waterProducts) cj["water_products"] = true;
    return cj;
}

Json renderJson(const RenderSettings& r) {
    Json bands = Json::array();
    for (const auto& b : r.bands) bands.push_back(Json::array({b.lo, b.hi}));
    Json rj = {{"bands_um", bands}, {"seed", r.seed}, {"threads", r.threads}, {"estimator", nm(r.estimator)}};
    if (!r.responseBands.empty()) {
        Json rb = Json::array();
        for (const ResponseBand& o : r.responseBands) {
            Json w = Json::array();
            for (const auto& [i, x] : o.weights) w.push_back(Json::array({i, x}));
            rb.push_back({{"kind", o.kind}, {"nominal_um", Json::array({o.nominal.lo, o.nominal.hi})}, {"weights", w}});
        }
        rj["response_bands"] = rb;
    }
    // Optional settings: written only when set (unset = the estimator's default), in the order set.
    for (const auto& [key, value] : r.settings) rj[key] = paramJson(value);
    return rj;
}

}  // namespace

std::string toJsonText(const SceneIR& s) {
    Json j;
    j["format"] = "littoral-scene-ir";
    j["version"] = kFormatVersion;
    j["name"] = s.name;
    Json meta = Json::object();
    for (const auto& [k, v] : s.metadata) meta[k] = v;
    j["metadata"] = meta;

    j["render"] = renderJson(s.render);
    j["domain"] = {{"x_m", Json::array({s.domain.x0, s.domain.x1})},
                   {"y_m", Json::array({s.domain.y0, s.domain.y1})},
                   {"horizontal", s.domain.periodic ? "periodic" : "bounded"}};
    j["sun"] = {{"enabled", s.sun.enabled},
                {"zenith_rad", s.sun.zenith},
                {"azimuth_rad", s.sun.azimuth},
                {"half_angle_rad", s.sun.halfAngle},
                {"irradiance", spectrumJson(s.sun.irradiance)}};
    j["sky"] = {{"radiance", spectrumJson(s.sky.radiance)}};
    if (s.geo)
        j["geo"] = {{"frame", s.geo->frame},
                    {"latitude_deg", s.geo->latitudeDeg},
                    {"longitude_deg", s.geo->longitudeDeg},
                    {"altitude_m", s.geo->altitudeM},
                    {"utm_zone", s.geo->utmZone}};

    Json media = Json::array();
    for (const auto& m : s.media) media.push_back(mediumJson(m));
    j["media"] = media;

    Json mats = Json::array();
    for (const auto& m : s.materials) mats.push_back(materialJson(m));
    j["materials"] = mats;

    Json meshes = Json::array();
    for (const auto& m : s.meshes)
        meshes.push_back({{"name", m.name},
                          {"file", m.file},
                          {"materials", m.materials},
                          {"inside", m.inside},
                          {"outside", m.outside},
                          {"closed", m.closed}});
    j["meshes"] = meshes;

    Json inst = Json::array();
    for (const auto& in : s.instances)
        inst.push_back({{"mesh", in.mesh},
                        {"rotation", std::vector<double>(in.rotation, in.rotation + 9)},
                        {"translation_m", vecJson(in.translation)}});
    j["instances"] = inst;

    Json sensors = Json::array();
    for (const auto& c : s.sensors) sensors.push_back(sensorJson(c));
    j["sensors"] = sensors;

    Json probes = Json::array();
    for (const auto& p : s.probes) {
        Json pj = {{"name", p.name}, {"position_m", vecJson(p.position)}, {"quantities", p.quantities}, {"medium", p.medium}};
        if (p.samples) pj["samples"] = *p.samples;
        probes.push_back(pj);
    }
    j["probes"] = probes;
    // Names were validated on the way in; replace (not throw on) any invalid UTF-8 in free text
    // such as a file name recorded in the metadata, so writing an IR cannot fail half-way.
    return j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

void writeIR(const SceneIR& s, const fs::path& dir) {
    createOutputFolder(dir);
    std::set<std::string> files;
    for (const auto& m : s.meshes) {
        if (m.file.empty() || fs::path(m.file).is_absolute() || m.file.find("..") != std::string::npos)
            throw InternalError("IR mesh '" + m.name + "' needs a relative file path inside the IR directory");
        if (!files.insert(m.file).second) throw InternalError("IR meshes share the file " + m.file);
        writePly(dir / m.file, m.data);
    }
    writeTextFileAtomic(dir / "scene.json", toJsonText(s));
}

// ---------------------------------------------------------------------------------------------
// Reading: strict, every mistake names scene.json and the JSON path.

namespace {

class JReader {
public:
    JReader(const Json& j, std::string path, const std::string& file) : j_(j), path_(std::move(path)), file_(file) {}

    [[noreturn]] void fail(const std::string& msg) const {
        throw InputError(SourceLoc{file_}, (path_.empty() ? std::string("(top level)") : path_) + ": " + msg);
    }
    void expectKeys(const std::vector<std::string>& allowed) const {
        if (!j_.is_object()) fail("expected an object");
        for (auto it = j_.begin(); it != j_.end(); ++it) {
            if (std::find(allowed.begin(), allowed.end(), it.key()) != allowed.end()) continue;
            std::string m = fmt::format("unknown key '{}' (allowed: {})", it.key(), joinList(allowed));
            const auto near = closestMatch(it.key(), allowed);
            if (!near.empty()) m += fmt::format("; did you mean '{}'?", near);
            fail(m);
        }
    }
    bool has(const std::string& k) const { return j_.is_object() && j_.contains(k); }
    JReader operator[](const std::string& k) const {
        if (!j_.is_object()) fail("expected an object");
        auto it = j_.find(k);
        if (it == j_.end()) fail("missing key '" + k + "'");
        return JReader(*it, path_.empty() ? k : path_ + "." + k, file_);
    }
    JReader at(size_t i) const { return JReader(j_.at(i), fmt::format("{}[{}]", path_, i), file_); }
    size_t size() const {
        if (!j_.is_array()) fail("expected an array");
        return j_.size();
    }
    double num() const {
        if (!j_.is_number()) fail("expected a number");
        return j_.get<double>();
    }
    int64_t integer() const {
        if (!j_.is_number_integer()) fail("expected an integer");
        return j_.get<int64_t>();
    }
    uint64_t uinteger() const {
        if (!j_.is_number_unsigned() && !(j_.is_number_integer() && j_.get<int64_t>() >= 0))
            fail("expected a non-negative integer");
        return j_.get<uint64_t>();
    }
    bool boolean() const {
        if (!j_.is_boolean()) fail("expected true or false");
        return j_.get<bool>();
    }
    std::string str() const {
        if (!j_.is_string()) fail("expected a string");
        return j_.get<std::string>();
    }
    std::vector<std::string> strings() const {
        std::vector<std::string> v;
        for (size_t i = 0; i < size(); ++i) v.push_back(at(i).str());
        return v;
    }
    std::vector<double> nums() const {
        std::vector<double> v;
        for (size_t i = 0; i < size(); ++i) v.push_back(at(i).num());
        return v;
    }
    Vec3 vec3() const {
        const auto v = nums();
        if (v.size() != 3) fail("expected 3 numbers");
        return {v[0], v[1], v[2]};
    }
    Spectrum spectrum() const {
        if (j_.is_number()) return Spectrum::constant(num());
        expectKeys({"wavelengths_um", "values"});
        return Spectrum::tabulated((*this)["wavelengths_um"].nums(), (*this)["values"].nums(), file_ + ": " + path_);
    }
    template <class E> E choice() const {
        const std::string s = str();
        if (auto e = parseName<E>(s)) return *e;
        const auto names = allNames<E>();
        std::string m = fmt::format("unknown {} '{}' (allowed: {})", EnumNames<E>::what, s, joinList(names));
        const auto near = closestMatch(s, names);
        if (!near.empty()) m += fmt::format("; did you mean '{}'?", near);
        fail(m);
    }
    // A layer bound: a number, or null for "without limit" (`inf` is the value returned for null).
    double bound(double inf) const {
        if (j_.is_null()) return inf;
        return num();
    }
    JReader get(const std::string& k) const { return (*this)[k]; }
    // A value of a parameter of type `t`.
    ParamValue param(ParamType t) const {
        switch (t) {
            case ParamType::Boolean: return boolean();
            case ParamType::Integer: return integer();
            case ParamType::Real: break;
        }
        return num();
    }
    // A value whose type is the JSON value's own (render settings, checked by the renderer).
    ParamValue anyParam() const {
        if (j_.is_boolean()) return j_.get<bool>();
        if (j_.is_number_unsigned() && j_.get<uint64_t>() > static_cast<uint64_t>(std::numeric_limits<int64_t>::max()))
            fail("integer out of range");
        if (j_.is_number_integer()) return j_.get<int64_t>();
        if (j_.is_number()) return j_.get<double>();
        fail("expected a number or true/false");
    }
    const Json& json() const { return j_; }

private:
    const Json& j_;
    std::string path_;
    const std::string& file_;
};

// A phase function: its kind by name and that kind's parameters (core/phase_functions.h).
PhaseFunction readPhase(const JReader& ph) {
    const KindRegistry<PhaseKind>& kinds = phaseFunctionKinds();
    std::vector<std::string> keys = {"type"};
    for (const auto& k : kinds.allParamNames()) keys.push_back(k);
    ph.expectKeys(keys);
    PhaseFunction p;
    p.type = ph["type"].str();
    const PhaseKind* kind = kinds.find(p.type);
    if (!kind) ph["type"].fail(unknownKindMessage(kinds.family(), p.type, kinds.names()));
    for (size_t i = 1; i < keys.size(); ++i)
        if (ph.has(keys[i]) && !kind->info.param(keys[i]))
            ph[keys[i]].fail(fmt::format("only the {} {} has '{}'", kinds.kindsWithParam(keys[i]), kinds.family(), keys[i]));
    for (const ParamSpec& spec : kind->info.params) {
        if (!ph.has(spec.name) && spec.defaultValue) p.params.set(spec.name, spec.defaultParamValue());
        else p.params.set(spec.name, ph[spec.name].param(spec.type));
    }
    return p;
}

}  // namespace

namespace {

// Output bands as weighted means of the render bands: every weight names a band, is >= 0, and
// each band's weights sum to 1 (within rounding), so that no hand edit can scale a radiance.
void readResponseBands(const JReader& list, RenderSettings* r) {
    if (list.size() == 0) list.fail("list at least one band, or leave the key out");
    for (size_t k = 0; k < list.size(); ++k) {
        const JReader o = list.at(k);
        o.expectKeys({"kind", "nominal_um", "weights"});
        ResponseBand b;
        b.kind = o["kind"].str();
        if (b.kind != "rectangle" && b.kind != "gaussian" && b.kind != "table")
            o["kind"].fail("expected 'rectangle', 'gaussian' or 'table'");
        const auto n = o["nominal_um"].nums();
        if (n.size() != 2 || !(n[1] > n[0]) || n[0] <= 0) o["nominal_um"].fail("expected [lo, hi] with 0 < lo < hi");
        b.nominal = {n[0], n[1]};
        double sum = 0;
        const JReader w = o["weights"];
        for (size_t i = 0; i < w.size(); ++i) {
            const auto pair = w.at(i).nums();
            if (pair.size() != 2 || pair[0] < 0 || pair[0] >= static_cast<double>(r->bands.size()) ||
                pair[0] != std::floor(pair[0]) || !(pair[1] >= 0) || !std::isfinite(pair[1]))
                w.at(i).fail(fmt::format("expected [band index in [0, {}), weight >= 0]", r->bands.size()));
            b.weights.push_back({static_cast<int>(pair[0]), pair[1]});
            sum += pair[1];
        }
        if (!(std::abs(sum - 1.0) <= 1e-6)) w.fail(fmt::format("the weights sum to {}, not 1", sum));
        r->responseBands.push_back(std::move(b));
    }
}

// The render section: bands, seed, threads, estimator, and the optional settings kept generically
// (their keys, types and ranges belong to the estimators, which check them:
// render::makeRenderConfig); each keeps its JSON type and order.
void readRender(const JReader& rr, RenderSettings* out) {
    RenderSettings& r = *out;
    if (!rr.json().is_object()) rr.fail("expected an object");
    r.bands.clear();
    auto bands = rr["bands_um"];
    if (bands.size() == 0) bands.fail("at least one band is required");
    for (size_t i = 0; i < bands.size(); ++i) {
        const auto v = bands.at(i).nums();
        if (v.size() != 2 || !(v[1] > v[0]) || v[0] <= 0) bands.at(i).fail("expected [lo, hi] with 0 < lo < hi");
        r.bands.push_back({v[0], v[1]});
    }
    r.seed = rr["seed"].uinteger();
    r.threads = static_cast<int>(rr["threads"].integer());
    r.estimator = rr["estimator"].choice<Estimator>();
    if (rr.has("response_bands")) readResponseBands(rr["response_bands"], &r);
    for (auto it = rr.json().begin(); it != rr.json().end(); ++it) {
        const std::string& k = it.key();
        if (k == "bands_um" || k == "seed" || k == "threads" || k == "estimator" || k == "response_bands") continue;
        r.settings.set(k, rr[k].anyParam());
    }
}

void readDomain(const JReader& d, Domain* out) {
    Domain& dom = *out;
    d.expectKeys({"x_m", "y_m", "horizontal"});
    const auto x = d["x_m"].nums(), y = d["y_m"].nums();
    if (x.size() != 2 || !(x[1] > x[0])) d["x_m"].fail("expected [min, max] with min < max");
    if (y.size() != 2 || !(y[1] > y[0])) d["y_m"].fail("expected [min, max] with min < max");
    dom.x0 = x[0];
    dom.x1 = x[1];
    dom.y0 = y[0];
    dom.y1 = y[1];
    const std::string h = d["horizontal"].str();
    if (h != "bounded" && h != "periodic") d["horizontal"].fail("expected \"bounded\" or \"periodic\", found '" + h + "'");
    dom.periodic = h == "periodic";
}

void readSunAndSky(const JReader& r, SceneIR* out) {
    SceneIR& s = *out;
    auto sun = r["sun"];
    sun.expectKeys({"enabled", "zenith_rad", "azimuth_rad", "half_angle_rad", "irradiance"});
    s.sun.enabled = sun["enabled"].boolean();
    s.sun.zenith = sun["zenith_rad"].num();
    s.sun.azimuth = sun["azimuth_rad"].num();
    s.sun.halfAngle = sun["half_angle_rad"].num();
    s.sun.irradiance = sun["irradiance"].spectrum();
    auto sky = r["sky"];
    sky.expectKeys({"radiance"});
    s.sky.radiance = sky["radiance"].spectrum();
}

// One medium: index, layers (checked contiguous) and scatterers, solver.
Medium readMedium(const JReader& m) {
    m.expectKeys({"name", "refractive_index", "layers", "solver"});
    Medium md;
    md.name = m["name"].str();
    md.refractiveIndex = m["refractive_index"].spectrum();
    md.layers.clear();
    auto layers = m["layers"];
    for (size_t li = 0; li < layers.size(); ++li) {
        auto l = layers.at(li);
        l.expectKeys({"z_top_m", "z_bottom_m", "absorption_per_m", "scatterers"});
        Layer ly;
        ly.zTop = l["z_top_m"].bound(kInfinity);
        ly.zBottom = l["z_bottom_m"].bound(-kInfinity);
        ly.absorption = l["absorption_per_m"].spectrum();
        auto sc = l["scatterers"];
        for (size_t k = 0; k < sc.size(); ++k) {
            auto c = sc.at(k);
            c.expectKeys({"name", "scattering_per_m", "phase"});
            Scatterer x;
            x.name = c["name"].str();
            x.scattering = c["scattering_per_m"].spectrum();
            x.phase = readPhase(c["phase"]);
            ly.scatterers.push_back(x);
        }
        md.layers.push_back(ly);
    }
    if (auto err = checkLayers(md); !err.empty()) layers.fail(err);
    if (m.has("solver")) md.solver = m["solver"].choice<Medium::Solver>();
    return md;
}

// A texture or class map's plan-view rectangle [x0, y0, x1, y1] with x1 > x0 and y1 > y0.
void readExtent(const JReader& e, Material* mt) {
    const auto v = e.nums();
    if (v.size() != 4 || !(v[2] > v[0]) || !(v[3] > v[1])) e.fail("expected [x0, y0, x1, y1] with x1 > x0 and y1 > y0");
    mt->textureX0 = v[0];
    mt->textureY0 = v[1];
    mt->textureX1 = v[2];
    mt->textureY1 = v[3];
}

// A number of the material's type, checked against its descriptor's range.
double materialNumber(const JReader& m, const MaterialKind& kind, const ParamSpec& p) {
    if (!m.has(p.name)) {
        if (!p.defaultValue) m.fail(fmt::format("a {} material needs '{}' ({})", kind.info.name, p.name, p.doc));
        return *p.defaultValue;
    }
    const JReader v = m[p.name];
    const double x = p.type == ParamType::Boolean ? (v.boolean() ? 1.0 : 0.0) : v.num();
    if (!p.inRange(x)) v.fail(fmt::format("{} is outside the allowed range {}", x, p.rangeText()));
    return x;
}

// The keys of the material's type: its raster and its numbers (core/material_kinds.h).
void readMaterialTypeKeys(const JReader& m, const MaterialKind& kind, Material* mt) {
    if (m.has("texture")) {
        auto t = m["texture"];
        t.expectKeys({"file", "extent_m"});
        mt->texture = t["file"].str();
        readExtent(t["extent_m"], mt);
    }
    if (m.has("class_map")) {
        auto c = m["class_map"];
        c.expectKeys({"file", "extent_m", "classes"});
        mt->texture = c["file"].str();
        readExtent(c["extent_m"], mt);
        mt->classMaterials = c["classes"].strings();
        if (mt->classMaterials.empty() || mt->classMaterials.size() > 65536)
            c["classes"].fail("expected 1 to 65536 class material names (one per raster value)");
    }
    for (const char* k : {"texture", "class_map"})
        if (kind.uses(k) && !m.has(k)) m.fail(fmt::format("a {} material needs '{}'", kind.info.name, k));
    for (const ParamSpec& p : kind.info.params) {
        const double x = materialNumber(m, kind, p);
        if (p.name == "wind_speed_mps") mt->windSpeed = x;
        else if (p.name == "wind_azimuth_rad") mt->windAzimuth = x;
        else if (p.name == "gram_charlier") mt->gramCharlier = x != 0.0;
        else throw InternalError("readMaterial: parameter '" + p.name + "' of " + kind.info.name + " is not read");
    }
    if (m.has("sea")) mt->sea = m["sea"].choice<CoxMunkSea>();
    if (m.has("slopes")) {
        mt->slopes = m["slopes"].choice<CoxMunkSlopes>();
        if (const std::string why = coxMunkSlopesProblem(mt->slopes, mt->sea, mt->gramCharlier); !why.empty())
            m["slopes"].fail(why);
    }
    if (m.has("shadowing")) mt->shadowing = m["shadowing"].choice<MicrofacetShadowing>();
}

// One material: its type, solver, reflectance and the keys of its type only (a key of another
// type would do nothing, so it is refused).
Material readMaterial(const JReader& m) {
    std::vector<std::string> keys = {"name", "type", "solver", "reflectance"};
    for (const MaterialKind& k : materialKinds().kinds()) {
        for (const ParamSpec& p : k.info.params) keys.push_back(p.name);
        for (const std::string& key : k.irKeys) keys.push_back(key);
    }
    m.expectKeys(keys);
    Material mt;
    mt.name = m["name"].str();
    mt.type = m["type"].choice<Material::Type>();
    const MaterialKind& kind = materialKind(mt.type);
    for (size_t i = 4; i < keys.size(); ++i)
        if (m.has(keys[i]) && !kind.uses(keys[i]))
            m[keys[i]].fail(fmt::format("a {} material does not use this key; it belongs to: {}", kind.info.name,
                                        irTypesWithKey(keys[i])));
    if (m.has("solver")) mt.solver = m["solver"].choice<Material::Solver>();
    if (m.has("reflectance")) mt.reflectance = m["reflectance"].spectrum();
    if (!kind.hasReflectance) {
        const auto& v = mt.reflectance.values();
        if (m.has("reflectance") && std::any_of(v.begin(), v.end(), [](double r) { return r != 0.0; }))
            m["reflectance"].fail(fmt::format("a {} material has no reflectance of its own; write 0", kind.info.name));
    } else if (!m.has("reflectance")) {
        m.fail(fmt::format("a {} material needs 'reflectance'", kind.info.name));
    }
    readMaterialTypeKeys(m, kind, &mt);
    return mt;
}

// One mesh entry; its materials and media must be defined already.
Mesh readMesh(const JReader& m, const SceneIR& s) {
    m.expectKeys({"name", "file", "materials", "inside", "outside", "closed"});
    Mesh me;
    me.name = m["name"].str();
    me.file = m["file"].str();
    me.materials = m["materials"].strings();
    me.inside = m["inside"].str();
    me.outside = m["outside"].str();
    me.closed = m["closed"].boolean();
    for (const auto& mn : me.materials)
        if (!s.findMaterial(mn)) m["materials"].fail("names material '" + mn + "', which is not defined");
    for (const auto& md : {me.inside, me.outside})
        if (!md.empty() && !s.findMedium(md)) m.fail("names medium '" + md + "', which is not defined");
    return me;
}

// One instance of a defined mesh.
Instance readInstance(const JReader& in, const SceneIR& s) {
    in.expectKeys({"mesh", "rotation", "translation_m"});
    Instance x;
    x.mesh = in["mesh"].str();
    if (!s.findMesh(x.mesh)) in["mesh"].fail("names mesh '" + x.mesh + "', which is not defined");
    const auto rot = in["rotation"].nums();
    if (rot.size() != 9) in["rotation"].fail("expected 9 numbers (row-major 3x3)");
    std::copy(rot.begin(), rot.end(), x.rotation);
    x.translation = in["translation_m"].vec3();
    return x;
}

// A sensor's PSF: its numbers checked as the scene reader checks them (a hand-edited IR may not
// hold what no scene file could).
SensorPsf readSensorPsf(const JReader& p) {
    SensorPsf psf;
    psf.type = p["type"].str();
    if (psf.type == "gaussian") {
        p.expectKeys({"type", "fwhm_px"});
        psf.fwhmPx = p["fwhm_px"].num();
        if (!(psf.fwhmPx >= 0.1 && psf.fwhmPx <= 50)) p["fwhm_px"].fail("expected a FWHM in [0.1, 50] px");
        return psf;
    }
    if (psf.type != "kernel") p["type"].fail("expected 'gaussian' or 'kernel'");
    p.expectKeys({"type", "width", "height", "values"});
    const int64_t w = p["width"].integer(), h = p["height"].integer();
    if (w < 1 || w > kMaxPsfSide || w % 2 == 0 || h < 1 || h > kMaxPsfSide || h % 2 == 0)
        p.fail(fmt::format("a PSF kernel's width and height must be odd, 1 to {}", kMaxPsfSide));
    psf.width = static_cast<int>(w);
    psf.height = static_cast<int>(h);
    double sum = 0;
    for (size_t i = 0; i < p["values"].size(); ++i) {
        const double v = p["values"].at(i).num();
        if (!(v >= 0) || !std::isfinite(v)) p["values"].at(i).fail("a PSF value must be finite and >= 0");
        psf.values.push_back(v);
        sum += v;
    }
    if (psf.values.size() != static_cast<size_t>(w * h))
        p["values"].fail(fmt::format("expected {} x {} = {} values, found {}", w, h, w * h, psf.values.size()));
    if (!(sum > 0)) p["values"].fail("a PSF kernel must not be all zero");
    return psf;
}

SensorDetector readSensorDetector(const JReader& d) {
    d.expectKeys({"aperture_diameter_m", "integration_time_s", "quantum_efficiency", "read_noise_e", "full_well_e", "bits",
                  "seed"});
    SensorDetector det;
    auto in = [&](const char* k, double lo, double hi) {
        const double v = d[k].num();
        if (!(v >= lo && v <= hi)) d[k].fail(fmt::format("{} is out of range; allowed [{}, {}]", v, lo, hi));
        return v;
    };
    det.apertureDiameter = in("aperture_diameter_m", 1e-5, 10);
    det.integrationTime = in("integration_time_s", 1e-9, 1e2);
    det.quantumEfficiency = in("quantum_efficiency", 1e-6, 1);
    det.readNoise = in("read_noise_e", 0, 1e6);
    det.fullWell = in("full_well_e", 1, 1e9);
    det.bits = static_cast<int>(in("bits", 1, 24));
    const int64_t seed = d["seed"].integer();
    if (seed < 0) d["seed"].fail("expected a seed >= 0");
    det.seed = static_cast<uint64_t>(seed);
    return det;
}

// One sensor; sizes are range-checked before narrowing.
Sensor readSensor(const JReader& c, const SceneIR& s) {
    // Any sensor type's parameters are known keys; those of this sensor's type are read, the others
    // refused.
    std::vector<std::string> keys = {"name", "type", "position_m", "forward", "up", "width", "height"};
    for (const std::string& k : sensorTypeKinds().allParamNames()) keys.push_back(k);
    keys.insert(keys.end(), {"samples_per_pixel", "medium", "psf", "detector", "water_products"});
    c.expectKeys(keys);
    Sensor se;
    se.name = c["name"].str();
    se.type = c["type"].choice<Sensor::Type>();
    se.position = c["position_m"].vec3();
    se.forward = c["forward"].vec3();
    se.up = c["up"].vec3();
    // Range-checked before the narrowing cast: a hand-edited 1e10 must not wrap to a small int.
    for (const char* k : {"width", "height", "samples_per_pixel"}) {
        const int64_t v = c[k].integer();
        if (v < 1 || v > 1'000'000) c[k].fail(fmt::format("{} is out of range; allowed [1, 1000000]", v));
    }
    se.width = static_cast<int>(c["width"].integer());
    se.height = static_cast<int>(c["height"].integer());
    const SensorKind& kind = sensorKind(se.type);
    // A parameter of another type would do nothing here: refused, naming the type that uses it.
    for (const std::string& k : sensorTypeKinds().allParamNames())
        if (c.has(k) && !kind.info.param(k))
            c[k].fail(fmt::format("a {} sensor does not use this key; it belongs to the {} sensor type", kind.info.name,
                                  sensorTypeKinds().kindsWithParam(k)));
    for (size_t i = 0; i < kind.info.params.size(); ++i) se.*kind.fields[i].field = c[kind.info.params[i].name].num();
    se.samplesPerPixel = static_cast<int>(c["samples_per_pixel"].integer());
    se.medium = c["medium"].str();
    if (!se.medium.empty() && !s.findMedium(se.medium)) c.fail("names medium '" + se.medium + "', which is not defined");
    if (c.has("psf")) se.psf = readSensorPsf(c["psf"]);
    if (c.has("detector")) se.detector = readSensorDetector(c["detector"]);
    if (c.has("water_products")) se.waterProducts = c["water_products"].boolean();
    return se;
}

// One probe.
Probe readProbe(const JReader& p) {
    p.expectKeys({"name", "position_m", "quantities", "medium", "samples"});
    Probe pr;
    pr.name = p["name"].str();
    pr.position = p["position_m"].vec3();
    pr.quantities = p["quantities"].strings();
    pr.medium = p["medium"].str();
    if (p.has("samples")) {
        const int64_t n = p["samples"].integer();
        if (n < 2 || n > (1 << 30)) p["samples"].fail("expected an integer in [2, 2^30]");
        pr.samples = static_cast<int>(n);
    }
    return pr;
}

}  // namespace

SceneIR fromJsonText(const std::string& text, const std::string& file) {
    Json j;
    try {
        j = Json::parse(text);
    } catch (const nlohmann::json::exception& e) {
        // parse_error, and out_of_range for a number such as 1e400 that no double holds.
        throw InputError(SourceLoc{file}, std::string("not valid JSON: ") + e.what());
    }
    JReader r(j, "", file);
    r.expectKeys({"format", "version", "name", "metadata", "render", "domain", "sun", "sky", "media", "materials",
                  "meshes", "instances", "sensors", "probes", "geo"});
    if (r["format"].str() != "littoral-scene-ir") r["format"].fail("expected \"littoral-scene-ir\"");
    if (r["version"].integer() != kFormatVersion)
        r["version"].fail(fmt::format("this Littoral reads IR version {}", kFormatVersion));
    SceneIR s;
    s.name = r["name"].str();
    {
        auto m = r["metadata"];
        if (!j["metadata"].is_object()) m.fail("expected an object");
        for (auto it = j["metadata"].begin(); it != j["metadata"].end(); ++it) s.metadata[it.key()] = m[it.key()].str();
    }
    readRender(r["render"], &s.render);
    readDomain(r["domain"], &s.domain);
    if (r.has("geo")) {
        const JReader g = r["geo"];
        g.expectKeys({"frame", "latitude_deg", "longitude_deg", "altitude_m", "utm_zone"});
        GeoReference geo;
        geo.frame = g["frame"].str();
        if (geo.frame != "local-cartesian" && geo.frame != "utm") g["frame"].fail("expected 'local-cartesian' or 'utm'");
        geo.latitudeDeg = g["latitude_deg"].num();
        geo.longitudeDeg = g["longitude_deg"].num();
        geo.altitudeM = g["altitude_m"].num();
        if (!(std::abs(geo.latitudeDeg) <= 90)) g["latitude_deg"].fail("expected a latitude in [-90, 90] deg");
        if (!(std::abs(geo.longitudeDeg) <= 180)) g["longitude_deg"].fail("expected a longitude in [-180, 180] deg");
        if (!(std::abs(geo.altitudeM) <= 1e5)) g["altitude_m"].fail("expected an altitude within 1e5 m");
        const int64_t zone = g["utm_zone"].integer();
        if (geo.frame == "utm" ? (zone < 1 || zone > 60) : zone != 0)
            g["utm_zone"].fail(geo.frame == "utm" ? "expected a UTM zone in [1, 60]" : "expected 0 (not a UTM frame)");
        geo.utmZone = static_cast<int>(zone);
        s.geo = geo;
    }
    readSunAndSky(r, &s);
    auto media = r["media"];
    for (size_t i = 0; i < media.size(); ++i) s.media.push_back(readMedium(media.at(i)));
    auto mats = r["materials"];
    for (size_t i = 0; i < mats.size(); ++i) s.materials.push_back(readMaterial(mats.at(i)));
    auto meshes = r["meshes"];
    for (size_t i = 0; i < meshes.size(); ++i) s.meshes.push_back(readMesh(meshes.at(i), s));
    auto inst = r["instances"];
    for (size_t i = 0; i < inst.size(); ++i) s.instances.push_back(readInstance(inst.at(i), s));
    auto sensors = r["sensors"];
    for (size_t i = 0; i < sensors.size(); ++i) s.sensors.push_back(readSensor(sensors.at(i), s));
    auto probes = r["probes"];
    for (size_t i = 0; i < probes.size(); ++i) s.probes.push_back(readProbe(probes.at(i)));
    validateNamesAndPaths(s, file);
    return s;
}

void validateNamesAndPaths(const SceneIR& s, const std::string& file) {
    auto fail = [&](const std::string& path, const std::string& msg) {
        throw InputError(SourceLoc{file}, path + ": " + msg);
    };
    auto name = [&](const std::string& path, const std::string& n, const char* what) {
        const std::string problem = outputNameProblem(n);
        if (!problem.empty()) fail(path, fmt::format("{} name '{}' {}", what, printableName(n), problem));
    };
    // A file named by the IR must stay inside the IR folder: relative, no "..", no empty parts.
    auto relative = [&](const std::string& path, const std::string& f) {
        const fs::path p(f);
        bool ok = !f.empty() && !p.is_absolute() && f.find('\0') == std::string::npos;
        for (const auto& part : p) ok = ok && part != ".." && part != "." && !part.empty();
        if (!ok)
            fail(path, fmt::format("'{}' must be a relative path inside the IR folder (no '..', not absolute)",
                                   printableName(f)));
    };
    name("name", s.name, "scene");
    for (size_t i = 0; i < s.sensors.size(); ++i) name(fmt::format("sensors[{}].name", i), s.sensors[i].name, "sensor");
    for (size_t i = 0; i < s.probes.size(); ++i) name(fmt::format("probes[{}].name", i), s.probes[i].name, "probe");
    for (size_t i = 0; i < s.meshes.size(); ++i) relative(fmt::format("meshes[{}].file", i), s.meshes[i].file);
    for (size_t i = 0; i < s.materials.size(); ++i)
        if (s.materials[i].type == Material::Type::Textured)
            relative(fmt::format("materials[{}].texture.file", i), s.materials[i].texture);
        else if (s.materials[i].type == Material::Type::Classified)
            relative(fmt::format("materials[{}].class_map.file", i), s.materials[i].texture);
    std::vector<std::string> sensorNames;
    for (const auto& c : s.sensors) sensorNames.push_back(c.name);
    if (const auto clash = findOutputClash(sensorNames, !s.probes.empty())) {
        if (clash->first == clash->second)
            fail(fmt::format("sensors[{}].name", clash->second),
                 fmt::format("sensor '{}' would write {}, the probe table's name", s.sensors[clash->second].name,
                             clash->file));
        fail(fmt::format("sensors[{}].name", clash->second),
             fmt::format("sensors '{}' and '{}' would both write {} (output names must differ after the suffixes "
                         "the renderer adds, ignoring case)",
                         s.sensors[clash->first].name, s.sensors[clash->second].name, clash->file));
    }
}

SceneIR readIR(const fs::path& dir) {
    const fs::path jsonPath = dir / "scene.json";
    if (!fs::exists(jsonPath)) throw InputError(SourceLoc{jsonPath.string()}, "no scene.json in the IR directory");
    SceneIR s = fromJsonText(readTextFile(jsonPath), jsonPath.string());
    for (auto& m : s.meshes) {
        m.data = readPly(dir / m.file);
        for (size_t f = 0; f < m.data.numTriangles(); ++f)
            if (m.data.materialOf(f) >= std::max<size_t>(1, m.materials.size()))
                throw InputError(SourceLoc{(dir / m.file).string()},
                                 fmt::format("face {} uses material slot {}, but mesh '{}' lists {} materials", f,
                                             m.data.materialOf(f), m.name, m.materials.size()));
    }
    return s;
}

}  // namespace littoral::ir
