#include "scenegen/texture_classes.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <unistd.h>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/resource_limits.h"
#include "core/stderr_capture.h"

namespace littoral::scenegen {
namespace {


// A grey image as floats (channel 0, or the mean of R, G, B for colour images), values in the
// file's nominal range mapped to [0, 1] for integer formats.
std::vector<float> readGrey(const std::filesystem::path& path, const SourceLoc& where, int* w, int* h) {
    // libpng prints its own lines before the failure reported below (core/stderr_capture.h).
    return quietLibraryCall([&] {
        noteInput(path);  // no output may replace it
        imageio::Reader in(path);
        if (!in.ok()) throw InputError(where, fmt::format("cannot read texture image {}: {}", path.string(), in.error()));
        const imageio::Header& spec = in.header();
        *w = spec.width;
        *h = spec.height;
        const int nc = spec.channels;
        requireMemory(4.0 * (double(nc) + 1.0) * double(spec.width) * double(spec.height),
                      fmt::format("texture image {} ({} x {} px, {} channels) would", path.string(), spec.width, spec.height, nc),
                      where);
        std::vector<float> rgb(static_cast<size_t>(spec.width) * spec.height * nc);
        if (!in.read(nc, imageio::PixelType::Float, rgb.data()))
            throw InputError(where, fmt::format("cannot read texture image {}: {}", path.string(), in.error()));
        std::vector<float> grey(static_cast<size_t>(spec.width) * spec.height);
        const int use = nc >= 3 ? 3 : 1;
        for (size_t i = 0; i < grey.size(); ++i) {
            float s = 0;
            for (int c = 0; c < use; ++c) {
                const float v = rgb[i * nc + c];
                // A NaN or infinity would spread through the class's mean and standard deviation into
                // every pixel of the remapped texture (and from there into the radiance).
                if (!std::isfinite(v))
                    throw InputError(where, fmt::format("texture image {}: pixel (column {}, row {}; counted from 0, row 0 "
                                                        "at the top), channel {} is {}; texture values must be finite "
                                                        "numbers",
                                                        path.string(), i % size_t(spec.width), i / size_t(spec.width), c,
                                                        v));
                s += v;
            }
            grey[i] = s / use;
        }
        return grey;
    });
}

}  // namespace

uint16_t ClassMap::at(double x, double y) const {
    const double u = (x - extent.x0) / extent.width(), v = (extent.y1 - y) / extent.height();
    const int i = std::clamp(static_cast<int>(std::floor(u * width)), 0, width - 1);
    const int j = std::clamp(static_cast<int>(std::floor(v * height)), 0, height - 1);
    return value[static_cast<size_t>(j) * width + i];
}

Vec2 ClassMap::pixelCentre(int i, int j) const {
    return {extent.x0 + (i + 0.5) * extent.width() / width, extent.y1 - (j + 0.5) * extent.height() / height};
}

ClassMap readClassMap(const std::filesystem::path& path, const bathymetry::Extent& extent) {
    // libpng prints its own lines before the failure reported below (core/stderr_capture.h).
    return quietLibraryCall([&] {
        const SourceLoc where{path.string()};
        noteInput(path);  // no output may replace it
        imageio::Reader in(path);
        if (!in.ok()) throw InputError(where, "cannot read classification map: " + in.error());
        const imageio::Header& spec = in.header();
        // One class index per pixel: a colour image has no single index per pixel (reading its red
        // channel would turn colours into arbitrary classes such as 128).
        if (spec.channels != 1)
            throw InputError(where, fmt::format("classification map has {} channels; it must be a single-channel image of "
                                                "class indices (8- or 16-bit grey, not RGB or with alpha)",
                                                spec.channels));
        requireMemory(4.0 * double(spec.width) * double(spec.height),
                      fmt::format("a classification map of {} x {} px would", spec.width, spec.height), where);
        if (!spec.storedAs(imageio::PixelType::UInt8) && !spec.storedAs(imageio::PixelType::UInt16))
            throw InputError(where, fmt::format("classification map must hold 8- or 16-bit unsigned integer class indices; "
                                                "this image is {}",
                                                spec.storedType));
        ClassMap m;
        m.width = spec.width;
        m.height = spec.height;
        m.extent = extent;
        const size_t n = static_cast<size_t>(m.width) * m.height;
        m.value.resize(n);
        if (!in.readIndices(m.value.data())) throw InputError(where, "cannot read classification map: " + in.error());
        return m;
    });
}

std::vector<float> remapMeanStd(const std::vector<float>& t, const std::vector<char>& mask, double mu, double sigma,
                                RemapStats* st) {
    RemapStats s;
    double sum = 0, sum2 = 0;
    for (size_t i = 0; i < t.size(); ++i)
        if (mask[i]) {
            ++s.pixels;
            sum += t[i];
        }
    std::vector<float> out(t.size(), static_cast<float>(mu));
    if (s.pixels == 0) {
        if (st) *st = s;
        return out;
    }
    const double m = sum / s.pixels;
    for (size_t i = 0; i < t.size(); ++i)
        if (mask[i]) sum2 += (t[i] - m) * (t[i] - m);
    const double sd = std::sqrt(sum2 / s.pixels);
    s.meanBefore = m;
    s.stdBefore = sd;
    if (sigma > 0 && sd == 0) throw InputError("texture is constant over its class; it cannot be given a standard deviation");
    const double gain = sd > 0 ? sigma / sd : 0.0;
    double a = 0, a2 = 0;
    for (size_t i = 0; i < t.size(); ++i) {
        if (!mask[i]) continue;
        double v = mu + (t[i] - m) * gain;  // t' = mu + (t - m) sigma / s
        if (v < 0) {
            v = 0;
            ++s.clampedToZero;
        }
        out[i] = static_cast<float>(v);
        a += out[i];
    }
    s.meanAfter = a / s.pixels;
    for (size_t i = 0; i < t.size(); ++i)
        if (mask[i]) a2 += (out[i] - s.meanAfter) * (out[i] - s.meanAfter);
    s.stdAfter = std::sqrt(a2 / s.pixels);
    if (st) *st = s;
    return out;
}

uint16_t TextureClasses::slotAt(double x, double y) const {
    return static_cast<uint16_t>(classOfValue[map.at(x, y)]);
}

std::vector<ir::Material> TextureClasses::materials() const {
    std::vector<ir::Material> out;
    for (size_t k = 0; k < classes.size(); ++k) {
        const auto& c = classes[k];
        ir::Material m;
        m.name = c.name;
        if (!c.solver.empty()) m.solver = parseName<ir::Material::Solver>(c.solver);
        m.origin = c.loc;
        if (textures[k].empty()) {
            m.type = ir::Material::Type::Lambertian;
            m.reflectance = c.reflectance.scaled(c.mean);
        } else {
            m.type = ir::Material::Type::Textured;
            m.reflectance = c.reflectance;
            m.texture = "textures/" + c.name + ".tif";
            m.textureX0 = map.extent.x0;
            m.textureY0 = map.extent.y0;
            m.textureX1 = map.extent.x1;
            m.textureY1 = map.extent.y1;
        }
        out.push_back(m);
    }
    return out;
}

ir::Material TextureClasses::classifiedMaterial(const std::string& name) const {
    ir::Material m;
    m.name = name;
    m.type = ir::Material::Type::Classified;
    m.texture = std::string("textures/") + kClassMapFile;
    m.textureX0 = map.extent.x0;
    m.textureY0 = map.extent.y0;
    m.textureX1 = map.extent.x1;
    m.textureY1 = map.extent.y1;
    m.classMaterials.assign(classOfValue.size(), "");
    for (size_t v = 0; v < classOfValue.size(); ++v)
        if (classOfValue[v] >= 0) m.classMaterials[v] = classes[static_cast<size_t>(classOfValue[v])].name;
    return m;
}

void TextureClasses::writeTextures(const std::filesystem::path& irDir) const {
    createOutputFolder(irDir / "textures");
    {
        // The class map itself, 16-bit so that any class index survives.
        const imageio::WriteSpec spec{map.width, map.height, 1, imageio::PixelType::UInt16, {},
                                      {{"compression", "zip"}, {"DateTime", ""}}};  // "": deterministic bytes
        imageio::writeFile(irDir / "textures" / kClassMapFile, spec, map.value.data(), "tif");
    }
    for (size_t k = 0; k < classes.size(); ++k) {
        if (textures[k].empty()) continue;
        const auto target = irDir / "textures" / (classes[k].name + ".tif");
        const imageio::WriteSpec spec{map.width, map.height, 1, imageio::PixelType::Float, {},
                                      {{"compression", "zip"}, {"DateTime", ""}}};  // "": deterministic bytes
        imageio::writeFile(target, spec, textures[k].data(), "tif");
    }
}

std::vector<double> TextureClasses::coverage() const {
    std::vector<double> c(classes.size(), 0.0);
    for (uint16_t v : map.value) c[classOfValue[v]] += 1.0;
    for (auto& x : c) x /= static_cast<double>(map.value.size());
    return c;
}

TextureClasses buildTextureClasses(const TextureClassesSpec& spec, const bathymetry::Extent& domain) {
    TextureClasses tc;
    tc.classes = spec.classes;
    tc.map = readClassMap(spec.map, spec.extent.value_or(domain));
    // The classes are looked up where each ray lands on the ground, which the domain bounds: the map
    // must cover it (else the edge pixels would be stretched over the rest).
    const bathymetry::Extent& e = tc.map.extent;
    const double tol = 1e-9 * std::max({1.0, domain.width(), domain.height()});
    if (e.x0 > domain.x0 + tol || e.x1 < domain.x1 - tol || e.y0 > domain.y0 + tol || e.y1 < domain.y1 - tol)
        throw InputError(spec.extent ? spec.extentLoc : spec.loc,
                         fmt::format("texture_classes.extent: the class map covers x [{}, {}], y [{}, {}] m, which does "
                                     "not cover the terrain of the scene domain x [{}, {}], y [{}, {}] m; give an extent "
                                     "that contains the domain",
                                     e.x0, e.x1, e.y0, e.y1, domain.x0, domain.x1, domain.y0, domain.y1));
    // Every raster value must have a class (an unclassified pixel would render with no material).
    int maxIndex = 0;
    for (const auto& c : spec.classes) maxIndex = std::max(maxIndex, c.index);
    uint16_t maxValue = 0;
    for (uint16_t v : tc.map.value) maxValue = std::max(maxValue, v);
    tc.classOfValue.assign(std::max<int>(maxIndex, maxValue) + 1, -1);
    for (size_t k = 0; k < spec.classes.size(); ++k) tc.classOfValue[spec.classes[k].index] = static_cast<int>(k);
    std::vector<std::string> known;
    for (const auto& c : spec.classes) known.push_back(std::to_string(c.index));
    for (int j = 0; j < tc.map.height; ++j)
        for (int i = 0; i < tc.map.width; ++i) {
            const uint16_t v = tc.map.value[static_cast<size_t>(j) * tc.map.width + i];
            if (tc.classOfValue[v] < 0) {
                size_t count = 0;
                for (uint16_t u : tc.map.value) count += u == v ? 1 : 0;
                throw InputError(spec.loc, fmt::format("texture_classes.classes: the classification map {} holds class "
                                                       "value {} ({} pixels, the first at column {}, row {}), but no "
                                                       "class has index {}; defined: {}",
                                                       spec.map.string(), v, count, i, j, v, fmt::join(known, ", ")));
            }
        }

    const size_t n = tc.map.value.size();
    tc.textures.resize(spec.classes.size());
    tc.stats.resize(spec.classes.size());
    for (size_t k = 0; k < spec.classes.size(); ++k) {
        const auto& c = spec.classes[k];
        std::vector<char> mask(n);
        for (size_t p = 0; p < n; ++p) mask[p] = tc.classOfValue[tc.map.value[p]] == static_cast<int>(k);
        if (!c.texture) {
            for (char m : mask) tc.stats[k].pixels += m ? 1 : 0;
            tc.stats[k].meanBefore = tc.stats[k].meanAfter = c.mean;
            continue;
        }
        int tw = 0, th = 0;
        const std::vector<float> tex = readGrey(*c.texture, c.textureLoc.file.empty() ? c.loc : c.textureLoc, &tw, &th);
        // Tile the texture over the map grid, one texture pixel per map pixel.
        std::vector<float> tiled(n);
        for (int j = 0; j < tc.map.height; ++j)
            for (int i = 0; i < tc.map.width; ++i)
                tiled[static_cast<size_t>(j) * tc.map.width + i] = tex[static_cast<size_t>(j % th) * tw + (i % tw)];
        try {
            tc.textures[k] = remapMeanStd(tiled, mask, c.mean, c.stddev, &tc.stats[k]);
        } catch (const InputError& e) {
            throw InputError(c.loc, fmt::format("texture class '{}': {}", c.name, e.message()));
        }
    }
    return tc;
}

}  // namespace littoral::scenegen
