// SPDX-License-Identifier: MIT
// What `plancheck scene` prints: parts, actions, checked pairs and the pairs
// in contact at the reference pose.
#pragma once

#include "src/scene.h"

#include <ostream>

namespace plancheck {

// Lengths and limits are printed in the scene's own units.
void print_scene_summary(const Scene& scene, std::ostream& out);

}  // namespace plancheck
