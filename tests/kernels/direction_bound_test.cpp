// SPDX-License-Identifier: MIT
// The best-direction skip test (kernels/direction_bound.h) against the exact
// double kernel: a pair it skips must have a kernel distance of at least the
// best one, on random pairs and on adversarial ones around a best pair
// (parallel faces at the same distance, shared vertices and edges, curved
// patches, gaps down to 1e-12, offsets up to 1e6).
#include "kernels/direction_bound.h"
#include "kernels/tri_distance.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

namespace plancheck {
namespace {

using Tri9 = std::array<double, 9>;

double magnitude(const Tri9& t) {
  double m = 0.0;
  for (double x : t) m = std::max(m, std::abs(x));
  return m;
}

struct Counts {
  int skipped = 0, tested = 0;
};

// The best pair (p0, q0) sets the direction; every pair (p, q) the test
// skips must have a kernel distance >= best. slack as DistanceQuery sizes
// it: 1e-13 times the largest coordinate magnitude.
void check_against(const Tri9& p0, const Tri9& q0, const std::vector<std::pair<Tri9, Tri9>>& others,
                   double size, Counts& counts) {
  Eigen::Vector3d pa, pb;
  const double best = std::sqrt(tri_distance_disjoint2(p0.data(), q0.data(), pa, pb));
  DirectionBound dir;
  if (!dir.set(pa.data(), pb.data(), best, 1e-13 * size)) return;
  for (const auto& [p, q] : others) {
    ++counts.tested;
    if (dir.low(q.data()) - dir.high(p.data()) < dir.cut) continue;
    ++counts.skipped;
    // tri_distance: 0 for an intersecting pair (a search's pairs are disjoint).
    const double d = tri_distance(p.data(), q.data()).distance;
    ASSERT_GE(d, best) << "skipped a closer pair: " << d << " < " << best;
  }
}

Tri9 translated(Tri9 t, const Eigen::Vector3d& by) {
  for (int v = 0; v < 3; ++v)
    for (int k = 0; k < 3; ++k) t[3 * v + k] += by[k];
  return t;
}

TEST(DirectionBound, RandomPairsNeverSkipACloserPair) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Counts counts;
  for (int it = 0; it < 400; ++it) {
    const double offset = it % 4 == 0 ? 0.0 : std::pow(10.0, it % 7);  // up to 1e6
    const Eigen::Vector3d o(offset * u(rng), offset * u(rng), offset * u(rng));
    auto tri = [&](const Eigen::Vector3d& at, double s) {
      Tri9 t;
      for (int v = 0; v < 3; ++v)
        for (int k = 0; k < 3; ++k) t[3 * v + k] = o[k] + at[k] + s * u(rng);
      return t;
    };
    const double gap = std::pow(10.0, -(it % 13));  // 1 down to 1e-12
    const Tri9 p0 = tri(Eigen::Vector3d(0, 0, -0.5), 0.4);
    Tri9 q0 = tri(Eigen::Vector3d(0, 0, 0.5), 0.4);
    // Move q0 so the pair's gap on z is about `gap`.
    double top = -1e300, bottom = 1e300;
    for (int v = 0; v < 3; ++v) {
      top = std::max(top, p0[3 * v + 2]);
      bottom = std::min(bottom, q0[3 * v + 2]);
    }
    q0 = translated(q0, Eigen::Vector3d(0, 0, top - bottom + gap));
    std::vector<std::pair<Tri9, Tri9>> others;
    for (int k = 0; k < 40; ++k) {
      const double reach = k % 2 ? 0.1 : 1.0;
      const Eigen::Vector3d da(reach * u(rng), reach * u(rng), reach * u(rng));
      const Eigen::Vector3d db(reach * u(rng), reach * u(rng), reach * u(rng));
      others.emplace_back(translated(p0, da), translated(q0, db));
      others.emplace_back(tri(Eigen::Vector3d(0, 0, -0.5), 0.5), tri(Eigen::Vector3d(0, 0, 0.5), 0.5));
    }
    others.emplace_back(p0, q0);  // the best pair itself
    double size = std::max(magnitude(p0), magnitude(q0));
    for (const auto& [p, q] : others) size = std::max({size, magnitude(p), magnitude(q)});
    check_against(p0, q0, others, size, counts);
  }
  // Not vacuous: the test settles a good share of these pairs.
  EXPECT_GT(counts.skipped, counts.tested / 10) << counts.skipped << " of " << counts.tested;
}

TEST(DirectionBound, AdversarialPairsNeverSkipACloserPair) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Counts counts;
  for (int it = 0; it < 300; ++it) {
    const double offset = std::pow(10.0, it % 7) * (it % 2 ? 1.0 : -1.0);
    const Eigen::Vector3d o(offset, -0.5 * offset, 0.25 * offset);
    const double gap = std::pow(10.0, -(it % 13));
    // A random frame: the parallel planes z' = 0 and z' = gap in it.
    Eigen::Quaterniond rot(u(rng), u(rng), u(rng), u(rng));
    rot.normalize();
    const Eigen::Matrix3d r = it % 5 == 0 ? Eigen::Matrix3d::Identity() : rot.toRotationMatrix();
    auto at = [&](double x, double y, double z) {
      return Eigen::Vector3d(o + r * Eigen::Vector3d(x, y, z));
    };
    auto tri = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
      return Tri9{a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2]};
    };
    // The best pair: facing triangles on the two planes.
    const Tri9 p0 = tri(at(0, 0, 0), at(1, 0, 0), at(0, 1, 0));
    const Tri9 q0 = tri(at(0.2, 0.2, gap), at(1.2, 0.2, gap), at(0.2, 1.2, gap));
    std::vector<std::pair<Tri9, Tri9>> others;
    for (int k = 0; k < 30; ++k) {
      const double x = 2 * u(rng), y = 2 * u(rng);
      // Parallel faces at the very same distance (ties; skipped or not, never closer).
      others.emplace_back(tri(at(x, y, 0), at(x + 0.5, y, 0), at(x, y + 0.5, 0)),
                          tri(at(x, y, gap), at(x + 0.4, y + 0.1, gap), at(x + 0.1, y + 0.6, gap)));
      // Sharing the best pair's vertices, bent away (a convex patch) or towards it.
      const double bend = (k % 2 ? 1 : -1) * 0.3 * std::abs(u(rng));
      others.emplace_back(tri(at(0, 0, 0), at(-1, 0, -bend), at(0, -1, -bend)), q0);
      others.emplace_back(p0, tri(at(0.2, 0.2, gap), at(-0.8, 0.2, gap + bend), at(0.2, -0.8, gap + bend)));
      // Sharing an edge, tilted.
      others.emplace_back(tri(at(1, 0, 0), at(0, 1, 0), at(1, 1, bend)), q0);
      // Slivers and zero-area triangles near the gap.
      others.emplace_back(tri(at(x, y, 0), at(x + 1e-9, y, 0), at(x + 2e-9, y, 0)),
                          tri(at(x, y, gap), at(x, y + 1e-12, gap), at(x, y, gap)));
      // Vertices just inside the slab (closer than the best).
      others.emplace_back(tri(at(0.3, 0.3, 1e-3 * gap), at(0.5, 0.3, 0), at(0.3, 0.5, 0)), q0);
    }
    double size = std::max(magnitude(p0), magnitude(q0));
    for (const auto& [p, q] : others) size = std::max({size, magnitude(p), magnitude(q)});
    check_against(p0, q0, others, size, counts);
  }
  // Most of these sit at the tie (not skipped); the rest must be.
  EXPECT_GT(counts.skipped, counts.tested / 100) << counts.skipped << " of " << counts.tested;
}

TEST(DirectionBound, CoincidentPointsSetNoDirection) {
  const double p[3] = {1, 2, 3};
  DirectionBound dir;
  EXPECT_FALSE(dir.set(p, p, 0.0, 1e-13));
  EXPECT_TRUE(std::isinf(dir.cut));
  const double a[3] = {0, 0, 0}, b[3] = {0, 0, 1e-120};
  EXPECT_FALSE(dir.set(a, b, 1e-120, 1e-13));
  const double c[3] = {0, 3, 4};
  ASSERT_TRUE(dir.set(a, c, 5.0, 1e-13));
  EXPECT_DOUBLE_EQ(dir.n[1], 0.6);
  EXPECT_DOUBLE_EQ(dir.n[2], 0.8);
}

}  // namespace
}  // namespace plancheck
