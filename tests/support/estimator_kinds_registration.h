#pragma once
// The scene-file parser reads the estimators' render settings from their descriptors, which
// render/ registers into core (render/estimator_settings.h); the `littoral` command does so in
// main(). Including this header in one file of a test executable does the same before any of its
// tests parses a scene.
#include <gtest/gtest.h>

#include "render/estimator_settings.h"

namespace littoral::testing_support {

class EstimatorKindsEnvironment : public ::testing::Environment {
public:
    void SetUp() override { littoral::render::registerEstimatorKinds(); }
};

inline ::testing::Environment* const kEstimatorKindsEnvironment =
    ::testing::AddGlobalTestEnvironment(new EstimatorKindsEnvironment);

}  // namespace littoral::testing_support
