#include "scenegen/scene_file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/kinds.h"
#include "core/material_kinds.h"
#include "core/output_names.h"
#include "core/phase_functions.h"
#include "core/probe_quantities.h"
#include "core/sensor_types.h"
#include "core/solar_position.h"
#include "core/spectral_response.h"
#include "core/suggest.h"
#include "core/text_checks.h"
#include "core/units.h"
#include "scenegen/water_constituents.h"

namespace littoral::scenegen {

namespace fs = std::filesystem;

// The data lines of a small CSV table (UTF-8 checked; a CRLF line end and a byte-order mark are
// dropped; blank lines and lines starting with '#' skipped), commas replaced by blanks:
// row(lineNo, line) for each.
template <class Row> void forEachCsvLine(std::string_view text, const std::string& file, Row&& row) {
    requireUtf8(text, file);
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
        row(lineNo, line);
    }
}

// A file named at the scene-file key `f`, parsed by parse(text, path): an unreadable file is an
// error at the key; a parse error located in the file (line > 0) stays there, any other is put at
// the key with the file's name.
template <class Parse> auto parseFileAtKey(const YamlNode& f, Parse&& parse) {
    const fs::path p = f.asExistingPath();
    std::string text;
    try {
        text = readTextFile(p);
    } catch (const InputError& e) {
        f.fail(fmt::format("cannot read '{}': {}", p.string(), e.message()));
    }
    try {
        return parse(text, p.string());
    } catch (const InputError& e) {
        if (e.where().line > 0) throw;  // located in the file
        f.fail(fmt::format("{}: {}", p.string(), e.message()));
    }
}

