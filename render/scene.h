#pragma once
// The renderer's view of a Scene IR: every spectrum averaged onto the render bands (InputError
// for a band outside a table), media and materials resolved to indices, textures loaded, the
// Embree BVH built. Immutable after construction and shared by all render threads.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/frame.h"
#include "core/scene_ir.h"
#include "render/bxdf.h"
#include "render/embree_scene.h"
#include "render/medium.h"
#include "render/sources.h"

namespace littoral::render {

// A single-channel raster draped in plan view over [x0, x1] x [y0, y1]: row 0 of the image is the
// north edge (y = y1), column 0 the west edge (x = x0), pixel-is-area; at() is the nearest pixel,
// and points outside the rectangle take the nearest edge pixel (the Scene checks that the meshes
// using a class map lie inside it).
template <class T> struct PlanRaster {
    int width = 0, height = 0;
    std::vector<T> values;
    double x0 = 0, y0 = 0, x1 = 1, y1 = 1;
    T at(double x, double y) const {
        const double u = (x - x0) / (x1 - x0);  // 0 at the west edge
        const double v = (y1 - y) / (y1 - y0);  // 0 at the north edge (image row 0)
        const int i = std::clamp(static_cast<int>(std::floor(u * width)), 0, width - 1);
        const int j = std::clamp(static_cast<int>(std::floor(v * height)), 0, height - 1);
        return values[static_cast<size_t>(j) * width + i];
    }
};
// A texture: per-pixel reflectance factors (float). A classification raster: class values.
using Texture = PlanRaster<float>;
using ClassRaster = PlanRaster<uint16_t>;

// Reads an 8- or 16-bit single-channel integer image without rescaling its values. InputError if it
// cannot.
std::shared_ptr<ClassRaster> loadClassRaster(const std::filesystem::path& path);

// A material on the render bands. Transport asks for its BxDF (Scene::bxdf) and that BxDF's flags;
// `type` is kept for messages, truth images and the periodic-wall test only.
struct MaterialData {
    std::string name;
    ir::Material::Type type = ir::Material::Type::Lambertian;
    std::optional<ir::Material::Solver> solver;  // as given (the dirsig estimator resolves defaults)
    std::vector<double> reflectance;  // per band (0 for interfaces and black)
    std::shared_ptr<const Texture> texture;
    // RoughDielectric: the Cox–Munk slope distribution, built once (with Gram–Charlier terms its
    // normalisation is a quadrature), in the frame whose x axis is the downwind direction
    // (windAzimuth 0); `downwind` is that direction in the world (horizontal, unit).
    std::optional<CoxMunkDistribution> slopes;
    MicrofacetShadowing shadowing = MicrofacetShadowing::SmithLight;
    Vec3 downwind{1, 0, 0};
    // Classified: the class map, and per raster value the index of the material it names (-1: the
    // value does not occur). Scene::materialIndex resolves a hit through it.
    std::shared_ptr<const ClassRaster> classMap;
    std::vector<int> classMaterial;
    // The lobes of the BxDF Scene::bxdf builds for this material, from its type's descriptor
    // (core/material_kinds.h): kTransmission for interfaces, kSpecular or kGlossy for smooth or
    // rough ones, kDiffuse for the rest; 0 for periodic walls, which are domain edges, not
    // surfaces. Transport decides by them without building the BxDF.
    uint8_t lobes = kReflection | kDiffuse;
    uint8_t bxdfFlags() const { return lobes; }
    // Interfaces let light through to the mesh's other medium; everything else is opaque.
    bool isInterface() const { return lobes & kTransmission; }
    bool isRough() const { return isInterface() && (lobes & kGlossy); }
    bool isOpaque() const { return !isInterface() && !isPeriodicWall(); }
    bool isPeriodicWall() const { return lobes == 0; }
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
    const std::vector<Medium>& media() const { return media_; }
    const std::vector<MaterialData>& materials() const { return materials_; }

