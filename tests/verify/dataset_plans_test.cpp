// SPDX-License-Identifier: MIT
// The default dataset's ten plans through the real verifier, against what the
// generator designed (datasets/change5/expected.json, computed there with its
// own kinematics and a brute-force distance): verdicts, first violations, the
// exact sets of colliding, too-close and out-of-limits states.
#include "src/scene/plan.h"
#include "src/scene/scene_loader.h"
#include "src/checks/verify.h"
#include "src/checks/built_ahead.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <set>

namespace plancheck {
namespace {

const std::filesystem::path kDir = std::filesystem::path(PLANCHECK_SOURCE_DIR) / "datasets/change5";

std::set<std::size_t> states_in(const nlohmann::json& ranges) {
  std::set<std::size_t> s;
  for (const auto& r : ranges)
    for (std::size_t i = r[0].get<std::size_t>(); i <= r[1].get<std::size_t>(); ++i) s.insert(i);
  return s;
}

TEST(DatasetPlans, VerdictsAndViolatingStatesAreTheDesignedOnes) {
  ASSERT_TRUE(std::filesystem::exists(kDir / "expected.json")) << "run `make dataset` first";
  std::ifstream f(kDir / "expected.json");
  const auto expected = nlohmann::json::parse(f);
  const Scene scene = load_scene(kDir / "scene.json");
  std::vector<Plan> plans;
  std::vector<std::string> names;
  for (const auto& [name, e] : expected["plans"].items()) {
    plans.push_back(load_plan(scene, kDir / e["file"].get<std::string>()));
    names.push_back(name);
  }
  ASSERT_EQ(plans.size(), 10u);
  const Checker checker(scene);
  const auto results = verify_plans(checker, scene, plans, VerifyOptions{});

  int safe = 0;
  std::set<std::string> kinds;
  for (std::size_t p = 0; p < plans.size(); ++p) {
    SCOPED_TRACE(names[p]);
    const auto& e = expected["plans"][names[p]];
    const PlanResult& r = results[p];
    EXPECT_EQ(r.states.size(), e["states"].get<std::size_t>());
    EXPECT_EQ(verdict_name(r.verdict), e["verdict"].get<std::string>());
    kinds.insert(verdict_name(r.verdict));
    if (r.verdict == Verdict::kSafe) ++safe;
    if (e["first_violation"].is_null()) {
      EXPECT_FALSE(r.first_violation.has_value());
    } else {
      ASSERT_TRUE(r.first_violation.has_value());
      EXPECT_EQ(r.first_violation->state, e["first_violation"]["state"].get<std::size_t>());
    }
    const double margin = scene.safety_margin;
    std::set<std::size_t> collide, close, limits;
    for (std::size_t s = 0; s < r.states.size(); ++s) {
      const StateResult& st = r.states[s];
      if (st.collision) collide.insert(s);
      else if (st.min_distance < margin) close.insert(s);
      if (st.limit_action >= 0) limits.insert(s);
      for (const PairContact& c : st.contacts) {
        bool listed = false;
        for (const auto& pair : e["colliding_parts"])
          listed |= pair[0] == checker.part_name(c.part_a) && pair[1] == checker.part_name(c.part_b);
        EXPECT_TRUE(listed) << "state " << s << ": " << checker.part_name(c.part_a) << " / "
                            << checker.part_name(c.part_b);
      }
    }
    EXPECT_EQ(collide, states_in(e["collision_states"]));
    EXPECT_EQ(close, states_in(e["clearance_states"]));
    EXPECT_EQ(limits, states_in(e["limit_states"]));
    if (!e["min_distance"].is_null()) {
      EXPECT_NEAR(r.min_distance, e["min_distance"].get<double>(), 1e-6);
    }
    ASSERT_TRUE(r.target_error.has_value());
    EXPECT_LE(*r.target_error, plans[p].tolerance);
  }
  // The dataset must keep exercising every kind of verdict it was made for.
  EXPECT_GE(safe, 5);
  EXPECT_EQ(kinds, (std::set<std::string>{"safe", "collision", "clearance", "limits"}));
}

int subtree_triangles(const Scene& scene, int node) {
  const Node& n = scene.nodes[static_cast<std::size_t>(node)];
  int t = n.part >= 0 ? static_cast<int>(scene.parts[static_cast<std::size_t>(n.part)].mesh.triangles.size()) : 0;
  for (int c : n.children) t += subtree_triangles(scene, c);
  return t;
}

// The collision structures built while the model loads (BuiltAhead, run to
// the end here; how far it gets in a run depends on the import's time) are
// the ones the checker builds itself: with them and without them, every
// state of three plans gets the same answer, bit for bit, probes included.
TEST(DatasetPlans, StructuresBuiltAheadChangeNoAnswer) {
  ASSERT_TRUE(std::filesystem::exists(kDir / "scene.json")) << "run `make dataset` first";
  const Scene scene = load_scene(kDir / "scene.json");
  BuiltAhead ahead;
  const std::atomic<bool> go_on{false};
  ahead.build(scene.model_file, scene.length_scale, go_on);
  // Every part of the default scene is one drawn object: each has one.
  std::size_t matched = 0;
  for (const Part& part : scene.parts) matched += ahead.find(part.mesh) != nullptr ? 1 : 0;
  EXPECT_EQ(matched, scene.parts.size());
  std::vector<Plan> plans;
  for (const char* name : {"plan01.csv", "plan04.csv", "plan07.csv"})
    plans.push_back(load_plan(scene, kDir / "plans" / name));
  const Checker with(scene, 2, &ahead), without(scene, 2);
  const auto a = verify_plans(with, scene, plans, VerifyOptions{});
  const auto b = verify_plans(without, scene, plans, VerifyOptions{});
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t p = 0; p < a.size(); ++p) {
    EXPECT_EQ(a[p].verdict, b[p].verdict);
    EXPECT_EQ(a[p].min_distance, b[p].min_distance);
    ASSERT_EQ(a[p].states.size(), b[p].states.size());
    for (std::size_t s = 0; s < a[p].states.size(); ++s) {
      const StateResult& x = a[p].states[s];
      const StateResult& y = b[p].states[s];
      ASSERT_EQ(x.collision, y.collision) << "state " << s;
      ASSERT_EQ(x.min_distance, y.min_distance) << "state " << s;
      ASSERT_EQ(x.part_a, y.part_a) << "state " << s;
      ASSERT_EQ(x.part_b, y.part_b) << "state " << s;
      ASSERT_EQ(x.point_a, y.point_a) << "state " << s;
      ASSERT_EQ(x.contacts.size(), y.contacts.size()) << "state " << s;
      for (std::size_t c = 0; c < x.contacts.size(); ++c) EXPECT_EQ(x.contacts[c].triangles, y.contacts[c].triangles);
    }
    ASSERT_EQ(a[p].probes.size(), b[p].probes.size());
    for (std::size_t s = 0; s < a[p].probes.size(); ++s)
      for (std::size_t q = 0; q < a[p].probes[s].size(); ++q) {
        EXPECT_EQ(a[p].probes[s][q].distance, b[p].probes[s][q].distance);
        EXPECT_EQ(a[p].probes[s][q].hit, b[p].probes[s][q].hit);
      }
  }
  EXPECT_EQ(with.triangle_count(), without.triangle_count());
  EXPECT_EQ(with.memory_bytes(), without.memory_bytes());
}

TEST(DatasetPlans, LoaderReadsTheFigure9HierarchyWithTable2Counts) {
  const Scene scene = load_scene(kDir / "scene.json");
  auto node = [&](const std::string& name) {
    for (std::size_t i = 0; i < scene.nodes.size(); ++i)
      if (scene.nodes[i].name == name) return static_cast<int>(i);
    ADD_FAILURE() << "no node " << name;
    return 0;
  };
  auto parent = [&](const std::string& name) {
    return scene.nodes[static_cast<std::size_t>(scene.nodes[static_cast<std::size_t>(node(name))].parent)].name;
  };
  // root -> {probe -> {lander, ascender}, arm -> J1 -> J2 -> J3 -> J4}
  EXPECT_EQ(parent("lander"), "probe");
  EXPECT_EQ(parent("ascender"), "probe");
  EXPECT_EQ(parent("probe"), parent("arm"));
  EXPECT_EQ(parent("J1"), "arm");
  EXPECT_EQ(parent("J2"), "J1");
  EXPECT_EQ(parent("J3"), "J2");
  EXPECT_EQ(parent("J4"), "J3");
  EXPECT_EQ(parent("Scoop"), "J4");
  // Table 2 (each within 1%; the generator hits them exactly).
  EXPECT_EQ(subtree_triangles(scene, node("lander")), 268730);
  EXPECT_EQ(subtree_triangles(scene, node("ascender")), 120676);
  EXPECT_EQ(scene.parts[static_cast<std::size_t>(scene.find_part("ArmJ1"))].mesh.triangles.size(), 5970u);
  EXPECT_EQ(scene.parts[static_cast<std::size_t>(scene.find_part("ArmJ2"))].mesh.triangles.size(), 8723u);
  EXPECT_EQ(scene.parts[static_cast<std::size_t>(scene.find_part("ArmJ3"))].mesh.triangles.size(), 8952u);
  EXPECT_EQ(scene.parts[static_cast<std::size_t>(scene.find_part("ArmJ4"))].mesh.triangles.size(), 7060u);
  EXPECT_EQ(scene.parts[static_cast<std::size_t>(scene.find_part("Scoop"))].mesh.triangles.size(), 2164u);
  EXPECT_EQ(subtree_triangles(scene, 0), 422275);
  // The four joints move the scoop: its chain is J1 > J2 > J3 > J4.
  const Part& scoop = scene.parts[static_cast<std::size_t>(scene.find_part("Scoop"))];
  ASSERT_EQ(scoop.chain.size(), 4u);
  for (int k = 0; k < 4; ++k) EXPECT_EQ(scene.actions[static_cast<std::size_t>(scoop.chain[static_cast<std::size_t>(k)])].name, "J" + std::to_string(k + 1));
}

}  // namespace
}  // namespace plancheck