Spectrum parseSpectrumCsv(std::string_view text, const std::string& file, double min, double max,
                          std::string_view unit) {
    std::vector<double> wl, val;
    forEachCsvLine(text, file, [&](int lineNo, const std::string& line) {
        std::istringstream ls(line);
        double w, v;
        std::string rest;
        if (!(ls >> w >> v) || (ls >> rest)) {
            if (wl.empty() && lineNo == 1) return;  // header row
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
    });
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
        return parseFileAtKey(*f, [&](const std::string& text, const std::string& path) {
            return parseSpectrumCsv(text, path, min, max, unit);
        });
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
    n.expectKeys({"model", "radiance", "hemisphere_irradiance", "sky_fraction", "sun_plane"});
    s->model = n.getEnum("model", "uniform", {"uniform", "simple"});
    if (s->model == "uniform") {
        for (const char* k : {"hemisphere_irradiance", "sky_fraction", "sun_plane"})
            if (n.has(k)) n[k].fail("only used with model: simple");
        s->radiance = parseSpectrum(n["radiance"], 0, 1e5, "W m^-2 sr^-1 um^-1");
    } else {
        if (n.has("radiance")) n["radiance"].fail("model: simple derives the sky radiance; use hemisphere_irradiance and sky_fraction");
        s->hemisphereIrradiance = n["hemisphere_irradiance"].asDouble(0, 1e5, "W m^-2 um^-1");
        s->skyFraction = n["sky_fraction"].asDouble(0, 1);
        s->sunPlane = n.getEnum("sun_plane", "horizontal", {"horizontal", "normal"});
    }
}

// A value of a parameter as its descriptor types it, range-checked at its location (below).
ParamValue parseParam(const YamlNode& v, const ParamSpec& p);

// The sensor keys: placement, the parameters of every sensor type (core/sensor_types.h), and the
// image.
std::vector<std::string> sensorKeys() {
    std::vector<std::string> keys = {"name",   "type",    "elevation_deg", "zenith_deg", "azimuth_deg", "range_m",
                                     "gsd_m",  "target",  "position",      "look_at",    "direction",   "up"};
    for (const SensorKind& k : sensorTypeKinds().kinds())
        for (const ParamSpec& p : k.info.params)
            if (std::find(keys.begin(), keys.end(), p.sceneName()) == keys.end()) keys.push_back(p.sceneName());
    keys.insert(keys.end(), {"width", "height", "samples_per_pixel", "medium", "psf", "detector", "water_products"});
    return keys;
}

// A band with a spectral response: `{centre_um, fwhm_um}` (Gaussian) or `{response: SPECTRUM}`
// (a table, inline or {file: srf.csv}, of relative response >= 0 that falls to at most 1 % of its
// peak at both ends, so that the table holds the whole band).
ResponseSpec parseResponseBand(const YamlNode& n) {
    n.expectKeys({"centre_um", "fwhm_um", "response"});
    ResponseSpec r;
    if (auto t = n.optional("response")) {
        for (const char* k : {"centre_um", "fwhm_um"})
            if (n.has(k)) n[k].fail("give a band either 'centre_um' and 'fwhm_um' (Gaussian) or 'response' (a table)");
        const Spectrum sp = parseSpectrum(*t, 0, 1e6, "");
        if (sp.isConstant() || sp.wavelengths().size() < 3)
            t->fail("a spectral response is a table of at least 3 (wavelength_um, response) rows");
        r.kind = ResponseSpec::Kind::Table;
        r.wl = sp.wavelengths();
        r.value = sp.values();
        const double peak = *std::max_element(r.value.begin(), r.value.end());
        if (!(peak > 0)) t->fail("the response is zero everywhere");
        for (const bool first : {true, false}) {
            const double v = first ? r.value.front() : r.value.back(), at = first ? r.wl.front() : r.wl.back();
            if (v > 0.01 * peak)
                t->fail(fmt::format("the table does not cover its band: the response at its {} end, {} um, is {:.3g} % "
                                    "of its peak (at most 1 %); extend the table until the response falls to zero",
                                    first ? "short" : "long", at, 100 * v / peak));
        }
        if (r.wl.front() < 0.2 || r.wl.back() > 20) t->fail("allowed wavelengths are 0.2 to 20 um");
        return r;
    }
    r.kind = ResponseSpec::Kind::Gaussian;
    r.centre = n["centre_um"].asDouble(0.2, 20, "um");
    r.fwhm = n["fwhm_um"].asDouble(0.0005, 1, "um");
    if (r.centre - kGaussianSupportFwhm * r.fwhm < 0.2 || r.centre + kGaussianSupportFwhm * r.fwhm > 20)
        n.fail(fmt::format("the band's support, centre +- {} FWHM = [{}, {}] um, leaves the allowed 0.2 to 20 um",
                           kGaussianSupportFwhm, r.centre - kGaussianSupportFwhm * r.fwhm,
                           r.centre + kGaussianSupportFwhm * r.fwhm));
    return r;
}

// A PSF kernel file: rows of non-negative numbers separated by commas or blanks, '#' comments;
// every row as long as the first, odd width and height up to ir::kMaxPsfSide.
ir::SensorPsf parsePsfKernelCsv(std::string_view text, const std::string& file) {
    ir::SensorPsf psf;
    psf.type = "kernel";
    forEachCsvLine(text, file, [&](int lineNo, std::string line) {
        if (const size_t h = line.find('#'); h != std::string::npos) line.resize(h);  // a trailing comment
        std::istringstream in(line);
        std::vector<double> row;
        std::string tok;
        while (in >> tok) {
            char* stop = nullptr;
            const double v = std::strtod(tok.c_str(), &stop);
            if (stop == tok.c_str() || *stop != '\0' || !std::isfinite(v) || v < 0)
                throw InputError(SourceLoc{file, lineNo, 1},
                                 fmt::format("PSF value '{}' is not a finite number >= 0", printableName(tok)));
            row.push_back(v);
        }
        if (row.empty()) return;
        if (psf.width == 0) psf.width = static_cast<int>(row.size());
        if (static_cast<int>(row.size()) != psf.width)
            throw InputError(SourceLoc{file, lineNo, 1}, fmt::format("this row has {} values, the first row {}; a "
                                                                     "kernel is a rectangle", row.size(), psf.width));
        if (++psf.height > ir::kMaxPsfSide || psf.width > ir::kMaxPsfSide)
            throw InputError(SourceLoc{file, lineNo, 1}, fmt::format("a PSF kernel is at most {} x {} values",
                                                                     ir::kMaxPsfSide, ir::kMaxPsfSide));
        psf.values.insert(psf.values.end(), row.begin(), row.end());
    });
    if (psf.width == 0) throw InputError(SourceLoc{file}, "the file holds no kernel rows");
    if (psf.width % 2 == 0 || psf.height % 2 == 0)
        throw InputError(SourceLoc{file}, fmt::format("the kernel is {} x {}; its width and height must be odd (its "
                                                      "centre is the pixel itself)", psf.width, psf.height));
    double sum = 0;
    for (double v : psf.values) sum += v;
    if (!(sum > 0)) throw InputError(SourceLoc{file}, "the kernel is all zero");
    return psf;
}

// `psf: {type: gaussian, fwhm_px: F}` or `psf: {type: kernel, file: K.csv}`.
ir::SensorPsf parseSensorPsf(const YamlNode& n) {
    const std::string type = n["type"].asEnum({"gaussian", "kernel"});
    if (type == "gaussian") {
        n.expectKeys({"type", "fwhm_px"});
        ir::SensorPsf psf;
        psf.type = type;
        psf.fwhmPx = n["fwhm_px"].asDouble(0.1, 50, "px");
        return psf;
    }
    n.expectKeys({"type", "file"});
    return parseFileAtKey(n["file"], parsePsfKernelCsv);
}

// `detector:` in the units of a data sheet (mm, ms, electrons, bits).
ir::SensorDetector parseSensorDetector(const YamlNode& n, uint64_t defaultSeed) {
    n.expectKeys({"aperture_mm", "integration_ms", "quantum_efficiency", "read_noise_e", "full_well_e", "bits", "seed"});
    ir::SensorDetector d;
    d.apertureDiameter = 1e-3 * n["aperture_mm"].asDouble(0.01, 10000, "mm");
    d.integrationTime = 1e-3 * n["integration_ms"].asDouble(1e-6, 1e5, "ms");
    d.quantumEfficiency = n["quantum_efficiency"].asDouble(1e-6, 1, "");
    d.readNoise = n.getDouble("read_noise_e", 0, 0, 1e6, "electrons");
    d.fullWell = n["full_well_e"].asDouble(1, 1e9, "electrons");
    d.bits = static_cast<int>(n.getInt("bits", 12, 1, 24));
    d.seed = static_cast<uint64_t>(n.getInt("seed", static_cast<long long>(defaultSeed), 0, 1LL << 62));
    return d;
}

// The scene keys of every sensor type's parameters, in registration order.
std::vector<std::string> sensorParamSceneKeys() {
    std::vector<std::string> keys;
    for (const SensorKind& k : sensorTypeKinds().kinds())
        for (const ParamSpec& p : k.info.params) keys.push_back(p.sceneName());
    return keys;
}

// The sensor types with a parameter written `sceneKey` ("orthographic", or "a or b").
std::string sensorTypesWith(const std::string& sceneKey) {
    std::string s;
    for (const SensorKind& k : sensorTypeKinds().kinds())
        if (k.info.paramBySceneKey(sceneKey)) s += (s.empty() ? "" : " or ") + k.info.name;
    return s;
}

// The optics of a pinhole or orthographic sensor: the parameters its type's descriptor declares,
// converted to the IR's metres; another type's parameter is refused naming the type that uses it.
void parseSensorOptics(const YamlNode& n, const SensorKind& kind, SensorSection* s) {
    std::vector<std::string> own;
    for (const ParamSpec& p : kind.info.params) own.push_back(p.sceneName());
    for (const std::string& k : sensorParamSceneKeys())
        if (n.has(k) && !kind.info.paramBySceneKey(k))
            n[k].fail(fmt::format("'{}' is only used by the {} sensor type (this sensor is {}, which uses {})", k,
                                  sensorTypesWith(k), kind.info.name, joinList(own, " and ")));
    for (size_t i = 0; i < kind.info.params.size(); ++i) {
        const ParamSpec& p = kind.info.params[i];
        const ParamValue v = p.defaultValue && !n.optional(p.sceneName()) ? p.defaultParamValue()
                                                                           : parseParam(n[p.sceneName()], p);
        s->optics.set(p.name, numberOf(v) * kind.fields[i].irScale);
    }
}

// A sensor's `up` (the node `u`, read as `up`) against its unit view direction `d`: refused at
// the key when it is zero or parallel to the view. Scaled by its largest component first, as the
// renderer does, so that [0, 1e200, 0] (whose length overflows) and [0, 1e-10, 0] are directions
// like any other.
void checkUp(const YamlNode& u, const Vec3& up, const Vec3& d) {
    const double m = std::max({std::abs(up.x), std::abs(up.y), std::abs(up.z)});
    if (!(m > 0)) u.fail("'up' must be non-zero (it sets the image's up direction)");
    if (length(cross(d, normalize(Vec3{up.x / m, up.y / m, up.z / m}))) < 1e-9) {
        auto c = [](double x) { return std::abs(x) < 1e-9 ? 0.0 : x; };  // no rounding noise in the message
        u.fail(fmt::format("'up' ({:g}, {:g}, {:g}) must not be parallel to the view direction ({:.6g}, {:.6g}, {:.6g})",
                           up.x, up.y, up.z, c(d.x), c(d.y), c(d.z)));
    }
}

// A frame sensor (Table 10.1): the unit vector from the target toward the sensor at elevation e
// and compass azimuth phi, and whether its image's up is the scene file's `up` (a nadir view) or
// far range.
Vec3 frameToSensor(double e, double phi) {
    return {std::cos(e) * std::sin(phi), std::cos(e) * std::cos(phi), std::sin(e)};
}
bool frameUsesUp(double e) { return std::abs(std::sin(e)) > 0.999; }

// A pinhole or orthographic sensor's placement: position, look_at or direction, up.
void parsePlacement(const YamlNode& n, SensorSection* s) {
    s->position = parseVec3(n["position"]);
    if (n.has("look_at") == n.has("direction")) n.fail("give exactly one of look_at, direction");
    const Vec3 d = n.has("look_at") ? parseVec3(n["look_at"]) - s->position : parseVec3(n["direction"]);
    if (length(d) < 1e-12) n.fail("the view direction has zero length");
    s->direction = normalize(d);
    if (auto u = n.optional("up")) {
        s->up = parseVec3(*u);
        checkUp(*u, s->up, s->direction);
    } else {
        s->up = std::abs(s->direction.z) > 0.99 ? Vec3{0, 1, 0} : Vec3{0, 0, 1};
    }
}

// A frame sensor (dissertation Table 10.1): placed by elevation, azimuth, range and GSD; scenegen
// makes it a pinhole (placeSensor).
void parseFramePlacement(const YamlNode& n, SensorSection* s) {
    if (n.has("elevation_deg") == n.has("zenith_deg")) n.fail("a frame sensor needs exactly one of elevation_deg, zenith_deg");
    s->elevation = n.has("elevation_deg") ? deg2rad(n["elevation_deg"].asDouble(1, 90, "degrees"))
                                          : kPi / 2 - deg2rad(n["zenith_deg"].asDouble(0, 89, "degrees"));
    s->compassAzimuth = deg2rad(n["azimuth_deg"].asDouble(0, 360, "degrees (clockwise from north)"));
    s->range = n["range_m"].asDouble(0.01, 1e6, "m");
    s->gsd = n["gsd_m"].asDouble(1e-5, 1e4, "m");
    if (auto t = n.optional("target")) s->target = parseVec3(*t);
    if (auto u = n.optional("up")) {
        s->up = parseVec3(*u);
        // Only a nadir view uses it (placeSensor): the image's up is otherwise far range.
        if (frameUsesUp(s->elevation)) checkUp(*u, s->up, -frameToSensor(s->elevation, s->compassAzimuth));
    } else {
        s->up = {0, 1, 0};
    }
}

SensorSection parseSensor(const YamlNode& n) {
    n.expectKeys(sensorKeys());
    SensorSection s;
    s.loc = n.loc();
    s.name = n["name"].asOutputName("sensor");
    // "frame" (a placement that makes a pinhole) and the registered sensor types.
    std::vector<std::string> types = {"frame"};
    for (const std::string& t : sensorTypeKinds().names()) types.push_back(t);
    s.type = n["type"].asEnum(types);
    s.width = static_cast<int>(n["width"].asInt(1, 20000));
    s.height = static_cast<int>(n["height"].asInt(1, 20000));
    s.samplesPerPixel = static_cast<int>(n.getInt("samples_per_pixel", 1, 1, 65536));
    s.medium = n.getEnum("medium", "auto", {"auto", "air", "water"});
    auto forbid = [&](const std::vector<std::string>& keys, const char* why) {
        for (const std::string& k : keys)
            if (n.has(k)) n[k].fail(fmt::format("not used by a {} sensor ({})", s.type, why));
    };
    if (s.type == "frame") {
        std::vector<std::string> unused = {"position", "look_at", "direction"};
        for (const std::string& k : sensorParamSceneKeys()) unused.push_back(k);
        forbid(unused, "it is placed by elevation, azimuth, range and GSD");
        parseFramePlacement(n, &s);
    } else {
        forbid({"elevation_deg", "zenith_deg", "azimuth_deg", "range_m", "gsd_m", "target"},
               "it is placed by position and direction");
        parsePlacement(n, &s);
        parseSensorOptics(n, sensorTypeKinds().get(s.type, ""), &s);
    }
    if (auto p = n.optional("psf")) s.psf = parseSensorPsf(*p);
    if (auto d = n.optional("detector")) {
        if (s.type == "orthographic")
            d->fail("an orthographic sensor has no optics to collect light (aperture and pixel solid angle): a detector "
                    "needs a frame or pinhole sensor");
        s.detector = parseSensorDetector(*d, 1);
        s.detectorSeedGiven = d->has("seed");
    }
    if (auto w = n.optional("water_products")) {
        s.waterProducts = w->asBool();
        s.waterProductsLoc = w->loc();
    }
    return s;
}

// The keys a probe entry shares with every probe of an array (name, quantities, medium, samples).
ProbeSection parseProbeCommon(const YamlNode& n) {
    ProbeSection p;
    p.loc = n.loc();
    p.name = n["name"].asOutputName("probe");
    // The quantities the renderer describes (render/probes.cpp, registered in core/kinds.h).
    const std::vector<std::string> allowed = probeQuantityKinds().names();
    if (allowed.empty()) n["quantities"].fail("no probe quantity is registered in this program (render::registerEstimatorKinds())");
    for (const auto& q : n["quantities"].items()) p.quantities.push_back(q.asEnum(allowed));
    if (p.quantities.empty()) n["quantities"].fail("list at least one of " + joinList(allowed));
    p.medium = n.getEnum("medium", "auto", {"auto", "air", "water"});
    if (auto sm = n.optional("samples")) p.samples = static_cast<int>(sm->asInt(2, 1 << 30));
    return p;
}

// "name_07": the index zero-padded to the digits of the largest, so that names sort in order.
std::string indexedName(const std::string& base, long long i, long long count) {
    const int width = static_cast<int>(std::to_string(std::max(0LL, count - 1)).size());
    return fmt::format("{}_{:0{}d}", base, i, width);
}

// A probe entry: one probe at `position`, or an array of them: `line` (a transect or a vertical
// profile, `count` probes evenly spaced from `from` to `to`, both ends included) or `grid` (a
// horizontal grid of count[0] x count[1] probes over the rectangle from `from` to `to` at their
// common height). Array probes are named <name>_<i> (line) or <name>_<i>_<j> (grid, i along x).
std::vector<ProbeSection> parseProbeEntry(const YamlNode& n) {
    n.expectKeys({"name", "position", "line", "grid", "quantities", "medium", "samples"});
    const ProbeSection common = parseProbeCommon(n);
    const int given = int(n.has("position")) + int(n.has("line")) + int(n.has("grid"));
    if (given != 1)
        n.fail(fmt::format("probe '{}': give exactly one of 'position' (one probe), 'line' or 'grid' (an array); "
                           "found {}",
                           common.name, given));
    if (auto pos = n.optional("position")) {
        ProbeSection p = common;
        p.position = parseVec3(*pos);
        return {p};
    }
    const bool isGrid = n.has("grid");
    const YamlNode a = n[isGrid ? "grid" : "line"];
    a.expectKeys({"from", "to", "count"});
    const Vec3 from = parseVec3(a["from"]), to = parseVec3(a["to"]);
    std::vector<ProbeSection> out;
    auto at = [&](double t) { return from + t * (to - from); };
    if (!isGrid) {
        const long long count = a["count"].asInt(2, kMaxArrayProbes);
        if (length(to - from) <= 0) a["to"].fail("a line needs 'to' apart from 'from'");
        for (long long i = 0; i < count; ++i) {
            ProbeSection p = common;
            p.name = indexedName(common.name, i, count);
            p.position = at(double(i) / double(count - 1));
            out.push_back(p);
        }
        return out;
    }
    const auto c = a["count"].asDoubleList(1, kMaxArrayProbes);
    if (c.size() != 2 || c[0] != std::floor(c[0]) || c[1] != std::floor(c[1]))
        a["count"].fail("expected [nx, ny]: two whole numbers, the probes along x and along y");
    const long long nx = static_cast<long long>(c[0]), ny = static_cast<long long>(c[1]);
    if (nx * ny > kMaxArrayProbes)
        a["count"].fail(fmt::format("{} x {} = {} probes; at most {} in one array", nx, ny, nx * ny, kMaxArrayProbes));
    if (from.z != to.z)
        a["to"].fail(fmt::format("a grid is horizontal: 'from' and 'to' must have the same z (found {} and {}); use "
                                 "'line' for a vertical profile",
                                 from.z, to.z));
    if ((nx > 1 && from.x == to.x) || (ny > 1 && from.y == to.y))
        a["to"].fail("a grid with more than one probe along an axis needs 'from' and 'to' apart along it");
    for (long long i = 0; i < nx; ++i)
        for (long long j = 0; j < ny; ++j) {
            ProbeSection p = common;
            p.name = indexedName(indexedName(common.name, i, nx), j, ny);
            p.position = {nx > 1 ? from.x + (to.x - from.x) * double(i) / double(nx - 1) : from.x,
                          ny > 1 ? from.y + (to.y - from.y) * double(j) / double(ny - 1) : from.y, from.z};
            out.push_back(p);
        }
    return out;
}

// A `materials` entry: its type (a scene-file material type of core/material_kinds.h) and the
// keys that type takes; a key of another type is refused, naming the types that take it.
MaterialSection parseMaterial(const YamlNode& n) {
    std::vector<std::string> keys{"name", "type"};
    for (const MaterialKind& k : materialKinds().kinds())
        for (const std::string& key : k.sceneKeys)
            if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
    n.expectKeys(keys);
    MaterialSection m;
    m.loc = n.loc();
    m.name = n["name"].asString();
    m.type = n.getEnum("type", "lambertian", sceneMaterialTypeNames());
    const MaterialKind& kind = *materialKinds().find(m.type);
    for (size_t i = 2; i < keys.size(); ++i) {
        if (!n.has(keys[i]) || kind.takesSceneKey(keys[i])) continue;
        if (keys[i] == "solver")
            n["solver"].fail(fmt::format("a {} material takes no solver ({}); remove 'solver'", m.type, kind.noSolverWhy));
        if (keys[i] == "reflectance")
            n["reflectance"].fail(fmt::format("a {} material has no reflectance: {}; remove 'reflectance'", m.type, kind.info.doc));
        n[keys[i]].fail(fmt::format("a {} material does not take '{}'; it is a key of: {}", m.type, keys[i],
                                    sceneTypesWithKey(keys[i])));
    }
    if (kind.type == ir::Material::Type::Dielectric) {
        // A transparent solid (glass, epoxy, ice): a smooth Fresnel interface around a medium of
        // this index and absorption. Objects use it; light refracts through it (docs/scene-format.md).
        if (m.name == "water")
            n["name"].fail("'water' is the name of the medium Littoral builds from water.optics; choose another name for "
                           "this dielectric");
        if (!n.has("refractive_index"))
            n.fail("a dielectric needs 'refractive_index' (a number, or a spectrum {wavelengths_um, values} or "
                   "{file}, in [1, 3]; e.g. 1.5 for glass, 1.55 for epoxy)");
        m.refractiveIndex = parseSpectrum(n["refractive_index"], 1.0, 3.0, "");
        if (auto a = n.optional("absorption_per_m")) m.absorption = parseSpectrum(*a, 0, 1000, "m^-1");
    }
    if (auto sv = n.optional("solver")) {
        m.solver = sv->asEnum(kind.solverNames());
    }
    if (kind.hasReflectance) m.reflectance = parseSpectrum(n["reflectance"], 0, 1, "(reflectance)");
    return m;
}

ParamValue parseParam(const YamlNode& v, const ParamSpec& p) {
    switch (p.type) {
        case ParamType::Boolean: return v.asBool();
        case ParamType::Integer:
            return static_cast<int64_t>(v.asInt(static_cast<long long>(p.lo), static_cast<long long>(p.hi)));
        case ParamType::Real: break;
    }
    return v.asDouble(p.lo, p.hi, p.unit);
}

// A phase function {type, <its parameters>}: the kinds and their parameters are the descriptors of
// core/phase_functions.h; every parameter of the kind gets a value (its default when not given).
ir::PhaseFunction parsePhase(const YamlNode& ph) {
    const KindRegistry<PhaseKind>& kinds = phaseFunctionKinds();
    std::vector<std::string> keys = {"type"};
    for (const auto& k : kinds.allParamNames()) keys.push_back(k);
    ph.expectKeys(keys);
    ir::PhaseFunction p;
    p.type = ph["type"].asEnum(kinds.names());
    const KindInfo& kind = kinds.find(p.type)->info;
    for (size_t i = 1; i < keys.size(); ++i)
        if (ph.has(keys[i]) && !kind.param(keys[i]))
            ph[keys[i]].fail(fmt::format("'{}' is only used by the {} {}", keys[i], kinds.kindsWithParam(keys[i]),
                                         kinds.family()));
    for (const ParamSpec& spec : kind.params) {
        if (!ph.has(spec.name) && spec.defaultValue) p.params.set(spec.name, spec.defaultParamValue());
        else p.params.set(spec.name, parseParam(ph[spec.name], spec));
    }
    return p;
}

// Grid on which constituent spectra are tabulated: 5 nm steps over the render bands.
std::vector<double> constituentGrid(const std::vector<Band>& bands) {
    double lo = bands.front().lo, hi = bands.front().hi;
    for (const Band& b : bands) lo = std::min(lo, b.lo), hi = std::max(hi, b.hi);
    std::vector<double> wl;
    const int n = std::max(1, static_cast<int>(std::ceil((hi - lo) / 0.005 - 1e-9)));
    for (int i = 0; i <= n; ++i) wl.push_back(lo + (hi - lo) * i / n);
    return wl;
}

// At most one medium model (water_constituents.h: preset, constituents, explicit) per node:
// "give one of 'preset', 'constituents' or absorption_per_m/scattering_per_m".
void checkOneMediumModel(const YamlNode& n) {
    int given = 0;
    std::vector<std::string> choices;
    for (const MediumModelKind& m : mediumModelKinds().kinds()) {
        bool chosen = false;
        for (const std::string& k : m.sceneKeys) chosen = chosen || n.has(k);
        given += chosen;
        choices.push_back(m.sceneKeys.size() == 1 ? "'" + m.sceneKeys[0] + "'" : joinList(m.sceneKeys, "/"));
    }
    if (given > 1) {
        const std::string last = choices.back();
        choices.pop_back();
        n.fail(fmt::format("give one of {} or {}", joinList(choices), last));
    }
}

// A `constituents:` map: its numeric keys from the constituents model's descriptor
// (water_constituents.h), `pure_water` and the phase functions of its scatterers besides:
// `pure_water_phase`, `particle_phase` (phytoplankton and sediment) and `phytoplankton_phase`,
// `sediment_phase` (each overriding particle_phase for its constituent). A phase function of a
// constituent that is absent, or a particle_phase both others override, is refused (not used).
WaterComposition parseConstituents(const YamlNode& c) {
    const MediumModelKind& model = *mediumModelKinds().find("constituents");
    std::vector<std::string> keys = {"pure_water"};
    for (const ParamSpec& p : model.info.params) keys.push_back(p.name);
    for (const char* k : {"pure_water_phase", "particle_phase", "phytoplankton_phase", "sediment_phase"}) keys.push_back(k);
    c.expectKeys(keys);
    WaterComposition comp;
    const std::string pw = c.getEnum("pure_water", "sea", {"sea", "fresh", "none"});
    comp.includePureWater = pw != "none";
    comp.water = pw == "fresh" ? WaterKind::Fresh : WaterKind::Sea;
    for (size_t i = 0; i < model.info.params.size(); ++i) {
        const ParamSpec& p = model.info.params[i];
        const auto v = c.optional(p.name);
        comp.*model.fields[i] = numberOf(v ? parseParam(*v, p) : p.defaultValue ? p.defaultParamValue() : parseParam(c[p.name], p));
    }
    auto phaseOf = [&](const char* key, bool present, const char* why) -> std::optional<ir::PhaseFunction> {
        const auto n = c.optional(key);
        if (!n) return std::nullopt;
        if (!present) n->fail(fmt::format("not used: {}", why));
        return parsePhase(*n);
    };
    if (auto p = phaseOf("pure_water_phase", comp.includePureWater, "pure_water is none (no pure water)")) comp.pureWaterPhase = *p;
    const bool phyto = comp.chlorophyllMgM3 > 0, sediment = comp.sedimentGM3 > 0;
    if (c.has("particle_phase") && c.has("phytoplankton_phase") && c.has("sediment_phase"))
        c["particle_phase"].fail("not used: phytoplankton_phase and sediment_phase both replace it");
    if (auto p = c.optional("particle_phase")) comp.phytoplanktonPhase = comp.sedimentPhase = parsePhase(*p);
    if (auto p = phaseOf("phytoplankton_phase", phyto, "chlorophyll_mg_m3 is 0 (no phytoplankton)")) comp.phytoplanktonPhase = *p;
    if (auto p = phaseOf("sediment_phase", sediment, "sediment_g_m3 is 0 (no sediment)")) comp.sedimentPhase = *p;
    return comp;
}

// `scatterers:` (the explicit model): a list of {name, scattering_per_m, phase}, each scatterer
// with its own b(lambda) and phase function (default HG g = 0.88), mixed by the renderer and the
// column solver as sum b_i p_i / sum b_i. At most PhaseFunction::kMaxComponents (the mixture's size).
void parseScatterers(const YamlNode& list, LayerOptics* o) {
    std::set<std::string> names;
    for (const auto& it : list.items()) {
        it.expectKeys({"name", "scattering_per_m", "phase"});
        ir::Scatterer sc;
        sc.name = it["name"].asString();
        if (sc.name.empty() || !names.insert(sc.name).second)
            it["name"].fail(sc.name.empty() ? "give the scatterer a name" : "scatterer '" + sc.name + "' is listed twice");
        sc.scattering = parseSpectrum(it["scattering_per_m"], 0, 1000, "m^-1");
        sc.phase = {"henyey-greenstein", {{"g", 0.88}}};
        if (auto ph = it.optional("phase")) {
            sc.phase = parsePhase(*ph);
            o->phaseGiven = true;
            o->phaseKey = "scatterers[].phase";
        }
        if (!(sc.scattering.isConstant() && sc.scattering.values()[0] == 0.0)) o->scatterers.push_back(std::move(sc));
    }
    if (names.empty()) list.fail("list at least one scatterer");
    if (names.size() > static_cast<size_t>(PhaseFunction::kMaxComponents))
        list.fail(fmt::format("{} scatterers; at most {} per layer (the phase-function mixture holds {})", names.size(),
                              PhaseFunction::kMaxComponents, PhaseFunction::kMaxComponents));
}

// The IOP keys shared by water.optics and each of its layers: a preset, a constituent mix, or
// absorption and scattering given directly; `phase` replaces the phase function of every
// scattering constituent.
void parseIops(const YamlNode& n, const std::vector<Band>& bands, LayerOptics* o) {
    o->loc = n.loc();
    checkOneMediumModel(n);
    if (auto pw = n.optional("pure_water"); pw && !n.has("preset"))
        pw->fail("pure_water goes beside 'preset' (for a preset that lists no pure water) or inside 'constituents'");
    if (auto p = n.optional("preset")) {
        const std::string name = p->asEnum(waterPresetKinds().names());
        const WaterPresetKind& kind = *waterPresetKinds().find(name);
        WaterIops w = kind.make();
        if (auto pw = n.optional("pure_water"); pw && kind.pureWater != "added")
            pw->fail(fmt::format("not used: preset '{}' {}; remove 'pure_water'", name,
                                 kind.pureWater == "in total" ? "gives measured totals, which hold the water's own IOPs"
                                                              : "is a purely refracting medium without water's IOPs"));
        if (kind.pureWater == "added" && n.getEnum("pure_water", "sea", {"sea", "fresh", "none"}) != "none") {
            WaterComposition water;
            water.water = n.getEnum("pure_water", "sea", {"sea", "fresh", "none"}) == "fresh" ? WaterKind::Fresh : WaterKind::Sea;
            try {
                const WaterIops pure = computeIops(water, constituentGrid(bands));
                w.components.insert(w.components.begin(), pure.components.begin(), pure.components.end());
                w.includesPureWater = true;
            } catch (const InputError& e) {
                n.optional("pure_water") ? n["pure_water"].fail(e.message()) : p->fail(e.message() + " (the pure water "
                                                                                        "this preset adds; pure_water: "
                                                                                        "none leaves it out)");
            }
        }
        o->preset = name;
        o->absorption = w.absorption();
        for (const IopComponent& c : w.components)
            if (!(c.scattering.isConstant() && c.scattering.values()[0] == 0.0))
                o->scatterers.push_back({c.name, c.scattering, c.phase});
    } else if (auto c = n.optional("constituents")) {
        WaterComposition comp = parseConstituents(*c);
        if (n.has("phase"))
            for (const char* k : {"pure_water_phase", "particle_phase", "phytoplankton_phase", "sediment_phase"})
                if (c->has(k))
                    (*c)[k].fail(fmt::format("not used: 'phase' beside 'constituents' replaces the phase function of "
                                             "every constituent; give '{}' or 'phase', not both", k));
        WaterIops w;
        try {
            w = computeIops(comp, constituentGrid(bands));
        } catch (const InputError& e) {
            c->fail(e.message());
        }
        o->preset = "constituents";
        o->absorption = w.absorption();
        for (const IopComponent& k : w.components)
            if (!(k.scattering.isConstant() && k.scattering.values()[0] == 0.0))
                o->scatterers.push_back({k.name, k.scattering, k.phase});
    } else {
        if (auto a = n.optional("absorption_per_m")) o->absorption = parseSpectrum(*a, 0, 1000, "m^-1");
        if (auto l = n.optional("scatterers")) {
            for (const char* k : {"scattering_per_m", "phase"})
                if (n.has(k)) n[k].fail(fmt::format("give '{}' of each scatterer under 'scatterers', not beside it", k));
            parseScatterers(*l, o);
        } else if (auto b = n.optional("scattering_per_m")) {
            const Spectrum sb = parseSpectrum(*b, 0, 1000, "m^-1");
            if (!(sb.isConstant() && sb.values()[0] == 0.0))
                o->scatterers.push_back({"particles", sb, {"henyey-greenstein", {{"g", 0.88}}}});
        }
    }
    if (auto ph = n.optional("phase")) {
        const ir::PhaseFunction f = parsePhase(*ph);
        for (auto& sc : o->scatterers) sc.phase = f;
        o->phaseGiven = true;
        o->phaseKey = "phase";
    }
}

void parseWater(const YamlNode& n, const std::vector<Band>& bands, SceneSpec* spec) {
    n.expectKeys({"level_m", "surface", "optics", "horizontal"});
    spec->hasWater = true;
    spec->waterLevel = n.getDouble("level_m", 0.0, -1e4, 1e4, "m");
    spec->periodic = n.getEnum("horizontal", "bounded", {"bounded", "periodic"}) == "periodic";
    if (auto s = n.optional("surface")) spec->waterSurface = *s;
    auto& o = spec->waterOptics;
    if (auto op = n.optional("optics")) {
        o.loc = op->loc();
        op->expectKeys({"preset", "pure_water", "constituents", "refractive_index", "absorption_per_m",
                        "scattering_per_m", "scatterers", "phase", "interface", "layers", "solver"});
        if (auto sv = op->optional("solver")) {
            o.solver = sv->asEnum(allNames<ir::Medium::Solver>());
            o.solverLoc = sv->loc();
        }
        if (auto ri = op->optional("refractive_index")) o.refractiveIndex = parseSpectrum(*ri, 1.0, 3.0, "");
        if (auto ls = op->optional("layers")) {
            for (const char* k :
                 {"preset", "pure_water", "constituents", "absorption_per_m", "scattering_per_m", "scatterers", "phase"})
                if (op->has(k)) (*op)[k].fail("give the IOPs of each layer under 'layers', not beside it");
            double expectTop = 0;
            for (const auto& it : ls->items()) {
                it.expectKeys({"depth_m", "preset", "pure_water", "constituents", "absorption_per_m",
                               "scattering_per_m", "scatterers", "phase"});
                const auto d = it["depth_m"].asDoubleList(0, 1e5, "m");
                if (d.size() != 2 || !(d[1] > d[0])) it["depth_m"].fail("expected [top, bottom] depths with top < bottom");
                if (d[0] != expectTop)
                    it["depth_m"].fail(o.layers.empty()
                                           ? fmt::format("the first layer must start at depth 0 (the surface), not {} m", d[0])
                                           : fmt::format("layers must be contiguous: this layer starts at {} m but the "
                                                         "one above ends at {} m ({})",
                                                         d[0], expectTop, d[0] > expectTop ? "a gap" : "an overlap"));
                expectTop = d[1];
                LayerOptics l;
                parseIops(it, bands, &l);
                o.layerTops.push_back(d[0]);
                o.layers.push_back(std::move(l));
            }
            if (o.layers.empty()) ls->fail("list at least one layer");
        } else {
            parseIops(*op, bands, &o.iops);
        }
        // The air-water interface is always evaluated by the Fresnel solver (smooth and rough alike):
        // a key that could only restate that is refused rather than silently read.
        if (auto in = op->optional("interface"))
            in->fail("the air-water interface always uses the Fresnel solver (smooth or, with "
                     "water.surface.roughness, rough); remove 'interface'");
    }
}

// The scene-file node of a render setting at key path "a" or "a.b", if given.
std::optional<YamlNode> settingNode(const YamlNode& render, const std::string& sceneKey) {
    const size_t dot = sceneKey.find('.');
    if (dot == std::string::npos) return render.optional(sceneKey);
    const auto section = render.optional(sceneKey.substr(0, dot));
    return section ? section->optional(sceneKey.substr(dot + 1)) : std::nullopt;
}

// The keys allowed under `render:` and under each of its sections ("photons", ...), from the
// settings the estimators declare (core/kinds.h), in declaration order.
struct RenderKeys {
    std::vector<std::string> top = {"estimator", "bands", "seed", "threads"};
    std::vector<std::pair<std::string, std::vector<std::string>>> sections;
};
RenderKeys renderKeys(const std::vector<const ParamSpec*>& settings) {
    RenderKeys k;
    auto addOnce = [](std::vector<std::string>& v, const std::string& s) {
        if (std::find(v.begin(), v.end(), s) == v.end()) v.push_back(s);
    };
    for (const ParamSpec* p : settings) {
        const std::string& key = p->sceneName();
        const size_t dot = key.find('.');
        addOnce(k.top, key.substr(0, dot));
        if (dot == std::string::npos) continue;
        const std::string section = key.substr(0, dot);
        auto it = std::find_if(k.sections.begin(), k.sections.end(), [&](const auto& s) { return s.first == section; });
        if (it == k.sections.end()) it = k.sections.insert(k.sections.end(), {section, {}});
        addOnce(it->second, key.substr(dot + 1));
    }
    return k;
}

// The optional settings: those the estimators declare, each typed and range-checked by the chosen
// estimator's declaration (or, for a setting it does not read, the first estimator's that does:
// makeRenderConfig then refuses it as not read). Stored in the chosen estimator's declaration order,
// each with its location, so "not read by this estimator" points here.
void parseRenderSettings(const YamlNode& n, const std::vector<const ParamSpec*>& settings, ir::RenderSettings* s) {
    const KindInfo* chosen = estimatorKinds().find(nameOf(s->estimator));
    std::vector<const ParamSpec*> order;
    if (chosen)
        for (const ParamSpec& p : chosen->params) order.push_back(&p);
    for (const ParamSpec* p : settings)
        if (!chosen || !chosen->param(p->name)) order.push_back(p);
    for (const ParamSpec* p : order)
        if (const auto v = settingNode(n, p->sceneName())) {
            s->settings.set(p->name, parseParam(*v, *p));
            s->locations[p->sceneName()] = v->loc();
        }
}

void parseRender(const YamlNode& n, RenderSection* r) {
    const std::vector<const ParamSpec*> settings = allRenderSettings();
    const RenderKeys keys = renderKeys(settings);
    // A program that parses scene files without linking the renderer (a fuzz target) has no
    // estimators registered, and so no optional settings.
    if (settings.empty())
        for (const auto& k : n.keys())
            if (std::find(keys.top.begin(), keys.top.end(), k) == keys.top.end())
                n[k].fail("no estimator is registered in this program, so it reads no optional render settings "
                          "(render::registerEstimatorKinds())");
    n.expectKeys(keys.top);
    auto& s = r->settings;
    if (auto e = n.optional("estimator")) {
        s.estimator = *parseName<ir::Estimator>(e->asEnum(allNames<ir::Estimator>()));
    }
    if (auto b = n.optional("bands")) {
        s.bands.clear();
        if (b->isMap()) {
            b->expectKeys({"range_um", "count"});
            const auto rng = parsePair((*b)["range_um"]);
            if (rng[0] < 0.2 || rng[1] > 20) (*b)["range_um"].fail("allowed wavelengths are 0.2 to 20 um");
            s.bands = uniformBands(rng[0], rng[1], static_cast<int>(b->getInt("count", 1, 1, 1000)));
        } else {
            std::vector<ResponseSpec> specs;
            bool responses = false;
            for (const auto& it : b->items()) {
                if (it.isMap()) {
                    specs.push_back(parseResponseBand(it));
                    responses = true;
                    continue;
                }
                const auto v = parsePair(it);
                if (v[0] < 0.2 || v[1] > 20) it.fail("allowed wavelengths are 0.2 to 20 um");
                s.bands.push_back({v[0], v[1]});
                specs.push_back({ResponseSpec::Kind::Rectangle, v[0], v[1], 0, 0, {}, {}});
            }
            if (specs.empty()) b->fail("list at least one band [lo_um, hi_um]");
            if (responses) {  // the renderer renders the sub-bands; the outputs are their weighted means
                try {
                    ResponseGrid g = responseGrid(specs);
                    s.bands = std::move(g.internal);
                    s.responseBands = std::move(g.outputs);
                } catch (const InputError& e) {
                    b->fail(e.message());
                }
            }
        }
    }
    s.seed = static_cast<uint64_t>(n.getInt("seed", 1, 0, (1LL << 62)));
    s.threads = static_cast<int>(n.getInt("threads", 0, 0, 1024));
    for (const auto& [section, sub] : keys.sections)
        if (auto node = n.optional(section)) node->expectKeys(sub);
    parseRenderSettings(n, settings, &s);
}

// The scene-file entry of item i: an array entry makes many probes.
template <class T>
size_t entryOf(const T&, size_t i) { return i; }
size_t entryOf(const ProbeSection& p, size_t) { return p.entry; }

template <class T>
void checkUniqueNames(const std::vector<T>& items, const char* what, const YamlNode& list) {
    std::set<std::string> seen;
    for (size_t i = 0; i < items.size(); ++i)
        if (!seen.insert(items[i].name).second)
            list.at(entryOf(items[i], i)).fail(fmt::format("{} name '{}' is used twice", what, items[i].name));
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

// Fails at `where` unless `sp` is tabulated over every band.
void checkCover(const std::vector<Band>& bands, const Spectrum& sp, const YamlNode& where, const std::string& what) {
    for (const auto& b : bands)
        if (!sp.covers(b.lo, b.hi))
            where.fail(fmt::format("{} is tabulated over [{}, {}] um, which does not cover the band [{}, {}] um", what,
                                   sp.minWavelength(), sp.maxWavelength(), b.lo, b.hi));
}

// The water's layers (the single IOP set when there are no layers).
std::vector<const LayerOptics*> waterLayers(const WaterOptics& o) {
    if (o.layers.empty()) return {&o.iops};
    std::vector<const LayerOptics*> all;
    for (const auto& l : o.layers) all.push_back(&l);
    return all;
}

void checkSpectraCoverBands(const SceneSpec& spec, const YamlNode& root) {
    const auto& bands = spec.render.settings.bands;
    if (auto ms = root.optional("materials"))
        for (size_t i = 0; i < spec.materials.size(); ++i) {
            const MaterialSection& m = spec.materials[i];
            checkCover(bands, m.reflectance, ms->at(i), "reflectance of '" + m.name + "'");
            if (m.refractiveIndex)
                checkCover(bands, *m.refractiveIndex, ms->at(i), "refractive index of '" + m.name + "'");
            checkCover(bands, m.absorption, ms->at(i), "absorption of '" + m.name + "'");
        }
    if (auto w = root.optional("water")) {
        const auto& o = spec.waterOptics;
        for (const LayerOptics* l : waterLayers(o)) {
            checkCover(bands, l->absorption, *w, "water absorption");
            for (const auto& sc : l->scatterers)
                checkCover(bands, sc.scattering, *w, "water scattering (" + sc.name + ")");
        }
        checkCover(bands, o.refractiveIndex, *w, "water refractive index");
    }
    if (spec.sun.irradiance) checkCover(bands, *spec.sun.irradiance, root["sun"], "sun irradiance");
    // Without a sky section the radiance is the constant 0 (docs/scene-format.md): nothing to cover.
    if (spec.sky.radiance && root.has("sky")) checkCover(bands, *spec.sky.radiance, root["sky"], "sky radiance");
}

void checkWaterOptics(const SceneSpec& spec, const YamlNode& w) {
    const auto& bands = spec.render.settings.bands;
    const auto& o = spec.waterOptics;
    // A rough surface refracts between different indices only (render/rough_dielectric.h):
    // water of the air's index leaves it nothing to be rough between, and the renderer would
    // refuse the interface.
    if (auto surface = w.optional("surface"); surface && surface->has("roughness")) {
        const std::vector<double> n = o.refractiveIndex.bandAverages(bands, "water refractive index");
        for (size_t b = 0; b < n.size(); ++b)
            if (std::abs(n[b] - 1.0) <= 1e-6)
                (*surface)["roughness"].fail(fmt::format(
                    "a rough surface needs water of another refractive index than the air's (1), but "
                    "water.optics.refractive_index is {} in band {} ([{}, {}] um); remove the roughness or give "
                    "the water its index",
                    n[b], b, bands[b].lo, bands[b].hi));
    }
    // Every accepted setting is read: a phase function written in the file is used only where
    // light is scattered rather than lost: by the path estimator, or by the dirsig estimator's
    // MediumPM solver (with `solver: attenuation`, dirsig treats scattering as loss).
    if (spec.render.settings.estimator == ir::Estimator::Dirsig && o.solver == "attenuation")
        for (const LayerOptics* l : waterLayers(o))
            if (l->phaseGiven)
                throw InputError(l->loc, fmt::format("water.optics {}: not used: water.optics.solver attenuation "
                                                     "treats scattering as loss (Beer–Lambert with c = a + b); use "
                                                     "the medium-pm solver (the default), render.estimator: path, "
                                                     "or remove '{}'",
                                                     l->phaseKey, l->phaseKey));
}

// Correct by default: water that scatters in some band is rendered with its in-scattered light.
// Under the dirsig estimator that is the MediumPM solver (the volume photon map); the path
// estimator always follows scattering. `solver: attenuation` keeps the loss-only water.
void defaultWaterSolver(SceneSpec* spec) {
    WaterOptics& o = spec->waterOptics;
    if (!spec->hasWater || !o.solver.empty() || spec->render.settings.estimator != ir::Estimator::Dirsig) return;
    for (const LayerOptics* l : waterLayers(o))
        for (const ir::Scatterer& sc : l->scatterers)
            for (double b : sc.scattering.bandAverages(spec->render.settings.bands, "water scattering"))
                if (b > 0) {
                    o.solver = nameOf(ir::Medium::Solver::MediumPM);
                    o.solverDefaulted = true;
                    return;
                }
}

}  // namespace

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
        for (size_t i = 0; i < s->size(); ++i)
            for (ProbeSection& p : parseProbeEntry(s->at(i))) {
                p.entry = i;
                spec.probes.push_back(std::move(p));
            }
        checkUniqueNames(spec.probes, "probe", *s);
    }
    checkOutputFiles(spec, root);
    if (auto s = root.optional("materials")) {
        for (const auto& it : s->items()) spec.materials.push_back(parseMaterial(it));
        checkUniqueNames(spec.materials, "material", *s);
    }
    if (auto s = root.optional("render")) parseRender(*s, &spec.render);
    for (SensorSection& s : spec.sensors)  // a detector's noise follows the render's seed unless given its own
        if (s.detector && !s.detectorSeedGiven) s.detector->seed = spec.render.settings.seed;
    if (auto s = root.optional("water")) parseWater(*s, spec.render.settings.bands, &spec);
    spec.bathymetry = root.optional("bathymetry");
    spec.objects = root.optional("objects");
    spec.textureClasses = root.optional("texture_classes");

    // Every spectrum must cover every band: checked here so the error names the scene file.
    checkSpectraCoverBands(spec, root);
    if (auto w = root.optional("water")) checkWaterOptics(spec, *w);
    defaultWaterSolver(&spec);
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
    c.psf = s.psf;
    c.detector = s.detector;
    if (s.type == "frame") {
        // Table 10.1 geometry: the sensor sits at compass azimuth phi (clockwise from north, as seen
        // from the target) and elevation e, at slant range d. The IFOV follows from the GSD along the
        // optical axis: ifov = gsd / d (small-angle), realised as a pinhole with a 10 um pitch.
        const double e = s.elevation, phi = s.compassAzimuth;
        const Vec3 toSensor = frameToSensor(e, phi);
        c.type = ir::Sensor::Type::Pinhole;
        c.position = s.target + toSensor * s.range;
        c.forward = -toSensor;
        // "Up" in the image is the direction away from the sensor on the ground (top of the frame is
        // far range); at nadir it is the given up vector (north by default).
        c.up = frameUsesUp(e) ? s.up : Vec3{0, 0, 1};
        c.pixelPitch = 10e-6;
        c.focalLength = c.pixelPitch * s.range / s.gsd;
    } else {
        const SensorKind& kind = sensorTypeKinds().get(s.type, "sensor '" + s.name + "'");
        c.type = kind.type;
        c.position = s.position;
        c.forward = s.direction;
        c.up = s.up;
        for (size_t i = 0; i < kind.info.params.size(); ++i)
            c.*kind.fields[i].field = s.optics.number(kind.info.params[i].name);
    }
    if (s.medium == "water") c.medium = "water";
    else if (s.medium == "auto" && hasWater && c.position.z < waterLevel) c.medium = "water";
    if (s.waterProducts && !hasWater)
        throw InputError(s.waterProductsLoc, fmt::format("sensor '{}': water_products needs water in the scene (there is no water "
                                            "section): the products split the radiance where it meets the sea surface",
                                            s.name));
    if (s.waterProducts && c.medium == "water")
        throw InputError(s.waterProductsLoc, fmt::format("sensor '{}': water_products needs a sensor in the air (this one is in the "
                                            "water): the products split what reaches a sensor above the sea surface",
                                            s.name));
    c.waterProducts = s.waterProducts;
    return c;
}

