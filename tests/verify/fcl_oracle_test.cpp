// SPDX-License-Identifier: MIT
// The default Chang'e-5-like scene against FCL 0.7 as an independent oracle:
// random states within the joint limits and states bisected to within 1e-6 m
// of first contact. Collision flags must be equal, distances within 1e-9 m.
// Also the search's starting points: a plan's states checked in order, each
// seeded by the one before (or from cold, by the coarse pass), and arbitrary
// seeds, give what a cold check gives, to within the tie tolerance.
#include "src/scene/plan.h"
#include "src/scene/scene_loader.h"
#include "src/scene/terrain.h"
#include "src/checks/verify.h"
#include "bench/fcl_peer/fcl_peer.h"
#include "support/sanitized.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <random>

namespace plancheck {
namespace {

const std::filesystem::path kScene = std::filesystem::path(PLANCHECK_SOURCE_DIR) / "datasets/change5/scene.json";

struct Fixture {
  Scene scene;
  std::unique_ptr<Checker> checker;
  Mesh terrain;
  std::unique_ptr<reference::FclPeer> fcl;

  Fixture() : scene(load_scene(kScene)) {
    checker = std::make_unique<Checker>(scene);
    std::vector<const Mesh*> meshes;
    for (const Part& p : scene.parts) meshes.push_back(&p.mesh);
    if (scene.terrain && scene.terrain->collide) {
      terrain = dem_mesh(*scene.terrain->grid, scene.terrain->origin);
      meshes.push_back(&terrain);
    }
    fcl = std::make_unique<reference::FclPeer>(scene, meshes, checker->pairs());
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

// Uniform in each driving parameter's limits (a fixed seed: the test is repeatable).
std::vector<double> random_state(const Scene& scene, std::mt19937_64& rng) {
  std::vector<double> p = scene.reference_parameters;
  for (const Action& a : scene.actions) {
    const double lo = a.has_limits ? a.lower : -3.14159265358979;
    const double hi = a.has_limits ? a.upper : 3.14159265358979;
    for (int k = 0; k < a.parameter_count; ++k) {
      const double u = static_cast<double>(rng() >> 11) * 0x1.0p-53;
      p[static_cast<std::size_t>(a.first_parameter + k)] = lo + u * (hi - lo);
    }
  }
  return p;
}

std::vector<double> lerp(const std::vector<double>& a, const std::vector<double>& b, double t) {
  std::vector<double> p(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) p[i] = a[i] + t * (b[i] - a[i]);
  return p;
}

void expect_agree(const std::vector<double>& state, const char* what, int* collisions) {
  Fixture& f = fixture();
  StateResult ours;
  f.checker->check_state(state, ours);
  const auto ref = f.fcl->check(state);
  ASSERT_EQ(ours.collision, ref.collision) << what;
  if (ours.collision) {
    ++*collisions;
    EXPECT_EQ(ours.min_distance, 0.0);
  } else {
    EXPECT_NEAR(ours.min_distance, ref.distance, 1e-9) << what;
    // The reported closest points are on the reported parts, at that distance.
    EXPECT_NEAR((ours.point_a - ours.point_b).norm(), ours.min_distance, 1e-12) << what;
  }
}

TEST(FclOracle, RandomStatesWithinLimitsAgree) {
  if (!std::filesystem::exists(kScene)) GTEST_FAIL() << "run `make dataset` first: " << kScene;
  Fixture& f = fixture();
  std::mt19937_64 rng(20201201);
  int collisions = 0;
  constexpr int kStates = testing::case_count(2000, 400);
  for (int i = 0; i < kStates; ++i) {
    const auto s = random_state(f.scene, rng);
    expect_agree(s, ("random state " + std::to_string(i)).c_str(), &collisions);
    if (::testing::Test::HasFatalFailure()) return;
  }
  std::cout << "[ agreement ] " << kStates << " random states, " << collisions << " colliding\n";
  // The sample must exercise both answers, or it shows nothing.
  EXPECT_GT(collisions, kStates / 20);
  EXPECT_LT(collisions, kStates - kStates / 20);
}

TEST(FclOracle, StatesBisectedToFirstContactAgree) {
  if (!std::filesystem::exists(kScene)) GTEST_FAIL() << "run `make dataset` first: " << kScene;
  Fixture& f = fixture();
  std::mt19937_64 rng(43065192);
  int found = 0, collisions = 0;
  for (int attempt = 0; attempt < 2000 && found < 60; ++attempt) {
    const auto a = random_state(f.scene, rng);
    const auto b = random_state(f.scene, rng);
    StateResult ra, rb;
    f.checker->check_state(a, ra);
    f.checker->check_state(b, rb);
    if (ra.collision || !rb.collision) continue;
    // Bisect the straight path a -> b until the safe end is within 1e-6 m of contact.
    double lo = 0.0, hi = 1.0;
    StateResult r;
    for (int it = 0; it < 80; ++it) {
      const double mid = 0.5 * (lo + hi);
      f.checker->check_state(lerp(a, b, mid), r);
      if (r.collision) hi = mid;
      else {
        lo = mid;
        if (r.min_distance < 1e-6) break;
      }
    }
    f.checker->check_state(lerp(a, b, lo), r);
    if (r.collision || r.min_distance >= 1e-6) continue;
    ++found;
    expect_agree(lerp(a, b, lo), "safe side of first contact", &collisions);
    expect_agree(lerp(a, b, hi), "colliding side of first contact", &collisions);
    if (::testing::Test::HasFatalFailure()) return;
  }
  std::cout << "[ agreement ] " << found << " first contacts bisected: " << 2 * found << " states\n";
  EXPECT_GE(found, 50);
  EXPECT_EQ(collisions, found);
}

// The collision-only check (distance off, as the bench's collide row and
// FCL's default request ask it) visits only the pairs whose boxes meet; the
// full check visits every pair in order. Both must list the same contacts:
// the same pairs in the same order, each with the same intersecting
// triangle pairs, and the flag must be FCL's.
TEST(FclOracle, CollisionOnlyListsTheFullChecksContacts) {
  if (!std::filesystem::exists(kScene)) GTEST_FAIL() << "run `make dataset` first: " << kScene;
  Fixture& f = fixture();
  std::mt19937_64 rng(33002);
  CheckRequest listed;  // the full listing, no distance
  listed.distance = false;
  CheckRequest first_each = listed;  // the bench's collide row: each pair's first triangle pair
  first_each.max_triangle_pairs = 0;
  CheckRequest first_only = first_each;  // the first contact only
  first_only.all_contacts = false;
  const int kStates = testing::case_count(600, 120);
  int collisions = 0, several = 0;
  for (int i = 0; i < kStates; ++i) {
    const auto state = random_state(f.scene, rng);
    const std::string what = "random state " + std::to_string(i);
    StateResult full, a, b, c;
    f.checker->check_state(state, full);
    f.checker->check_state(state, a, listed);
    f.checker->check_state(state, b, first_each);
    f.checker->check_state(state, c, first_only);
    ASSERT_EQ(a.collision, full.collision) << what;
    ASSERT_EQ(b.collision, full.collision) << what;
    ASSERT_EQ(c.collision, full.collision) << what;
    ASSERT_EQ(a.contacts.size(), full.contacts.size()) << what;
    ASSERT_EQ(b.contacts.size(), full.contacts.size()) << what;
    for (std::size_t k = 0; k < full.contacts.size(); ++k) {
      const PairContact& x = full.contacts[k];
      EXPECT_EQ(a.contacts[k].part_a, x.part_a) << what;
      EXPECT_EQ(a.contacts[k].part_b, x.part_b) << what;
      EXPECT_EQ(a.contacts[k].triangles, x.triangles) << what;
      EXPECT_EQ(b.contacts[k].part_a, x.part_a) << what;
      EXPECT_EQ(b.contacts[k].part_b, x.part_b) << what;
      ASSERT_EQ(b.contacts[k].triangles.size(), 1u) << what;
      EXPECT_EQ(b.contacts[k].triangles[0], x.triangles.at(0)) << what;
    }
    if (full.collision) {
      ++collisions;
      if (full.contacts.size() > 1) ++several;
      ASSERT_EQ(c.contacts.size(), 1u) << what;
      EXPECT_EQ(c.contacts[0].part_a, full.contacts[0].part_a) << what;
      EXPECT_EQ(c.contacts[0].part_b, full.contacts[0].part_b) << what;
    }
    // Distances off: none reported.
    EXPECT_EQ(a.part_a, -1) << what;
    EXPECT_FALSE(std::isfinite(a.min_distance) && !a.collision) << what;
    if (i % testing::case_count(4, 20) == 0) {
      const auto ref = f.fcl->check(state, false);
      ASSERT_EQ(b.collision, ref.collision) << what;
    }
    if (::testing::Test::HasFatalFailure()) return;
  }
  std::cout << "[ agreement ] " << kStates << " random states collision-only, " << collisions << " colliding, "
            << several << " with several colliding pairs\n";
  EXPECT_GT(collisions, kStates / 20);
  EXPECT_LT(collisions, kStates - kStates / 20);
  EXPECT_GT(several, 0);
}

// What a seed can change: which of pairs tied within kDistanceTieTolerance is
// reported, so the distance by at most that much; never a collision flag.
void expect_same_answer(const StateResult& got, const StateResult& cold, const std::string& what) {
  ASSERT_EQ(got.collision, cold.collision) << what;
  if (cold.collision) return;
  EXPECT_NEAR(got.min_distance, cold.min_distance, 2 * kDistanceTieTolerance) << what;
  EXPECT_NEAR((got.point_a - got.point_b).norm(), got.min_distance, 1e-12) << what;
  if (got.part_a != cold.part_a || got.part_b != cold.part_b) {
    EXPECT_LE(std::abs(got.min_distance - cold.min_distance), kDistanceTieTolerance) << what << ": other pair";
  }
}

TEST(FclOracle, PlansCheckedInSeededRunsOnTwoThreadsAgree) {
  if (!std::filesystem::exists(kScene)) GTEST_FAIL() << "run `make dataset` first: " << kScene;
  Fixture& f = fixture();
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(kScene.parent_path() / "plans")) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::vector<Plan> plans;
  for (const auto& file : files) plans.push_back(load_plan(f.scene, file));
  ASSERT_EQ(plans.size(), 10u);
  // Collision and distance only: the terrain stays as FCL sees it (undug).
  const auto results = verify_plans(*f.checker, f.scene, plans, VerifyOptions{2, false, false});
  std::size_t states = 0;
  int collisions = 0;
  for (std::size_t p = 0; p < plans.size(); ++p)
    for (std::size_t s = 0; s < plans[p].states.size(); ++s, ++states) {
      const std::string what = plans[p].name + " state " + std::to_string(s);
      StateResult cold;
      f.checker->check_state(plans[p].states[s], cold);
      expect_same_answer(results[p].states[s], cold, what);
      if (::testing::Test::HasFatalFailure()) return;
      if (cold.collision) ++collisions;
      // FCL on every 8th state (it takes ~9 ms a state here; every 40th under the sanitizers).
      if (states % static_cast<std::size_t>(testing::case_count(8, 40)) != 0) continue;
      const auto ref = f.fcl->check(plans[p].states[s]);
      ASSERT_EQ(results[p].states[s].collision, ref.collision) << what;
      if (!ref.collision) {
        EXPECT_NEAR(results[p].states[s].min_distance, ref.distance, 1e-9) << what;
      }
    }
  std::cout << "[ agreement ] " << states << " plan states in seeded runs, " << collisions << " colliding\n";
  EXPECT_GT(states, 2000u);
  EXPECT_GT(collisions, 0);
}

TEST(FclOracle, ArbitrarySeedsChangeNoAnswer) {
  if (!std::filesystem::exists(kScene)) GTEST_FAIL() << "run `make dataset` first: " << kScene;
  Fixture& f = fixture();
  std::mt19937_64 rng(7081);
  const int pairs = static_cast<int>(f.checker->pairs().size());
  std::vector<std::vector<double>> states;
  for (int i = 0; i < 300; ++i) states.push_back(random_state(f.scene, rng));
  // Valid seeds from other states, and pairs or slots out of range.
  std::vector<StateSeed> seeds;
  for (int i = 0; i < 40; ++i) {
    StateSeed seed;
    StateResult r;
    f.checker->check_state(states[static_cast<std::size_t>(i)], r, CheckRequest{}, &seed);
    seed.separation.clear();  // separations hold only for nearby states
    seeds.push_back(seed);
  }
  for (int i = 0; i < 20; ++i) {
    StateSeed seed;
    seed.pair = static_cast<int>(rng() % static_cast<std::uint64_t>(pairs + 3)) - 1;
    seed.slot_a = static_cast<std::uint32_t>(i % 2 ? rng() % 64 : rng());
    seed.slot_b = static_cast<std::uint32_t>(i % 3 ? rng() % 64 : rng());
    seeds.push_back(seed);
  }
  int checked = 0;
  for (std::size_t i = 0; i < states.size(); ++i) {
    StateResult cold;
    f.checker->check_state(states[i], cold);
    for (int k = 0; k < 3; ++k) {
      StateSeed seed = seeds[rng() % seeds.size()];
      StateResult got;
      f.checker->check_state(states[i], got, CheckRequest{}, &seed);
      expect_same_answer(got, cold, "state " + std::to_string(i) + " seeded with pair " + std::to_string(seed.pair));
      if (::testing::Test::HasFatalFailure()) return;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 900);
}

}  // namespace
}  // namespace plancheck
