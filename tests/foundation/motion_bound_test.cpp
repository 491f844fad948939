// SPDX-License-Identifier: MIT
// MotionBound against the paths themselves: on random chains of rotations,
// translations and scales, no vertex's path (as a fine polyline, which is
// never longer than the path) is longer than the bound, on whole segments and
// on sub-intervals; on a single rotation the bound is the exact arc length.
#include "src/scene/kinematics.h"
#include "src/geometry/motion_bound.h"
#include "support/fixtures.h"
#include "support/random_chain.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace plancheck {
namespace {

constexpr double kPi = 3.14159265358979323846;

using testing::random_chain_scene;

// Values as a plan writes them: angles up to 1.5 turns either way (in the
// action's unit), shifts up to 1 m, factors 0.5 .. 2.
std::vector<double> random_params(const Scene& scene, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> angle(-3 * kPi, 3 * kPi), shift(-1.0, 1.0), factor(0.5, 2.0);
  std::vector<double> q(scene.reference_parameters.size());
  for (const Action& a : scene.actions)
    for (int k = 0; k < a.parameter_count; ++k) {
      double& v = q[static_cast<std::size_t>(a.first_parameter + k)];
      v = a.type == ActionType::kRotate ? angle(rng) : a.type == ActionType::kScale ? factor(rng) : shift(rng);
      if (a.type != ActionType::kScale) v /= a.unit_to_si;
    }
  return q;
}

std::vector<double> lerp(const std::vector<double>& a, const std::vector<double>& b, double t) {
  std::vector<double> q(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) q[i] = a[i] + t * (b[i] - a[i]);
  return q;
}

TEST(MotionBound, NoVertexPathIsLongerThanTheBound) {
  std::mt19937_64 rng(20250605);
  constexpr int kSteps = 400;
  for (int trial = 0; trial < 300; ++trial) {
    const Scene scene = random_chain_scene(rng);
    const MotionBound bound(scene);
    const auto qa = random_params(scene, rng);
    const auto qb = random_params(scene, rng);
    // Whole segment and a random sub-interval of it.
    std::uniform_real_distribution<double> u(0.0, 1.0);
    double t0 = u(rng), t1 = u(rng);
    if (t0 > t1) std::swap(t0, t1);
    for (auto [ta, tb] : {std::pair{0.0, 1.0}, std::pair{t0, t1}}) {
      const auto a = lerp(qa, qb, ta), b = lerp(qa, qb, tb);
      const double m = bound.part_bound(0, a, b);
      const Mesh& mesh = scene.parts[0].mesh;
      std::vector<double> length(mesh.vertices.size(), 0.0);
      Affine prev = part_transform(scene, 0, a);
      for (int s = 1; s <= kSteps; ++s) {
        const Affine cur = part_transform(scene, 0, lerp(a, b, static_cast<double>(s) / kSteps));
        for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
          length[v] += (cur * mesh.vertices[v] - prev * mesh.vertices[v]).norm();
        prev = cur;
      }
      for (double l : length) ASSERT_LE(l, m) << "trial " << trial << " [" << ta << ", " << tb << "]";
    }
  }
}

TEST(MotionBound, SingleRotationBoundIsTheLongestArc) {
  Scene scene;
  Action a;
  a.type = ActionType::kRotate;
  a.pivot = Vec3(1, 0, 0);
  a.axis = Vec3::UnitZ();
  scene.actions.push_back(a);
  Part p;
  p.mesh = testing::box_mesh({2, -0.5, 0}, {4, 0.5, 7});  // farthest from the axis: (4, +-0.5, *)
  p.chain = {0};
  p.chain_id = 0;
  scene.parts.push_back(p);
  scene.chains.push_back(p.chain);
  const MotionBound bound(scene);
  const double r = std::sqrt(3.0 * 3.0 + 0.25);
  const std::vector<double> qa{-2.0}, qb{1.0};
  EXPECT_NEAR(bound.part_bound(0, qa, qb), 3.0 * r, 1e-8);
  EXPECT_EQ(bound.part_bound(0, qa, qa), 1e-12);  // only the rounding pad
  EXPECT_EQ(bound.part_bound(5, qa, qb), 0.0);    // past the parts: the static terrain
}

// Written in degrees, the turn is the written difference: 0 -> 720 is two
// turns (though both ends pose alike), 170 -> -170 is 340 degrees.
TEST(MotionBound, DegreesBoundTheWrittenTurnNotTheReducedOne) {
  Scene scene;
  Action a;
  a.type = ActionType::kRotate;
  a.pivot = Vec3(1, 0, 0);
  a.axis = Vec3::UnitZ();
  a.unit_to_si = kPi / 180;
  a.whole_turn = 360;
  scene.actions.push_back(a);
  Action slide;
  slide.type = ActionType::kTranslateAxis;
  slide.axis = Vec3::UnitX();
  slide.first_parameter = 1;
  slide.unit_to_si = 0.001;  // millimetres
  scene.actions.push_back(slide);
  Part p;
  p.mesh = testing::box_mesh({2, -0.5, 0}, {4, 0.5, 7});
  p.chain = {0};
  p.chain_id = 0;
  scene.parts.push_back(p);
  Part q = p;
  q.chain = {1};
  q.chain_id = 1;
  scene.parts.push_back(q);
  scene.chains = {p.chain, q.chain};
  const MotionBound bound(scene);
  const double r = std::sqrt(3.0 * 3.0 + 0.25);
  // The bound is the exact arc length padded by 1e-9 relative for rounding.
  auto expect_bound = [&](int part, std::vector<double> qa, std::vector<double> qb, double exact) {
    const double m = bound.part_bound(part, qa, qb);
    EXPECT_GE(m, exact) << qa[0] << " -> " << qb[0];
    EXPECT_LE(m, exact * (1 + 2e-9) + 1e-12) << qa[0] << " -> " << qb[0];
  };
  expect_bound(0, {0, 0}, {720, 0}, 4 * kPi * r);
  expect_bound(0, {170, 0}, {-170, 0}, 340 * kPi / 180 * r);
  expect_bound(0, {1e4, 0}, {1e4 + 200, 0}, 200 * kPi / 180 * r);
  expect_bound(1, {0, -250}, {0, 750}, 1.0);  // 1000 mm
}

// pair_bounds (every pair at once, each part's bound per shared prefix
// computed once) against pair_bound pair by pair, its slow reference: the
// same values bit for bit. Parts on one random chain, on a prefix of it, on
// a copy of the whole chain, and static, paired every way and with a static
// index past the parts (the terrain's), on whole segments and pieces.
TEST(MotionBound, PairBoundsEqualPairBoundPairByPair) {
  std::mt19937_64 rng(20261128);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    Scene scene = random_chain_scene(rng);
    const Part& first = scene.parts[0];
    Part prefix = first, whole = first, fixed = first;
    prefix.name = "Prefix";
    prefix.chain.resize(1 + rng() % first.chain.size());
    for (Vec3& v : prefix.mesh.vertices) v += Vec3(0.3, -0.2, 0.5);
    whole.name = "Whole";
    for (Vec3& v : whole.mesh.vertices) v *= 1.5;
    fixed.name = "Fixed";
    fixed.chain.clear();
    scene.parts.push_back(prefix);
    scene.parts.push_back(whole);
    scene.parts.push_back(fixed);
    const MotionBound bound(scene);
    const int n = static_cast<int>(scene.parts.size());
    std::vector<std::pair<int, int>> pairs;
    for (int a = 0; a <= n; ++a)
      for (int b = a + 1; b <= n; ++b) pairs.emplace_back(a, b);
    std::shuffle(pairs.begin(), pairs.end(), rng);
    const MotionBound::PairPlan plan = bound.pair_plan(pairs);
    const auto qa = random_params(scene, rng), qb = random_params(scene, rng);
    const double t0 = u(rng), t1 = u(rng);
    for (auto [ta, tb] : {std::pair{0.0, 1.0}, std::pair{std::min(t0, t1), std::max(t0, t1)}}) {
      const auto a = lerp(qa, qb, ta), b = lerp(qa, qb, tb);
      std::vector<double> all, planned;
      bound.pair_bounds(pairs, a, b, all);
      bound.pair_bounds(plan, a, b, planned);  // the plan made once, used on every motion
      ASSERT_EQ(all.size(), pairs.size());
      ASSERT_EQ(planned.size(), pairs.size());
      for (std::size_t k = 0; k < pairs.size(); ++k) {
        ASSERT_EQ(all[k], bound.pair_bound(pairs[k].first, pairs[k].second, a, b))
            << "trial " << trial << " pair " << pairs[k].first << "-" << pairs[k].second;
        ASSERT_EQ(planned[k], all[k]) << "trial " << trial << " pair " << k;
      }
    }
  }
}

}  // namespace
}  // namespace plancheck
