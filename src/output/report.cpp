// SPDX-License-Identifier: MIT
#include "src/output/report.h"
#include "src/scene/terrain.h"

#include "src/base/error.h"
#include "src/base/files.h"
#include "src/base/text.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <map>
#include <ostream>
#include <string>

namespace plancheck {

namespace {

using Json = nlohmann::ordered_json;

std::string num(double v) { return csv_number(v); }

Json num_json(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

Json point_json(const Vec3& p, double unit) { return Json::array({p.x() / unit, p.y() / unit, p.z() / unit}); }


// Names on a terminal: escaped (text.h), whatever the model file holds.
std::string pair_text(const Checker& c, int a, int b) {
  if (a < 0) return "-";
  return printable(c.part_name(a)) + " / " + printable(c.part_name(b));
}

// A violation between states that is only the step budget running out
// (SegmentResult::unresolved, no witness): no pair was found closer.
bool uncertified(const PlanResult& r, const Violation& v) {
  return v.between && v.part_a < 0 && v.state < r.segments.size() && r.segments[v.state].unresolved;
}

std::string violation_text(const Checker& checker, const Scene& scene, const PlanResult& r) {
  if (!r.first_violation) return "none";
  const Violation& v = *r.first_violation;
  std::string s = std::string(verdict_name(v.kind)) +
                  (v.between ? " between states " + std::to_string(v.state) + " and " + std::to_string(v.state + 1)
                             : " at state " + std::to_string(v.state));
  if (v.part_a >= 0) s += " (" + pair_text(checker, v.part_a, v.part_b) + ")";
  if (v.action >= 0) s += " (" + printable(scene.actions[static_cast<std::size_t>(v.action)].name) + ")";
  if (uncertified(r, v))
    s += " (not certified: the motion needs more than " + std::to_string(r.segments[v.state].steps) +
         " pair checks)";
  if (v.kind == Verdict::kTarget && r.target_error)
    s += " (error " + num(*r.target_error / scene.length_scale) + " " + scene.length_unit + ")";
  return s;
}

}  // namespace

void print_plan_lines(const Checker& checker, const Scene& scene, const std::vector<PlanResult>& results,
                      const RunInfo& info, std::ostream& out) {
  std::size_t states = 0;
  std::size_t width = 4;
  for (const PlanResult& r : results) width = std::max(width, printable(r.plan->name).size());
  for (const PlanResult& r : results) {
    states += r.states.size();
    std::string name = printable(r.plan->name);
    name.resize(width, ' ');
    char head[64];
    std::snprintf(head, sizeof head, "%-9s %5zu states", verdict_name(r.verdict), r.states.size());
    // A verdict-only run's minimum may be a certified lower bound only.
    const bool bound = r.min_part_a < 0 && std::isfinite(r.min_distance);
    out << name << "  " << head << "  min " << (bound ? ">= " : "")
        << (r.min_part_a >= 0 || bound ? num(r.min_distance / scene.length_scale) : "-") << " " << scene.length_unit;
    if (r.min_part_a >= 0)
      out << " at state " << r.min_distance_state << " (" << pair_text(checker, r.min_part_a, r.min_part_b) << ")";
    out << "  first violation: " << violation_text(checker, scene, r);
    if (r.dig && r.dig->dug) {
      // Depth reached and mass collected: what an operator checks per scoop.
      char dig[160];
      std::snprintf(dig, sizeof dig, "  scoop: depth %.4g %s, collected %.4g kg (%.3g of capacity%s)",
                    r.dig->deepest / scene.length_scale, scene.length_unit.c_str(), r.dig->collected_mass,
                    scene.scoop->capacity > 0 ? r.dig->collected_volume / scene.scoop->capacity : 0.0,
                    r.dig->over_capacity ? ", more was dug" : "");
      out << dig;
    }
    out << "\n";
  }
  char tail[160];
  std::snprintf(tail, sizeof tail, "%zu plans, %zu states, %.3f s (load %.3f, build %.3f, check %.3f), %d threads\n",
                results.size(), states, info.load_seconds + info.build_seconds + info.check_seconds,
                info.load_seconds, info.build_seconds, info.check_seconds, info.threads);
  out << tail;
}

void write_atomically(const std::filesystem::path& path, const std::string& text) { write_file_atomically(path, text); }

std::string csv_field(std::string_view text) {
  const bool quote = text.find_first_of(",\"\r\n") != std::string_view::npos ||
                     (!text.empty() && (text.front() == ' ' || text.front() == '\t' || text.back() == ' ' ||
                                        text.back() == '\t'));
  if (!quote) return std::string(text);
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::string plan_csv_name(std::string_view plan_name) {
  std::string name(plan_name);
  for (char& c : name)
    if (c == '/' || c == '\\') c = '_';
  if (name.empty() || name.front() == '.') name.insert(name.begin(), '_');
  return name + ".csv";
}

void check_plan_csv_names(const std::vector<Plan>& plans) {
  std::map<std::string, const Plan*> seen;
  for (const Plan& p : plans) {
    const auto [at, fresh] = seen.emplace(plan_csv_name(p.name), &p);
    if (fresh) continue;
    const Plan& first = *at->second;
    fail(p.file, "writes the same report file " + at->first + " as " + first.file.string() +
                     (first.name == p.name ? " (both plans are named '" + p.name + "')"
                                           : " (plans named '" + first.name + "' and '" + p.name + "')") +
                     "; give one another '# name:'");
  }
}

// Distances carry 12 significant digits (the contract asks for at least 9).
std::string csv_number(double v) {
  if (!std::isfinite(v)) return "";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.12g", v);
  return buf;
}

void write_reports(const Checker& checker, const Scene& scene, const std::vector<PlanResult>& results,
                   const RunInfo& info, const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  const double unit = scene.length_scale;

  Json plans = Json::array();
  for (const PlanResult& r : results) {
    const Plan& plan = *r.plan;

    std::string csv = "state,collision,min_distance,part_a,part_b,ax,ay,az,bx,by,bz,limits";
    const bool probes = !r.probes.empty();
    const bool dig = r.dig.has_value();
    if (probes)
      for (const ProbeConfig& pc : scene.probes)
        csv.append(",").append(csv_field("probe:" + pc.name)).append(",").append(csv_field("probe:" + pc.name + ":hit"));
    if (dig) csv += ",scoop_depth,scoop_volume";
    // --continuous: the segment from this state to the next (empty on the last row).
    const bool segments = !r.segments.empty();
    if (segments)
      csv += ",segment_min_distance,segment_min_sampled,segment_collision,segment_clearance,segment_part_a,"
             "segment_part_b,segment_t,segment_steps";
    // --verdict-only: each state's verdict (min_distance may be a lower bound).
    if (info.verdict_only) csv += ",verdict";
    csv += "\n";
    const double unit3 = unit * unit * unit;
    for (std::size_t s = 0; s < r.states.size(); ++s) {
      const StateResult& st = r.states[s];
      csv += std::to_string(s) + "," + (st.collision ? "1" : "0") + ",";
      if (st.part_a >= 0) {
        csv += num(st.min_distance / unit) + "," + csv_field(checker.part_name(st.part_a)) + "," +
               csv_field(checker.part_name(st.part_b));
        for (const Vec3* p : {&st.point_a, &st.point_b})
          for (int i = 0; i < 3; ++i) csv.append(",").append(num((*p)[i] / unit));  // append: no GCC 12 -Wrestrict false alarm
      } else if (st.distance_is_bound) {
        csv += num(st.min_distance / unit) + ",,,,,,,,";
      } else {
        csv += ",,,,,,,,";
      }
      csv += ",";
      if (st.limit_action >= 0) csv += csv_field(scene.actions[static_cast<std::size_t>(st.limit_action)].name);
      if (probes)
        for (const ProbeReading& pr : r.probes.at(s)) {
          csv.append(",").append(num(pr.distance / unit)).append(",");
          if (pr.hit >= 0) csv.append(csv_field(r.probe_targets.at(static_cast<std::size_t>(pr.hit))));
        }
      if (dig) csv.append(",").append(num(r.dig_steps.at(s).depth / unit)).append(",").append(num(r.dig_steps.at(s).volume / unit3));
      if (segments) {
        const SegmentResult& g = r.segments.at(s);
        if (g.checked) {
          csv.append(",").append(num(g.lower_bound / unit)).append(",").append(num(g.min_sampled / unit));
          csv.append(g.collision ? ",1" : ",0").append(g.clearance ? ",1" : ",0").append(",");
          if (g.part_a >= 0)
            csv.append(csv_field(checker.part_name(g.part_a))).append(",").append(csv_field(checker.part_name(g.part_b)));
          else csv.append(",");
          csv.append(",").append(g.witness_t >= 0.0 ? num(g.witness_t) : "").append(",").append(std::to_string(g.steps));
        } else {
          csv += ",,,,,,,,";
        }
      }
      if (info.verdict_only) csv.append(",").append(verdict_name(state_verdict(st, scene.safety_margin)));
      csv += "\n";
    }
    write_atomically(dir / plan_csv_name(plan.name), csv);

    Json collisions = Json::array();
    for (std::size_t s = 0; s < r.states.size() && collisions.size() < kMaxCollisionStatesListed; ++s) {
      const StateResult& st = r.states[s];
      if (!st.collision) continue;
      Json pairs = Json::array();
      for (const PairContact& c : st.contacts) {
        Json tris = Json::array();
        for (std::size_t k = 0; k < c.triangles.size() && k < kMaxTrianglePairsListed; ++k)
          tris.push_back(Json::array({c.triangles[k].first, c.triangles[k].second}));
        pairs.push_back({{"parts", {checker.part_name(c.part_a), checker.part_name(c.part_b)}}, {"triangles", tris}});
      }
      collisions.push_back({{"state", s}, {"pairs", pairs}});
    }

    Json first = nullptr;
    if (r.first_violation) {
      const Violation& v = *r.first_violation;
      first = {{"state", v.state}, {"kind", verdict_name(v.kind)}};
      if (v.part_a >= 0) first["parts"] = {checker.part_name(v.part_a), checker.part_name(v.part_b)};
      if (v.action >= 0) first["action"] = scene.actions[static_cast<std::size_t>(v.action)].name;
      if (v.between) first["between"] = true;
      if (uncertified(r, v)) first["uncertified"] = true;
    }

    Json p = {{"name", plan.name},
              {"file", plan.file.string()},
              {"csv", plan_csv_name(plan.name)},
              {"states", r.states.size()},
              {"verdict", verdict_name(r.verdict)},
              {"first_violation", first}};
    const bool has_min = r.min_part_a >= 0;
    // --verdict-only: the plan's minimum may be a certified lower bound (no parts, no points).
    const bool min_bound = !has_min && std::isfinite(r.min_distance);
    p["min_distance"] = has_min || min_bound ? num_json(r.min_distance / unit) : Json(nullptr);
    p["min_distance_state"] = has_min || min_bound ? Json(r.min_distance_state) : Json(nullptr);
    if (info.verdict_only) p["min_distance_is_bound"] = min_bound;
    p["min_distance_parts"] =
        has_min ? Json::array({checker.part_name(r.min_part_a), checker.part_name(r.min_part_b)}) : Json(nullptr);
    p["min_distance_points"] =
        has_min ? Json::array({point_json(r.min_point_a, unit), point_json(r.min_point_b, unit)}) : Json(nullptr);
    p["collisions"] = collisions;
    p["target_error"] = r.target_error ? Json(*r.target_error / unit) : Json(nullptr);
    if (probes) {
      // Per probe: the shortest reading over the plan (first state on ties).
      Json list = Json::array();
      for (std::size_t k = 0; k < scene.probes.size(); ++k) {
        std::size_t best = 0;
        for (std::size_t s = 1; s < r.probes.size(); ++s)
          if (r.probes[s][k].distance < r.probes[best][k].distance) best = s;
        const ProbeReading& pr = r.probes[best][k];
        list.push_back({{"name", scene.probes[k].name},
                        {"min_distance", pr.distance / unit},
                        {"state", best},
                        {"hit", pr.hit >= 0 ? Json(r.probe_targets[static_cast<std::size_t>(pr.hit)]) : Json(nullptr)}});
      }
      p["probes"] = list;
    }
    if (dig) {
      const DigSummary& d = *r.dig;
      p["scoop"] = {{"model", d.model},
                    {"dug", d.dug},
                    {"dug_volume", d.dug_volume / unit3},
                    {"collected_volume", d.collected_volume / unit3},
                    {"collected_mass_kg", d.collected_mass},
                    {"capacity", scene.scoop->capacity / unit3},
                    {"over_capacity", d.over_capacity},
                    {"spilled_volume", d.spilled_volume / unit3},
                    {"deepest", {{"depth", d.deepest / unit}, {"state", d.deepest_state},
                                 {"point", point_json(d.deepest_point, unit)}}}};
    }
    p["seconds"] = r.seconds;
    plans.push_back(p);
  }

  Json report = {{"format", "plancheck-report/1"},
                 {"scene", info.scene_arg.string()},
                 {"length_unit", scene.length_unit},
                 {"safety_margin", scene.safety_margin / unit},
                 {"threads", info.threads},
                 {"left_out", {{"static_triangles", info.left_out_static_triangles},
                               {"reason", "beyond reach of the moving parts"}}},
                 {"plans", plans},
                 {"seconds", {{"load", info.load_seconds}, {"build", info.build_seconds}, {"check", info.check_seconds}}}};
  if (scene.terrain && scene.terrain->grid) {
    // The part of the raster that was read (docs/terrain-gdal.md): pixels
    // as GDAL counts them (column, row from the north-west corner, 0-based),
    // the extent in map units.
    const Dem& g = *scene.terrain->grid;
    const auto e = window_extent(g);
    report["terrain"] = {{"dem", g.source.file.string()},
                         {"driver", g.source.driver},
                         {"band", g.source.band},
                         {"raster_pixels", {g.source.raster_cols, g.source.raster_rows}},
                         {"window", {{"pixels", {g.source.col_off, g.source.row_off, g.ncols, g.nrows}},
                                     {"whole", g.source.whole},
                                     {"map_extent", {e[0], e[1], e[2], e[3]}}}}};
  }
  if (info.continuous_tolerance > 0.0) {
    report["continuous"] = {{"tolerance", info.continuous_tolerance / unit},
                            {"contact_tolerance", info.contact_tolerance / unit}};
    report["seconds"]["continuous"] = info.continuous_seconds;
  }
  if (info.verdict_only) report["verdict_only"] = true;
  if (info.ranks > 0) {
    // Under mpirun: how the work was spread (timing-like fields, like "threads").
    report["ranks"] = info.ranks;
    report["hosts"] = info.hosts;
    Json chunks = Json::array();
    for (const ChunkSeconds& c : info.chunks) chunks.push_back({{"rank", c.rank}, {"items", {c.begin, c.end}}, {"seconds", c.seconds}});
    report["seconds"]["chunks"] = chunks;
  }
  // Names are checked UTF-8 where they are read; a path (the scene's, the
  // plans') need not be, and is written with U+FFFD for what is not.
  write_atomically(dir / "report.json", report.dump(2, ' ', false, Json::error_handler_t::replace) + "\n");
}

}  // namespace plancheck
