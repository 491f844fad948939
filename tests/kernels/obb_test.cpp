// SPDX-License-Identifier: MIT
// The ball pre-check of the distance descent (kernels/obb.h balls_within)
// against the ball bound it stands in for: whenever it says the balls are
// within reach, the ball test the descent would have run (ball_gap > 0 and
// its square, shrunk, at least fl(cut^2)) must fail, so the same node pairs
// prune. Random centres and radii with offsets up to 1e6, cuts from 0 to
// infinity, and centres placed within a few ulps of the reach.
#include "kernels/obb.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace plancheck {
namespace {

// The descent's prune test on the ball bound (collision_model.cpp lower2),
// with its shrink factor and without.
bool ball_prunes(double gap, double cut) {
  const double best2 = cut * cut;
  for (double shrink : {1.0 - 1e-12, 1.0})
    if (gap > 0.0 && gap * gap * shrink >= best2) return true;
  return false;
}

struct Counts {
  int within = 0, pruned = 0;
};

// One case: centre b at distance `centres` from ca along a random direction.
void check(const double* ca, const double* dir, double centres, double ra, double rb, double cut,
           Counts& counts) {
  double cb[3];
  for (int k = 0; k < 3; ++k) cb[k] = ca[k] + centres * dir[k];
  const double dx = cb[0] - ca[0], dy = cb[1] - ca[1], dz = cb[2] - ca[2];
  const double d2 = dx * dx + dy * dy + dz * dz;
  for (double extra : {0.0, 1e-300, 1e-9}) {
    const bool prunes = ball_prunes(ball_gap(d2, ca, cb, ra, rb, extra), cut);
    counts.pruned += prunes;
    if (balls_within(d2, ra, rb, cut)) {
      ++counts.within;
      ASSERT_FALSE(prunes) << "balls within reach, yet the ball test prunes: d2 " << d2 << " ra " << ra
                           << " rb " << rb << " cut " << cut << " extra " << extra;
    }
  }
}

TEST(Obb, BallsWithinReachNeverPrune) {
  std::mt19937_64 rng(16);
  std::uniform_real_distribution<double> u(-1.0, 1.0), pos(0.0, 1.0);
  std::normal_distribution<double> g;
  Counts counts;
  const double inf = std::numeric_limits<double>::infinity();
  for (int n = 0; n < 200000; ++n) {
    const double offset = std::pow(10.0, 6.0 * pos(rng));
    const double ca[3] = {offset * u(rng), offset * u(rng), offset * u(rng)};
    double dir[3] = {g(rng), g(rng), g(rng)};
    const double len = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    for (double& c : dir) c /= len;
    const double scale = std::pow(10.0, -6.0 + 8.0 * pos(rng));
    const double ra = scale * pos(rng), rb = n % 7 == 0 ? 0.0 : scale * pos(rng);
    const int kind = n % 5;
    const double cut = kind == 0 ? 0.0 : kind == 1 ? inf : scale * std::pow(10.0, -3.0 + 4.0 * pos(rng));
    const double reach = ra + rb + (std::isfinite(cut) ? cut : 0.0);
    // Around the reach: relative offsets from -1e-9 to 1e-9, and ulps.
    for (double rel : {-1e-9, -1e-12, -3e-13, -1e-13, -1e-15, 0.0, 1e-15, 1e-13, 1e-12, 1e-9, 1e-3})
      ASSERT_NO_FATAL_FAILURE(check(ca, dir, reach * (1.0 + rel), ra, rb, cut, counts));
    double c = reach;
    for (int k = 0; k < 4; ++k) {
      c = std::nextafter(c, inf);
      ASSERT_NO_FATAL_FAILURE(check(ca, dir, c, ra, rb, cut, counts));
    }
    // Anywhere from the centres together to far apart.
    ASSERT_NO_FATAL_FAILURE(check(ca, dir, 2.0 * reach * pos(rng), ra, rb, cut, counts));
  }
  // Not vacuous: both outcomes occur often.
  EXPECT_GT(counts.within, 1000000);
  EXPECT_GT(counts.pruned, 100000);
}

// Nothing is proven from a NaN or infinite distance.
TEST(Obb, BallsWithinProvesNothingFromNaN) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(balls_within(nan, 1.0, 1.0, 1.0));
  EXPECT_FALSE(balls_within(inf, 1.0, 1.0, 1.0));
  EXPECT_FALSE(balls_within(1.0, nan, 1.0, 1.0));
  EXPECT_TRUE(balls_within(1.0, 1.0, 1.0, inf));  // no best yet: the ball test cannot prune
}

}  // namespace
}  // namespace plancheck
