// SPDX-License-Identifier: MIT
#include "src/output/report_html.h"

#include "src/dig.h"
#include "src/error.h"
#include "src/kinematics.h"
#include "src/output/html_page.h"
#include "src/probes.h"
#include "src/terrain.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

namespace plancheck {

namespace {

using Json = nlohmann::ordered_json;

// Page coordinates: the scene's length_unit, shifted by `centre` (metres) so
// float32 keeps its precision in scenes placed far from their origin.
struct Frame {
  Vec3 centre = Vec3::Zero();
  double unit = 1.0;  // metres per length_unit
  Vec3 point(const Vec3& p) const { return (p - centre) / unit; }
  // The same motion in page coordinates: y -> R y + (R c + t - c) / unit.
  void affine(const Affine& t, std::vector<float>& out) const {
    const Mat3 r = t.linear();
    const Vec3 shift = (r * centre + t.translation() - centre) / unit;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) out.push_back(static_cast<float>(r(i, j)));
      out.push_back(static_cast<float>(shift[i]));
    }
  }
};

template <class T>
std::string b64(const std::vector<T>& v) {
  return base64(v.data(), v.size() * sizeof(T));
}

Json num_json(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

Json point_json(const Vec3& p) { return Json::array({p.x(), p.y(), p.z()}); }

Json part_json(const Scene& scene, const Part& part, const Frame& frame) {
  std::vector<float> positions;
  positions.reserve(part.mesh.vertices.size() * 3);
  for (const Vec3& v : part.mesh.vertices) {
    const Vec3 p = frame.point(v);
    for (int i = 0; i < 3; ++i) positions.push_back(static_cast<float>(p[i]));
  }
  std::vector<std::uint32_t> indices;
  indices.reserve(part.mesh.triangles.size() * 3);
  for (const Tri& t : part.mesh.triangles) indices.insert(indices.end(), t.begin(), t.end());
  const Node& node = scene.nodes[static_cast<std::size_t>(part.node)];
  return {{"name", part.name},
          {"node", part.node},
          {"path", node.path},
          {"chain", part.chain_id},
          {"triangles", part.mesh.triangles.size()},
          {"positions", b64(positions)},
          {"indices", b64(indices)}};
}

// Heights in page coordinates (NaN where the DEM has no data).
std::vector<float> heights(const Dem& dem, const Vec3& origin, const Frame& frame, const SampleRect& rect) {
  std::vector<float> z;
  for (int r = rect.r0; r <= rect.r1; ++r)
    for (int c = rect.c0; c <= rect.c1; ++c)
      z.push_back(dem.is_valid(c, r) ? static_cast<float>((origin.z() + dem.height(c, r) - frame.centre.z()) / frame.unit)
                                     : std::numeric_limits<float>::quiet_NaN());
  return z;
}

Json rect_json(const Dem& dem, const Vec3& origin, const Frame& frame, const SampleRect& rect) {
  return {{"c0", rect.c0}, {"r0", rect.r0}, {"c1", rect.c1}, {"r1", rect.r1},
          {"z", b64(heights(dem, origin, frame, rect))}};
}

// The samples where two grids differ (empty when equal).
SampleRect difference(const Dem& a, const Dem& b) {
  SampleRect out;
  for (int r = 0; r < a.nrows; ++r)
    for (int c = 0; c < a.ncols; ++c)
      if (a.height(c, r) != b.height(c, r)) out.add(SampleRect{c, r, c, r});
  return out;
}

Json plan_json(const Checker& checker, const Scene& scene, const PlanResult& r, const Frame& frame) {
  const Plan& plan = *r.plan;
  const std::size_t n = r.states.size();
  Json p;
  p["name"] = plan.name;
  // The values as the plan holds them, one row per state.
  p["params"] = plan.states;
  if (!plan.times.empty()) p["times"] = plan.times;

  std::vector<float> chains;
  chains.reserve(n * scene.chains.size() * 12);
  std::vector<Affine> transforms;
  std::vector<float> points, scoop;
  Json dist = Json::array(), pair = Json::array(), verdict = Json::array(), limit = Json::array();
  Json contacts = Json::object();
  for (std::size_t s = 0; s < n; ++s) {
    chain_transforms(scene, plan.states[s], transforms);
    for (const Affine& t : transforms) frame.affine(t, chains);
    const StateResult& st = r.states[s];
    dist.push_back(st.part_a >= 0 ? num_json(st.min_distance / frame.unit) : Json(nullptr));
    pair.push_back(Json::array({st.part_a, st.part_b}));
    verdict.push_back(static_cast<int>(state_verdict(st, scene.safety_margin)));
    limit.push_back(st.limit_action);
    for (const Vec3* q : {&st.point_a, &st.point_b}) {
      const Vec3 v = st.part_a >= 0 ? frame.point(*q) : Vec3::Zero();
      for (int i = 0; i < 3; ++i) points.push_back(static_cast<float>(v[i]));
    }
    if (scene.scoop) {
      const Vec3 v = frame.point(checker.target_point(plan.states[s]));
      for (int i = 0; i < 3; ++i) scoop.push_back(static_cast<float>(v[i]));
    }
    if (st.collision) {
      Json list = Json::array();
      for (const PairContact& c : st.contacts) {
        Json tris = Json::array();
        for (const auto& [a, b] : c.triangles) tris.push_back(Json::array({a, b}));
        list.push_back({{"parts", {c.part_a, c.part_b}}, {"triangles", tris}});
      }
      contacts[std::to_string(s)] = list;
    }
  }
  p["chains"] = b64(chains);
  p["distance"] = dist;
  p["pair"] = pair;
  p["verdict"] = verdict;
  p["limit"] = limit;
  p["points"] = b64(points);
  p["contacts"] = contacts;
  if (!scoop.empty()) p["scoop_point"] = b64(scoop);
  if (plan.target) p["target"] = point_json(frame.point(*plan.target));
  p["tolerance"] = plan.tolerance / frame.unit;

  if (!r.segments.empty()) {
    Json lower = Json::array(), bad = Json::array();
    for (const SegmentResult& g : r.segments) {
      lower.push_back(g.checked ? num_json(g.lower_bound / frame.unit) : Json(nullptr));
      bad.push_back(g.checked && (g.collision || g.clearance || g.unresolved) ? 1 : 0);
    }
    p["segment_lower_bound"] = lower;
    p["segment_violation"] = bad;
  }
  if (!r.probes.empty()) {
    Json readings = Json::array();
    for (const auto& row : r.probes) {
      Json line = Json::array();
      for (const ProbeReading& pr : row) line.push_back(Json::array({pr.distance / frame.unit, pr.hit}));
      readings.push_back(line);
    }
    p["probes"] = readings;
    p["probe_targets"] = r.probe_targets;
  }
  return p;
}

}  // namespace

