#include "core/material_kinds.h"

#include <algorithm>
#include <numbers>

#include "core/cox_munk_fit.h"
#include "core/error.h"
#include "core/names.h"

namespace littoral {

namespace {
using T = ir::Material::Type;
using S = ir::Material::Solver;
constexpr uint8_t kDiffuseLobes = kReflection | kDiffuse;
const std::vector<S> kDiffuseSolvers{S::Classic, S::Generic, S::SurfacePM};
constexpr const char* kFresnelOnly = "its faces are always evaluated by the Fresnel solver (Table 10.4)";

MaterialKind lambertian() {
    MaterialKind k;
    k.info = {"material type", "lambertian", "a diffuse (Lambertian) reflector", {}};
    k.type = T::Lambertian;
    k.hasReflectance = true;
    k.lobes = kDiffuseLobes;
    k.namedSolvers = kDiffuseSolvers;
    k.inSceneFiles = true;
    k.sceneKeys = {"reflectance", "solver"};
    return k;
}

MaterialKind textured() {
    MaterialKind k;
    k.info = {"material type", "textured",
              "Lambertian, its reflectance multiplied by a texture draped over a plan-view rectangle", {}};
    k.type = T::Textured;
    k.hasReflectance = true;
    k.irKeys = {"texture"};
    k.lobes = kDiffuseLobes;
    k.namedSolvers = kDiffuseSolvers;
    return k;
}

MaterialKind dielectric() {
    MaterialKind k;
    k.info = {"material type", "dielectric",
              "a smooth Fresnel interface between the mesh's two media (a scene file's dielectric is a transparent "
              "solid of its refractive_index: it reflects by Fresnel's law, not by a reflectance)",
              {}};
    k.type = T::Dielectric;
    k.lobes = kReflection | kTransmission | kSpecular;
    k.defaultSolver = S::Fresnel;
    k.namedSolvers = {S::Fresnel};
    k.noSolverWhy = kFresnelOnly;
    k.inSceneFiles = true;
    k.sceneKeys = {"refractive_index", "absorption_per_m"};
    return k;
}

MaterialKind roughDielectric() {
    MaterialKind k;
    k.info = {"material type",
              "rough-dielectric",
              "a Cox–Munk microfacet interface between the mesh's two media (water.surface.roughness)",
              {{"wind_speed_mps", "", ParamType::Real, std::nullopt, CoxMunkLimits::kMinWind, CoxMunkLimits::kMaxWind,
                "m/s", "wind speed at 12.5 m that sets the slope variances"},
               {"wind_azimuth_rad", "", ParamType::Real, 0.0, -2 * std::numbers::pi, 2 * std::numbers::pi, "rad",
                "direction the wind blows toward, counter-clockwise from +x (east)"},
               {"gram_charlier", "", ParamType::Boolean, 0.0, 0, 1, "",
                "Cox and Munk's skewness and peakedness terms (clean sea only)"}}};
    k.type = T::RoughDielectric;
    k.irKeys = {"sea", "slopes", "shadowing"};
    k.lobes = kReflection | kTransmission | kGlossy;
    k.defaultSolver = S::Fresnel;
    k.namedSolvers = {S::Fresnel};
    k.noSolverWhy = kFresnelOnly;
    return k;
}

MaterialKind black() {
    MaterialKind k;
    k.info = {"material type", "black", "absorbs everything (a diffuse reflector of reflectance 0)", {}};
    k.type = T::Black;
    k.lobes = kDiffuseLobes;
    k.noSolverWhy = "it reflects nothing";
    k.inSceneFiles = true;
    return k;
}

MaterialKind periodic() {
    MaterialKind k;
    k.info = {"material type", "periodic",
              "a side wall of a horizontally periodic domain: rays leave through it and re-enter through the "
              "opposite wall",
              {}};
    k.type = T::Periodic;
    k.lobes = 0;
    k.noSolverWhy = "it is an edge of the domain, not a surface";
    return k;
}

MaterialKind classified() {
    MaterialKind k;
    k.info = {"material type", "classified",
              "a class map: the material at a point is the diffuse material its class names, looked up where the "
              "ray lands",
              {}};
    k.type = T::Classified;
    k.irKeys = {"class_map"};
    k.lobes = kDiffuseLobes;
    k.noSolverWhy = "each class's material carries its own";
    return k;
}

bool contains(const std::vector<std::string>& v, std::string_view s) { return std::find(v.begin(), v.end(), s) != v.end(); }

std::string orList(const std::vector<std::string>& v) {
    std::string s;
    for (size_t i = 0; i < v.size(); ++i) s += (i == 0 ? "" : i + 1 == v.size() ? " or " : ", ") + v[i];
    return s;
}
}  // namespace

bool MaterialKind::uses(std::string_view irKey) const { return info.param(irKey) || contains(irKeys, irKey); }
bool MaterialKind::takesSceneKey(std::string_view key) const { return contains(sceneKeys, key); }

const KindRegistry<MaterialKind>& materialKinds() {
    static const KindRegistry<MaterialKind> registry = [] {
        KindRegistry<MaterialKind> r("material type");
        r.add(lambertian());
        r.add(textured());
        r.add(dielectric());
        r.add(roughDielectric());
        r.add(black());
        r.add(periodic());
        r.add(classified());
        return r;
    }();
    return registry;
}

const MaterialKind& materialKind(ir::Material::Type type) {
    for (const MaterialKind& k : materialKinds().kinds())
        if (k.type == type) return k;
    throw InternalError("no material-type descriptor for " + std::string(nameOf(type)));
}

std::vector<std::string> sceneMaterialTypeNames() {
    std::vector<std::string> v;
    for (const MaterialKind& k : materialKinds().kinds())
        if (k.inSceneFiles) v.push_back(k.info.name);
    return v;
}

std::string sceneTypesWithKey(std::string_view key) {
    std::vector<std::string> v;
    for (const MaterialKind& k : materialKinds().kinds())
        if (k.inSceneFiles && k.takesSceneKey(key)) v.push_back(k.info.name);
    return orList(v);
}

std::string irTypesWithKey(std::string_view key) {
    std::vector<std::string> v;
    for (const MaterialKind& k : materialKinds().kinds())
        if (k.uses(key)) v.push_back(k.info.name);
    return orList(v);
}

std::vector<std::string> MaterialKind::solverNames() const {
    std::vector<std::string> v;
    for (ir::Material::Solver s : namedSolvers) v.emplace_back(nameOf(s));
    return v;
}

}  // namespace littoral