    // Global material index of a hit: through the mesh's slot list, and for a classified material
    // through its class map at the hit's plan position (x, y), so every estimator, the photon pass and
    // the truth images see the class of the point the ray landed on.
    int materialIndex(const SurfaceHit& h) const {
        const int m = meshMaterials_[h.mesh][h.slot];
        const MaterialData& d = materials_[static_cast<size_t>(m)];
        return d.classMap ? d.classMaterial[d.classMap->at(h.p.x, h.p.y)] : m;
    }
    const MaterialData& material(const SurfaceHit& h) const { return materials_[materialIndex(h)]; }
    // The flags of bxdf(h), without building it (MaterialData::bxdfFlags).
    uint8_t bxdfFlags(const SurfaceHit& h) const { return material(h).bxdfFlags(); }
    // Is the hit on a periodic side wall of the domain (see wrapRay)?
    bool isPeriodicWall(const SurfaceHit& h) const { return material(h).isPeriodicWall(); }
    // The BxDF at a hit for the bands of g, in the hit's local frame (+z = the mesh's outward
    // normal): Lambertian with unit reflectance for diffuse materials (the per-band reflectance is
    // albedo()), a smooth dielectric between the mesh's outside and inside media for interfaces.
    // Rough interfaces: the Cox–Munk microfacet BxDF (render/rough_dielectric.h) between the same
    // two media, in the frame shadingFrame(h) returns.
    BxDF bxdf(const SurfaceHit& h, BandGroup g) const;
    // The local frame of bxdf(h): +z the mesh's outward geometric normal; x along the downwind
    // direction projected on the face for rough interfaces (the slope distribution is anisotropic),
    // any tangent otherwise.
    Frame shadingFrame(const SurfaceHit& h) const {
        const MaterialData& m = material(h);
        return m.isRough() ? roughShadingFrame(h, m) : Frame::fromNormal(h.ng);
    }
    // The rough interface of material `material` seen as a horizontal surface (+z up, x downwind)
    // between its mesh's media for the bands of g, for sampling directions before a hit is known.
    RoughDielectricBxDF roughBxdf(int material, double nOut, double nIn) const;
    // shadingFrame's branch for rough interfaces (out of line; the common case is inline).
    Frame roughShadingFrame(const SurfaceHit& h, const MaterialData& m) const;
    // Per-band diffuse reflectance at a hit (texture applied); zero for interfaces and black.
    Spec albedo(const SurfaceHit& h, BandGroup g) const;
    // Medium on the side of the hit the ray came from, and on the far side (interfaces).
    int nearMedium(const SurfaceHit& h) const { return h.front ? meshOutside_[h.mesh] : meshInside_[h.mesh]; }
    int farMedium(const SurfaceHit& h) const { return h.front ? meshInside_[h.mesh] : meshOutside_[h.mesh]; }

    // A ray that hit a Periodic side wall leaves through it and re-enters through the opposite wall
    // of the domain: the same direction d from the hit point moved by the domain's width (or
    // depth). Estimators treat the wall like an index-matched interface: the segment ends there,
    // the medium is unchanged, and at most kMaxWraps wraps are followed per path.
    // nullopt if the hit is not on a domain edge (the wall mesh does not match the domain).
    std::optional<Ray> wrapRay(const SurfaceHit& h, const Vec3& d) const;
    static constexpr int kMaxWraps = 1024;

    // Free flight along `ray` through scattering medium `medium` with the numbers uBand, uDist,
    // sampled before the geometry is traced: Embree is asked only up to the collision depth (a
    // short segment in open water is answered by the clearance grid, render/clearance_grid.h),
    // and if a surface comes first the flight is sampled again to it with the same numbers (the
    // same collision depth, now beyond the surface: reached with weight T / P(no event)). The
    // result equals sampling up to the closest hit; *hit and *h tell the surface reached.
    FreeFlight flightToSurface(const Ray& ray, int medium, BandGroup g, double uBand, double uDist, SurfaceHit* h,
                               bool* hit) const;
    const ir::Domain& domain() const { return ir_.domain; }
    int insideMedium(int mesh) const { return meshInside_[mesh]; }
    int outsideMedium(int mesh) const { return meshOutside_[mesh]; }
    bool meshClosed(int mesh) const { return ir_.meshes[mesh].closed; }
    // Medium index for a name ("" = air = 0); InputError naming `who` if unknown.
    int mediumIndex(const std::string& name, const std::string& who) const;

private:
    void resolveClassMaps();
    void addMesh(const ir::Mesh& mesh);

    const ir::SceneIR& ir_;
    std::vector<Band> bands_;
    std::unique_ptr<EmbreeScene> geometry_;
    SunSource sun_;
    SkySource sky_;
    std::vector<Medium> media_;
    std::vector<MaterialData> materials_;
    std::vector<std::vector<int>> meshMaterials_;
    std::vector<int> meshInside_, meshOutside_;
};

}  // namespace littoral::render
