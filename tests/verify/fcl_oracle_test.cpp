// SPDX-License-Identifier: MIT
// The default Chang'e-5-like scene against FCL 0.7 as an independent oracle:
// random states within the joint limits and states bisected to within 1e-6 m
// of first contact. Collision flags must be equal, distances within 1e-9 m.
#include "src/scene_loader.h"
#include "src/terrain.h"
#include "src/verify.h"
#include "support/fcl_reference.h"

#include <gtest/gtest.h>

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
  std::unique_ptr<testing::FclReference> fcl;

  Fixture() : scene(load_scene(kScene)) {
    checker = std::make_unique<Checker>(scene);
    std::vector<const Mesh*> meshes;
    for (const Part& p : scene.parts) meshes.push_back(&p.mesh);
    if (scene.terrain && scene.terrain->collide) {
      terrain = dem_mesh(load_dem(scene.terrain->dem, scene.length_scale), scene.terrain->origin);
      meshes.push_back(&terrain);
    }
    fcl = std::make_unique<testing::FclReference>(scene, meshes, checker->pairs());
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
  constexpr int kStates = 2000;
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

}  // namespace
}  // namespace plancheck
