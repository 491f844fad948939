// SPDX-License-Identifier: MIT
#include "src/output/report_html.h"

#include "src/checks/dig.h"
#include "src/base/error.h"
#include "src/scene/kinematics.h"
#include "src/output/scene_page.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <numeric>
#include <optional>
#include <set>
#include <sstream>
#include <string>

namespace plancheck {

namespace {

using Json = PageJson;

constexpr float kNoValue = std::numeric_limits<float>::quiet_NaN();

// The samples where two grids differ (empty when equal).
SampleRect difference(const Dem& a, const Dem& b) {
  SampleRect out;
  for (int r = 0; r < a.nrows; ++r)
    for (int c = 0; c < a.ncols; ++c)
      if (a.height(c, r) != b.height(c, r)) out.add(SampleRect{c, r, c, r});
  return out;
}

// The terrain a plan digs, as the page replays it: per changed rectangle
// (state, c0, r0, c1, r1) its heights as steps from the undisturbed
// terrain, int8 (-128: no data) in units of the rectangle's own step
// (largest change / 127), so an unchanged sample stays exactly as it was
// (drawn, never judged; a fifth of the bytes of float32 heights).
class DigTrack {
 public:
  DigTrack(const Dem& base, const PageFrame& frame) : base_(base), frame_(frame) {}
  void add(std::int32_t state, const Dem& now, const SampleRect& r) {
    rects_.insert(rects_.end(), {state, r.c0, r.r0, r.c1, r.r1});
    double largest = 0.0;
    for (int row = r.r0; row <= r.r1; ++row)
      for (int c = r.c0; c <= r.c1; ++c)
        if (now.is_valid(c, row) && base_.is_valid(c, row))
          largest = std::max(largest, std::abs(now.height(c, row) - base_.height(c, row)));
    const double step = largest > 0.0 ? largest / 127.0 : 1.0;
    steps_.push_back(static_cast<float>(step / frame_.unit));
    for (int row = r.r0; row <= r.r1; ++row)
      for (int c = r.c0; c <= r.c1; ++c)
        dz_.push_back(now.is_valid(c, row) && base_.is_valid(c, row)
                          ? static_cast<std::int8_t>(std::lround((now.height(c, row) - base_.height(c, row)) / step))
                          : std::int8_t{-128});
  }
  bool empty() const { return rects_.empty(); }
  Json json() const {
    return {{"rects", ints_json(rects_)}, {"step", base64_array(steps_)}, {"dz", base64_array(dz_)}};
  }

