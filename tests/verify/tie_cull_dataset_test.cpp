// SPDX-License-Identifier: MIT
// The tie cull of the distance search (DistanceRequest::tie_cull) on the
// default scene's own tie: the arm's base (ArmJ1) over the deck (TopDeck),
// parallel faces 0.11 m apart, along every state of the ten plans, each
// search seeded from the previous state's answer as a plan's states seed
// each other, with the tie tolerance and with the previous distance as the
// upper bound, either part as a. (Every other state: neighbours 2 apart
// still share the tie.) Against the search without the cull: the same answer bit for
// bit; and the cull at work on most states.
#include "src/checks/verify.h"
#include "src/geometry/collision_model.h"
#include "src/scene/kinematics.h"
#include "src/scene/plan.h"
#include "src/scene/scene_loader.h"
#include "support/same_answer.h"
#include "support/sanitized.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <utility>
#include <string>

namespace plancheck {
namespace {

namespace fs = std::filesystem;

const fs::path kDataset = fs::path(PLANCHECK_SOURCE_DIR) / "datasets/change5";

int part_named(const Scene& scene, const std::string& name) {
  for (std::size_t i = 0; i < scene.parts.size(); ++i)
    if (scene.parts[i].name == name) return static_cast<int>(i);
  return -1;
}

TEST(TieCullDataset, ArmBaseOverDeckAnswersAsWithoutTheCull) {
  const Scene scene = load_scene(kDataset / "scene.json");
  const int arm = part_named(scene, "ArmJ1"), deck = part_named(scene, "TopDeck");
  ASSERT_GE(arm, 0);
  ASSERT_GE(deck, 0);
  const CollisionModel a(scene.parts[static_cast<std::size_t>(arm)].mesh);
  const CollisionModel b(scene.parts[static_cast<std::size_t>(deck)].mesh);
  int states = 0, culled = 0;
  const int plans = testing::case_count(10, 2);
  for (int p = 1; p <= plans; ++p) {
    const std::string name = "plan" + std::string(p < 10 ? "0" : "") + std::to_string(p) + ".csv";
    const Plan plan = load_plan(scene, kDataset / "plans" / name);
    DistanceResult last;
    for (std::size_t s = 0; s < plan.states.size(); s += testing::case_count(2, 8)) {
      SCOPED_TRACE(name + " state " + std::to_string(s));
      const Affine ta = part_transform(scene, arm, plan.states[s]);
      const Affine tb = part_transform(scene, deck, plan.states[s]);
      for (int kind = 0; kind < 4; ++kind) {
        DistanceRequest q;
        q.abs_tolerance = kDistanceTieTolerance;
        if (kind >= 1 && last.found) {
          q.seed_slot_a = last.slot_a;
          q.seed_slot_b = last.slot_b;
        }
        if ((kind == 2 || kind == 3) && last.found) q.upper_bound = last.distance;
        DistanceRequest slow = q;
        slow.tie_cull = false;
        // Kind 3: the deck as a (the arm's boxes mapped), seeded likewise.
        if (kind == 3) std::swap(q.seed_slot_a, q.seed_slot_b);
        if (kind == 3) std::swap(slow.seed_slot_a, slow.seed_slot_b);
        DistanceResult rf, rs;
        if (kind == 3) {
          distance(b, tb, a, ta, q, rf);
          distance(b, tb, a, ta, slow, rs);
        } else {
          distance(a, ta, b, tb, q, rf);
          distance(a, ta, b, tb, slow, rs);
        }
        ASSERT_TRUE(testing::same_answer(rf, rs)) << "request kind " << kind;
        ASSERT_LE(rf.node_pairs_visited, rs.node_pairs_visited);
        culled += rf.node_pairs_visited < rs.node_pairs_visited;
        if (kind == 1) last = rf;
      }
      ++states;
    }
  }
  ASSERT_GT(states, 0);
  // Seeded, the tie's node pairs go: the cull at work on most searches.
  EXPECT_GT(culled, states);
}

}  // namespace
}  // namespace plancheck
