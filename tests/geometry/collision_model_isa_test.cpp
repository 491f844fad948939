// SPDX-License-Identifier: MIT
// The SIMD leaf prefilters change no answer: collide() and distance() give
// bitwise the same results with every instruction set as with kernels that
// prove nothing (every pair on the double path, as before the prefilters).
#include "src/geometry/collision_model.h"

#include "kernels/leaf_bounds.h"
#include "support/test_meshes.h"

#include <gtest/gtest.h>

#include <bit>
#include <random>
#include <vector>

namespace plancheck {
namespace {

Affine random_pose(std::mt19937_64& rng, const Vec3& around, double spread, bool scaled) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Affine t = testing::random_rigid(rng, around, spread);
  if (scaled) t = t * Eigen::Scaling(0.7 + 0.5 * (u(rng) + 1), 0.8 + 0.2 * (u(rng) + 1), 1.1);
  return t;
}

struct Answers {
  std::vector<CollideResult> collide;
  std::vector<DistanceResult> distance, tolerant;
};

// Restores the run-time choice when a test ends.
struct KernelsGuard {
  const LeafKernels& saved = leaf_kernels();
  ~KernelsGuard() { set_leaf_kernels(saved); }
};

Answers run_all(const LeafKernels& k, const CollisionModel& a, const CollisionModel& b,
                const std::vector<std::pair<Affine, Affine>>& poses) {
  set_leaf_kernels(k);
  Answers out;
  for (const auto& [ta, tb] : poses) {
    CollideResult c;
    collide(a, ta, b, tb, CollideRequest{64}, c);
    out.collide.push_back(c);
    DistanceResult d;
    distance(a, ta, b, tb, DistanceRequest{}, d);
    out.distance.push_back(d);
    DistanceRequest tol;
    tol.rel_tolerance = 0.05;
    tol.abs_tolerance = 1e-12;
    distance(a, ta, b, tb, tol, d);
    out.tolerant.push_back(d);
  }
  return out;
}

bool same(double x, double y) { return std::bit_cast<std::uint64_t>(x) == std::bit_cast<std::uint64_t>(y); }

void expect_same(const DistanceResult& x, const DistanceResult& y, const char* isa, std::size_t i) {
  EXPECT_EQ(x.found, y.found) << isa << " pose " << i;
  EXPECT_TRUE(same(x.distance, y.distance)) << isa << " pose " << i << ": " << x.distance << " vs " << y.distance;
  EXPECT_EQ(x.triangle_a, y.triangle_a) << isa << " pose " << i;
  EXPECT_EQ(x.triangle_b, y.triangle_b) << isa << " pose " << i;
  for (int k = 0; k < 3; ++k) {
    EXPECT_TRUE(same(x.point_a[k], y.point_a[k])) << isa << " pose " << i;
    EXPECT_TRUE(same(x.point_b[k], y.point_b[k])) << isa << " pose " << i;
  }
}

void compare_all(const CollisionModel& a, const CollisionModel& b,
                 const std::vector<std::pair<Affine, Affine>>& poses) {
  KernelsGuard guard;
  const Answers ref = run_all(leaf_kernels_none(), a, b, poses);
  int colliding = 0, found = 0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    colliding += ref.collide[i].collide;
    found += ref.distance[i].found;
  }
  // Both kinds of answer occur, so both filters are exercised.
  EXPECT_GT(colliding, 0);
  EXPECT_LT(colliding, static_cast<int>(poses.size()));
  EXPECT_EQ(found, static_cast<int>(poses.size()));
  for (int k = 0; k < kIsaCount; ++k) {
    const LeafKernels* isa = leaf_kernels_for(static_cast<Isa>(k));
    if (isa == nullptr) continue;
    const Answers got = run_all(*isa, a, b, poses);
    std::uint64_t tests_ref = 0, tests_got = 0;
    for (std::size_t i = 0; i < poses.size(); ++i) {
      EXPECT_EQ(got.collide[i].collide, ref.collide[i].collide) << isa->name << " pose " << i;
      EXPECT_EQ(got.collide[i].triangle_pairs, ref.collide[i].triangle_pairs) << isa->name << " pose " << i;
      expect_same(got.distance[i], ref.distance[i], isa->name, i);
      expect_same(got.tolerant[i], ref.tolerant[i], isa->name, i);
      tests_ref += ref.distance[i].triangle_pairs_tested;
      tests_got += got.distance[i].triangle_pairs_tested;
    }
    // The double path runs no more kernels than before (the same pairs
    // reach it, minus those proven unable to change the answer).
    EXPECT_LE(tests_got, tests_ref) << isa->name;
  }
}

TEST(CollisionModelIsa, SphereVsTorusSameAnswersAtEveryWidth) {
  const CollisionModel a(testing::make_sphere(Vec3(0, 0, 0), 1.0, 24, 32));
  const CollisionModel b(testing::make_torus(Vec3(0, 0, 0), 1.6, 0.5, 48, 24));
  std::mt19937_64 rng(5);
  std::vector<std::pair<Affine, Affine>> poses;
  for (int i = 0; i < 150; ++i)
    poses.emplace_back(random_pose(rng, Vec3(0, 0, 0), 0.2, i % 7 == 3),
                       random_pose(rng, Vec3(0.5, 0, 0), 1.5, i % 5 == 4));
  compare_all(a, b, poses);
}

TEST(CollisionModelIsa, FarFromOriginSoupsSameAnswersAtEveryWidth) {
  const Vec3 far(1.7e6, -0.9e6, 1.2e6);
  const CollisionModel a(testing::make_soup(11, 3000, far, 1.0, 0.2));
  const CollisionModel b(testing::make_soup(12, 3000, Vec3(0, 0, 0), 1.0, 0.2));
  std::mt19937_64 rng(6);
  std::vector<std::pair<Affine, Affine>> poses;
  for (int i = 0; i < 60; ++i) {
    Affine tb = random_pose(rng, far, 2.5, false);
    // a about its own far centre (rotated in place) or untouched.
    Affine ta = Affine::Identity();
    if (i % 3 == 0) ta = Eigen::Translation3d(far) * random_pose(rng, Vec3(0, 0, 0), 0.1, false) *
                         Eigen::Translation3d(-far);
    poses.emplace_back(ta, tb);
  }
  compare_all(a, b, poses);
}

}  // namespace
}  // namespace plancheck