void write_report_html(const Checker& checker, const Scene& scene, const std::vector<PlanResult>& results,
                       const std::filesystem::path& dir, const ReportPageOptions& options) {
  Json report;
  {
    std::ifstream f(dir / "report.json");
    if (!f) fail(dir / "report.json", "cannot read (write_reports first)");
    report = Json::parse(f);
  }

  // The centre of the parts' reference boxes.
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Part& part : scene.parts)
    for (const Vec3& v : part.mesh.vertices) {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
  Frame frame;
  frame.unit = scene.length_scale;
  if (lo.allFinite() && hi.allFinite()) frame.centre = 0.5 * (lo + hi);

  Json page = {{"kind", "report"}, {"format", "plancheck-report-page/1"}, {"report", report}};
  page["length_unit"] = scene.length_unit;
  page["angle_unit"] = scene.angle_unit;
  page["safety_margin"] = scene.safety_margin / frame.unit;
  page["centre"] = point_json(frame.centre / frame.unit);
  page["parameter_names"] = scene.parameter_names;
  Json names = Json::array();
  for (std::size_t i = 0; i < checker.part_count(); ++i) names.push_back(checker.part_name(static_cast<int>(i)));
  page["checked_part_names"] = names;
  page["terrain_index"] = checker.terrain_index();
  Json nodes = Json::array();
  for (const Node& node : scene.nodes) nodes.push_back({{"name", node.name}, {"parent", node.parent}, {"part", node.part}});
  page["nodes"] = nodes;
  Json parts = Json::array();
  for (const Part& part : scene.parts) parts.push_back(part_json(scene, part, frame));
  page["parts"] = parts;
  page["chains"] = scene.chains.size();

  Json probes = Json::array();
  for (const ProbeConfig& pc : scene.probes) {
    Json dirs = Json::array();
    for (const Vec3& d : ProbeCaster::fan_directions(pc)) dirs.push_back(point_json(d));
    probes.push_back({{"name", pc.name}, {"part", pc.part_index}, {"origin", point_json(frame.point(pc.origin))},
                      {"directions", dirs}, {"max_range", pc.max_range / frame.unit}});
  }
  page["probes"] = probes;

  Json plans = Json::array();
  for (const PlanResult& r : results) plans.push_back(plan_json(checker, scene, r, frame));

  // The terrain as the DEM gives it, and per plan the samples each state dug.
  if (scene.terrain) {
    const Vec3 origin = scene.terrain->origin;
    std::unique_ptr<Digger> digger;
    Dem base;
    if (scene.scoop) {
      digger = std::make_unique<Digger>(scene);
      base = digger->undisturbed();
    } else {
      base = load_dem(scene.terrain->dem, scene.length_scale);
    }
    const SampleRect all{0, 0, base.ncols - 1, base.nrows - 1};
    page["terrain"] = {{"ncols", base.ncols}, {"nrows", base.nrows}, {"cellsize", base.cellsize / frame.unit},
                       {"x0", (origin.x() + base.x0 - frame.centre.x()) / frame.unit},
                       {"y0", (origin.y() + base.y0 - frame.centre.y()) / frame.unit},
                       {"z", rect_json(base, origin, frame, all)["z"]}};
    if (digger) {
      // The same walk as verify's (deterministic), recording what changed.
      Dem grid = base;
      for (std::size_t k = 0; k < results.size(); ++k) {
        if (!options.dig_carry) grid = base;
        Json start = nullptr;
        if (options.dig_carry) {
          const SampleRect d = difference(base, grid);
          if (!d.empty()) start = rect_json(grid, origin, frame, d);
        }
        Json steps = Json::array();
        std::vector<DigStep> unused;
        digger->dig_plan(results[k].plan->states, grid, unused,
                         [&](std::size_t s, const Dem& now, const SampleRect& changed) {
                           if (changed.empty()) return;
                           Json d = rect_json(now, origin, frame, changed);
                           d["state"] = s;
                           steps.push_back(std::move(d));
                         });
        plans[k]["dig_start"] = start;
        plans[k]["dig"] = steps;
      }
    }
  } else {
    page["terrain"] = nullptr;
  }
  page["plans"] = plans;

  write_html_page(dir / "report.html", "plancheck report: " + report.value("scene", std::string()), page.dump());
}

}  // namespace plancheck