namespace {

// The mean over the solar disc (half-angle `halfAngle`, centre at `zenith`, uniform in solid angle)
// of max(0, cos theta): the factor that turns the beam irradiance into irradiance on the ground.
// A 256 x 256 midpoint rule in (cos of the angle from the centre, azimuth about it).
double meanDiscCosine(double zenith, double halfAngle) {
    constexpr int kN = 256;
    const double cosMax = std::cos(halfAngle), sz = std::sin(zenith), cz = std::cos(zenith);
    double sum = 0;
    for (int i = 0; i < kN; ++i) {
        const double u = cosMax + (1.0 - cosMax) * (i + 0.5) / kN, r = std::sqrt(std::max(0.0, 1.0 - u * u));
        for (int k = 0; k < kN; ++k) sum += std::max(0.0, cz * u + sz * r * std::cos(2.0 * kPi * (k + 0.5) / kN));
    }
    return sum / (kN * kN);
}

// Sun and sky: the sun's direction (from a date and the origin when given), the simple
// atmosphere's split of E_h between the sky and the sun, or the given spectra.
void applySunAndSky(const SceneSpec& spec, ir::SceneIR* ir) {
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
        // DIRSIG "simple atmosphere" (spec/seed-ch01-04.md §4.0): L_sky = F E_h / pi, and the sun's
        // share (1 - F) E_h is measured on the plane `sun_plane` names:
        //   horizontal  (1 - F) E_h on a horizontal plane: (1 - F) E_h / <cos> normal to the beam,
        //               <cos> the disc's mean cosine (the sky and the sun then add up to E_h on the
        //               ground);
        //   normal      (1 - F) E_h normal to the beam: DIRSIG's Eq. 4.5 (solarIrradiance =
        //               (1 - skyfraction) hemisphereIrradiance), (1 - F) E_h cos(zenith) on the ground.
        // The two differ by 1 / cos(zenith): a factor of two at 60 degrees.
        ir->sky.radiance = Spectrum::constant(spec.sky.skyFraction * spec.sky.hemisphereIrradiance * kInvPi);
        // Horizontal: the mean of max(0, cos) over the disc, not the cosine of its centre, so that a
        // sun at the horizon (a disc partly below it, whose centre's cosine is near 0) still puts
        // exactly (1 - F) E_h on the ground.
        const double cz = meanDiscCosine(sunZenith, spec.sun.halfAngle);
        const double share = (1 - spec.sky.skyFraction) * spec.sky.hemisphereIrradiance;
        const double beam = spec.sky.sunPlane == "normal" ? share : (cz > 1e-9 ? share / cz : 0.0);
        ir->sun.irradiance = Spectrum::constant(spec.sun.enabled ? beam : 0.0);
        ir->metadata["sky.sun_plane"] = spec.sky.sunPlane;
        if (spec.sky.skyFraction >= 1.0) ir->sun.enabled = false;
    } else {
        ir->sky.radiance = spec.sky.radiance.value_or(Spectrum::constant(0.0));
        ir->sun.irradiance = spec.sun.irradiance.value_or(Spectrum::constant(0.0));
    }
}

