#pragma once
// What a probe can measure ("Ed", "Lu", ...; kinds without parameters), described beside its
// evaluation in render/probes.cpp and registered here by render::registerEstimatorKinds(), so that
// the scene-file parser (scenegen/, which may not use render/) reads the same names.
#include "core/kinds.h"

namespace littoral {

KindRegistry<KindInfo>& probeQuantityKindsForRegistration();
const KindRegistry<KindInfo>& probeQuantityKinds();

}  // namespace littoral
