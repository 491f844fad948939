// SPDX-License-Identifier: MIT
// Two meshes at random rigid poses beside FCL, in the style of FCL's own
// mesh-mesh tests (plancheck_bench two_mesh ..., `plancheck bench --two-mesh`).
#pragma once

#include "src/scene/scene.h"

#include <cstdint>

namespace plancheck::bench {

// The environment: a torus (major radius 3 m, tube 1 m) with smooth bumps
// and a little fixed noise on its tube, 50 x 20 quads = 2,000 triangles.
Mesh bumpy_torus();
// The object: an ellipsoid (semi-axes 0.7, 0.4, 0.3 m) with dents, 12
// slices x 9 stacks = 192 triangles; non-convex.
Mesh dented_ellipsoid();

// argv[0] is "two_mesh"; returns the process exit status (0 ok, 2 bad
// input, 3 when an answer check fails, so nothing is timed).
int run_two_mesh(int argc, char** argv);

}  // namespace plancheck::bench
