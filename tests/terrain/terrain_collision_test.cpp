// SPDX-License-Identifier: MIT
// The terrain as a static part: collision and minimum distance of a moving
// ball against a bumpy grid with a NODATA hole, against all-pairs brute force.
#include "src/scene_loader.h"
#include "src/terrain.h"
#include "src/verify.h"
#include "src/kinematics.h"

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

}  // namespace
}  // namespace plancheck
