// SPDX-License-Identifier: MIT
#include "kernels/box.h"

#include "src/scene/scene.h"

#include <gtest/gtest.h>

#include <random>

namespace plancheck {
namespace {

AffineMap random_map(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  AffineMap m;
  for (int k = 0; k < 9; ++k) {
    m.l[k] = u(rng);
    m.abs_l[k] = std::abs(m.l[k]);
  }
  for (double& t : m.t) t = 1e3 * u(rng);
  return m;
}

// Every point of a box, mapped, lies in the mapped box; the box distance is
// a lower bound of the distance of any two contained points.
TEST(Box, MappedBoxContainsMappedPointsAndDistanceIsALowerBound) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0), f(0.0, 1.0);
  const double no_margin[3] = {0, 0, 0};
  for (int it = 0; it < 2000; ++it) {
    const AffineMap m = random_map(rng);
    float lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
      const float a = static_cast<float>(u(rng)), b = static_cast<float>(u(rng));
      lo[k] = std::min(a, b);
      hi[k] = std::max(a, b);
    }
    double mlo[3], mhi[3];
    map_box(m, lo, hi, no_margin, mlo, mhi);
    double wlo[3], whi[3];
    widen_box(lo, hi, no_margin, wlo, whi);
    for (int s = 0; s < 20; ++s) {
      double x[3], y[3], mx[3];
      for (int k = 0; k < 3; ++k) {
        x[k] = lo[k] + f(rng) * (static_cast<double>(hi[k]) - lo[k]);
        y[k] = wlo[k] + f(rng) * (whi[k] - wlo[k]);
      }
      m.apply(x, mx);
      for (int k = 0; k < 3; ++k) {
        // Exact containment up to the rounding the callers' margins cover.
        const double tol = 1e-12 * (std::abs(mx[k]) + 1.0);
        ASSERT_GE(mx[k], mlo[k] - tol);
        ASSERT_LE(mx[k], mhi[k] + tol);
      }
      const double d2 = (Vec3(mx[0], mx[1], mx[2]) - Vec3(y[0], y[1], y[2])).squaredNorm();
      ASSERT_LE(box_distance_squared(mlo, mhi, wlo, whi), d2 * (1 + 1e-12) + 1e-12);
    }
  }
}

TEST(Box, OverlapIsClosedAndSymmetric) {
  const double a_lo[3] = {0, 0, 0}, a_hi[3] = {1, 1, 1};
  const double b_lo[3] = {1, 0.5, 0.5}, b_hi[3] = {2, 2, 2};  // shares the face x = 1
  EXPECT_TRUE(boxes_overlap(a_lo, a_hi, b_lo, b_hi));
  EXPECT_TRUE(boxes_overlap(b_lo, b_hi, a_lo, a_hi));
  EXPECT_EQ(box_distance_squared(a_lo, a_hi, b_lo, b_hi), 0.0);
  const double c_lo[3] = {1.5, 3, 0}, c_hi[3] = {2, 4, 1};
  EXPECT_FALSE(boxes_overlap(a_lo, a_hi, c_lo, c_hi));
  EXPECT_DOUBLE_EQ(box_distance_squared(a_lo, a_hi, c_lo, c_hi), 0.25 + 4.0);
}

}  // namespace
}  // namespace plancheck
