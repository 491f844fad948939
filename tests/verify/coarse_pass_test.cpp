// SPDX-License-Identifier: MIT
// A cold state's coarse pass (check_pairs) only seeds the exact pass and
// proves pairs beyond the best, which the exact pass then skips: neither may
// change the minimum. Against the pair-by-pair path (pose_parts,
// pair_collides, pair_distance: each checked pair searched exactly on its own,
// no coarse pass, no skip), on the default scene's cold states: the state's
// minimum is the smallest of the pairs' (within the tie tolerance), its pair
// is one of those within the tie tolerance of it, and its points are that far
// apart.
#include "src/checks/verify.h"
#include "src/scene/scene_loader.h"
#include "support/fixtures.h"
#include "support/sanitized.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace plancheck {
namespace {

namespace fs = std::filesystem;

const fs::path kDataset = fs::path(PLANCHECK_SOURCE_DIR) / "datasets/change5";

TEST(CoarsePass, ColdMinimumIsTheSmallestPairDistance) {
  const Scene scene = load_scene(kDataset / "scene.json");
  const Checker checker(scene);
  const auto pairs = checker.pairs();
  std::mt19937_64 rng(20261127);
  PosedParts posed;
  int apart = 0;
  const int n = testing::case_count(400, 40);
  for (int i = 0; i < n; ++i) {
    const std::vector<double> p = testing::random_state(scene, rng, i % 5 == 0 ? 0.2 : 0.0);
    const std::string at = "cold state " + std::to_string(i);
    StateResult got;
    checker.check_state(p, got, row_request());
    checker.pose_parts(p, posed);
    bool colliding = false;
    for (std::size_t k = 0; k < pairs.size(); ++k) colliding = colliding || checker.pair_collides(posed, k);
    ASSERT_EQ(got.collision, colliding) << at;
    if (colliding) continue;
    ++apart;
    std::vector<double> exact(pairs.size(), std::numeric_limits<double>::infinity());
    double smallest = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      PairAnswer a;
      checker.pair_distance(posed, k, std::numeric_limits<double>::infinity(), a);
      if (a.exact) exact[k] = a.distance;
      smallest = std::min(smallest, exact[k]);
    }
    ASSERT_TRUE(std::isfinite(smallest)) << at;
    EXPECT_NEAR(got.min_distance, smallest, 2 * kDistanceTieTolerance) << at;
    // The reported pair is within the tie tolerance of the minimum.
    bool pair_found = false;
    for (std::size_t k = 0; k < pairs.size(); ++k)
      if (pairs[k].first == got.part_a && pairs[k].second == got.part_b) {
        pair_found = true;
        EXPECT_LE(exact[k], smallest + 2 * kDistanceTieTolerance) << at;
      }
    EXPECT_TRUE(pair_found) << at;
    EXPECT_NEAR((got.point_a - got.point_b).norm(), got.min_distance, 1e-12) << at;
    if (HasFailure()) return;
  }
  // Enough states apart that the comparison means something.
  EXPECT_GT(apart, n / 2);
}


// One checked pair (a scene of two meshes, one moving: no coarse pass runs,
// there is nothing to order): the state's answer is still the pair's own
// exact search, on cold states near and far, and its points are that far
// apart.
TEST(CoarsePass, OnePairSceneMinimumIsThePairsDistance) {
  const testing::TempDir dir("one-pair");
  auto join = [](Mesh a, const Mesh& b) {
    const auto base = static_cast<std::uint32_t>(a.vertices.size());
    a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
    for (Tri t : b.triangles) a.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    return a;
  };
  // An L of two boxes (not convex) and a bar that moves and turns over it.
  const Mesh env = join(testing::box_mesh({-1, -1, -0.2}, {1, 1, 0}), testing::box_mesh({-1, -1, 0}, {-0.6, 1, 1}));
  const Mesh bar = join(testing::box_mesh({-0.5, -0.05, -0.05}, {0.5, 0.05, 0.05}), testing::box_mesh({0.4, -0.05, 0.05}, {0.5, 0.05, 0.4}));
  testing::write_obj(dir / "two.obj", {{"Env", env}, {"Bar", bar}});
  dir.write("scene.json", R"({"format": "plancheck-scene/1", "model": "two.obj", "length_unit": "m", "angle_unit": "deg",
    "actions": [{"name": "T", "node": "Bar", "type": "translate", "limits": [-1.5, 1.5]},
                {"name": "R", "node": "Bar", "type": "rotate", "pivot": [0, 0, 0], "axis": [0.3, 0.4, 1], "limits": [-180, 180]}]})");
  const Scene scene = load_scene(dir / "scene.json");
  const Checker checker(scene);
  ASSERT_EQ(checker.pairs().size(), 1u);
  std::mt19937_64 rng(20261128);
  PosedParts posed;
  int apart = 0;
  const int n = testing::case_count(400, 40);
  for (int i = 0; i < n; ++i) {
    const std::vector<double> p = testing::random_state(scene, rng, 0.0);
    const std::string at = "cold state " + std::to_string(i);
    StateResult got;
    checker.check_state(p, got, row_request());
    checker.pose_parts(p, posed);
    ASSERT_EQ(got.collision, checker.pair_collides(posed, 0)) << at;
    if (got.collision) continue;
    ++apart;
    PairAnswer a;
    checker.pair_distance(posed, 0, std::numeric_limits<double>::infinity(), a);
    ASSERT_TRUE(a.exact) << at;
    EXPECT_NEAR(got.min_distance, a.distance, 2 * kDistanceTieTolerance) << at;
    EXPECT_NEAR((got.point_a - got.point_b).norm(), got.min_distance, 1e-12) << at;
    if (HasFailure()) return;
  }
  EXPECT_GT(apart, n / 4);
}

}  // namespace
}  // namespace plancheck
