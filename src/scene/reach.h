// SPDX-License-Identifier: MIT
// How far a moving part can get from its chain's first pivot over every
// state: the bound that leaves out unreachable static triangles (checks/
// verify.cpp) and the terrain window (scene/terrain_window.cpp).
#pragma once

#include "src/scene/scene.h"

#include <vector>

namespace plancheck {

// Reach of a part on a chain of rotations (any axes, limits ignored, so the
// bound holds for every state): a rotation about an axis through pivot p
// keeps |y - p|, hence a point x posed by A1(A2(...Ak(x))) stays within
// |x - p_k| + sum_i |p_{i+1} - p_i| of p_1 (triangle inequality, innermost
// action first). Chains with other actions have no such bound here.
struct Reach {
  bool bounded = false;
  Vec3 centre = Vec3::Zero();  // p_1
  double r_max = 0.0;          // max over the part's triangle vertices (m)
  double r_min = 0.0;          // min over them (m)
};

// The reach of `mesh` moved by `chain` (indices into scene.actions).
Reach part_reach(const Scene& scene, const std::vector<int>& chain, const Mesh& mesh);

// The farthest a point x (reference pose) carried by `chain` gets from the
// chain's first pivot; negative when the chain has no bound (see Reach).
double point_reach(const Scene& scene, const std::vector<int>& chain, const Vec3& x);

}  // namespace plancheck
