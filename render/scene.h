#pragma once
// The renderer's view of a Scene IR: every spectrum averaged onto the render bands (InputError
// for a band outside a table), media and materials resolved to indices, textures loaded, the
// Embree BVH built. Immutable after construction and shared by all render threads.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/scene_ir.h"
#include "render/embree_scene.h"
#include "render/sources.h"

namespace littoral::render {

// A homogeneous medium on the render bands. Index 0 of Scene::media is the implicit air
// (n = 1, no absorption or scattering) that mesh sides with an empty medium name refer to.
struct MediumData {
    std::string name;
    std::vector<double> n, a, b, c;  // per band; c = a + b (m^-1), Eq. 2.4
    ir::PhaseFunction phase;
    bool attenuating = false;        // any band with c > 0
};

// A single-channel texture draped in plan view over [x0, x1] x [y0, y1]. Row 0 of the image is
// the north edge (y = y1), column 0 the west edge (x = x0); lookup is nearest-texel and points
// outside the rectangle take the nearest edge texel.
struct Texture {
    int width = 0, height = 0;
    std::vector<float> texels;
    double x0 = 0, y0 = 0, x1 = 1, y1 = 1;
    double lookup(double x, double y) const;
};

struct MaterialData {
    std::string name;
    ir::Material::Type type = ir::Material::Type::Lambertian;
    ir::Material::Solver solver = ir::Material::Solver::Classic;
    std::vector<double> reflectance;  // per band
    std::shared_ptr<const Texture> texture;
    bool isSpecularInterface() const { return type == ir::Material::Type::Dielectric; }
    bool isOpaque() const { return !isSpecularInterface(); }
};

// Reads a texture with OpenImageIO (first channel, converted to float). InputError if it cannot.
std::shared_ptr<Texture> loadTexture(const std::filesystem::path& path);

class Scene {
public:
    // `irDir` resolves texture paths (relative to the IR directory). Throws InputError on bands
    // outside a spectrum's table, unknown material or medium names, unsupported material/solver
    // combinations, unreadable textures.
    Scene(const ir::SceneIR& ir, const std::filesystem::path& irDir);

    const ir::SceneIR& ir() const { return ir_; }
    const std::vector<Band>& bands() const { return bands_; }
    int bandCount() const { return static_cast<int>(bands_.size()); }
    const EmbreeScene& geometry() const { return *geometry_; }
    const SunSource& sun() const { return sun_; }
    const SkySource& sky() const { return sky_; }
    const std::vector<MediumData>& media() const { return media_; }
    const std::vector<MaterialData>& materials() const { return materials_; }

    // Global material index of a hit (through the mesh's slot list).
    int materialIndex(const SurfaceHit& h) const { return meshMaterials_[h.mesh][h.slot]; }
    int insideMedium(int mesh) const { return meshInside_[mesh]; }
    int outsideMedium(int mesh) const { return meshOutside_[mesh]; }
    bool meshClosed(int mesh) const { return ir_.meshes[mesh].closed; }
    // Medium index for a name ("" = air = 0); InputError naming `who` if unknown.
    int mediumIndex(const std::string& name, const std::string& who) const;

private:
    const ir::SceneIR& ir_;
    std::vector<Band> bands_;
    std::unique_ptr<EmbreeScene> geometry_;
    SunSource sun_;
    SkySource sky_;
    std::vector<MediumData> media_;
    std::vector<MaterialData> materials_;
    std::vector<std::vector<int>> meshMaterials_;
    std::vector<int> meshInside_, meshOutside_;
};

}  // namespace littoral::render
