// SPDX-License-Identifier: MIT
// `plancheck dig SCENE PLAN --out DIR`: the terrain before and after one plan.
#include "src/cli/commands.h"

#include "src/checks/dig.h"
#include "src/base/error.h"
#include "src/base/text.h"
#include "src/scene/plan.h"
#include "src/output/dig_png.h"
#include "src/output/report.h"
#include "src/base/progress.h"
#include "src/scene/scene_loader.h"

#include <cstdio>
#include <ostream>

namespace plancheck {

int run_dig(const DigArgs& args, std::ostream& out, std::ostream& err) {
  const Scene scene = load_scene(args.scene, args.scene_options);
  if (!scene.terrain) fail(args.scene, "terrain: missing (plancheck dig needs a terrain and a scoop block)");
  if (!scene.scoop) fail(args.scene, "scoop: missing (plancheck dig needs a terrain and a scoop block)");
  const Plan plan = load_plan(scene, args.plan);
  const Digger digger(scene);
  Dem grid = digger.undisturbed();
  std::vector<DigStep> steps;
  DigSummary sum;
  {
    Progress progress("dig", plan.states.size(), "states", ProgressOptions{.quiet = args.quiet}, &err);
    sum = digger.dig_plan(plan.states, grid, steps, [&](std::size_t, const Dem&, const SampleRect&) { progress.add(); });
  }

  std::filesystem::create_directories(args.out);
  write_dem(args.out / "before.asc", digger.undisturbed(), scene.length_scale);
  write_dem(args.out / "after.asc", grid, scene.length_scale);
  // GeoTIFFs for GIS: the window's georeference and nodata (GDAL encodes,
  // the report writer writes).
  write_atomically(args.out / "before.tif", geotiff_bytes(digger.undisturbed(), scene.length_scale));
  write_atomically(args.out / "after.tif", geotiff_bytes(grid, scene.length_scale));
  DigMapRequest map_request;
  map_request.before = &digger.undisturbed();
  map_request.after = &grid;
  map_request.origin = digger.origin();
  map_request.target = plan.target;
  if (sum.dug) map_request.deepest = sum.deepest_point;
  map_request.plan_name = plan.name;
  map_request.length_unit = scene.length_unit;
  map_request.length_scale = scene.length_scale;
  const DigMapResult map = write_dig_png(args.out / "dig.png", map_request);

  const double u = scene.length_scale, u3 = u * u * u;
  char line[400];
  std::snprintf(line, sizeof line,
                "%s: model %s, deepest %.4g %s at state %zu, dug %.6g %s^3, collected %.6g %s^3 = %.4g kg "
                "(capacity %.6g%s), spilled %.6g\n",
                printable(plan.name).c_str(), sum.model.c_str(), sum.deepest / u, scene.length_unit.c_str(), sum.deepest_state,
                sum.dug_volume / u3, scene.length_unit.c_str(), sum.collected_volume / u3, scene.length_unit.c_str(),
                sum.collected_mass, scene.scoop->capacity / u3, sum.over_capacity ? ", exceeded" : "",
                sum.spilled_volume / u3);
  out << line;
  std::snprintf(line, sizeof line,
                "wrote %s/before.asc, after.asc, before.tif, after.tif, dig.png (heights %.4g..%.4g %s, difference up to %.4g %s)\n",
                args.out.string().c_str(), map.z_min / u, map.z_max / u, scene.length_unit.c_str(), map.diff_max / u,
                scene.length_unit.c_str());
  out << line;
  // Map coordinates, when the raster has a CRS (terrain.map_origin's frame).
  auto map_line = [&](const char* what, const Vec3& p) {
    if (const auto m = map_point(grid, digger.origin(), scene.length_scale, p)) {
      std::snprintf(line, sizeof line, "%s at map E %.10g, N %.10g, H %.10g %s\n", what, m->x(), m->y(), m->z(),
                    scene.length_unit.c_str());
      out << line;
    }
  };
  if (plan.target) map_line("target", *plan.target);
  if (sum.dug) map_line("deepest scoop point", sum.deepest_point);
  return 0;
}

}  // namespace plancheck
