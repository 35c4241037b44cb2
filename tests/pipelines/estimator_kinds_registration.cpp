// Registers the estimators' descriptors before any test of this executable parses a scene.
#include "tests/support/estimator_kinds_registration.h"
