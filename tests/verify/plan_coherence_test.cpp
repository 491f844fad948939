// SPDX-License-Identifier: MIT
// What a plan's states carry to the next (StateSeed) against the states
// checked without it, and the plan path's short listing of contacts. The repeated-search memo (StateSeed::searches) must
// give the very bits a fresh search gives; a seed from a state far away
// must give the cold answer. References: the same state checked with the
// memo emptied (bitwise), cold (within the tie tolerance), and pair by pair
// (pose_parts + pair_distance: every pair searched exactly on its own).
#include "src/checks/verify.h"
#include "src/geometry/motion_bound.h"
#include "src/scene/scene_loader.h"
#include "support/fixtures.h"
#include "support/sanitized.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace plancheck {
namespace {

namespace fs = std::filesystem;

const fs::path kDataset = fs::path(PLANCHECK_SOURCE_DIR) / "datasets/change5";

bool same_bits(double x, double y) { return std::bit_cast<std::uint64_t>(x) == std::bit_cast<std::uint64_t>(y); }

void expect_same_bits(const StateResult& got, const StateResult& want, const std::string& at) {
  ASSERT_EQ(got.collision, want.collision) << at;
  EXPECT_TRUE(same_bits(got.min_distance, want.min_distance)) << at << ": " << got.min_distance << " vs " << want.min_distance;
  EXPECT_EQ(got.part_a, want.part_a) << at;
  EXPECT_EQ(got.part_b, want.part_b) << at;
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(same_bits(got.point_a[i], want.point_a[i])) << at;
    EXPECT_TRUE(same_bits(got.point_b[i], want.point_b[i])) << at;
  }
  EXPECT_TRUE(same_bits(got.distance_tolerance, want.distance_tolerance)) << at;
  EXPECT_EQ(got.distance_is_bound, want.distance_is_bound) << at;
  ASSERT_EQ(got.contacts.size(), want.contacts.size()) << at;
  for (std::size_t c = 0; c < got.contacts.size(); ++c) {
    EXPECT_EQ(got.contacts[c].part_a, want.contacts[c].part_a) << at;
    EXPECT_EQ(got.contacts[c].part_b, want.contacts[c].part_b) << at;
    EXPECT_EQ(got.contacts[c].triangles, want.contacts[c].triangles) << at;
  }
}

// The smallest exact pair distance, each pair searched on its own.
double pair_by_pair_minimum(const Checker& checker, const std::vector<double>& p) {
  PosedParts posed;
  checker.pose_parts(p, posed);
  double smallest = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < checker.pairs().size(); ++k) {
    if (checker.pair_collides(posed, k)) return 0.0;
    PairAnswer a;
    checker.pair_distance(posed, k, std::numeric_limits<double>::infinity(), a);
    if (a.exact) smallest = std::min(smallest, a.distance);
  }
  return smallest;
}

// Plan-like walks where joints are held for a while (so some pairs' parts
// do not move and their searches repeat bitwise), a state repeated outright,
// and jumps across the limits (incoherent states, seeds that cannot help).
std::vector<std::vector<double>> held_walk(const Scene& scene, std::mt19937_64& rng, int n) {
  std::vector<std::vector<double>> states;
  std::vector<double> q = testing::random_state(scene, rng, 0.0);
  std::uniform_real_distribution<double> step(-0.8, 0.8);
  for (int i = 0; i < n; ++i) {
    const int kind = static_cast<int>(rng() % 8);
    if (kind == 0) {
      q = testing::random_state(scene, rng, 0.0);  // a jump
    } else if (kind != 1) {                          // kind 1: the same state again
      // Move one or two parameters a little; the rest stay bitwise the same.
      for (int m = 0; m < 1 + kind % 2; ++m) {
        const std::size_t j = rng() % q.size();
        q[j] += step(rng);
      }
    }
    states.push_back(q);
  }
  return states;
}

