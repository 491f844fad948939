// SPDX-License-Identifier: MIT
// BoxMotion against the poses themselves: on random chains of rotations and
// translations, no vertex posed anywhere in a random box (its corners first,
// then random points) is farther than the bound from where it is at a random
// point c of the box; the samples come within half of the bound, so a
// halved bound fails. Twice the reach from a straight motion's midpoint is
// a rate: no vertex moves farther between two points of the motion than
// that rate times their share of it (the continuous check's march,
// src/checks/continuous.h PoseRates), for both kinds of clusters. The
// balls of whole-triangle clusters hold every point of the part anywhere in
// the box: each triangle's corners, midpoints and centroid lie within
// radius + move of one ball's centre and move no farther than that ball's
// move, and a ball made a hair smaller misses some.
#include "src/geometry/box_motion.h"
#include "src/scene/plan.h"
#include "src/scene/kinematics.h"
#include "support/random_chain.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace plancheck {
namespace {

// The largest distance of any vertex, posed at q, from itself posed at c.
double moved(const Scene& scene, const std::vector<double>& c, const std::vector<double>& q) {
  const Affine tc = part_transform(scene, 0, c), tq = part_transform(scene, 0, q);
  double m = 0.0;
  for (const Vec3& v : scene.parts[0].mesh.vertices) m = std::max(m, (tq * v - tc * v).norm());
  return m;
}

// A random box [lo, hi] of the chain's parameters and a point c in it:
// from a hair to about a radian (or a metre) wide, some axes fixed.
void random_box(const Scene& scene, std::mt19937_64& rng, std::vector<double>& lo, std::vector<double>& hi,
                std::vector<double>& c) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const Action& a : scene.actions)
    for (int k = 0; k < a.parameter_count; ++k) {
      const std::size_t i = static_cast<std::size_t>(a.first_parameter + k);
      const double width = std::pow(10.0, -3.0 * u(rng)) / a.unit_to_si;
      lo[i] = (u(rng) * 8.0 - 4.0) / a.unit_to_si;
      hi[i] = lo[i] + width * (rng() % 4 == 0 ? 0.0 : 1.0);
      c[i] = lo[i] + u(rng) * (hi[i] - lo[i]);
    }
}

// Largest vertex move over the box seen by sampling, against the bound; the
// bound scaled by `scale` (a test of the test: 0.5 must fail somewhere).
bool holds_everywhere(double scale, double* tightest = nullptr) {
  std::mt19937_64 rng(20261128);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst = 0.0;
  for (int trial = 0; trial < 300; ++trial) {
    const Scene scene = testing::random_chain_scene(rng, /*scales=*/false);
    const BoxMotion bound(scene);
    const std::size_t p = scene.reference_parameters.size();
    std::vector<double> lo(p), hi(p), c(p);
    random_box(scene, rng, lo, hi, c);
    const double m = scale * bound.reach(0, lo, hi, c);
    std::vector<double> q(p);
    for (int s = 0; s < 200; ++s) {
      for (std::size_t i = 0; i < p; ++i) {
        const double t = s < 64 ? static_cast<double>((s >> (i % 6)) & 1) : u(rng);  // corners first
        q[i] = lo[i] + t * (hi[i] - lo[i]);
      }
      const double d = moved(scene, c, q);
      if (d > m) return false;
      if (m > 0.0) worst = std::max(worst, d / m);
    }
  }
  if (tightest) *tightest = worst;
  return true;
}

TEST(BoxMotion, NoVertexMovesFartherThanTheBound) {
  double tightest = 0.0;
  EXPECT_TRUE(holds_everywhere(1.0, &tightest));
  // The sampling comes near the bound somewhere (it is not vacuous).
  EXPECT_GT(tightest, 0.5);
}

TEST(BoxMotion, AHalvedBoundFails) { EXPECT_FALSE(holds_everywhere(0.5)); }

