// SPDX-License-Identifier: MIT
// `plancheck dig SCENE PLAN --out DIR`: the terrain before and after one plan.
#include "src/commands.h"

#include "src/dig.h"
#include "src/error.h"
#include "src/plan.h"
#include "src/png_map.h"
#include "src/scene_loader.h"

#include <cstdio>
#include <ostream>

namespace plancheck {

int run_dig(const DigArgs& args, std::ostream& out) {
  const Scene scene = load_scene(args.scene, args.scene_options);
  if (!scene.terrain) fail(args.scene, "terrain: missing (plancheck dig needs a terrain and a scoop block)");
  if (!scene.scoop) fail(args.scene, "scoop: missing (plancheck dig needs a terrain and a scoop block)");
  const Plan plan = load_plan(scene, args.plan);
  const Digger digger(scene);
  Dem grid = digger.undisturbed();
  std::vector<DigStep> steps;
  const DigSummary sum = digger.dig_plan(plan.states, grid, steps);

  std::filesystem::create_directories(args.out);
  write_dem(args.out / "before.asc", digger.undisturbed(), scene.length_scale);
  write_dem(args.out / "after.asc", grid, scene.length_scale);
  const int pixels = std::max(1, 600 / std::max(grid.ncols, grid.nrows));
  const MapScale map = write_dig_png(args.out / "dig.png", digger.undisturbed(), grid, pixels);

  const double u = scene.length_scale, u3 = u * u * u;
  char line[400];
  std::snprintf(line, sizeof line,
                "%s: model %s, deepest %.4g %s at state %zu, dug %.6g %s^3, collected %.6g %s^3 = %.4g kg "
                "(capacity %.6g%s), spilled %.6g\n",
                plan.name.c_str(), sum.model.c_str(), sum.deepest / u, scene.length_unit.c_str(), sum.deepest_state,
                sum.dug_volume / u3, scene.length_unit.c_str(), sum.collected_volume / u3, scene.length_unit.c_str(),
                sum.collected_mass, scene.scoop->capacity / u3, sum.over_capacity ? ", exceeded" : "",
                sum.spilled_volume / u3);
  out << line;
  std::snprintf(line, sizeof line,
                "wrote %s/before.asc, after.asc, dig.png (heights %.4g..%.4g %s, difference up to %.4g %s)\n",
                args.out.string().c_str(), map.z_min / u, map.z_max / u, scene.length_unit.c_str(), map.diff_max / u,
                scene.length_unit.c_str());
  out << line;
  return 0;
}

}  // namespace plancheck
