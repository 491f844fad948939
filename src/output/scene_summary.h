// SPDX-License-Identifier: MIT
// What `plancheck scene` prints: parts, actions, checked pairs and the pairs
// in contact at the reference pose.
#pragma once

#include "src/scene/scene.h"

#include <ostream>
#include <string>
#include <vector>

namespace plancheck {

struct ReferenceContact {
  std::string a, b;   // part names ("terrain" for the terrain)
  bool allowed;       // listed in allowed_collisions (else a checked pair in collision)
};

// Pairs of parts that touch or intersect at the reference pose, among all
// pairs that move relative to each other (allowed ones included).
std::vector<ReferenceContact> reference_contacts(const Scene& scene);

// Lengths and limits are printed in the scene's own units.
void print_scene_summary(const Scene& scene, std::ostream& out);

}  // namespace plancheck
