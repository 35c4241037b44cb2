#include "render/scene.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/log.h"
#include "core/material_kinds.h"
#include "core/stderr_capture.h"
#include "core/suggest.h"

namespace littoral::render {

std::shared_ptr<ClassRaster> loadClassRaster(const std::filesystem::path& path) {
    // libpng prints its own lines before the failure reported below (core/stderr_capture.h).
    return quietLibraryCall([&] {
        noteInput(path);  // no output may replace it
        imageio::Reader in(path);
        if (!in.ok()) throw InputError(fmt::format("{}: cannot read class map: {}", path.string(), in.error()));
        const imageio::Header& spec = in.header();
        if (spec.channels != 1 || (!spec.storedAs(imageio::PixelType::UInt8) && !spec.storedAs(imageio::PixelType::UInt16)))
            throw InputError(fmt::format("{}: a class map must be a single-channel 8- or 16-bit integer image ({} channels, {})",
                                         path.string(), spec.channels, spec.storedType));
        auto r = std::make_shared<ClassRaster>();
        r->width = spec.width;
        r->height = spec.height;
        if (r->width <= 0 || r->height <= 0) throw InputError(fmt::format("{}: class map has no pixels", path.string()));
        const size_t n = static_cast<size_t>(r->width) * r->height;
        r->values.resize(n);
        if (!in.readIndices(r->values.data())) throw InputError(fmt::format("{}: cannot read class map: {}", path.string(), in.error()));
        return r;
    });
}

std::shared_ptr<Texture> loadTexture(const std::filesystem::path& path) {
    // libpng prints its own lines before the failure reported below (core/stderr_capture.h).
    return quietLibraryCall([&] {
        noteInput(path);  // no output may replace it
        imageio::Reader in(path);
        if (!in.ok()) throw InputError(fmt::format("{}: cannot read texture: {}", path.string(), in.error()));
        const imageio::Header& spec = in.header();
        auto t = std::make_shared<Texture>();
        t->width = spec.width;
        t->height = spec.height;
        if (t->width <= 0 || t->height <= 0) throw InputError(fmt::format("{}: texture has no pixels", path.string()));
        std::vector<float> all(static_cast<size_t>(spec.width) * spec.height * spec.channels);
        if (!in.read(spec.channels, imageio::PixelType::Float, all.data()))
            throw InputError(fmt::format("{}: cannot read texture: {}", path.string(), in.error()));
        // 8-bit images are normalised by OIIO to [0, 1]; float images are taken as they are.
        t->values.resize(static_cast<size_t>(spec.width) * spec.height);
        for (size_t i = 0; i < t->values.size(); ++i) {
            const float v = all[i * spec.channels];
            // The texture multiplies a reflectance: a NaN, an infinity or a negative value would make
            // the radiance of every ray that lands there meaningless.
            if (!(std::isfinite(v) && v >= 0))
                throw InputError(SourceLoc{path.string()},
                                 fmt::format("texture pixel (column {}, row {}; counted from 0, row 0 = north), channel 0 "
                                             "is {}; a texture multiplies a reflectance, so its values must be finite and "
                                             ">= 0",
                                             i % size_t(spec.width), i / size_t(spec.width), v));
            t->values[i] = v;
        }
        return t;
    });
}

namespace {

// The raster of a textured or classified material (`what`: "texture" or "class map"), read by
// `load` from the IR folder and placed on the material's plan-view extent, which must not be empty.
template <class Load>
auto placedOnExtent(Load&& load, const std::filesystem::path& irDir, const ir::Material& m, const std::string& who,
                    const char* what) {
    if (!(m.textureX1 > m.textureX0) || !(m.textureY1 > m.textureY0))
        throw InputError(fmt::format("{}: {} extent [{}, {}] x [{}, {}] is empty", who, what, m.textureX0, m.textureX1,
                                     m.textureY0, m.textureY1));
    auto raster = load(irDir / m.texture);
    raster->x0 = m.textureX0;
    raster->x1 = m.textureX1;
    raster->y0 = m.textureY0;
    raster->y1 = m.textureY1;
    return raster;
}

// The renderer's material for an IR material: reflectance on the render bands, the raster it is
// draped with, and the Cox–Munk slopes of a rough interface.
MaterialData makeMaterial(const ir::Material& m, const std::vector<Band>& bands, const std::filesystem::path& irDir,
                          bool periodicDomain) {
    MaterialData d;
    d.name = m.name;
    d.type = m.type;
    d.lobes = materialKind(m.type).lobes;
    d.solver = m.solver;
    const std::string who = fmt::format("material '{}'", m.name);
    using T = ir::Material::Type;
    switch (m.type) {
        case T::Lambertian:
        case T::Textured:
            d.reflectance = m.reflectance.bandAverages(bands, who + " reflectance");
            for (double r : d.reflectance)
                if (!(r >= 0 && r <= 1))
                    throw InputError(fmt::format("{}: reflectance {} outside [0, 1]", who, r));
            if (m.type == T::Textured) {
                if (m.texture.empty()) throw InputError(fmt::format("{}: Textured material needs a texture", who));
                d.texture = placedOnExtent(loadTexture, irDir, m, who, "texture");
            }
            break;
        case T::Dielectric:
            d.reflectance.assign(bands.size(), 0.0);
            break;
        case T::RoughDielectric: {
            d.reflectance.assign(bands.size(), 0.0);
            // The frame of the BxDF has its x axis downwind (Scene::shadingFrame), so the
            // distribution's own wind azimuth is 0.
            CoxMunkParams p;
            p.windSpeed = m.windSpeed;
            p.windAzimuth = 0.0;
            p.sea = m.sea;
            p.slopes = m.slopes;
            p.gramCharlier = m.gramCharlier;
            try {
                d.slopes.emplace(p, m.origin, "wind_speed");
            } catch (const InputError& e) {
                if (!m.origin.file.empty()) throw InputError(m.origin, who + ": " + e.message());
                throw InputError(who + ": " + e.message());
            }
            d.shadowing = m.shadowing;
            if (!std::isfinite(m.windAzimuth))
                throw InputError(fmt::format("{}: wind azimuth {} is not a finite angle", who, m.windAzimuth));
            d.downwind = Vec3{std::cos(m.windAzimuth), std::sin(m.windAzimuth), 0.0};
            break;
        }
        case T::Periodic:
            if (!periodicDomain)
                throw InputError(fmt::format("{}: a periodic wall needs a periodic domain (domain.horizontal: "
                                             "periodic)",
                                             who));
            d.reflectance.assign(bands.size(), 0.0);
            break;
        case T::Black:
            d.reflectance.assign(bands.size(), 0.0);
            break;
        case T::Classified: {
            d.reflectance.assign(bands.size(), 0.0);
            if (m.texture.empty()) throw InputError(fmt::format("{}: a classified material needs a class map", who));
            d.classMap = placedOnExtent(loadClassRaster, irDir, m, who, "class map");
            break;
        }
    }
    return d;
}

}  // namespace

int Scene::mediumIndex(const std::string& name, const std::string& who) const {
    if (name.empty()) return 0;
    for (size_t i = 1; i < media_.size(); ++i)
        if (media_[i].name() == name) return static_cast<int>(i);
    throw InputError(fmt::format("{}: unknown medium '{}'", who, name));
}

// Class maps: each raster value names a diffuse material (resolved once all are known), and every
// value that occurs has one.
void Scene::resolveClassMaps() {
    const ir::SceneIR& ir = ir_;
    for (size_t k = 0; k < ir.materials.size(); ++k) {
        MaterialData& d = materials_[k];
        if (!d.classMap) continue;
        const ir::Material& m = ir.materials[k];
        const std::string who = fmt::format("material '{}'", m.name);
        d.classMaterial.assign(m.classMaterials.size(), -1);
        for (size_t v = 0; v < m.classMaterials.size(); ++v) {
            if (m.classMaterials[v].empty()) continue;
            for (size_t j = 0; j < ir.materials.size(); ++j)
                if (ir.materials[j].name == m.classMaterials[v]) d.classMaterial[v] = static_cast<int>(j);
            if (d.classMaterial[v] < 0)
                throw InputError(fmt::format("{}: class {} names material '{}', which is not defined", who, v,
                                             m.classMaterials[v]));
            const auto t = ir.materials[static_cast<size_t>(d.classMaterial[v])].type;
            if (!materialKind(t).hasReflectance)
                throw InputError(fmt::format("{}: class {} names material '{}', which is {}; classes must be diffuse "
                                             "(lambertian or textured)",
                                             who, v, m.classMaterials[v], nameOf(t)));
        }
        std::vector<size_t> count(65536, 0);
        for (uint16_t v : d.classMap->values) ++count[v];
        for (size_t v = 0; v < count.size(); ++v)
            if (count[v] > 0 && (v >= d.classMaterial.size() || d.classMaterial[v] < 0))
                throw InputError(fmt::format("{}: the class map {} holds value {} ({} pixels), which names no material",
                                             who, m.texture, v, count[v]));
    }
}

// A mesh's material slots and media, checked: every slot names a material, rough interfaces
// separate different indices, and class maps cover the faces that use them.
void Scene::addMesh(const ir::Mesh& mesh) {
    const ir::SceneIR& ir = ir_;
    const std::string who = fmt::format("mesh '{}'", mesh.name);
    std::vector<int> slots;
    for (const std::string& name : mesh.materials) {
        int idx = -1;
        for (size_t k = 0; k < ir.materials.size(); ++k)
            if (ir.materials[k].name == name) idx = static_cast<int>(k);
        if (idx < 0) throw InputError(fmt::format("{}: unknown material '{}'", who, name));
        slots.push_back(idx);
    }
    if (slots.empty() && !mesh.data.triangles.empty())
        throw InputError(fmt::format("{}: no materials", who));
    if (!mesh.data.faceMaterial.empty() && mesh.data.faceMaterial.size() != mesh.data.triangles.size())
        throw InputError(fmt::format("{}: {} per-face material slots for {} triangles", who,
                                     mesh.data.faceMaterial.size(), mesh.data.triangles.size()));
    for (uint16_t s : mesh.data.faceMaterial)
        if (s >= slots.size())
            throw InputError(fmt::format("{}: a face uses material slot {} but the mesh lists {} materials", who,
                                         s, slots.size()));
    const int in = mediumIndex(mesh.inside, who + " inside"), out = mediumIndex(mesh.outside, who + " outside");
    // A rough interface refracts only between different indices (render/rough_dielectric.h).
    for (int k : slots)
        if (materials_[static_cast<size_t>(k)].isRough())
            for (size_t b = 0; b < bands_.size(); ++b)
                if (std::abs(media_[static_cast<size_t>(in)].n(static_cast<int>(b)) -
                             media_[static_cast<size_t>(out)].n(static_cast<int>(b))) <= 1e-6)
                    throw InputError(fmt::format("{}: rough interface '{}' between media of equal refractive index "
                                                 "({}) in band {}; a rough interface needs different indices",
                                                 who, materials_[static_cast<size_t>(k)].name,
                                                 media_[static_cast<size_t>(in)].n(static_cast<int>(b)), b));
    // A class map must cover, in plan view, every mesh that uses it (the lookup would otherwise
    // clamp to its edge pixels and invent classes there).
    for (size_t s = 0; s < slots.size(); ++s) {
        const MaterialData& d = materials_[static_cast<size_t>(slots[s])];
        if (!d.classMap) continue;
        BBox3 b;
        for (size_t f = 0; f < mesh.data.triangles.size(); ++f)
            if (mesh.data.materialOf(f) == s)
                for (uint32_t v : mesh.data.triangles[f]) b.expand(mesh.data.positions[v]);
        if (b.empty()) continue;
        const ClassRaster& r = *d.classMap;
        const double tol = 1e-6 * std::max({1.0, r.x1 - r.x0, r.y1 - r.y0});
        if (b.lo.x < r.x0 - tol || b.hi.x > r.x1 + tol || b.lo.y < r.y0 - tol || b.hi.y > r.y1 + tol)
            throw InputError(fmt::format("{}: the class map of material '{}' covers [{}, {}] x [{}, {}] m, but the "
                                         "faces that use it span [{}, {}] x [{}, {}] m; the map must cover them",
                                         who, d.name, r.x0, r.x1, r.y0, r.y1, b.lo.x, b.hi.x, b.lo.y, b.hi.y));
    }
    meshMaterials_.push_back(std::move(slots));
    meshInside_.push_back(in);
    meshOutside_.push_back(out);
}

Scene::Scene(const ir::SceneIR& ir, const std::filesystem::path& irDir) : ir_(ir), bands_(ir.render.bands) {
    if (bands_.empty()) throw InputError("render.bands: at least one band is required");
    for (size_t i = 0; i < bands_.size(); ++i)
        if (!(bands_[i].hi > bands_[i].lo) || !(bands_[i].lo > 0))
            throw InputError(fmt::format("render.bands[{}]: [{}, {}] um is not a positive, non-empty interval", i,
                                         bands_[i].lo, bands_[i].hi));

    // Media: index 0 is the implicit air.
    media_.push_back(Medium::air(bands_.size()));
    for (const ir::Medium& m : ir.media) media_.emplace_back(m, bands_, fmt::format("medium '{}'", m.name));

    for (const ir::Material& m : ir.materials) materials_.push_back(makeMaterial(m, bands_, irDir, ir.domain.periodic));
    resolveClassMaps();
    for (size_t mi = 0; mi < ir.meshes.size(); ++mi) addMesh(ir.meshes[mi]);

    sun_ = makeSun(ir.sun, bands_);
    sky_ = makeSky(ir.sky, bands_);
    geometry_ = std::make_unique<EmbreeScene>(ir);
    log::debug("scene '{}': {} triangles, {} media, {} materials, {} bands", ir.name, geometry_->triangleCount(),
               media_.size() - 1, materials_.size(), bands_.size());
}

BxDF Scene::bxdf(const SurfaceHit& h, BandGroup g) const {
    const MaterialData& m = materials_[materialIndex(h)];
    if (m.isRough())
        return roughBxdf(materialIndex(h), media_[meshOutside_[h.mesh]].n(g.begin), media_[meshInside_[h.mesh]].n(g.begin));
    if (m.isInterface())
        return DielectricBxDF{media_[meshOutside_[h.mesh]].n(g.begin), media_[meshInside_[h.mesh]].n(g.begin)};
    return LambertianBxDF{1.0};
}

RoughDielectricBxDF Scene::roughBxdf(int material, double nOut, double nIn) const {
    const MaterialData& m = materials_[static_cast<size_t>(material)];
    LITTORAL_CHECK(m.slopes.has_value());
    return RoughDielectricBxDF(nOut, nIn, *m.slopes, m.shadowing);
}

Frame Scene::roughShadingFrame(const SurfaceHit& h, const MaterialData& m) const {
    // Downwind projected on the face; on a face that is (nearly) vertical and facing downwind the
    // projection vanishes, and the crosswind axis serves (the distribution is then rotated by
    // 90 degrees on that face, which only a wall-like face can notice).
    const Vec3 d = m.downwind - dot(m.downwind, h.ng) * h.ng;
    if (dot(d, d) > 1e-12) return Frame::fromNormalAndTangent(h.ng, m.downwind);
    return Frame::fromNormalAndTangent(h.ng, Vec3{-m.downwind.y, m.downwind.x, 0.0});
}

Spec Scene::albedo(const SurfaceHit& h, BandGroup g) const {
    const MaterialData& m = materials_[materialIndex(h)];
    Spec rho(g.count);
    for (int i = 0; i < g.count; ++i) rho[i] = m.reflectance[g.begin + i];
    if (m.texture) rho *= m.texture->at(h.p.x, h.p.y);
    return rho;
}

FreeFlight Scene::flightToSurface(const Ray& ray, int medium, BandGroup g, double uBand, double uDist, SurfaceHit* h,
                                  bool* hit) const {
    const Medium& md = media_[medium];
    FreeFlight ff = md.sampleFreeFlight(ray, ray.tMax, g, uBand, uDist);
    Ray limited = ray;
    if (ff.scattered) limited.tMax = std::min(ray.tMax, ff.t);
    *hit = geometry_->intersect(limited, h);
    if (*hit) ff = md.sampleFreeFlight(ray, h->t, g, uBand, uDist);
    return ff;
}

std::optional<Ray> Scene::wrapRay(const SurfaceHit& h, const Vec3& d) const {
    const ir::Domain& D = ir_.domain;
    const double Lx = D.x1 - D.x0, Ly = D.y1 - D.y0;
    // The wall the hit lies on is the nearest domain edge in plan view. Embree reports the hit
    // distance in single precision, so a hit on a wall far from the ray origin can sit ~1e-5 m
    // off the edge: the nearest edge is taken within a tolerance of 1e-4 of the domain size,
    // without asking the direction (a ray that hit the wall from inside is leaving). The other
    // axis also wraps when the hit is at a corner and the ray leaves through it too.
    const double tol = 1e-4 * std::max({1.0, Lx, Ly});
    Point3 p = h.p;
    const double ex[4] = {std::abs(p.x - D.x0), std::abs(p.x - D.x1), std::abs(p.y - D.y0),
                          std::abs(p.y - D.y1)};
    const int nearest = static_cast<int>(std::min_element(ex, ex + 4) - ex);
    if (ex[nearest] > tol) return std::nullopt;  // not on a domain edge
    const bool onX = nearest < 2;
    bool moved = false;
    auto wrapX = [&](bool force) {
        if (ex[0] <= ex[1] && ex[0] < tol && (force || d.x < 0)) p.x = D.x0 + Lx, moved = true;
        else if (ex[1] < ex[0] && ex[1] < tol && (force || d.x > 0)) p.x = D.x1 - Lx, moved = true;
    };
    auto wrapY = [&](bool force) {
        if (ex[2] <= ex[3] && ex[2] < tol && (force || d.y < 0)) p.y = D.y0 + Ly, moved = true;
        else if (ex[3] < ex[2] && ex[3] < tol && (force || d.y > 0)) p.y = D.y1 - Ly, moved = true;
    };
    if (onX) wrapX(true), wrapY(false);
    else wrapY(true), wrapX(false);
    if (!moved) return std::nullopt;  // not on a domain edge, or leaving inward: no wrap
    // Start just inside the opposite wall, pushed off it along its inward normal (not along d,
    // which may graze the wall), so the ray cannot meet the wall it enters through.
    const double eps = offsetDistance(p);
    if (std::abs(p.x - D.x0) < tol) p.x += eps;
    else if (std::abs(p.x - D.x1) < tol) p.x -= eps;
    if (std::abs(p.y - D.y0) < tol) p.y += eps;
    else if (std::abs(p.y - D.y1) < tol) p.y -= eps;
    Ray r;
    r.o = p;
    r.d = d;
    return r;
}

}  // namespace littoral::render
