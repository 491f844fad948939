// SPDX-License-Identifier: MIT
// piece_lower_bound (src/checks/continuous.h) against distances known in
// closed form: a point passing an obstacle point in a straight line, and a
// point turning about a centre past one (the two motions whose distance
// curves the most for their speed and acceleration: the bound's constant is
// exact for both at the closest approach). The bound must never exceed the
// true minimum over the piece, and must certify pieces the first order
// cannot.
#include "src/checks/continuous.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <random>

namespace plancheck {
namespace {

struct Motion {
  std::function<double(double)> distance;  // at t
  double speed = 0.0;                       // bound of |y'|
  double accel = 0.0;                       // bound of |y''|
};

// A point moving in a straight line at `speed`, closest (at `gap`) to the
// obstacle at t0.
Motion straight(double gap, double speed, double t0) {
  return {[=](double t) { return std::hypot(gap, speed * (t - t0)); }, speed, 0.0};
}

// A point on a circle of radius r about the origin turning at w (rad per
// unit of t), nearest an obstacle at distance b > r from the origin at t0.
Motion turning(double r, double b, double w, double t0) {
  return {[=](double t) { return std::sqrt(r * r + b * b - 2.0 * r * b * std::cos(w * (t - t0))); }, r * w,
          r * w * w};
}

// The least distance over [t1, t2]: dense samples and the closest approach t0.
double least(const Motion& m, double t1, double t2, double t0) {
  double out = std::min(m.distance(t1), m.distance(t2));
  for (int i = 1; i < 4000; ++i) out = std::min(out, m.distance(t1 + (t2 - t1) * i / 4000.0));
  if (t0 > t1 && t0 < t2) out = std::min(out, m.distance(t0));
  return out;
}

TEST(PieceLowerBound, NeverAboveTheTrueMinimum) {
  std::mt19937_64 rng(20261202);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int second_order_wins = 0;
  for (int i = 0; i < 20000; ++i) {
    const bool turn = i % 2 == 1;
    const double t0 = u(rng);
    Motion m;
    if (turn) {
      const double r = 0.05 + 3.0 * u(rng);
      m = turning(r, r + 0.001 + 0.2 * u(rng), 0.01 + 3.0 * u(rng), t0);
    } else {
      m = straight(0.001 + 0.2 * u(rng), 0.01 + 3.0 * u(rng), t0);
    }
    // Pieces around the closest approach, most of them short (where the
    // second order counts), some anywhere.
    const double half = std::pow(10.0, -4.0 + 3.5 * u(rng));
    double t1 = t0 - half * u(rng) * 2.0, t2 = t0 + half * u(rng) * 2.0;
    if (i % 5 == 0) {
      t1 = u(rng);
      t2 = t1 + 0.3 * u(rng);
    }
    // Lower bounds at the ends, sometimes below the distances.
    const double shrink = i % 3 == 0 ? 1.0 - 0.01 * u(rng) : 1.0;
    const double v1 = m.distance(t1) * shrink, v2 = m.distance(t2) * shrink;
    const double bound = piece_lower_bound(t1, v1, t2, v2, m.speed, m.accel);
    const double truth = least(m, t1, t2, t0);
    ASSERT_LE(bound, truth + 1e-12) << (turn ? "turning" : "straight") << " case " << i << ": [" << t1 << ", "
                                    << t2 << "] v " << v1 << ", " << v2 << " speed " << m.speed << " accel "
                                    << m.accel;
    const double first = std::min({v1, v2, 0.5 * (v1 + v2 - m.speed * (t2 - t1))});
    second_order_wins += bound > first + 1e-9;
  }
  EXPECT_GT(second_order_wins, 5000);
}

TEST(PieceLowerBound, CertifiesAPassAlongTheMarginTheFirstOrderCannot) {
  // 5 cm at the closest approach, moving at 1 m per unit of t: over a piece
  // of 0.004 either side the first order proves only 4.6 cm.
  const Motion m = straight(0.05, 1.0, 0.5);
  const double t1 = 0.496, t2 = 0.504;
  const double v = m.distance(t1);
  const double bound = piece_lower_bound(t1, v, t2, v, m.speed, m.accel);
  EXPECT_LT(0.5 * (2.0 * v - m.speed * (t2 - t1)), 0.0462);
  EXPECT_GT(bound, 0.04998);
  EXPECT_LE(bound, 0.05);
}

TEST(PieceLowerBound, FirstOrderOnlyWhenItCannotBoundTheCurve) {
  // No room (the first order's bound at or below 0), no acceleration bound,
  // not finite: the first order's value.
  EXPECT_EQ(piece_lower_bound(0.0, 0.01, 1.0, 0.01, 1.0, 0.0), std::min(0.01, 0.5 * (0.02 - 1.0)));
  EXPECT_EQ(piece_lower_bound(0.0, 0.05, 0.01, 0.05, 1.0, std::numeric_limits<double>::infinity()),
            0.5 * (0.1 - 0.01));
  EXPECT_TRUE(std::isnan(piece_lower_bound(0.0, std::nan(""), 0.01, 0.05, 1.0, 0.0)));
  EXPECT_EQ(piece_lower_bound(0.0, 0.05, 0.01, 0.05, std::numeric_limits<double>::infinity(), 0.0),
            -std::numeric_limits<double>::infinity());
  // A still pair: its ends' least value.
  EXPECT_EQ(piece_lower_bound(0.0, 0.05, 1.0, 0.07, 0.0, 0.0), 0.05);
}

}  // namespace
}  // namespace plancheck