// The water medium: refractive index and one layer, or the stack of layers below the level.
void applyWater(const SceneSpec& spec, ir::SceneIR* ir) {
    const WaterOptics& o = spec.waterOptics;
    ir::Medium w;
    w.name = "water";
    w.origin = o.solver.empty() || o.solverDefaulted ? o.loc : o.solverLoc;
    if (!o.solver.empty()) w.solver = parseName<ir::Medium::Solver>(o.solver);
    w.refractiveIndex = o.refractiveIndex;
    auto layerOf = [](const LayerOptics& l) {
        ir::Layer ly;
        ly.absorption = l.absorption;
        ly.scatterers = l.scatterers;
        return ly;
    };
    if (o.layers.empty()) {
        w.layers = {layerOf(o.iops)};
        if (!o.iops.preset.empty()) ir->metadata["water.iop_preset"] = o.iops.preset;
    } else {
        w.layers.clear();
        for (size_t i = 0; i < o.layers.size(); ++i) {
            ir::Layer ly = layerOf(o.layers[i]);
            ly.zTop = i == 0 ? ir::kInfinity : spec.waterLevel - o.layerTops[i];
            ly.zBottom = i + 1 < o.layers.size() ? spec.waterLevel - o.layerTops[i + 1] : -ir::kInfinity;
            w.layers.push_back(ly);
        }
    }
    ir->media.push_back(w);
}