TEST(PlanCoherence, RepeatedSearchesGiveTheBitsOfAFreshSearch) {
  const Scene scene = load_scene(kDataset / "scene.json");
  const Checker checker(scene);
  std::mt19937_64 rng(20261128);
  const int runs = testing::case_count(12, 3);
  std::size_t remembered = 0, states = 0;
  for (int run = 0; run < runs; ++run) {
    const auto walk = held_walk(scene, rng, 24);
    StateSeed with_memo, without_memo;
    for (std::size_t s = 0; s < walk.size(); ++s) {
      const std::string at = "run " + std::to_string(run) + " state " + std::to_string(s);
      // Searches remembered for this state to reuse where its inputs repeat.
      for (const StateSeed::Search& m : with_memo.searches) remembered += m.valid ? 1 : 0;
      StateResult got, want, cold;
      checker.check_state(walk[s], got, CheckRequest{}, &with_memo);
      without_memo.searches.clear();  // every search run afresh, the same seed otherwise
      checker.check_state(walk[s], want, CheckRequest{}, &without_memo);
      expect_same_bits(got, want, at);
      checker.check_state(walk[s], cold);
      ASSERT_EQ(got.collision, cold.collision) << at;
      if (!got.collision) {
        EXPECT_NEAR(got.min_distance, cold.min_distance, 2 * kDistanceTieTolerance) << at;
        if (s % 4 == 0) {
          EXPECT_NEAR(got.min_distance, pair_by_pair_minimum(checker, walk[s]), 2 * kDistanceTieTolerance) << at;
        }
      }
      if (::testing::Test::HasFatalFailure()) return;
      ++states;
    }
  }
  EXPECT_EQ(states, static_cast<std::size_t>(runs) * 24);
  EXPECT_GT(remembered, 0u);
}

// `count` random states of the scene (within its limits) as one plan.
Plan random_plan(const Scene& scene, std::uint64_t seed, int count) {
  std::mt19937_64 rng(seed);
  Plan plan;
  plan.name = "random";
  for (int i = 0; i < count; ++i) plan.states.push_back(testing::random_state(scene, rng, 0.0));
  return plan;
}

// verify_plans lists every contact with its triangle pairs only for the
// first listed_collisions colliding states of a plan (what report.json
// shows); the rest keep the first contact's first triangle pair. Against the
// full listing of every state: everything else bitwise the same. Random
// states as one plan (a third of them colliding), with the dig pass (the
// dug terrain's pairs listed by it) and without.
TEST(PlanCoherence, ListingOnlyWhatTheReportShowsKeepsEverythingElse) {
  const Scene scene = load_scene(kDataset / "scene.json");
  const Checker checker(scene);
  const Plan plan = random_plan(scene, 33, testing::case_count(160, 40));
  const std::vector<Plan> plans{plan, plan};
  for (const bool regolith : {false, true}) {
    VerifyOptions all{2, false, regolith};
    VerifyOptions some = all;
    some.listed_collisions = 5;
    const auto want = verify_plans(checker, scene, plans, all);
    const auto got = verify_plans(checker, scene, plans, some);
    std::size_t short_listed = 0;
    for (std::size_t p = 0; p < plans.size(); ++p) {
      std::size_t colliding = 0;
      for (std::size_t s = 0; s < plan.states.size(); ++s) {
        const std::string at = "regolith " + std::to_string(regolith) + " plan " + std::to_string(p) + " state " + std::to_string(s);
        const StateResult& g = got[p].states[s];
        const StateResult& w = want[p].states[s];
        if (!w.collision || colliding++ < some.listed_collisions) {
          expect_same_bits(g, w, at);
          continue;
        }
        // The full listing cut to the first contact's first triangle pair
        // (and the dug terrain's contacts, listed by the dig pass).
        StateResult first = w;
        first.contacts.clear();
        bool kept_first = false;
        for (const PairContact& c : w.contacts) {
          if (regolith && c.part_b == checker.terrain_index()) {
            first.contacts.push_back(c);
            continue;
          }
          if (kept_first) continue;
          kept_first = true;
          first.contacts.push_back(c);
          first.contacts.back().triangles.resize(1);
        }
        expect_same_bits(g, first, at);
        for (const PairContact& c : w.contacts) short_listed += c.triangles.size() > 1 ? 1 : 0;
        if (::testing::Test::HasFatalFailure()) return;
      }
      EXPECT_GT(colliding, some.listed_collisions) << "regolith " << regolith;
    }
    EXPECT_GT(short_listed, 0u) << "regolith " << regolith;  // some listing was cut
  }
}

