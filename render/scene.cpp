#include "render/scene.h"

#include <algorithm>
#include <cmath>

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include "core/error.h"
#include "core/log.h"
#include "core/suggest.h"

namespace littoral::render {

namespace {

const char* solverName(ir::Material::Solver s) {
    switch (s) {
        case ir::Material::Solver::Classic: return "Classic";
        case ir::Material::Solver::Generic: return "Generic";
        case ir::Material::Solver::Fresnel: return "Fresnel";
        case ir::Material::Solver::SurfacePM: return "SurfacePM";
    }
    return "?";
}

}  // namespace

double Texture::lookup(double x, double y) const {
    const double u = (x - x0) / (x1 - x0);  // 0 at the west edge
    const double v = (y1 - y) / (y1 - y0);  // 0 at the north edge (image row 0)
    const int i = std::clamp(static_cast<int>(std::floor(u * width)), 0, width - 1);
    const int j = std::clamp(static_cast<int>(std::floor(v * height)), 0, height - 1);
    return texels[static_cast<size_t>(j) * width + i];
}

std::shared_ptr<Texture> loadTexture(const std::filesystem::path& path) {
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) throw InputError(fmt::format("{}: cannot read texture: {}", path.string(), OIIO::geterror()));
    const OIIO::ImageSpec& spec = in->spec();
    auto t = std::make_shared<Texture>();
    t->width = spec.width;
    t->height = spec.height;
    if (t->width <= 0 || t->height <= 0) throw InputError(fmt::format("{}: texture has no pixels", path.string()));
    std::vector<float> all(static_cast<size_t>(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, all.data()))
        throw InputError(fmt::format("{}: cannot read texture: {}", path.string(), in->geterror()));
    // 8-bit images are normalised by OIIO to [0, 1]; float images are taken as they are.
    t->texels.resize(static_cast<size_t>(spec.width) * spec.height);
    for (size_t i = 0; i < t->texels.size(); ++i) t->texels[i] = all[i * spec.nchannels];
    return t;
}

int Scene::mediumIndex(const std::string& name, const std::string& who) const {
    if (name.empty()) return 0;
    for (size_t i = 1; i < media_.size(); ++i)
        if (media_[i].name == name) return static_cast<int>(i);
    throw InputError(fmt::format("{}: unknown medium '{}'", who, name));
}