// Along random straight motions qa -> qb (the box they span, its centre
// the midpoint), no vertex moves between q(t1) and q(t2) farther than
// scale * 2 reach * (t2 - t1): whole motions, halves, short pieces
// anywhere and pieces at the ends.
bool rate_holds(double scale, BoxMotion::Points points, double* tightest = nullptr) {
  std::mt19937_64 rng(20261202);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst = 0.0;
  for (int trial = 0; trial < 300; ++trial) {
    const Scene scene = testing::random_chain_scene(rng, /*scales=*/trial % 3 == 0);
    const BoxMotion bound(scene, points);
    const std::size_t p = scene.reference_parameters.size();
    std::vector<double> qa(p), qb(p), lo(p), hi(p), mid(p);
    for (const Action& a : scene.actions)
      for (int k = 0; k < a.parameter_count; ++k) {
        const std::size_t i = static_cast<std::size_t>(a.first_parameter + k);
        // Motions from a hair to about two radians (or metres) long.
        const double length = 2.0 * std::pow(10.0, -3.0 * u(rng)) / a.unit_to_si;
        qa[i] = (u(rng) * 8.0 - 4.0) / a.unit_to_si;
        qb[i] = qa[i] + (u(rng) < 0.5 ? -length : length) * (rng() % 4 == 0 ? 0.0 : 1.0);
        lo[i] = std::min(qa[i], qb[i]);
        hi[i] = std::max(qa[i], qb[i]);
        mid[i] = std::clamp(qa[i] + 0.5 * (qb[i] - qa[i]), lo[i], hi[i]);
      }
    const double rate = scale * 2.0 * bound.reach(0, lo, hi, mid);
    std::vector<double> x, y;
    for (int s = 0; s < 60; ++s) {
      double t1 = u(rng), t2 = u(rng);
      if (s == 0) t1 = 0.0, t2 = 1.0;
      if (s == 1) t1 = 0.0, t2 = 0.5;
      if (s % 4 == 2) t2 = t1 + 1e-3 * u(rng);
      if (s % 4 == 3) t1 = 0.0, t2 = 0.05 * u(rng);
      if (t2 < t1) std::swap(t1, t2);
      t2 = std::min(t2, 1.0);
      if (!(t2 > t1)) continue;
      state_between(qa, qb, t1, x);
      state_between(qa, qb, t2, y);
      const double d = moved(scene, x, y);
      // Plus the rounding of two poses (vertices within metres: 1e-14 m)
      // and of the parameters state_between gives (a few ulps each, times
      // a lever of metres); the march's guards hold far more.
      const double m = rate * (t2 - t1);
      if (d > m + 1e-12) return false;
      if (m > 0.0) worst = std::max(worst, d / m);
    }
  }
  if (tightest) *tightest = worst;
  return true;
}

TEST(BoxMotion, TwiceTheReachFromTheMidpointIsARateAlongTheMotion) {
  for (const BoxMotion::Points points : {BoxMotion::Points::kCorners, BoxMotion::Points::kTriangles}) {
    double tightest = 0.0;
    EXPECT_TRUE(rate_holds(1.0, points, &tightest));
    EXPECT_GT(tightest, 0.5);
  }
}

// Whether every sampled point of every triangle, posed at random q of a
// random box, lies within shrink * (radius + move) of the centre of a ball
// whose move (times shrink) bounds its displacement from c.
bool balls_hold(double shrink) {
  std::mt19937_64 rng(20261203);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 300; ++trial) {
    const Scene scene = testing::random_chain_scene(rng, /*scales=*/false);
    const BoxMotion bound(scene, BoxMotion::Points::kTriangles);
    const std::size_t p = scene.reference_parameters.size();
    std::vector<double> lo(p), hi(p), c(p);
    random_box(scene, rng, lo, hi, c);
    std::vector<BoxMotion::Ball> balls;
    if (!bound.balls(0, lo, hi, c, balls)) return false;  // rigid chains always have them
    const Mesh& mesh = scene.parts[0].mesh;
    const Affine tc = part_transform(scene, 0, c);
    std::vector<double> q(p);
    for (int s = 0; s < 40; ++s) {
      for (std::size_t i = 0; i < p; ++i) q[i] = lo[i] + (s < 16 ? static_cast<double>((s >> (i % 4)) & 1) : u(rng)) * (hi[i] - lo[i]);
      const Affine tq = part_transform(scene, 0, q);
      for (const Tri& t : mesh.triangles) {
        const Vec3 x = mesh.vertices[t[0]], y = mesh.vertices[t[1]], z = mesh.vertices[t[2]];
        for (const Vec3& point : {x, y, z, Vec3(0.5 * (x + y)), Vec3(0.5 * (y + z)), Vec3(0.5 * (z + x)), Vec3((x + y + z) / 3.0)}) {
          const Vec3 at = tq * point;
          const double moved = (at - tc * point).norm();
          bool held = false;
          for (const BoxMotion::Ball& b : balls)
            held = held || ((at - b.centre).norm() <= shrink * (b.radius + b.move) + 1e-12 &&
                            moved <= shrink * b.move + 1e-12 && (tc * point - b.centre).norm() <= shrink * b.radius + 1e-12);
          if (!held) return false;
        }
      }
    }
  }
  return true;
}

TEST(BoxMotion, EveryPointOfThePartStaysInOneOfItsBalls) {
  EXPECT_TRUE(balls_hold(1.0));
  EXPECT_FALSE(balls_hold(0.9));
}

TEST(BoxMotion, HalfTheRateFails) {
  EXPECT_FALSE(rate_holds(0.5, BoxMotion::Points::kCorners));
  EXPECT_FALSE(rate_holds(0.5, BoxMotion::Points::kTriangles));
}

}  // namespace
}  // namespace plancheck
