// SPDX-License-Identifier: MIT
#include "src/output/scene_page.h"

#include "src/checks/probes.h"

#include <algorithm>
#include <climits>
#include <cstdint>
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

PageJson quantized_json(const std::vector<float>& values, int stride) {
  const std::size_t k = static_cast<std::size_t>(stride);
  std::vector<double> lo(k, std::numeric_limits<double>::infinity()), hi(k, -std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < values.size(); ++i)
    if (std::isfinite(values[i])) {
      lo[i % k] = std::min(lo[i % k], static_cast<double>(values[i]));
      hi[i % k] = std::max(hi[i % k], static_cast<double>(values[i]));
    }
  std::vector<double> step(k);
  for (std::size_t c = 0; c < k; ++c) {
    if (!(lo[c] <= hi[c])) lo[c] = hi[c] = 0.0;
    step[c] = hi[c] > lo[c] ? (hi[c] - lo[c]) / 65534.0 : 1.0;
  }
  std::vector<std::uint16_t> q(values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    q[i] = std::isfinite(values[i])
               ? static_cast<std::uint16_t>(std::clamp(std::lround((values[i] - lo[i % k]) / step[i % k]), 0L, 65534L))
               : std::uint16_t{65535};
  return {{"lo", lo}, {"step", step}, {"q", base64_array(q)}};
}

PageJson ints_json(const std::vector<std::int32_t>& values) {
  if (std::all_of(values.begin(), values.end(), [](std::int32_t v) { return v >= INT16_MIN && v <= INT16_MAX; })) {
    const std::vector<std::int16_t> small(values.begin(), values.end());
    return {{"i16", base64_array(small)}};
  }
  return {{"i32", base64_array(values)}};
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
  PageJson out = {{"name", part.name},
                  {"node", part.node},
                  {"path", scene.nodes[static_cast<std::size_t>(part.node)].path},
                  {"chain", part.chain_id},
                  {"triangles", part.mesh.triangles.size()},
                  {"positions", base64_array(positions)}};
  // Indices as uint16 where the part's vertices allow it: a third of the
  // default scene's page.
  if (part.mesh.vertices.size() <= 65536) {
    const std::vector<std::uint16_t> small(indices.begin(), indices.end());
    out["indices16"] = base64_array(small);
  } else {
    out["indices"] = base64_array(indices);
  }
  return out;
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
