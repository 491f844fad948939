// SPDX-License-Identifier: MIT
// The small scene both scene-level stability suites pose: a bar lying
// exactly on a slab, turning about y through (-10, 0, 0).
#pragma once

#include "src/scene/plan.h"
#include "src/scene/scene_loader.h"
#include "src/checks/verify.h"
#include "support/fixtures.h"

#include <string>
#include <vector>

namespace plancheck::stability {

using testing::TempDir;

constexpr double kLunarRadius = 1737400.0;  // m

// A slab (static) and a bar (rotating about y through (-10, 0, 0)) lying
// exactly on it at the reference pose: touching, so a collision.
// Positive angles press the bar's far end into the slab, negative ones lift it.
struct BarScene {
  TempDir dir{"stability-scene"};
  Scene scene;
  explicit BarScene(const std::string& axis = "[0, 1, 0]", const std::string& limits = "") {
    testing::write_obj(dir / "model.obj", {{"Slab", testing::box_mesh({-3, -1, -1}, {3, 1, 0})},
                                           {"Bar", testing::box_mesh({0, -0.125, 0}, {2, 0.125, 0.25})}});
    testing::write_text(dir / "scene.json", R"({"format": "plancheck-scene/1", "model": "model.obj",
      "length_unit": "m", "angle_unit": "deg",
      "actions": [{"name": "J1", "node": "Bar", "type": "rotate", "pivot": [-10, 0, 0], "axis": )" +
                                                axis + limits + "}]}");
    scene = load_scene(dir / "scene.json");
  }
  // The plan's states after loading (a one-column CSV in degrees).
  std::vector<std::vector<double>> states(const std::vector<std::string>& degrees) {
    std::string csv = "J1\n";
    for (const std::string& d : degrees) csv += d + "\n";
    testing::write_text(dir / "plan.csv", csv);
    return load_plan(scene, dir / "plan.csv").states;
  }
};

// Every length in the scene moved by t (in double, through the API).
inline Scene translated(const Scene& s, const Vec3& t) {
  Scene out = s;
  for (Part& p : out.parts)
    for (Vec3& v : p.mesh.vertices) v += t;
  for (Action& a : out.actions) {
    a.pivot += t;
    a.fixed_point += t;
  }
  for (Node& n : out.nodes) n.origin += t;
  return out;
}

inline StateResult check(const Checker& c, const std::vector<double>& params) {
  StateResult r;
  c.check_state(params, r);
  return r;
}

}  // namespace plancheck::stability
