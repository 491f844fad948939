// SPDX-License-Identifier: MIT
// row_request (what a CSV row and the API's full check need) against the
// full request, state by state: the same collision flag, the same first
// colliding pair with the first triangle pair the full listing found, the
// same minimum distance, pair and points bit for bit, the same limits and
// guard; on the default scene's cold states (within limits and beyond) and
// along the default plans with each state seeding the next.
#include "src/checks/verify.h"
#include "src/scene/plan.h"
#include "src/scene/scene_loader.h"
#include "support/fixtures.h"
#include "support/sanitized.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <string>
#include <vector>

namespace plancheck {
namespace {

namespace fs = std::filesystem;

const fs::path kDataset = fs::path(PLANCHECK_SOURCE_DIR) / "datasets/change5";

struct Tally {
  int states = 0, colliding = 0;
};

void expect_same_row(const StateResult& row, const StateResult& full, const std::string& at, Tally& tally) {
  ++tally.states;
  ASSERT_EQ(row.collision, full.collision) << at;
  if (full.collision) {
    ++tally.colliding;
    ASSERT_EQ(row.contacts.size(), 1u) << at;
    EXPECT_EQ(row.contacts[0].part_a, full.contacts[0].part_a) << at;
    EXPECT_EQ(row.contacts[0].part_b, full.contacts[0].part_b) << at;
    ASSERT_EQ(row.contacts[0].triangles.size(), 1u) << at;
    EXPECT_EQ(row.contacts[0].triangles[0], full.contacts[0].triangles[0]) << at;
  } else {
    EXPECT_TRUE(row.contacts.empty()) << at;
  }
  EXPECT_EQ(row.min_distance, full.min_distance) << at;
  EXPECT_EQ(row.part_a, full.part_a) << at;
  EXPECT_EQ(row.part_b, full.part_b) << at;
  EXPECT_EQ(row.point_a, full.point_a) << at;
  EXPECT_EQ(row.point_b, full.point_b) << at;
  EXPECT_EQ(row.limit_action, full.limit_action) << at;
  EXPECT_EQ(row.distance_tolerance, full.distance_tolerance) << at;
  EXPECT_EQ(row.distance_is_bound, full.distance_is_bound) << at;
}

TEST(RowRequest, ColdStatesOfTheDefaultSceneGiveTheFullRow) {
  const Scene scene = load_scene(kDataset / "scene.json");
  const Checker checker(scene);
  std::mt19937_64 rng(20261127);
  Tally tally;
  const int n = testing::case_count(600, 60);
  for (int i = 0; i < n; ++i) {
    // Within limits, and every fifth state up to 20% beyond them.
    const std::vector<double> p = testing::random_state(scene, rng, i % 5 == 0 ? 0.2 : 0.0);
    StateResult full, row;
    checker.check_state(p, full);
    checker.check_state(p, row, row_request());
    expect_same_row(row, full, "cold state " + std::to_string(i), tally);
    if (HasFatalFailure()) return;
  }
  // Both kinds of state occurred: the comparison is not vacuous.
  EXPECT_GT(tally.colliding, 0);
  EXPECT_LT(tally.colliding, tally.states);
}

TEST(RowRequest, DefaultPlansGiveTheFullRowsWithSeeds) {
  const Scene scene = load_scene(kDataset / "scene.json");
  const Checker checker(scene);
  Tally tally;
  for (const auto& entry : fs::directory_iterator(kDataset / "plans")) {
    const Plan plan = load_plan(scene, entry.path());
    StateSeed seed_full, seed_row;
    const std::size_t step = testing::case_count(1, 7);
    for (std::size_t s = 0; s < plan.states.size(); s += step) {
      StateResult full, row;
      checker.check_state(plan.states[s], full, CheckRequest{}, &seed_full);
      checker.check_state(plan.states[s], row, row_request(), &seed_row);
      expect_same_row(row, full, plan.name + " state " + std::to_string(s), tally);
      if (HasFatalFailure()) return;
    }
  }
  EXPECT_GT(tally.states, 0);
}

}  // namespace
}  // namespace plancheck
