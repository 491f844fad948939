// SPDX-License-Identifier: MIT
// The terrain as a static part: collision and minimum distance of a moving
// ball against a bumpy grid with a NODATA hole, against all-pairs brute force.
#include "src/scene/scene_loader.h"
#include "src/scene/terrain.h"
#include "src/checks/verify.h"
#include "src/scene/kinematics.h"
#include "src/scene/plan.h"

#include "tests/support/brute_force.h"
#include "tests/support/fixtures.h"
#include "tests/support/test_meshes.h"

#include <gtest/gtest.h>

#include <random>
#include <string>

namespace plancheck {
namespace {

TEST(TerrainCollision, BallAgainstBumpyGridMatchesBruteForce) {
  testing::TempDir dir("terrain_collision");
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::string dem = "ncols 12\nnrows 12\nxllcorner 0\nyllcorner 0\ncellsize 0.1\nNODATA_value -9999\n";
  for (int r = 0; r < 12; ++r) {
    for (int c = 0; c < 12; ++c) {
      if (c) dem += " ";
      dem += (r == 4 && c == 6) ? std::string("-9999") : std::to_string(0.2 * u(rng));
    }
    dem += "\n";
  }
  testing::write_text(dir / "site.asc", dem);
  testing::write_obj(dir / "m.obj", {{"Ball", testing::make_sphere(Vec3(0.55, 0.55, 0.4), 0.15, 8, 12)}});
  testing::write_text(dir / "s.json", R"({"format": "plancheck-scene/1", "model": "m.obj",
      "actions": [{"name": "T", "node": "Ball", "type": "translate"}],
      "terrain": {"dem": "site.asc", "origin": [0, 0, 0], "collide": true}})");
  const Scene scene = load_scene(dir / "s.json");
  const Checker checker(scene, 2);
  ASSERT_EQ(checker.part_name(static_cast<int>(checker.part_count()) - 1), "terrain");
  const Mesh terrain = dem_mesh(load_dem(dir / "site.asc", 1.0), Vec3::Zero());
  const int ball = scene.find_part("Ball");
  int collisions = 0, clear = 0;
  for (int k = 0; k < 150; ++k) {
    const std::vector<double> params{0.6 * u(rng) - 0.3, 0.6 * u(rng) - 0.3, -0.45 * u(rng) + 0.1};
    StateResult out;
    checker.check_state(params, out);
    const Mesh& m = scene.parts[static_cast<std::size_t>(ball)].mesh;
    const auto vb = testing::posed_vertices(m, part_transform(scene, ball, params));
    const bool expect = !testing::brute_force_collide(m, vb, terrain, terrain.vertices, true).empty();
    ASSERT_EQ(out.collision, expect) << k;
    if (expect) {
      ++collisions;
      EXPECT_EQ(checker.part_name(out.contacts[0].part_b), "terrain");
      EXPECT_EQ(out.min_distance, 0.0);
    } else {
      ++clear;
      const auto ref = testing::brute_force_distance(m, vb, terrain, terrain.vertices);
      EXPECT_NEAR(out.min_distance, ref.distance, 1e-9) << k;
    }
  }
  EXPECT_GT(collisions, 20);  // both outcomes are exercised
  EXPECT_GT(clear, 20);
}

// The scoop digs a pit 5 cm deep on flat ground; the template's rim rises
// 12.5 mm at 8.5 cm from M, under a Foot hovering 5 mm above the ground
// there. verify_plans sees Foot meet the rim from the digging state on (and
// a probe read the pit); the undisturbed terrain never shows either.
TEST(TerrainCollision, PartsMeetTheRimAndProbesReadThePitTheScoopDigs) {
  testing::TempDir dir("terrain_rim");
  std::string dem = "ncols 40\nnrows 40\nxllcorner 0\nyllcorner 0\ncellsize 0.01\n";
  for (int r = 0; r < 40; ++r) {
    for (int c = 0; c < 40; ++c) dem += c ? " 0.1" : "0.1";
    dem += "\n";
  }
  testing::write_text(dir / "site.asc", dem);
  testing::write_obj(dir / "m.obj",
                     {{"Scoop", testing::box_mesh(Vec3(0.19, 0.19, 0.3), Vec3(0.21, 0.21, 0.35))},
                      {"Foot", testing::box_mesh(Vec3(0.28, 0.195, 0.105), Vec3(0.29, 0.205, 0.115))}});
  testing::write_text(dir / "s.json", R"({"format": "plancheck-scene/1", "model": "m.obj",
      "actions": [{"name": "S", "node": "Scoop", "type": "translate"},
                  {"name": "F", "node": "Foot", "type": "translate"}],
      "allowed_collisions": [["Scoop", "terrain"]],
      "terrain": {"dem": "site.asc", "origin": [0, 0, 0], "collide": true},
      "scoop": {"part": "Scoop", "bottom_point": [0.2, 0.2, 0.3], "width": 0.1,
                "template": {"pit": -1.0, "rim": 0.25, "rim_start": 0.7}, "capacity": 1, "bulk_density": 1240},
      "probes": [{"name": "down", "part": "Foot", "origin": [0.2, 0.2, 0.2], "direction": [0, 0, -1],
                  "max_range": 1.0}]})");
  const Scene scene = load_scene(dir / "s.json");
  const Checker checker(scene, 2);
  ASSERT_TRUE(checker.terrain_is_dug());
  Plan plan;
  plan.name = "dig";
  plan.states = {{0, 0, 0, 0, 0, 0}, {0, 0, -0.25, 0, 0, 0}, {0, 0, 0, 0, 0, 0}};  // above, in the soil, out again
  const std::vector<Plan> plans{plan};
  for (bool carry : {false, true}) {
    SCOPED_TRACE(carry);
    const auto results = verify_plans(checker, scene, plans, VerifyOptions{2, carry});
    const PlanResult& r = results[0];
    ASSERT_EQ(r.states.size(), 3u);
    EXPECT_FALSE(r.states[0].collision);
    EXPECT_NEAR(r.states[0].min_distance, 0.005, 1e-6);  // the OBJ holds 7 digits
    EXPECT_EQ(checker.part_name(r.states[0].part_b), "terrain");
    for (std::size_t s : {1u, 2u}) {
      ASSERT_TRUE(r.states[s].collision) << s;
      EXPECT_EQ(checker.part_name(r.states[s].contacts.back().part_a), "Foot");
      EXPECT_EQ(checker.part_name(r.states[s].contacts.back().part_b), "terrain");
      EXPECT_EQ(r.states[s].min_distance, 0.0);
    }
    EXPECT_EQ(r.verdict, Verdict::kCollision);
    ASSERT_TRUE(r.first_violation);
    EXPECT_EQ(r.first_violation->state, 1u);
    // The probe above M: 10 cm to the ground, then 15 cm into the pit.
    ASSERT_EQ(r.probes.size(), 3u);
    EXPECT_NEAR(r.probes[0][0].distance, 0.1, 1e-6);
    EXPECT_NEAR(r.probes[1][0].distance, 0.15, 1e-6);
    EXPECT_NEAR(r.probes[2][0].distance, 0.15, 1e-6);
  }
  // Against the undisturbed terrain (check_state, or verify without the dig pass) Foot stays clear.
  StateResult undisturbed;
  checker.check_state(plan.states[1], undisturbed);
  EXPECT_FALSE(undisturbed.collision);
  const auto plain = verify_plans(checker, scene, plans, VerifyOptions{2, false, false});
  EXPECT_EQ(plain[0].verdict, Verdict::kSafe);
}

}  // namespace
}  // namespace plancheck
