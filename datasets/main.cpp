// SPDX-License-Identifier: MIT
// generate_change5 OUTDIR: writes the default dataset (change5.3ds,
// scene.json, site.asc, plans/plan01..10.csv, expected.json). Same bytes on
// every run: fixed seeds, no clock, no threads, fixed number formatting.
#include "datasets/change5.h"
#include "datasets/checker.h"
#include "datasets/plans.h"
#include "datasets/tds_writer.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

namespace fs = std::filesystem;
using nlohmann::ordered_json;

namespace plancheck::dataset {
namespace {

constexpr double kSafetyMargin = 0.05;
constexpr double kCheckCutoff = 0.10;  // distances above this are not needed
constexpr double kTolerance = 0.02;
constexpr const char* kJointNames[4] = {"J1", "J2", "J3", "J4"};

const std::vector<std::pair<std::string, std::string>> kAllowed{
    {"ArmJ1", "ArmMount"}, {"ArmJ2", "ArmJ1"}, {"ArmJ3", "ArmJ2"},
    {"ArmJ4", "ArmJ3"},    {"Scoop", "terrain"}, {"Scoop", "CanHandle"}};

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

void write_text(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out << text;
  if (!out) throw std::runtime_error(file.string() + ": write failed");
}

ordered_json vec(const Vec3& v) { return ordered_json::array({v.x(), v.y(), v.z()}); }

// Round to 6 decimals so scene.json shows short numbers.
Vec3 r6(const Vec3& v) {
  auto r = [](double x) { double y = std::round(x * 1e6) / 1e6; return y == 0.0 ? 0.0 : y; };
  return {r(v.x()), r(v.y()), r(v.z())};
}

ordered_json scene_json() {
  ordered_json s;
  s["format"] = "plancheck-scene/1";
  s["model"] = "change5.3ds";
  s["length_unit"] = "m";
  s["angle_unit"] = "deg";
  const Vec3 pivots[4] = {kShoulderPivot, kShoulderPivot, kElbowPivot, kWristPivot};
  const Vec3 axes[4] = {Vec3::UnitZ(), kPitchAxis, kPitchAxis, kPitchAxis};
  ordered_json actions = ordered_json::array();
  for (int k = 0; k < 4; ++k) {
    auto i = static_cast<std::size_t>(k);
    const std::string name = kJointNames[i];
    actions.push_back({{"name", name}, {"node", name}, {"type", "rotate"}, {"pivot", vec(pivots[i])},
                       {"axis", vec(axes[i])}, {"limits", {kLimits[i].lower, kLimits[i].upper}}});
  }
  s["actions"] = actions;
  ordered_json allowed = ordered_json::array();
  for (const auto& [a, b] : kAllowed) allowed.push_back({a, b});
  s["allowed_collisions"] = allowed;
  s["safety_margin"] = kSafetyMargin;
  s["terrain"] = {{"dem", "site.asc"}, {"origin", vec(kDemOrigin)}, {"collide", true}};
  s["scoop"] = {{"part", "Scoop"},
                {"bottom_point", vec(kScoopBottom)},
                {"width", 0.10},
                {"template", {{"pit", -1.0}, {"rim", 0.25}, {"rim_start", 0.7}}},
                {"capacity", 0.0008},
                {"bulk_density", 1240}};
  s["probes"] = ordered_json::array(
      {{{"name", "scoop_down"}, {"part", "Scoop"}, {"origin", vec(r6(kScoopBottom - Vec3(0, 0, 0.001)))},
        {"direction", {0, 0, -1}}, {"max_range", 3.0}},
       {{"name", "elbow_fan"}, {"part", "ArmJ3"}, {"origin", vec(r6(kElbowPivot + Vec3(0.10, 0, -0.06)))},
        {"direction", {0, 0, -1}}, {"fan", {{"count", 16}, {"half_angle", 40}}}, {"max_range", 2.5}}});
  return s;
}

std::string dem_text(const std::vector<double>& dem) {
  std::ostringstream out;
  out << "ncols " << kDemSize << "\nnrows " << kDemSize << "\nxllcorner 0.0\nyllcorner 0.0\ncellsize "
      << fmt("%.2f", kDemCell) << "\nNODATA_value -9999\n";
  for (int r = 0; r < kDemSize; ++r) {
    for (int c = 0; c < kDemSize; ++c) {
      if (c) out << ' ';
      out << fmt("%.4f", dem[static_cast<std::size_t>(r * kDemSize + c)]);
    }
    out << '\n';
  }
  return out.str();
}

std::string plan_text(const PlanOut& p, const Vec3& target) {
  std::ostringstream out;
  out << "# name: " << p.name << "\n# task: " << p.task << "\n# target: " << fmt("%.6f", target.x()) << ", "
      << fmt("%.6f", target.y()) << ", " << fmt("%.6f", target.z()) << "\n# tolerance: " << fmt("%.2f", kTolerance)
      << "\nJ1,J2,J3,J4\n";
  for (const Joints& q : p.states)
    out << fmt("%.6f", q[0]) << ',' << fmt("%.6f", q[1]) << ',' << fmt("%.6f", q[2]) << ',' << fmt("%.6f", q[3]) << '\n';
  return out.str();
}

// [[first, last], ...] runs of consecutive state numbers.
ordered_json ranges(const std::vector<int>& states) {
  ordered_json out = ordered_json::array();
  for (std::size_t i = 0; i < states.size();) {
    std::size_t j = i;
    while (j + 1 < states.size() && states[j + 1] == states[j] + 1) ++j;
    out.push_back({states[i], states[j]});
    i = j + 1;
  }
  return out;
}

ordered_json expect_plan(const Checker& checker, const PlanOut& p, const Vec3& target, bool& as_designed) {
  std::vector<int> collision, clearance, limits;
  double best = kCheckCutoff;
  int best_state = -1;
  std::pair<std::string, std::string> best_parts;
  ordered_json first = nullptr;
  std::set<std::pair<std::string, std::string>> colliding;
  for (std::size_t i = 0; i < p.states.size(); ++i) {
    const Joints& q = p.states[i];
    StateCheck c = checker.check(q);
    int state = static_cast<int>(i);
    if (c.min_distance < best) {
      best = c.min_distance;
      best_state = state;
      best_parts = {c.part_a, c.part_b};
    }
    bool over = false;
    for (std::size_t k = 0; k < 4; ++k) over = over || q[k] < kLimits[k].lower || q[k] > kLimits[k].upper;
    if (c.collision) {
      collision.push_back(state);
      colliding.insert(c.colliding.begin(), c.colliding.end());
    } else if (c.min_distance < kSafetyMargin) {
      clearance.push_back(state);
    }
    if (over) limits.push_back(state);
    if (first.is_null()) {
      if (c.collision) first = {{"state", state}, {"kind", "collision"}, {"parts", {c.colliding.begin()->first, c.colliding.begin()->second}}};
      else if (c.min_distance < kSafetyMargin) first = {{"state", state}, {"kind", "clearance"}, {"parts", {c.part_a, c.part_b}}};
      else if (over) first = {{"state", state}, {"kind", "limits"}};
    }
  }
  std::string verdict = first.is_null() ? "safe" : first["kind"].get<std::string>();
  as_designed = verdict == p.designed;
  ordered_json j;
  j["file"] = "plans/" + p.name + ".csv";
  j["task"] = p.task;
  j["states"] = p.states.size();
  j["verdict"] = verdict;
  j["first_violation"] = first;
  j["collision_states"] = ranges(collision);
  ordered_json pairs = ordered_json::array();
  for (const auto& [a, b] : colliding) pairs.push_back({a, b});
  j["colliding_parts"] = pairs;
  j["clearance_states"] = ranges(clearance);
  j["limit_states"] = ranges(limits);
  if (best_state >= 0) {
    j["min_distance"] = std::round(best * 1e6) / 1e6;
    j["min_distance_state"] = best_state;
    j["min_distance_parts"] = {best_parts.first, best_parts.second};
  } else {
    j["min_distance"] = nullptr;  // above the cutoff everywhere
    j["min_distance_state"] = nullptr;
    j["min_distance_parts"] = nullptr;
  }
  j["target"] = vec(target);
  j["tolerance"] = kTolerance;
  return j;
}

int run(const fs::path& out) {
  fs::create_directories(out / "plans");
  Model model = build_model();
  std::vector<TdsNode> nodes;
  for (const ModelNode& n : model.nodes) {
    TdsNode t{n.name, n.parent, {}};
    for (const Vec3& v : n.mesh.vertices)
      t.mesh.vertices.push_back({static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())});
    for (const Tri& f : n.mesh.triangles) t.mesh.faces.push_back({f[0], f[1], f[2]});
    if (t.mesh.vertices.size() > kTdsMaxObjectElements || t.mesh.faces.size() > kTdsMaxObjectElements)
      throw std::logic_error("part " + n.name + " is too big for one 3ds object; the contract wants one name per part");
    nodes.push_back(std::move(t));
  }
  tds_write(out / "change5.3ds", nodes);