Scene::Scene(const ir::SceneIR& ir, const std::filesystem::path& irDir) : ir_(ir), bands_(ir.render.bands) {
    if (bands_.empty()) throw InputError("render.bands: at least one band is required");
    for (size_t i = 0; i < bands_.size(); ++i)
        if (!(bands_[i].hi > bands_[i].lo) || !(bands_[i].lo > 0))
            throw InputError(fmt::format("render.bands[{}]: [{}, {}] um is not a positive, non-empty interval", i,
                                         bands_[i].lo, bands_[i].hi));

    // Media: index 0 is the implicit air.
    MediumData air;
    air.name = "";
    air.n.assign(bands_.size(), 1.0);
    air.a.assign(bands_.size(), 0.0);
    air.b = air.a;
    air.c = air.a;
    media_.push_back(air);
    for (const ir::Medium& m : ir.media) {
        MediumData d;
        d.name = m.name;
        const std::string who = fmt::format("medium '{}'", m.name);
        d.n = m.refractiveIndex.bandAverages(bands_, who + " refractiveIndex");
        d.a = m.absorption.bandAverages(bands_, who + " absorption");
        d.b = m.scattering.bandAverages(bands_, who + " scattering");
        d.c.resize(bands_.size());
        for (size_t k = 0; k < bands_.size(); ++k) {
            if (!(d.n[k] >= 1.0 - 1e-12) || !(d.a[k] >= 0) || !(d.b[k] >= 0))
                throw InputError(fmt::format("{}: band {} has n = {}, a = {}, b = {} (need n >= 1, a >= 0, b >= 0)",
                                             who, k, d.n[k], d.a[k], d.b[k]));
            d.c[k] = d.a[k] + d.b[k];
            d.attenuating |= d.c[k] > 0;
        }
        d.phase = m.phase;
        media_.push_back(std::move(d));
    }

    std::vector<std::string> surfacePmStandIns;
    for (const ir::Material& m : ir.materials) {
        MaterialData d;
        d.name = m.name;
        d.type = m.type;
        d.solver = m.solver;
        const std::string who = fmt::format("material '{}'", m.name);
        using T = ir::Material::Type;
        using S = ir::Material::Solver;
        switch (m.type) {
            case T::Lambertian:
            case T::Textured:
                if (m.solver == S::SurfacePM) {
                    // Until the surface photon map exists, Generic stands in (see the warning below).
                    surfacePmStandIns.push_back("'" + m.name + "'");
                    d.solver = S::Generic;
                } else if (m.solver != S::Classic && m.solver != S::Generic) {
                    throw InputError(fmt::format("{}: solver {} cannot evaluate a diffuse material (use Classic or "
                                                 "Generic)",
                                                 who, solverName(m.solver)));
                }
                d.reflectance = m.reflectance.bandAverages(bands_, who + " reflectance");
                for (double r : d.reflectance)
                    if (!(r >= 0 && r <= 1))
                        throw InputError(fmt::format("{}: reflectance {} outside [0, 1]", who, r));
                if (m.type == T::Textured) {
                    if (m.texture.empty()) throw InputError(fmt::format("{}: Textured material needs a texture", who));
                    if (!(m.textureX1 > m.textureX0) || !(m.textureY1 > m.textureY0))
                        throw InputError(fmt::format("{}: texture extent [{}, {}] x [{}, {}] is empty", who,
                                                     m.textureX0, m.textureX1, m.textureY0, m.textureY1));
                    auto tex = loadTexture(irDir / m.texture);
                    tex->x0 = m.textureX0;
                    tex->x1 = m.textureX1;
                    tex->y0 = m.textureY0;
                    tex->y1 = m.textureY1;
                    d.texture = std::move(tex);
                }
                break;
            case T::Dielectric:
                if (m.solver != S::Fresnel && m.solver != S::Generic)
                    throw InputError(fmt::format("{}: a Dielectric interface needs the Fresnel (or Generic) solver, "
                                                 "not {}",
                                                 who, solverName(m.solver)));
                break;
            case T::RoughDielectric:
                throw InputError(fmt::format("{}: RoughDielectric (Cox–Munk) interfaces are not supported by this "
                                             "renderer version; use a faceted Dielectric surface",
                                             who));
            case T::Black:
                d.reflectance.assign(bands_.size(), 0.0);
                break;
        }
        materials_.push_back(std::move(d));
    }
    if (!surfacePmStandIns.empty())
        // SurfacePM (photon-mapped) and Generic (hemisphere-sampled) estimate the same integral:
        // sky fraction plus background reflections (dissertation Ch. 6, where GRS and SRS converge).
        log::warn("material(s) {}: the SurfacePM solver needs the surface photon map, which this version does not "
                  "build; rendering with the Generic solver (same integral, hemisphere sampling)",
                  joinList(surfacePmStandIns));

    for (size_t mi = 0; mi < ir.meshes.size(); ++mi) {
        const ir::Mesh& mesh = ir.meshes[mi];
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
        meshMaterials_.push_back(std::move(slots));
        meshInside_.push_back(mediumIndex(mesh.inside, who + " inside"));
        meshOutside_.push_back(mediumIndex(mesh.outside, who + " outside"));
    }

    sun_ = makeSun(ir.sun, bands_);
    sky_ = makeSky(ir.sky, bands_);
    geometry_ = std::make_unique<EmbreeScene>(ir);
    log::debug("scene '{}': {} triangles, {} media, {} materials, {} bands", ir.name, geometry_->triangleCount(),
               media_.size() - 1, materials_.size(), bands_.size());
}

}  // namespace littoral::render