// verify_plans keeps one StateSeed per thread and reset()s it at the start
// of each run of a plan's states, where it used to make a fresh one: a reset
// seed must be a fresh seed (nothing carried, no pair, no search
// remembered) and give every state the bits a fresh seed gives, in the
// full, row and verdict-only requests, on walks with held joints, repeats
// and jumps (incoherent states).
TEST(PlanCoherence, AResetSeedIsAFreshSeed) {
  const Scene scene = load_scene(kDataset / "scene.json");
  const Checker checker(scene);
  std::mt19937_64 rng(20261202);
  const int runs = testing::case_count(10, 3);
  const std::vector<CheckRequest> requests{CheckRequest{}, row_request(), verdict_only_request(scene.safety_margin)};
  for (std::size_t q = 0; q < requests.size(); ++q) {
    StateSeed reused;
    for (int run = 0; run < runs; ++run) {
      const auto walk = held_walk(scene, rng, 20);
      reused.reset();
      EXPECT_EQ(reused.pair, -1);
      EXPECT_TRUE(reused.separation.empty());
      EXPECT_TRUE(reused.at.empty());
      for (const StateSeed::Search& m : reused.searches) ASSERT_FALSE(m.valid);
      StateSeed fresh;
      for (std::size_t s = 0; s < walk.size(); ++s) {
        const std::string at = "request " + std::to_string(q) + " run " + std::to_string(run) + " state " + std::to_string(s);
        StateResult got, want;
        checker.check_state(walk[s], got, requests[q], &reused);
        checker.check_state(walk[s], want, requests[q], &fresh);
        expect_same_bits(got, want, at);
        // What each carries to the next state, bitwise.
        ASSERT_EQ(reused.pair, fresh.pair) << at;
        ASSERT_EQ(reused.separation.size(), fresh.separation.size()) << at;
        for (std::size_t k = 0; k < fresh.separation.size(); ++k)
          ASSERT_TRUE(same_bits(reused.separation[k], fresh.separation[k])) << at << " pair " << k;
        if (::testing::Test::HasFatalFailure()) return;
      }
    }
  }
}

// The plan path against cold checks on random states written as one plan
// (a seed from a state far away carries nothing that changes a verdict):
// each state's verdict, collision and first contact as the cold batch's,
// and a verdict-only state's distance (exact or a bound) never above the
// cold one's exact distance by more than the tie tolerance.
TEST(PlanCoherence, RandomStatesAsOnePlanKeepTheColdVerdicts) {
  const Scene scene = load_scene(kDataset / "scene.json");
  const Checker checker(scene);
  const Plan plan = random_plan(scene, 1202, testing::case_count(200, 48));
  const std::vector<Plan> plans{plan};
  for (const bool verdict_only : {false, true}) {
    VerifyOptions o{1, false, false};
    o.verdict_only = verdict_only;
    o.listed_collisions = kMaxCollisionStatesListed;
    const auto results = verify_plans(checker, scene, plans, o);
    ASSERT_EQ(results[0].states.size(), plan.states.size());
    for (std::size_t s = 0; s < plan.states.size(); ++s) {
      const std::string at = std::string(verdict_only ? "verdict-only" : "full") + " state " + std::to_string(s);
      StateResult cold;
      checker.check_state(plan.states[s], cold);
      const StateResult& got = results[0].states[s];
      ASSERT_EQ(state_verdict(got, scene.safety_margin), state_verdict(cold, scene.safety_margin)) << at;
      ASSERT_EQ(got.collision, cold.collision) << at;
      if (got.collision) {
        ASSERT_FALSE(got.contacts.empty()) << at;
        EXPECT_EQ(got.contacts[0].part_a, cold.contacts[0].part_a) << at;
        EXPECT_EQ(got.contacts[0].part_b, cold.contacts[0].part_b) << at;
      } else if (got.distance_is_bound) {
        EXPECT_LE(got.min_distance, cold.min_distance + 2 * kDistanceTieTolerance) << at;
      } else {
        EXPECT_NEAR(got.min_distance, cold.min_distance, 2 * kDistanceTieTolerance) << at;
      }
    }
  }
}

