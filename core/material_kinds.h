#pragma once
// Material types: one descriptor per type (family "material type"), read by the scene-file
// parser (the types a `materials` entry may name, their keys and solvers), the Scene IR writer
// and reader (which keys a type writes and accepts, the ranges of its numbers), the dirsig
// estimator's solver choice and the renderer (the lobes of the type's BxDF, which transport asks
// instead of the type). The BxDF factory itself is render/scene.cpp's makeMaterial, an exhaustive
// switch over ir::Material::Type: a type without one does not compile (-Werror=switch).
//
//   const MaterialKind& k = materialKind(ir::Material::Type::RoughDielectric);
//   k.lobes & kGlossy;            // true
//   k.uses("wind_speed_mps");     // true
#include <string>
#include <string_view>
#include <vector>

#include "core/bxdf_flags.h"
#include "core/kinds.h"
#include "core/scene_ir.h"

namespace littoral {

struct MaterialKind {
    KindInfo info;  // family "material type"; params: the type's numbers in the Scene IR
    ir::Material::Type type = ir::Material::Type::Lambertian;
    // The type's other Scene IR keys (besides name, type, reflectance and solver): "texture",
    // "class_map", "sea", "shadowing". Every IR material carries `reflectance`; a type whose BxDF
    // has no diffuse lobe writes it as 0 and refuses any other value.
    std::vector<std::string> irKeys;
    bool hasReflectance = false;  // its `reflectance` is the diffuse reflectance (else it must be 0)
    uint8_t lobes = 0;  // BxDFFlags of the BxDF the renderer builds (0: a domain edge, no surface)
    // The dirsig estimator's solver for the type's faces when the material names none, and the
    // solvers a material of this type may name (empty: none; `noSolverWhy` says why).
    ir::Material::Solver defaultSolver = ir::Material::Solver::Classic;
    std::vector<ir::Material::Solver> namedSolvers;
    std::string noSolverWhy;
    // Scene files: the keys a `materials` entry of this type takes besides name and type. A type
    // with none is made by scene assembly only (`inSceneFiles` false), except black.
    bool inSceneFiles = false;
    std::vector<std::string> sceneKeys;

    bool uses(std::string_view irKey) const;  // a parameter or an IR key of this type
    bool takesSceneKey(std::string_view key) const;
    bool isInterface() const { return lobes & kTransmission; }
    std::vector<std::string> solverNames() const;  // of namedSolvers, in order
};
inline const KindInfo& kindInfo(const MaterialKind& k) { return k.info; }

const KindRegistry<MaterialKind>& materialKinds();
// The descriptor of a type (InternalError if none is registered: the registration test checks
// every enumerator).
const MaterialKind& materialKind(ir::Material::Type type);
// The types a scene file's `materials[].type` may name, in registration order.
std::vector<std::string> sceneMaterialTypeNames();
// The types whose scene-file entries take `key` ("lambertian", "lambertian or dielectric").
std::string sceneTypesWithKey(std::string_view key);
// The types that use the IR key (a parameter or an IR key).
std::string irTypesWithKey(std::string_view key);

}  // namespace littoral
