// SPDX-License-Identifier: MIT
#include "support/bar_scene.h"

#include <algorithm>
#include <cmath>

namespace plancheck::testing {

double bar_distance(double degrees) {
  const double a = degrees * 3.14159265358979323846 / 180.0;
  const double h = 1.0 - static_cast<double>(0.9f);
  return 1.0 - 2.0 * std::max(0.0, std::sin(a)) - h * std::cos(a);
}

void write_bar_scene(const TempDir& dir) {
  write_obj(dir / "model.obj", {{"Slab", box_mesh({-3, -1, -1}, {3, 1, 0})}, {"Bar", box_mesh({0, -0.1, 0.9}, {2, 0.1, 1.1})}});
  write_text(dir / "scene.json", R"({
  "format": "plancheck-scene/1", "model": "model.obj", "length_unit": "m", "angle_unit": "deg",
  "actions": [{"name": "J1", "node": "Bar", "type": "rotate", "pivot": [0, 0, 1], "axis": [0, 1, 0], "limits": [-90, 30]}],
  "safety_margin": 0.05
})");
}

}  // namespace plancheck::testing