// What a verdict-only state proves for the next (StateSeed::separation)
// on walks with held joints, repeats and jumps: on every pair of a state
// without contact, at least the pair's box gap and at least what the
// previous state's separation less both parts' motion bound carries (the
// plan path roots the gaps of the pairs beyond the cutoff after its pair
// loop: left out, or the carried part dropped, these fail), and never more
// than the pair's exact distance (every pair searched on its own).
TEST(PlanCoherence, VerdictOnlySeparationsAreTheGapsAndCarriedBounds) {
  const Scene scene = load_scene(kDataset / "scene.json");
  const Checker checker(scene);
  const MotionBound motion(scene);
  const auto pairs = checker.pairs();
  const CheckRequest request = verdict_only_request(scene.safety_margin);
  std::mt19937_64 rng(20261203);
  std::size_t states = 0, above_gap = 0, carried_seen = 0;
  for (int run = 0; run < testing::case_count(8, 2); ++run) {
    const auto walk = held_walk(scene, rng, 24);
    StateSeed seed;
    for (std::size_t s = 0; s < walk.size(); ++s) {
      const std::string at = "run " + std::to_string(run) + " state " + std::to_string(s);
      const std::vector<double> before = seed.separation;
      const std::vector<double> before_at = seed.at;
      StateResult r;
      checker.check_state(walk[s], r, request, &seed);
      ASSERT_EQ(seed.separation.size(), pairs.size()) << at;
      if (r.collision) continue;
      PosedParts posed;
      checker.pose_parts(walk[s], posed);
      std::vector<double> gap, guard;
      checker.pair_gaps(posed, gap, guard);
      for (std::size_t k = 0; k < pairs.size(); ++k) {
        const double sep = seed.separation[k];
        if (std::isfinite(gap[k])) {
          EXPECT_GE(sep, gap[k]) << at << " pair " << k;
        }
        above_gap += sep > gap[k];
        if (!before.empty()) {
          const double m = motion.part_bound(pairs[k].first, before_at, walk[s]) +
                           motion.part_bound(pairs[k].second, before_at, walk[s]);
          const double carried = before[k] - m;
          if (carried > 0.0 && std::isfinite(gap[k])) {
            EXPECT_GE(sep, carried) << at << " pair " << k;
            carried_seen += carried > gap[k];
          }
        }
        if (s % 6 == 0 && sep > 0.0) {
          PairAnswer a;
          checker.pair_distance(posed, k, std::numeric_limits<double>::infinity(), a);
          ASSERT_TRUE(a.exact) << at << " pair " << k;
          EXPECT_LE(sep, a.distance) << at << " pair " << k;
        }
      }
      if (::testing::Test::HasFailure()) return;
      ++states;
    }
  }
  EXPECT_GT(states, 20u);
  EXPECT_GT(above_gap, 0u);      // some pairs searched or carried beyond their gap
  EXPECT_GT(carried_seen, 0u);   // and some carried beyond it
}

}  // namespace
}  // namespace plancheck
