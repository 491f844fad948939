// SPDX-License-Identifier: MIT
// The crossing witness (src/geometry/crossing.h): whenever it certifies a
// pair for corner moves da, db, every such move leaves the triangles
// intersecting by the exact test (kernels/tri_tri_overlap.h), including the
// extreme moves; grazing and touching pairs are refused.
#include "src/geometry/crossing.h"

#include "kernels/tri_tri_overlap.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

namespace plancheck {
namespace {

using Six = std::array<Vec3, 6>;

bool overlap(const Six& x) {
  return tri_tri_overlap(x[0].data(), x[1].data(), x[2].data(), x[3].data(), x[4].data(), x[5].data());
}

// A 2 m square's triangle in z = 0, and a 1 m tall triangle standing
// through it, its lower edge `depth` below the plane.
Six standing(double depth) {
  return {Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(0, 1, 0),
          Vec3(-0.1, 0, -depth), Vec3(0.1, 0, -depth), Vec3(0, 0, 1 - depth)};
}

TEST(Crossing, DeepCrossingHoldsForMovesBelowItsRoom) {
  const Six x = standing(0.3);
  ASSERT_TRUE(overlap(x));
  EXPECT_TRUE(crossing_certain(x, 0.0, 0.0));
  EXPECT_TRUE(crossing_certain(x, 0.01, 0.01));
  // The standing triangle's lower corners are 0.3 below the plane: moves
  // of 0.3 can lift them onto it, so no certificate.
  EXPECT_FALSE(crossing_certain(x, 0.3, 0.0));
  EXPECT_FALSE(crossing_certain(x, 0.0, 0.3));
  EXPECT_FALSE(crossing_certain(x, 1.0, 1.0));
}

TEST(Crossing, GrazingAndTouchingPairsAreRefused) {
  // Touching: the standing triangle's lower edge lies in the plane.
  const Six touch = standing(0.0);
  ASSERT_TRUE(overlap(touch));
  EXPECT_FALSE(crossing_certain(touch, 0.0, 0.0));
  // One ulp-scale below the plane: intersecting, far too thin to survive 1 nm.
  const Six graze = standing(1e-12);
  ASSERT_TRUE(overlap(graze));
  EXPECT_FALSE(crossing_certain(graze, 1e-9, 0.0));
  // Crossing the plane at the square's edge (x = 1 corner region): the
  // crossing point 1 mm inside the boundary refuses a 1 cm move.
  Six edge = standing(0.3);
  for (int i = 3; i < 6; ++i) edge[i] += Vec3(0.0, -1.0 + 0.001, 0.0);
  ASSERT_TRUE(overlap(edge));
  EXPECT_FALSE(crossing_certain(edge, 0.01, 0.0));
  // Coplanar overlap: no edge crosses a plane.
  Six flat = standing(0.3);
  for (int i = 3; i < 6; ++i) flat[i].z() = 0.0;
  EXPECT_FALSE(crossing_certain(flat, 0.0, 0.0));
  // Apart, and not finite.
  Six apart = standing(-0.5);
  EXPECT_FALSE(crossing_certain(apart, 0.0, 0.0));
  Six nan = standing(0.3);
  nan[4].x() = std::nan("");
  EXPECT_FALSE(crossing_certain(nan, 0.0, 0.0));
  EXPECT_FALSE(crossing_certain(standing(0.3), std::nan(""), 0.0));
}

// Random pairs at every scale: a certificate for (da, db) holds under
// random moves of every corner within them, and under the extreme ones
// (every corner moved by exactly da or db, along a random direction or
// along the other triangle's normal, both ways).
TEST(Crossing, CertifiedPairsStayIntersectingUnderEveryMove) {
  std::mt19937_64 rng(33);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto dir = [&] {
    Vec3 v;
    do v = Vec3(u(rng), u(rng), u(rng));
    while (v.norm() < 0.1 || v.norm() > 1.0);
    return v.normalized();
  };
  int certified = 0, refused_overlapping = 0;
  for (int n = 0; n < 20000; ++n) {
    const double scale = std::pow(10.0, std::uniform_int_distribution<int>(-3, 2)(rng));
    const Vec3 offset = Vec3(u(rng), u(rng), u(rng)) * 100.0 * scale;
    Six x;
    for (Vec3& c : x) c = offset + Vec3(u(rng), u(rng), u(rng)) * scale;
    if (!overlap(x)) continue;
    // Moves from 1e-4 to 0.1 of the triangles' size, log-uniform.
    const double da = 0.1 * scale * std::pow(10.0, -3.0 * std::abs(u(rng)));
    const double db = 0.1 * scale * std::pow(10.0, -3.0 * std::abs(u(rng)));
    if (!crossing_certain(x, da, db)) {
      ++refused_overlapping;
      continue;
    }
    ++certified;
    const Vec3 na = (x[1] - x[0]).cross(x[2] - x[0]).normalized();
    const Vec3 nb = (x[4] - x[3]).cross(x[5] - x[3]).normalized();
    for (int trial = 0; trial < 40; ++trial) {
      Six y = x;
      for (int c = 0; c < 6; ++c) {
        const double d = c < 3 ? da : db;
        Vec3 step;
        switch (trial % 4) {
          case 0: step = dir() * d * std::abs(u(rng)); break;   // anywhere within
          case 1: step = dir() * d; break;                      // on the sphere
          case 2: step = (c < 3 ? nb : na) * d * ((c + trial / 4) % 2 ? 1.0 : -1.0); break;
          default: step = (c < 3 ? nb : na) * d * (u(rng) < 0 ? 1.0 : -1.0); break;
        }
        y[c] += step;
      }
      ASSERT_TRUE(overlap(y)) << "pair " << n << " trial " << trial << " scale " << scale;
    }
  }
  // The test has teeth: many certificates, and many intersecting pairs
  // whose room is below the moves asked.
  EXPECT_GT(certified, 1000);
  EXPECT_GT(refused_overlapping, 1000);
}

}  // namespace
}  // namespace plancheck
