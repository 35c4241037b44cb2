#pragma once
// The render settings each estimator declares (core/kinds.h: name = scene.json key, sceneKey =
// key path under `render:`, type, default, the one range, unit, doc). Each estimator's descriptor
// sits at the end of its implementation file; the settings read by makeRenderConfig's shared
// logic are declared once here and composed into both. registerEstimatorKinds() (one line per
// estimator, estimator.cpp) puts the descriptors into core's estimatorKinds(), where the
// scene-file parser (scenegen/, which may not use render/) reads them; main() and
// makeRenderConfig call it.
#include "core/kinds.h"

namespace littoral::render {

// Shared settings (estimator.cpp).
ParamSpec maxBouncesSetting(double defaultValue);
ParamSpec maxSpecularDepthSetting(double defaultValue);
ParamSpec probeSamplesSetting();
ParamSpec probeBatchesSetting();
ParamSpec probePhotonsSetting();
ParamSpec marchStepSetting();
ParamSpec targetRelativeErrorSetting();
ParamSpec maxSamplesPerPixelSetting();

const KindInfo& dirsigEstimatorKind();  // dirsig_estimator.cpp
const KindInfo& pathEstimatorKind();    // path_estimator.cpp

// Registers every estimator's descriptor (idempotent, thread-safe).
void registerEstimatorKinds();

}  // namespace littoral::render
