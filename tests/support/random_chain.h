// SPDX-License-Identifier: MIT
// Random chains of actions on one box-shaped part, for the motion-bound
// tests (tests/foundation/motion_bound_test.cpp, tests/geometry/box_motion_test.cpp).
#pragma once

#include "src/scene/scene.h"

#include <random>

namespace plancheck::testing {

// One part on a chain of 1 to 5 actions: rotations about random pivots and
// axes (half of them written in degrees), translations along an axis or
// free (half in millimetres) and, with `scales`, scales about random fixed
// points; every parameter's reference value 0.
Scene random_chain_scene(std::mt19937_64& rng, bool scales = true);

}  // namespace plancheck::testing
