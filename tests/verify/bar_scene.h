// SPDX-License-Identifier: MIT
// The slewing bar of the motion tests: Bar [0.2, 2] x [-0.05, 0.05] x
// [0.95, 1.05] on the chain Slew (rotate about +z through the origin,
// outermost), Boom (translate along +x), Grow (scale about (0, 0, 1),
// innermost); posts are static boxes; safety margin 0.05 m.
#pragma once

#include "support/fixtures.h"

#include <string>
#include <utility>
#include <vector>

namespace plancheck::testing {

inline void write_bar_scene(const TempDir& dir, const std::vector<std::pair<Vec3, Vec3>>& posts) {
  std::vector<std::pair<std::string, Mesh>> parts{{"Bar", box_mesh({0.2, -0.05, 0.95}, {2, 0.05, 1.05})}};
  for (std::size_t i = 0; i < posts.size(); ++i)
    parts.emplace_back("Post" + std::to_string(i), box_mesh(posts[i].first, posts[i].second));
  write_obj(dir / "model.obj", parts);
  write_text(dir / "scene.json", R"({
  "format": "plancheck-scene/1", "model": "model.obj", "length_unit": "m", "angle_unit": "deg",
  "actions": [
    {"name": "Slew", "node": "Bar", "type": "rotate", "pivot": [0, 0, 0], "axis": [0, 0, 1]},
    {"name": "Boom", "node": "Bar", "type": "translate", "axis": [1, 0, 0]},
    {"name": "Grow", "node": "Bar", "type": "scale", "fixed_point": [0, 0, 1]}],
  "safety_margin": 0.05
})");
}

}  // namespace plancheck::testing
