#pragma once
// The lobes of a BxDF as bit flags. Material-type descriptors (core/material_kinds.h) declare the
// lobes of the BxDF the renderer builds for each type, and transport decides by these flags
// (render/bxdf_types.h brings them into namespace render).
#include <cstdint>

namespace littoral {

enum BxDFFlags : uint8_t {
    kReflection = 1,
    kTransmission = 2,
    kDiffuse = 4,
    kSpecular = 8,
    kGlossy = 16,  // a real, non-delta lobe that is not Lambertian (the rough interface)
};

}  // namespace littoral