// Materials; a dielectric material also brings the medium of its name.
void applyMaterials(const SceneSpec& spec, ir::SceneIR* ir) {
    for (const auto& m : spec.materials) {
        ir::Material mt;
        mt.name = m.name;
        if (materialKinds().find(m.type)->type == ir::Material::Type::Dielectric) {
            // A smooth interface around a medium of the material's name: the objects that use it get
            // that medium inside (scenegen/assemble.cpp).
            mt.type = ir::Material::Type::Dielectric;
            mt.origin = m.loc;
            ir->materials.push_back(mt);
            ir::Layer layer;
            layer.absorption = m.absorption;
            ir::Medium md;
            md.name = m.name;
            md.refractiveIndex = *m.refractiveIndex;
            md.layers = {layer};
            md.origin = m.loc;
            ir->media.push_back(md);
            continue;
        }
        mt.type = materialKinds().find(m.type)->type;
        if (!m.solver.empty()) mt.solver = parseName<ir::Material::Solver>(m.solver);
        mt.reflectance = m.reflectance;
        mt.origin = m.loc;
        ir->materials.push_back(mt);
    }
}

void applyProbes(const SceneSpec& spec, ir::SceneIR* ir) {
    for (const auto& p : spec.probes) {
        ir::Probe pr;
        pr.name = p.name;
        pr.position = p.position;
        pr.quantities = p.quantities;
        pr.samples = p.samples;
        if (p.medium == "water" || (p.medium == "auto" && spec.hasWater && p.position.z < spec.waterLevel))
            pr.medium = "water";
        ir->probes.push_back(pr);
    }
}

}  // namespace

void applyCommonSections(const SceneSpec& spec, ir::SceneIR* ir) {
    ir->name = spec.scene.name;
    ir->render = spec.render.settings;
    applySunAndSky(spec, ir);
    ir->domain.x0 = spec.scene.x0;
    ir->domain.x1 = spec.scene.x1;
    ir->domain.y0 = spec.scene.y0;
    ir->domain.y1 = spec.scene.y1;
    ir->domain.periodic = spec.hasWater && spec.periodic;
    if (spec.hasWater) applyWater(spec, ir);
    applyMaterials(spec, ir);
    for (const auto& s : spec.sensors) ir->sensors.push_back(placeSensor(s, spec.waterLevel, spec.hasWater));
    applyProbes(spec, ir);
    ir->metadata["source"] = spec.file.filename().string();
}

}  // namespace littoral::scenegen
