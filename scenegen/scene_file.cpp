#include "scenegen/scene_file.h"

#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/output_names.h"
#include "core/solar_position.h"
#include "core/text_checks.h"
#include "core/units.h"

namespace littoral::scenegen {

namespace fs = std::filesystem;

Spectrum parseSpectrumCsv(std::string_view text, const std::string& file, double min, double max,
                          std::string_view unit) {
    requireUtf8(text, file);
    std::vector<double> wl, val;
    size_t pos = 0;
    int lineNo = 0;
    while (pos < text.size()) {
        const size_t nl = text.find('\n', pos);
        std::string line(text.substr(pos, (nl == std::string_view::npos ? text.size() : nl) - pos));
        pos = nl == std::string_view::npos ? text.size() : nl + 1;
        ++lineNo;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (lineNo == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // UTF-8 byte-order mark
        const size_t first = line.find_first_not_of(" \t");
        if (first == std::string::npos || line[first] == '#') continue;
        std::replace(line.begin(), line.end(), ',', ' ');
        std::istringstream ls(line);
        double w, v;
        std::string rest;
        if (!(ls >> w >> v) || (ls >> rest)) {
            if (wl.empty() && lineNo == 1) continue;  // header row
            throw InputError(SourceLoc{file, lineNo, 1}, "expected 'wavelength_um, value' (two numbers)");
        }
        if (!std::isfinite(w) || !(w >= 0.2 && w <= 20.0))
            throw InputError(SourceLoc{file, lineNo, 1},
                             fmt::format("wavelength {} um is out of range; allowed [0.2, 20] um", w));
        if (!std::isfinite(v) || v < min || v > max)
            throw InputError(SourceLoc{file, lineNo, 1},
                             fmt::format("value {} is out of range; allowed [{}, {}] {}", v, min, max, unit));
        wl.push_back(w);
        val.push_back(v);
    }
    if (wl.empty())
        throw InputError(SourceLoc{file}, "the file holds no 'wavelength_um, value' rows (it is empty, or only a "
                                          "header and comments)");
    return Spectrum::tabulated(wl, val, file);
}

// A spectrum in a scene file: a number (constant), a table
// {wavelengths_um: [...], values: [...]}, or {file: name.csv} with "wavelength_um,value" rows.
Spectrum parseSpectrum(const YamlNode& n, double min, double max, std::string_view unit) {
    if (n.isScalar()) return Spectrum::constant(n.asDouble(min, max, unit));
    n.expectKeys({"wavelengths_um", "values", "file"});
    std::vector<double> wl, val;
    if (auto f = n.optional("file")) {
        if (n.has("wavelengths_um") || n.has("values")) n.fail("give either 'file' or 'wavelengths_um' + 'values', not both");
        const fs::path p = f->asExistingPath();
        std::string text;
        try {
            text = readTextFile(p);
        } catch (const InputError& e) {
            f->fail(fmt::format("cannot read '{}': {}", p.string(), e.message()));
        }
        try {
            return parseSpectrumCsv(text, p.string(), min, max, unit);
        } catch (const InputError& e) {
            if (e.where().line > 0) throw;  // located in the CSV file
            f->fail(fmt::format("{}: {}", p.string(), e.message()));
        }
    }
    wl = n["wavelengths_um"].asDoubleList(0.2, 20.0, "um");
    val = n["values"].asDoubleList(min, max, unit);
    try {
        return Spectrum::tabulated(wl, val, n.path());
    } catch (const InputError& e) {
        n.fail(e.message());
    }
}

namespace {

Vec3 parseVec3(const YamlNode& n) {
    const auto v = n.asDoubleList();
    if (v.size() != 3) n.fail(fmt::format("expected [x, y, z] (3 numbers), found {} numbers", v.size()));
    return {v[0], v[1], v[2]};
}

std::vector<double> parsePair(const YamlNode& n) {
    const auto v = n.asDoubleList();
    if (v.size() != 2 || !(v[1] > v[0])) n.fail("expected [min, max] with min < max");
    return v;
}

void parseSceneSection(const YamlNode& n, SceneSection* s) {
    n.expectKeys({"name", "origin", "domain"});
    if (auto nm = n.optional("name")) s->name = nm->asOutputName("scene");
    if (auto o = n.optional("origin")) {
        o->expectKeys({"latitude", "longitude", "altitude"});
        GeoOrigin g;
        g.latitude = (*o)["latitude"].asDouble(-90, 90, "degrees");
        g.longitude = (*o)["longitude"].asDouble(-180, 180, "degrees");
        g.altitude = o->getDouble("altitude", 0.0, -500, 9000, "m");
        s->origin = g;
    }
    if (auto d = n.optional("domain")) {
        d->expectKeys({"x", "y"});
        const auto x = parsePair((*d)["x"]), y = parsePair((*d)["y"]);
        s->x0 = x[0]; s->x1 = x[1]; s->y0 = y[0]; s->y1 = y[1];
        if (s->x1 - s->x0 > 100000 || s->y1 - s->y0 > 100000) d->fail("domain larger than 100 km is not supported");
    }
}

void parseSun(const YamlNode& n, SunSection* s) {
    n.expectKeys({"enabled", "zenith_deg", "azimuth_deg", "date_time_utc", "angular_diameter_deg", "irradiance"});
    s->enabled = n.getBool("enabled", true);
    const bool angles = n.has("zenith_deg") || n.has("azimuth_deg");
    if (auto dt = n.optional("date_time_utc")) {
        if (angles) n.fail("give either zenith_deg/azimuth_deg or date_time_utc, not both");
        const std::string t = dt->asString();
        int Y, M, D, h, m, sec;
        char z = 0;
        if (std::sscanf(t.c_str(), "%4d-%2d-%2dT%2d:%2d:%2d%c", &Y, &M, &D, &h, &m, &sec, &z) != 7 || z != 'Z' ||
            M < 1 || M > 12 || D < 1 || D > 31 || h > 23 || m > 59 || sec > 60)
            dt->fail("expected an ISO 8601 UTC time like 2009-08-12T15:30:00Z, found '" + t + "'");
        s->dateTimeUtc = t;
    } else if (s->enabled) {
        s->zenith = deg2rad(n["zenith_deg"].asDouble(0, 90, "degrees"));
        s->compassAzimuth = deg2rad(n.getDouble("azimuth_deg", 0, 0, 360, "degrees (clockwise from north)"));
    }
    s->halfAngle = 0.5 * deg2rad(n.getDouble("angular_diameter_deg", 0.53, 0.01, 5.0, "degrees"));
    if (auto irr = n.optional("irradiance")) s->irradiance = parseSpectrum(*irr, 0, 1e5, "W m^-2 um^-1");
}

void parseSky(const YamlNode& n, SkySection* s) {
    n.expectKeys({"model", "radiance", "hemisphere_irradiance", "sky_fraction"});
    s->model = n.getEnum("model", "uniform", {"uniform", "simple"});
    if (s->model == "uniform") {
        for (const char* k : {"hemisphere_irradiance", "sky_fraction"})
            if (n.has(k)) n[k].fail("only used with model: simple");
        s->radiance = parseSpectrum(n["radiance"], 0, 1e5, "W m^-2 sr^-1 um^-1");
    } else {
        if (n.has("radiance")) n["radiance"].fail("model: simple derives the sky radiance; use hemisphere_irradiance and sky_fraction");
        s->hemisphereIrradiance = n["hemisphere_irradiance"].asDouble(0, 1e5, "W m^-2 um^-1");
        s->skyFraction = n["sky_fraction"].asDouble(0, 1);
    }
}

const std::vector<std::string> kSensorKeys = {
    "name", "type", "elevation_deg", "zenith_deg", "azimuth_deg", "range_m", "gsd_m", "target",
    "position", "look_at", "direction", "up", "focal_length_mm", "pixel_pitch_um", "pixel_size_m",
    "width", "height", "samples_per_pixel", "medium"};

SensorSection parseSensor(const YamlNode& n) {
    n.expectKeys(kSensorKeys);
    SensorSection s;
    s.loc = n.loc();
    s.name = n["name"].asOutputName("sensor");
    s.type = n["type"].asEnum({"frame", "pinhole", "orthographic"});
    s.width = static_cast<int>(n["width"].asInt(1, 20000));
    s.height = static_cast<int>(n["height"].asInt(1, 20000));
    s.samplesPerPixel = static_cast<int>(n.getInt("samples_per_pixel", 1, 1, 65536));
    s.medium = n.getEnum("medium", "auto", {"auto", "air", "water"});
    auto forbid = [&](std::initializer_list<const char*> keys, const char* why) {
        for (const char* k : keys)
            if (n.has(k)) n[k].fail(fmt::format("not used by a {} sensor ({})", s.type, why));
    };
    if (s.type == "frame") {
        forbid({"position", "look_at", "direction", "focal_length_mm", "pixel_pitch_um", "pixel_size_m"},
               "it is placed by elevation, azimuth, range and GSD");
        if (n.has("elevation_deg") == n.has("zenith_deg")) n.fail("a frame sensor needs exactly one of elevation_deg, zenith_deg");
        s.elevation = n.has("elevation_deg") ? deg2rad(n["elevation_deg"].asDouble(1, 90, "degrees"))
                                             : kPi / 2 - deg2rad(n["zenith_deg"].asDouble(0, 89, "degrees"));
        s.compassAzimuth = deg2rad(n["azimuth_deg"].asDouble(0, 360, "degrees (clockwise from north)"));
        s.range = n["range_m"].asDouble(0.01, 1e6, "m");
        s.gsd = n["gsd_m"].asDouble(1e-5, 1e4, "m");
        if (auto t = n.optional("target")) s.target = parseVec3(*t);
        if (auto u = n.optional("up")) s.up = parseVec3(*u);
        else s.up = {0, 1, 0};
    } else {
        forbid({"elevation_deg", "zenith_deg", "azimuth_deg", "range_m", "gsd_m", "target"},
               "it is placed by position and direction");
        s.position = parseVec3(n["position"]);
        if (n.has("look_at") == n.has("direction")) n.fail("give exactly one of look_at, direction");
        const Vec3 d = n.has("look_at") ? parseVec3(n["look_at"]) - s.position : parseVec3(n["direction"]);
        if (length(d) < 1e-12) n.fail("the view direction has zero length");
        s.direction = normalize(d);
        if (auto u = n.optional("up")) s.up = parseVec3(*u);
        else s.up = std::abs(s.direction.z) > 0.99 ? Vec3{0, 1, 0} : Vec3{0, 0, 1};
        if (length(cross(s.direction, s.up)) < 1e-9) n["up"].fail("'up' must not be parallel to the view direction");
        if (s.type == "pinhole") {
            forbid({"pixel_size_m"}, "pinhole cameras use focal_length_mm and pixel_pitch_um");
            s.focalLength = n["focal_length_mm"].asDouble(1e-3, 1e5, "mm") * 1e-3;
            s.pixelPitch = n["pixel_pitch_um"].asDouble(1e-2, 1e5, "um") * 1e-6;
        } else {
            forbid({"focal_length_mm", "pixel_pitch_um"}, "orthographic cameras use pixel_size_m");
            s.pixelSize = n["pixel_size_m"].asDouble(1e-6, 1e4, "m");
        }
    }
    return s;
}

ProbeSection parseProbe(const YamlNode& n) {
    n.expectKeys({"name", "position", "quantities", "medium"});
    ProbeSection p;
    p.loc = n.loc();
    p.name = n["name"].asOutputName("probe");
    p.position = parseVec3(n["position"]);
    for (const auto& q : n["quantities"].items()) p.quantities.push_back(q.asEnum({"Ed", "Eu", "Eod", "Eou", "Lu"}));
    if (p.quantities.empty()) n["quantities"].fail("list at least one of Ed, Eu, Eod, Eou, Lu");
    p.medium = n.getEnum("medium", "auto", {"auto", "air", "water"});
    return p;
}

MaterialSection parseMaterial(const YamlNode& n) {
    n.expectKeys({"name", "type", "reflectance", "solver"});
    MaterialSection m;
    m.loc = n.loc();
    m.name = n["name"].asString();
    m.type = n.getEnum("type", "lambertian", {"lambertian", "black"});
    m.solver = n.getEnum("solver", "classic", {"classic", "generic", "surface-pm"});
    if (m.type == "black") {
        if (n.has("reflectance")) n["reflectance"].fail("a black material reflects nothing; remove 'reflectance'");
    } else {
        m.reflectance = parseSpectrum(n["reflectance"], 0, 1, "(reflectance)");
    }
    return m;
}

void parseWater(const YamlNode& n, SceneSpec* spec) {
    n.expectKeys({"level_m", "surface", "optics"});
    spec->hasWater = true;
    spec->waterLevel = n.getDouble("level_m", 0.0, -1e4, 1e4, "m");
    if (auto s = n.optional("surface")) spec->waterSurface = *s;
    auto& o = spec->waterOptics;
    if (auto op = n.optional("optics")) {
        op->expectKeys({"preset", "refractive_index", "absorption_per_m", "scattering_per_m", "phase", "interface"});
        if (auto p = op->optional("preset")) {
            const std::string name = p->asEnum(iopPresetNames());
            iopPreset(name, &o);
            if (op->has("absorption_per_m") || op->has("scattering_per_m"))
                op->fail("give either 'preset' or absorption_per_m/scattering_per_m, not both");
        } else {
            if (auto a = op->optional("absorption_per_m")) o.absorption = parseSpectrum(*a, 0, 1000, "m^-1");
            if (auto b = op->optional("scattering_per_m")) o.scattering = parseSpectrum(*b, 0, 1000, "m^-1");
        }
        if (auto ri = op->optional("refractive_index")) o.refractiveIndex = parseSpectrum(*ri, 1.0, 3.0, "");
        if (auto ph = op->optional("phase")) {
            ph->expectKeys({"type", "g"});
            const std::string t = (*ph)["type"].asEnum({"isotropic", "henyey-greenstein", "petzold", "rayleigh"});
            using T = ir::PhaseFunction::Type;
            o.phase.type = t == "isotropic" ? T::Isotropic
                         : t == "henyey-greenstein" ? T::HenyeyGreenstein
                         : t == "petzold" ? T::Petzold : T::Rayleigh;
            if (o.phase.type == T::HenyeyGreenstein) o.phase.g = (*ph)["g"].asDouble(-0.999, 0.999);
            else if (ph->has("g")) (*ph)["g"].fail("'g' is only used by the henyey-greenstein phase function");
            else o.phase.g = 0;
        }
        o.interfaceSolver = op->getEnum("interface", "fresnel", {"fresnel"});
    }
}

void parseRender(const YamlNode& n, RenderSection* r) {
    n.expectKeys({"bands", "seed", "threads", "max_bounces", "max_specular_depth", "hemisphere_samples",
                  "probe_samples", "photons", "search_radius_m", "march_step_m"});
    auto& s = r->settings;
    if (auto b = n.optional("bands")) {
        s.bands.clear();
        if (b->isMap()) {
            b->expectKeys({"range_um", "count"});
            const auto rng = parsePair((*b)["range_um"]);
            if (rng[0] < 0.2 || rng[1] > 20) (*b)["range_um"].fail("allowed wavelengths are 0.2 to 20 um");
            s.bands = uniformBands(rng[0], rng[1], static_cast<int>(b->getInt("count", 1, 1, 1000)));
        } else {
            for (const auto& it : b->items()) {
                const auto v = parsePair(it);
                if (v[0] < 0.2 || v[1] > 20) it.fail("allowed wavelengths are 0.2 to 20 um");
                s.bands.push_back({v[0], v[1]});
            }
            if (s.bands.empty()) b->fail("list at least one band [lo_um, hi_um]");
        }
    }
    s.seed = static_cast<uint64_t>(n.getInt("seed", 1, 0, (1LL << 62)));
    s.threads = static_cast<int>(n.getInt("threads", 0, 0, 1024));
    s.maxBounces = static_cast<int>(n.getInt("max_bounces", 8, 0, 1000));
    s.maxSpecularDepth = static_cast<int>(n.getInt("max_specular_depth", s.maxSpecularDepth, 0, 1000));
    s.hemisphereSamples = static_cast<int>(n.getInt("hemisphere_samples", 64, 1, 1 << 20));
    s.probeSamples = static_cast<int>(n.getInt("probe_samples", s.probeSamples, 2, 1 << 26));
    if (auto p = n.optional("photons")) {
        p->expectKeys({"surface", "volume"});
        s.surfacePhotons = static_cast<uint64_t>(p->getInt("surface", 0, 0, 10'000'000'000LL));
        s.volumePhotons = static_cast<uint64_t>(p->getInt("volume", 0, 0, 10'000'000'000LL));
    }
    if (auto sr = n.optional("search_radius_m")) {
        sr->expectKeys({"surface", "volume"});
        s.surfaceSearchRadius = sr->getDouble("surface", s.surfaceSearchRadius, 1e-4, 100, "m");
        s.volumeSearchRadius = sr->getDouble("volume", s.volumeSearchRadius, 1e-4, 100, "m");
    }
    s.marchStep = n.getDouble("march_step_m", s.marchStep, 1e-4, 100, "m");
}

template <class T>
void checkUniqueNames(const std::vector<T>& items, const char* what, const YamlNode& list) {
    std::set<std::string> seen;
    for (size_t i = 0; i < items.size(); ++i)
        if (!seen.insert(items[i].name).second)
            list.at(i).fail(fmt::format("{} name '{}' is used twice", what, items[i].name));
}

// Every sensor writes S.exr, S_truth.exr, ... (core/output_names.h): two sensors must not write
// one file, ignoring case ("cam" writes cam_truth.exr, so "cam_truth" would overwrite it).
void checkOutputFiles(const SceneSpec& spec, const YamlNode& root) {
    std::vector<std::string> names;
    for (const auto& s : spec.sensors) names.push_back(s.name);
    const auto clash = findOutputClash(names, !spec.probes.empty());
    if (!clash) return;
    const YamlNode where = root["sensors"].at(clash->second)["name"];
    if (clash->first == clash->second)
        where.fail(fmt::format("sensor '{}' would write {}, which is the probe table's file name",
                               spec.sensors[clash->second].name, clash->file));
    where.fail(fmt::format("sensors '{}' (line {}) and '{}' would both write {}; output file names must differ after "
                           "the suffixes the renderer adds (.exr, .img, .hdr, .png, _truth.exr, _material.png), "
                           "ignoring case",
                           spec.sensors[clash->first].name, spec.sensors[clash->first].loc.line,
                           spec.sensors[clash->second].name, clash->file));
}

}  // namespace

std::vector<std::string> iopPresetNames() { return {"pure", "low", "moderate", "high", "coastal", "bay", "turbid"}; }

bool iopPreset(const std::string& name, WaterOptics* o) {
    const std::vector<double> wl = {0.4, 0.5, 0.6};
    auto tab = [&](std::vector<double> v) { return Spectrum::tabulated(wl, v, "IOP preset " + name); };
    o->preset = name;
    // Table 10.3 of the dissertation: chlorophyll + TSS (+ CDOM for absorption), summed per
    // wavelength (spec/seed-ch05-10.md §3.4). Pure water is not included, as in the source.
    if (name == "low") {
        o->absorption = tab({0.020562, 0.006904, 0.002113});
        o->scattering = tab({0.084518, 0.069118, 0.058300});
    } else if (name == "moderate") {
        o->absorption = tab({0.102812, 0.034525, 0.010567});
        o->scattering = tab({0.422594, 0.345598, 0.291507});
    } else if (name == "high") {
        o->absorption = tab({0.205626, 0.069051, 0.021136});
        o->scattering = tab({0.845189, 0.691194, 0.583016});
    } else if (name == "coastal") {  // Table 9.3, group #1 (spectrally flat)
        o->absorption = Spectrum::constant(0.038);
        o->scattering = Spectrum::constant(0.350);
    } else if (name == "bay") {  // Table 9.3, group #3
        o->absorption = Spectrum::constant(0.143);
        o->scattering = Spectrum::constant(0.180);
    } else if (name == "turbid") {  // Table 9.3, group #4b
        o->absorption = Spectrum::constant(0.268);
        o->scattering = Spectrum::constant(0.680);
    } else if (name == "pure") {  // no attenuation: a purely refracting medium
        o->absorption = Spectrum::constant(0.0);
        o->scattering = Spectrum::constant(0.0);
    } else {
        return false;
    }
    return true;
}

SceneSpec parseScene(const YamlNode& root, const fs::path& file) {
    root.expectKeys({"scene", "sun", "sky", "sensors", "probes", "water", "bathymetry", "objects", "materials",
                     "texture_classes", "render"});
    SceneSpec spec;
    spec.file = file;
    if (auto s = root.optional("scene")) parseSceneSection(*s, &spec.scene);
    if (auto s = root.optional("sun")) parseSun(*s, &spec.sun);
    else spec.sun.enabled = false;
    if (auto s = root.optional("sky")) parseSky(*s, &spec.sky);
    else spec.sky.radiance = Spectrum::constant(0.0);
    if (spec.sun.enabled && spec.sun.dateTimeUtc && !spec.scene.origin)
        root["sun"]["date_time_utc"].fail("a sun given by date and time needs scene.origin (latitude, longitude)");
    if (spec.sun.enabled && spec.sky.model == "simple" && spec.sun.irradiance)
        root["sun"]["irradiance"].fail("with sky model 'simple' the sun irradiance is (1 - sky_fraction) * hemisphere_irradiance; remove it");
    if (spec.sun.enabled && spec.sky.model != "simple" && !spec.sun.irradiance)
        root["sun"].fail("missing required key 'irradiance' (or use sky model 'simple')");

    if (auto s = root.optional("sensors")) {
        for (const auto& it : s->items()) spec.sensors.push_back(parseSensor(it));
        checkUniqueNames(spec.sensors, "sensor", *s);
    }
    if (auto s = root.optional("probes")) {
        for (const auto& it : s->items()) spec.probes.push_back(parseProbe(it));
        checkUniqueNames(spec.probes, "probe", *s);
    }
    checkOutputFiles(spec, root);
    if (auto s = root.optional("materials")) {
        for (const auto& it : s->items()) spec.materials.push_back(parseMaterial(it));
        checkUniqueNames(spec.materials, "material", *s);
    }
    if (auto s = root.optional("water")) parseWater(*s, &spec);
    spec.bathymetry = root.optional("bathymetry");
    spec.objects = root.optional("objects");
    spec.textureClasses = root.optional("texture_classes");
    if (auto s = root.optional("render")) parseRender(*s, &spec.render);

    // Every spectrum must cover every band: checked here so the error names the scene file.
    const auto& bands = spec.render.settings.bands;
    auto checkCover = [&](const Spectrum& sp, const YamlNode& where, const std::string& what) {
        for (const auto& b : bands)
            if (!sp.covers(b.lo, b.hi))
                where.fail(fmt::format("{} is tabulated over [{}, {}] um, which does not cover the band [{}, {}] um",
                                       what, sp.minWavelength(), sp.maxWavelength(), b.lo, b.hi));
    };
    if (auto ms = root.optional("materials"))
        for (size_t i = 0; i < spec.materials.size(); ++i)
            checkCover(spec.materials[i].reflectance, ms->at(i), "reflectance of '" + spec.materials[i].name + "'");
    if (auto w = root.optional("water")) {
        checkCover(spec.waterOptics.absorption, *w, "water absorption");
        checkCover(spec.waterOptics.scattering, *w, "water scattering");
        checkCover(spec.waterOptics.refractiveIndex, *w, "water refractive index");
    }
    if (spec.sun.irradiance) checkCover(*spec.sun.irradiance, root["sun"], "sun irradiance");
    // Without a sky section the radiance is the constant 0 (docs/scene-format.md): nothing to cover.
    if (spec.sky.radiance && root.has("sky")) checkCover(*spec.sky.radiance, root["sky"], "sky radiance");
    return spec;
}

SceneSpec loadSceneFile(const fs::path& file) {
    const YamlNode root = YamlNode::loadFile(file);
    return parseScene(root, file);
}

ir::Sensor placeSensor(const SensorSection& s, double waterLevel, bool hasWater) {
    ir::Sensor c;
    c.name = s.name;
    c.width = s.width;
    c.height = s.height;
    c.samplesPerPixel = s.samplesPerPixel;
    if (s.type == "frame") {
        // Table 10.1 geometry: the sensor sits at compass azimuth phi (clockwise from north, as seen
        // from the target) and elevation e, at slant range d. The IFOV follows from the GSD along the
        // optical axis: ifov = gsd / d (small-angle), realised as a pinhole with a 10 um pitch.
        const double e = s.elevation, phi = s.compassAzimuth;
        const Vec3 toSensor{std::cos(e) * std::sin(phi), std::cos(e) * std::cos(phi), std::sin(e)};
        c.type = ir::Sensor::Type::Pinhole;
        c.position = s.target + toSensor * s.range;
        c.forward = -toSensor;
        // "Up" in the image is the direction away from the sensor on the ground (top of the frame is
        // far range); at nadir it is the given up vector (north by default).
        c.up = std::abs(toSensor.z) > 0.999 ? s.up : Vec3{0, 0, 1};
        c.pixelPitch = 10e-6;
        c.focalLength = c.pixelPitch * s.range / s.gsd;
    } else {
        c.type = s.type == "pinhole" ? ir::Sensor::Type::Pinhole : ir::Sensor::Type::Orthographic;
        c.position = s.position;
        c.forward = s.direction;
        c.up = s.up;
        c.focalLength = s.focalLength;
        c.pixelPitch = s.pixelPitch;
        c.pixelSize = s.pixelSize;
    }
    if (s.medium == "water") c.medium = "water";
    else if (s.medium == "auto" && hasWater && c.position.z < waterLevel) c.medium = "water";
    return c;
}

void applyCommonSections(const SceneSpec& spec, ir::SceneIR* ir) {
    ir->name = spec.scene.name;
    ir->render = spec.render.settings;
    // Sun: compass azimuth (clockwise from north) -> IR azimuth (counter-clockwise from east).
    ir->sun.enabled = spec.sun.enabled;
    ir->sun.zenith = spec.sun.zenith;
    ir->sun.azimuth = std::remainder(kPi / 2 - spec.sun.compassAzimuth, 2 * kPi);
    double sunZenith = spec.sun.zenith;
    if (spec.sun.enabled && spec.sun.dateTimeUtc) {
        // NREL SPA (core/solar_position.h) at the scene origin; parseSun checked the format.
        SolarPositionInput in;
        std::sscanf(spec.sun.dateTimeUtc->c_str(), "%4d-%2d-%2dT%2d:%2d:%lfZ", &in.year, &in.month, &in.day, &in.hour,
                    &in.minute, &in.second);
        in.latitudeDeg = spec.scene.origin->latitude;
        in.longitudeDeg = spec.scene.origin->longitude;
        in.elevationM = spec.scene.origin->altitude;
        const SolarPosition p = solarPosition(in);
        const SunAnglesIr a = sunAnglesForIr(p);
        ir->sun.zenith = sunZenith = a.zenith;
        ir->sun.azimuth = a.azimuth;
        ir->metadata["sun.date_time_utc"] = *spec.sun.dateTimeUtc;
        ir->metadata["sun.zenith_deg"] = fmt::format("{:.6f}", p.zenithDeg);
        ir->metadata["sun.azimuth_deg"] = fmt::format("{:.6f}", p.azimuthDeg);
        if (p.zenithDeg >= 90.0) ir->sun.enabled = false;  // below the horizon: sky only
    }
    ir->sun.halfAngle = spec.sun.halfAngle;
    if (spec.sky.model == "simple") {
        // DIRSIG "simple atmosphere" (spec/seed-ch01-04.md §4.0): L_sky = F E_h / pi and the sun
        // carries the rest of the horizontal irradiance, (1 - F) E_h, i.e. (1 - F) E_h / cos(zenith)
        // on a plane normal to the beam.
        ir->sky.radiance = Spectrum::constant(spec.sky.skyFraction * spec.sky.hemisphereIrradiance * kInvPi);
        const double cz = std::cos(sunZenith);
        ir->sun.irradiance = Spectrum::constant(
            spec.sun.enabled && cz > 1e-6 ? (1 - spec.sky.skyFraction) * spec.sky.hemisphereIrradiance / cz : 0.0);
        if (spec.sky.skyFraction >= 1.0) ir->sun.enabled = false;
    } else {
        ir->sky.radiance = spec.sky.radiance.value_or(Spectrum::constant(0.0));
        ir->sun.irradiance = spec.sun.irradiance.value_or(Spectrum::constant(0.0));
    }
    if (spec.hasWater) {
        ir::Medium w;
        w.name = "water";
        w.refractiveIndex = spec.waterOptics.refractiveIndex;
        w.absorption = spec.waterOptics.absorption;
        w.scattering = spec.waterOptics.scattering;
        w.phase = spec.waterOptics.phase;
        ir->media.push_back(w);
        ir->metadata["water.iop_preset"] = spec.waterOptics.preset;
    }
    for (const auto& m : spec.materials) {
        ir::Material mt;
        mt.name = m.name;
        mt.type = m.type == "black" ? ir::Material::Type::Black : ir::Material::Type::Lambertian;
        mt.solver = m.solver == "generic" ? ir::Material::Solver::Generic
                  : m.solver == "surface-pm" ? ir::Material::Solver::SurfacePM : ir::Material::Solver::Classic;
        mt.reflectance = m.reflectance;
        ir->materials.push_back(mt);
    }
    for (const auto& s : spec.sensors) ir->sensors.push_back(placeSensor(s, spec.waterLevel, spec.hasWater));
    for (const auto& p : spec.probes) {
        ir::Probe pr;
        pr.name = p.name;
        pr.position = p.position;
        pr.quantities = p.quantities;
        if (p.medium == "water" || (p.medium == "auto" && spec.hasWater && p.position.z < spec.waterLevel))
            pr.medium = "water";
        ir->probes.push_back(pr);
    }
    ir->metadata["source"] = spec.file.filename().string();
}

}  // namespace littoral::scenegen
