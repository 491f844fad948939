// SPDX-License-Identifier: MIT
#include "src/output/scene_page.h"

#include "src/checks/probes.h"

#include <limits>

namespace plancheck {

void PageFrame::affine(const Affine& t, std::vector<float>& out) const {
  const Mat3 r = t.linear();
  const Vec3 shift = (r * centre + t.translation() - centre) / unit;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) out.push_back(static_cast<float>(r(i, j)));
    out.push_back(static_cast<float>(shift[i]));
  }
}

PageFrame page_frame(const Scene& scene) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Part& part : scene.parts)
    for (const Vec3& v : part.mesh.vertices) {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
  PageFrame frame;
  frame.unit = scene.length_scale;
  if (lo.allFinite() && hi.allFinite()) frame.centre = 0.5 * (lo + hi);
  return frame;
}

PageJson dem_rect_json(const Dem& dem, const Vec3& origin, const PageFrame& frame, const SampleRect& rect) {
  std::vector<float> z;
  for (int r = rect.r0; r <= rect.r1; ++r)
    for (int c = rect.c0; c <= rect.c1; ++c)
      z.push_back(dem.is_valid(c, r)
                      ? static_cast<float>((origin.z() + dem.height(c, r) - frame.centre.z()) / frame.unit)
                      : std::numeric_limits<float>::quiet_NaN());
  return {{"c0", rect.c0}, {"r0", rect.r0}, {"c1", rect.c1}, {"r1", rect.r1}, {"z", base64_array(z)}};
}

namespace {

PageJson part_json(const Scene& scene, const Part& part, const PageFrame& frame) {
  std::vector<float> positions;
  positions.reserve(part.mesh.vertices.size() * 3);
  for (const Vec3& v : part.mesh.vertices) {
    const Vec3 p = frame.point(v);
    for (int i = 0; i < 3; ++i) positions.push_back(static_cast<float>(p[i]));
  }
  std::vector<std::uint32_t> indices;
  indices.reserve(part.mesh.triangles.size() * 3);
  for (const Tri& t : part.mesh.triangles) indices.insert(indices.end(), t.begin(), t.end());
  return {{"name", part.name},
          {"node", part.node},
          {"path", scene.nodes[static_cast<std::size_t>(part.node)].path},
          {"chain", part.chain_id},
          {"triangles", part.mesh.triangles.size()},
          {"positions", base64_array(positions)},
          {"indices", base64_array(indices)}};
}

}  // namespace

PageJson scene_page_json(const Checker& checker, const Scene& scene, const PageFrame& frame) {
  PageJson page;
  page["length_unit"] = scene.length_unit;
  page["angle_unit"] = scene.angle_unit;
  page["safety_margin"] = scene.safety_margin / frame.unit;
  page["centre"] = point_json(frame.centre / frame.unit);
  page["parameter_names"] = scene.parameter_names;
  PageJson names = PageJson::array();
  for (std::size_t i = 0; i < checker.part_count(); ++i) names.push_back(checker.part_name(static_cast<int>(i)));
  page["checked_part_names"] = names;
  page["terrain_index"] = checker.terrain_index();
  PageJson nodes = PageJson::array();
  for (const Node& node : scene.nodes)
    nodes.push_back({{"name", node.name}, {"parent", node.parent}, {"part", node.part}});
  page["nodes"] = nodes;
  PageJson parts = PageJson::array();
  for (const Part& part : scene.parts) parts.push_back(part_json(scene, part, frame));
  page["parts"] = parts;
  page["chains"] = scene.chains.size();
  page["chain_actions"] = scene.chains;

  PageJson probes = PageJson::array();
  for (const ProbeConfig& pc : scene.probes) {
    PageJson dirs = PageJson::array();
    for (const Vec3& d : ProbeCaster::fan_directions(pc)) dirs.push_back(point_json(d));
    probes.push_back({{"name", pc.name}, {"part", pc.part_index}, {"origin", point_json(frame.point(pc.origin))},
                      {"directions", dirs}, {"max_range", pc.max_range / frame.unit}});
  }
  page["probes"] = probes;
  if (scene.scoop)
    page["scoop"] = {{"part", scene.scoop->part_index}, {"bottom_point", point_json(frame.point(scene.scoop->bottom_point))}};

  if (scene.terrain) {
    const Vec3 origin = scene.terrain->origin;
    const Dem& base = *scene.terrain->grid;
    const SampleRect all{0, 0, base.ncols - 1, base.nrows - 1};
    page["terrain"] = {{"ncols", base.ncols}, {"nrows", base.nrows}, {"cellsize", base.cellsize / frame.unit},
                       {"x0", (origin.x() + base.x0 - frame.centre.x()) / frame.unit},
                       {"y0", (origin.y() + base.y0 - frame.centre.y()) / frame.unit},
                       {"z", dem_rect_json(base, origin, frame, all)["z"]}};
  } else {
    page["terrain"] = nullptr;
  }
  return page;
}

}  // namespace plancheck