  std::vector<double> dem = build_terrain();
  write_text(out / "site.asc", dem_text(dem));
  write_text(out / "scene.json", scene_json().dump(2) + "\n");

  Checker checker(model, dem, kAllowed, kCheckCutoff);
  std::vector<PlanOut> plans = build_plans(dem, checker);
  ordered_json expected;
  expected["format"] = "plancheck-expected/1";
  expected["note"] =
      "Computed by the generator: its own forward kinematics and an exact brute-force triangle distance "
      "(grid-pruned) on the float vertices of change5.3ds; the DEM as two triangles per square between cell "
      "centres. Distances above 'cutoff' are not computed (min_distance null). States next to a range boundary "
      "may differ by one in a verifier that triangulates the DEM differently.";
  expected["safety_margin"] = kSafetyMargin;
  expected["cutoff"] = kCheckCutoff;
  ordered_json tri_counts;
  tri_counts["lander"] = kLanderTriangles;
  tri_counts["ascender"] = kAscenderTriangles;
  for (std::size_t k = 0; k < 4; ++k) tri_counts[kJointNames[k]] = kJointTriangles[k];
  tri_counts["Scoop"] = kScoopTriangles;
  expected["triangles"] = tri_counts;
  {
    // The reference pose (all joints 0): which parts touch (the joint contacts
    // that allowed_collisions declares) and the closest pair otherwise.
    Checker bare(model, dem, {}, kCheckCutoff);
    StateCheck touching = bare.check(Joints{0, 0, 0, 0});
    StateCheck rest = checker.check(Joints{0, 0, 0, 0});
    ordered_json contacts = ordered_json::array();
    for (const auto& [a, b] : touching.colliding) contacts.push_back({a, b});
    ordered_json ref;
    ref["contacts"] = contacts;
    if (rest.part_a.empty()) {
      ref["min_distance"] = nullptr;
      ref["min_distance_parts"] = nullptr;
    } else {
      ref["min_distance"] = std::round(rest.min_distance * 1e6) / 1e6;
      ref["min_distance_parts"] = {rest.part_a, rest.part_b};
    }
    expected["reference_pose"] = ref;
  }
  ordered_json plans_json;
  bool all_as_designed = true;
  for (const PlanOut& p : plans) {
    Vec3 target = r6(scoop_bottom(p.states.back()));
    write_text(out / "plans" / (p.name + ".csv"), plan_text(p, target));
    bool ok = false;
    plans_json[p.name] = expect_plan(checker, p, target, ok);
    plans_json[p.name]["designed"] = p.designed;
    if (!ok) {
      std::cerr << "generate_change5: " << p.name << " was designed '" << p.designed << "' but checks as '"
                << plans_json[p.name]["verdict"].get<std::string>() << "'\n";
      all_as_designed = false;
    }
  }
  expected["plans"] = plans_json;
  write_text(out / "expected.json", expected.dump(2) + "\n");
  std::size_t triangles = 0, states = 0;
  for (const ModelNode& n : model.nodes) triangles += n.mesh.triangles.size();
  for (const PlanOut& p : plans) states += p.states.size();
  std::cout << "generate_change5: wrote " << out.string() << " (" << model.nodes.size() << " nodes, " << triangles
            << " triangles, " << plans.size() << " plans, " << states << " states)\n";
  return all_as_designed ? 0 : 3;
}

}  // namespace
}  // namespace plancheck::dataset

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: generate_change5 OUTDIR\n";
    return 2;
  }
  try {
    return plancheck::dataset::run(argv[1]);
  } catch (const std::exception& e) {
    std::cerr << "generate_change5: " << e.what() << "\n";
    return 2;
  }
}