 private:
  const Dem& base_;
  const PageFrame& frame_;
  std::vector<std::int32_t> rects_;
  std::vector<float> steps_;
  std::vector<std::int8_t> dz_;
};

// JSON text without the whitespace between its tokens (report.json is
// written indented: 2.7 times the bytes for 2,000 plans).
std::string minified(std::string_view json) {
  std::string out;
  out.reserve(json.size());
  bool in_string = false;
  for (std::size_t i = 0; i < json.size(); ++i) {
    const char c = json[i];
    if (in_string) {
      out += c;
      if (c == '\\' && i + 1 < json.size()) out += json[++i];
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
      out += c;
    } else if (c != ' ' && c != '\n' && c != '\r' && c != '\t') {
      out += c;
    }
  }
  return out;
}

// Parameters as float32 when every value keeps its pose within 1/4096 of a
// plan unit (float32 keeps 24 bits: values up to 2^11 in magnitude, the
// degrees, radians and metres of an arm); else float64. Half the bytes of
// a page of many plans.
bool params_fit_float32(const Plan& plan) {
  for (const auto& row : plan.states)
    for (double v : row)
      if (!(std::abs(v) <= 2048.0)) return false;
  return true;
}

// The scene's actions, for src/viewer/kinematics.js (geometry in metres).
Json actions_json(const Scene& scene) {
  Json out = Json::array();
  for (const Action& a : scene.actions) {
    const char* type = a.type == ActionType::kRotate          ? "rotate"
                       : a.type == ActionType::kTranslateAxis ? "translate_axis"
                       : a.type == ActionType::kTranslateFree ? "translate"
                                                              : "scale";
    out.push_back({{"name", a.name}, {"type", type}, {"pivot", point_json(a.pivot)}, {"axis", point_json(a.axis)},
                   {"fixed_point", point_json(a.fixed_point)}, {"unit_to_si", a.unit_to_si},
                   {"whole_turn", a.whole_turn}, {"first_parameter", a.first_parameter},
                   {"parameter_count", a.parameter_count}, {"mimic", a.mimic}, {"multiplier", a.multiplier},
                   {"offset", a.offset}});
  }
  return out;
}

// The states at which the page's own poses are compared with the checker's:
// the closest approach and, for a violating plan, the first violation.
std::vector<std::size_t> pose_check_states(const PlanResult& r) {
  std::set<std::size_t> s;
  if (!r.states.empty()) s.insert(std::min(r.min_distance_state, r.states.size() - 1));
  if (r.first_violation) {
    s.insert(r.first_violation->state);
    if (r.first_violation->between && r.first_violation->state + 1 < r.states.size())
      s.insert(r.first_violation->state + 1);
  }
  return {s.begin(), s.end()};
}

Json plan_json(const Scene& scene, const PlanResult& r, const PageFrame& frame, bool detail) {
  const Plan& plan = *r.plan;
  const std::size_t n = r.states.size();
  Json p;
  p["name"] = plan.name;
  p["detail"] = detail;
  // The values as the plan holds them, one row per state (posed in the page).
  if (params_fit_float32(plan)) {
    std::vector<float> v;
    v.reserve(n * scene.parameter_names.size());
    for (const auto& row : plan.states)
      for (double x : row) v.push_back(static_cast<float>(x));
    p["params_type"] = "f32";
    p["params"] = base64_array(v);
  } else {
    std::vector<double> v;
    for (const auto& row : plan.states) v.insert(v.end(), row.begin(), row.end());
    p["params_type"] = "f64";
    p["params"] = base64_array(v);
  }
  if (!plan.times.empty()) p["times"] = plan.times;

  // The checker's transforms where the page checks its own.
  {
    const std::vector<std::size_t> states = pose_check_states(r);
    std::vector<Affine> transforms;
    std::vector<float> t;
    for (std::size_t s : states) {
      chain_transforms(scene, plan.states[s], transforms);
      for (const Affine& a : transforms) frame.affine(a, t);
    }
    p["checker_poses"] = {{"states", states}, {"transforms", base64_array(t)}};
  }

  std::vector<float> dist(n);
  std::vector<std::uint8_t> verdict(n);
  for (std::size_t s = 0; s < n; ++s) {
    const StateResult& st = r.states[s];
    dist[s] = st.part_a >= 0 && std::isfinite(st.min_distance) ? static_cast<float>(st.min_distance / frame.unit)
                                                                : kNoValue;
    verdict[s] = static_cast<std::uint8_t>(state_verdict(st, scene.safety_margin));
  }
  p["distance"] = base64_array(dist);
  p["verdict"] = base64_array(verdict);
  if (plan.target) p["target"] = point_json(frame.point(*plan.target));
  p["tolerance"] = plan.tolerance / frame.unit;
  if (!detail) return p;

  std::vector<std::int32_t> pair;
  std::vector<float> points;
  pair.reserve(2 * n);
  points.reserve(6 * n);
  Json limit = Json::object(), contacts = Json::object();
  for (std::size_t s = 0; s < n; ++s) {
    const StateResult& st = r.states[s];
    pair.push_back(st.part_a);
    pair.push_back(st.part_b);
    for (const Vec3* q : {&st.point_a, &st.point_b}) {
      const Vec3 v = frame.point(*q);
      for (int i = 0; i < 3; ++i) points.push_back(st.part_a >= 0 ? static_cast<float>(v[i]) : kNoValue);
    }
    if (st.limit_action >= 0) limit[std::to_string(s)] = scene.actions[static_cast<std::size_t>(st.limit_action)].name;
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
  p["pair"] = ints_json(pair);
  p["points"] = quantized_json(points, 3);
  p["limit"] = limit;
  p["contacts"] = contacts;

  if (!r.segments.empty()) {
    std::vector<float> lower;
    std::vector<std::uint8_t> bad;
    for (const SegmentResult& g : r.segments) {
      lower.push_back(g.checked && std::isfinite(g.lower_bound) ? static_cast<float>(g.lower_bound / frame.unit)
                                                               : kNoValue);
      bad.push_back(g.checked && (g.collision || g.clearance || g.unresolved) ? 1 : 0);
    }
    p["segment_lower_bound"] = base64_array(lower);
    p["segment_violation"] = base64_array(bad);
  }
  if (!r.probes.empty()) {
    std::vector<float> distance;
    std::vector<std::int32_t> hit;
    for (const auto& row : r.probes)
      for (const ProbeReading& pr : row) {
        distance.push_back(static_cast<float>(pr.distance / frame.unit));
        hit.push_back(pr.hit);
      }
    p["probe_distance"] = quantized_json(distance, 1);
    p["probe_hit"] = ints_json(hit);
    p["probe_targets"] = r.probe_targets;
  }
  return p;
}

}  // namespace

HtmlPlanChoice parse_html_plans(std::string_view text) {
  HtmlPlanChoice out;
  if (text.empty()) throw InputError("--html-plans: empty (a count, or plan names separated by commas)");
  if (std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    if (text.size() > 9) throw InputError("--html-plans: " + std::string(text) + " is too large a count");
    out.closest = static_cast<std::size_t>(std::stoul(std::string(text)));
    return out;
  }
  std::size_t from = 0;
  while (true) {
    const std::size_t comma = text.find(',', from);
    const std::string_view name = text.substr(from, comma == std::string_view::npos ? std::string_view::npos : comma - from);
    if (name.empty()) throw InputError("--html-plans: an empty plan name in \"" + std::string(text) + "\"");
    out.names.emplace_back(name);
    if (comma == std::string_view::npos) break;
    from = comma + 1;
  }
  out.closest = 0;
  return out;
}

void check_html_plans(const HtmlPlanChoice& choice, const std::vector<Plan>& plans) {
  for (const std::string& name : choice.names)
    if (std::none_of(plans.begin(), plans.end(), [&](const Plan& p) { return p.name == name; }))
      throw InputError("--html-plans: no plan is named \"" + name + "\"");
}

std::vector<bool> html_detail_plans(const std::vector<PlanResult>& results, const HtmlPlanChoice& choice) {
  std::vector<bool> detail(results.size(), false);
  std::vector<std::size_t> others;
  for (std::size_t k = 0; k < results.size(); ++k) {
    const PlanResult& r = results[k];
    if (r.verdict != Verdict::kSafe ||
        std::find(choice.names.begin(), choice.names.end(), r.plan->name) != choice.names.end())
      detail[k] = true;
    else
      others.push_back(k);
  }
  // NaN (no distance) last.
  auto key = [&](std::size_t k) {
    const double d = results[k].min_distance;
    return std::isnan(d) ? std::numeric_limits<double>::infinity() : d;
  };
  std::stable_sort(others.begin(), others.end(), [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
  for (std::size_t i = 0; i < others.size() && i < choice.closest; ++i) detail[others[i]] = true;
  return detail;
}

void write_report_html(const Checker& checker, const Scene& scene, const std::vector<PlanResult>& results,
                       const std::filesystem::path& dir, const ReportPageOptions& options) {
  // report.json goes into the page as its text (it is JSON already).
  std::string report;
  {
    std::ifstream f(dir / "report.json", std::ios::binary);
    if (!f) fail(dir / "report.json", "cannot read (write_reports first)");
    std::ostringstream text;
    text << f.rdbuf();
    report = minified(text.str());
  }
  const PageFrame frame = page_frame(scene);
  const std::vector<bool> detail = html_detail_plans(results, options.plans);

  Json head = {{"kind", "report"}, {"format", "plancheck-report-page/2"}};
  head.update(scene_page_json(checker, scene, frame));
  head["actions"] = actions_json(scene);
  head["centre_m"] = point_json(frame.centre);
  head["unit_m"] = frame.unit;
  head["detail_rule"] = {{"closest", options.plans.closest}, {"names", options.plans.names}};

  std::string text = head.dump();
  text.pop_back();  // the closing brace: the report and the plans follow
  // The title's scene; the plans are skipped as they are read.
  const Json top = Json::parse(report, [](int depth, Json::parse_event_t, Json&) { return depth <= 1; });
  HtmlPageWriter page(dir / "report.html", "plancheck report: " + top.value("scene", std::string()));
  page.data(text);
  page.data(",\"report\":");
  page.data(report);
  report.clear();
  report.shrink_to_fit();
  page.data(",\"plans\":[");

  // Per plan with detail, the samples each state dug: the same walk as
  // verify's (deterministic), recording what changed. With --dig-carry
  // every plan digs from the terrain the previous ones left.
  std::optional<Digger> digger;
  std::optional<Dem> grid;
  if (scene.terrain && scene.scoop) {
    digger.emplace(scene);
    grid.emplace(digger->undisturbed());
  }
  // Map coordinates (the raster's CRS, map units) of the target and the
  // deepest scoop point, for the page to show beside the frame's.
  const bool map_frame = scene.terrain && !scene.terrain->grid->source.crs_wkt.empty();
  auto map_of = [&](const Vec3& p) {
    const Vec3 m = *map_point(*scene.terrain->grid, scene.terrain->origin, scene.length_scale, p);
    return Json::array({m.x(), m.y(), m.z()});
  };
  for (std::size_t k = 0; k < results.size(); ++k) {
    Json p = plan_json(scene, results[k], frame, detail[k]);
    if (map_frame) {
      const PlanResult& r = results[k];
      Json map = Json::object();
      if (r.plan->target) map["target"] = map_of(*r.plan->target);
      if (r.dig && r.dig->dug) map["deepest"] = map_of(r.dig->deepest_point);
      p["map"] = map;
    }
    if (digger && (detail[k] || options.dig_carry)) {
      const Dem& base = digger->undisturbed();
      if (!options.dig_carry) *grid = base;
      DigTrack start(base, frame), steps(base, frame);
      if (options.dig_carry && detail[k]) {
        const SampleRect d = difference(base, *grid);
        if (!d.empty()) start.add(-1, *grid, d);
      }
      std::vector<DigStep> unused;
      digger->dig_plan(results[k].plan->states, *grid, unused, [&](std::size_t s, const Dem& now, const SampleRect& changed) {
        if (!changed.empty() && detail[k]) steps.add(static_cast<std::int32_t>(s), now, changed);
      });
      if (detail[k]) {
        p["dig_start"] = start.empty() ? Json(nullptr) : start.json();
        p["dig"] = steps.json();
      }
    }
    if (k) page.data(",");
    page.data(p.dump());
  }
  page.data("]}");
  page.finish();
}

}  // namespace plancheck
