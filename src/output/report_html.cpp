// SPDX-License-Identifier: MIT
#include "src/output/report_html.h"

#include "src/checks/dig.h"
#include "src/base/error.h"
#include "src/scene/kinematics.h"
#include "src/output/scene_page.h"

#include <fstream>
#include <string>

namespace plancheck {

namespace {

using Json = PageJson;

// The samples where two grids differ (empty when equal).
SampleRect difference(const Dem& a, const Dem& b) {
  SampleRect out;
  for (int r = 0; r < a.nrows; ++r)
    for (int c = 0; c < a.ncols; ++c)
      if (a.height(c, r) != b.height(c, r)) out.add(SampleRect{c, r, c, r});
  return out;
}

Json plan_json(const Checker& checker, const Scene& scene, const PlanResult& r, const PageFrame& frame) {
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
    dist.push_back(st.part_a >= 0 ? number_or_null(st.min_distance / frame.unit) : Json(nullptr));
    pair.push_back(Json::array({st.part_a, st.part_b}));
    verdict.push_back(static_cast<int>(state_verdict(st, scene.safety_margin)));
    limit.push_back(st.limit_action >= 0 ? Json(scene.actions[static_cast<std::size_t>(st.limit_action)].name)
                                         : Json(nullptr));
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
  p["chains"] = base64_array(chains);
  p["distance"] = dist;
  p["pair"] = pair;
  p["verdict"] = verdict;
  p["limit"] = limit;
  p["points"] = base64_array(points);
  p["contacts"] = contacts;
  if (!scoop.empty()) p["scoop_point"] = base64_array(scoop);
  if (plan.target) p["target"] = point_json(frame.point(*plan.target));
  p["tolerance"] = plan.tolerance / frame.unit;

  if (!r.segments.empty()) {
    Json lower = Json::array(), bad = Json::array();
    for (const SegmentResult& g : r.segments) {
      lower.push_back(g.checked ? number_or_null(g.lower_bound / frame.unit) : Json(nullptr));
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
  const PageFrame frame = page_frame(scene);
  Json page = {{"kind", "report"}, {"format", "plancheck-report-page/1"}, {"report", report}};
  page.update(scene_page_json(checker, scene, frame));

  Json plans = Json::array();
  for (const PlanResult& r : results) {
    plans.push_back(plan_json(checker, scene, r, frame));
    // Map coordinates (the raster's CRS, map units) of the target and the
    // deepest scoop point, for a page to show beside the frame's.
    if (scene.terrain && !scene.terrain->grid->source.crs_wkt.empty()) {
      auto map_of = [&](const Vec3& p) {
        const Vec3 m = *map_point(*scene.terrain->grid, scene.terrain->origin, scene.length_scale, p);
        return Json::array({m.x(), m.y(), m.z()});
      };
      Json map = Json::object();
      if (r.plan->target) map["target"] = map_of(*r.plan->target);
      if (r.dig && r.dig->dug) map["deepest"] = map_of(r.dig->deepest_point);
      plans.back()["map"] = map;
    }
  }

  // Per plan, the samples each state dug: the same walk as verify's
  // (deterministic), recording what changed.
  if (scene.terrain && scene.scoop) {
    const Vec3 origin = scene.terrain->origin;
    const Digger digger(scene);
    const Dem& base = digger.undisturbed();
    Dem grid = base;
    for (std::size_t k = 0; k < results.size(); ++k) {
      if (!options.dig_carry) grid = base;
      Json start = nullptr;
      if (options.dig_carry) {
        const SampleRect d = difference(base, grid);
        if (!d.empty()) start = dem_rect_json(grid, origin, frame, d);
      }
      Json steps = Json::array();
      std::vector<DigStep> unused;
      digger.dig_plan(results[k].plan->states, grid, unused, [&](std::size_t s, const Dem& now, const SampleRect& changed) {
        if (changed.empty()) return;
        Json d = dem_rect_json(now, origin, frame, changed);
        d["state"] = s;
        steps.push_back(std::move(d));
      });
      plans[k]["dig_start"] = start;
      plans[k]["dig"] = steps;
    }
  }
  page["plans"] = plans;

  write_html_page(dir / "report.html", "plancheck report: " + report.value("scene", std::string()), page.dump());
}

}  // namespace plancheck
