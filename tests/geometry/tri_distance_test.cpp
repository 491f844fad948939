// SPDX-License-Identifier: MIT
#include "kernels/tri_distance.h"

#include "support/brute_force.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

namespace plancheck {
namespace {

using Tri3 = std::array<Vec3, 3>;

void flatten(const Tri3& t, double* out) {
  for (int k = 0; k < 3; ++k)
    for (int c = 0; c < 3; ++c) out[3 * k + c] = t[k][c];
}

TriDistance kernel(const Tri3& p, const Tri3& q) {
  double a[9], b[9];
  flatten(p, a);
  flatten(q, b);
  return tri_distance(a, b);
}

// Distance from x to the closed triangle t, by the reference (a degenerate
// "triangle" q = (x, x, x)).
long double point_to_triangle(const Vec3& x, const Tri3& t) {
  const Vec3 q[3] = {x, x, x};
  return testing::reference_tri_distance(t.data(), q);
}

// The returned points must lie on their triangles and realise the distance.
void expect_consistent(const Tri3& p, const Tri3& q, const TriDistance& d, double scale) {
  EXPECT_LE(static_cast<double>(point_to_triangle(d.point_p, p)), 1e-14 * scale);
  EXPECT_LE(static_cast<double>(point_to_triangle(d.point_q, q)), 1e-14 * scale);
  EXPECT_NEAR((d.point_p - d.point_q).norm(), d.distance, 1e-14 * scale);
}

TEST(TriDistance, RandomDisjointMatchesIndependentReference) {
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int disjoint = 0;
  double worst = 0.0;
  for (int it = 0; it < 20000; ++it) {
    Tri3 p, q;
    const Vec3 shift = Vec3(u(rng), u(rng), u(rng)) * (it % 3 == 0 ? 0.3 : 2.0);
    for (auto& v : p) v = Vec3(u(rng), u(rng), u(rng));
    for (auto& v : q) v = Vec3(u(rng), u(rng), u(rng)) + shift;
    const TriDistance d = kernel(p, q);
    const bool exact = testing::exact_tri_tri_reference(p.data(), q.data());
    ASSERT_EQ(d.intersecting, exact) << it;
    if (exact) {
      EXPECT_EQ(d.distance, 0.0);
      // The common point lies (approximately) on both triangles.
      EXPECT_LE(static_cast<double>(point_to_triangle(d.point_p, p)), 1e-9);
      EXPECT_LE(static_cast<double>(point_to_triangle(d.point_p, q)), 1e-9);
      continue;
    }
    ++disjoint;
    const double ref = static_cast<double>(testing::reference_tri_distance(p.data(), q.data()));
    ASSERT_GT(ref, 0.0);
    const double rel = std::abs(d.distance - ref) / ref;
    worst = std::max(worst, rel);
    ASSERT_LE(rel, 1e-12) << it << " kernel " << d.distance << " reference " << ref;
    expect_consistent(p, q, d, 1.0);
  }
  EXPECT_GT(disjoint, 5000);
  RecordProperty("worst_relative_error", std::to_string(worst));
}

TEST(TriDistance, FarFromOriginAndSmallGaps) {
  // A vertex of q straight above p's interior, at heights 1e-3 .. 1e-9,
  // 1.7374e6 m from the origin: the distance is the height (to rounding of
  // the shifted coordinates).
  const Vec3 o(1.7374e6, 0.25, -1.7374e6);
  const Tri3 p = {o + Vec3(0, 0, 0), o + Vec3(4, 0, 0), o + Vec3(0, 4, 0)};
  for (double gap = 1e-3; gap >= 1e-9; gap /= 10) {
    const Tri3 q = {o + Vec3(1, 1, gap), o + Vec3(1, 2, 1), o + Vec3(2, 1, 1)};
    const double h = q[0].z() - o.z();
    const TriDistance d = kernel(p, q);
    EXPECT_FALSE(d.intersecting);
    EXPECT_NEAR(d.distance, h, 1e-15 * 2e6);
    EXPECT_EQ(d.point_q, q[0]);
  }
}

TEST(TriDistance, DegenerateTrianglesGiveNoNaN) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int it = 0; it < 5000; ++it) {
    Tri3 p, q;
    for (auto& v : p) v = Vec3(u(rng), u(rng), u(rng));
    for (auto& v : q) v = Vec3(u(rng), u(rng), u(rng)) + Vec3(1.5, 0, 0);
    // Collapse one or both: repeated vertices or collinear ones.
    switch (it % 4) {
      case 0: q[1] = q[0]; break;
      case 1: q[2] = q[0] + 0.5 * (q[1] - q[0]); break;
      case 2: q[1] = q[2] = q[0]; break;
      default: p[2] = p[1]; q[2] = q[1]; break;
    }
    const TriDistance d = kernel(p, q);
    ASSERT_TRUE(std::isfinite(d.distance)) << it;
    ASSERT_TRUE(d.point_p.allFinite() && d.point_q.allFinite()) << it;
    if (d.intersecting) continue;
    const double ref = static_cast<double>(testing::reference_tri_distance(p.data(), q.data()));
    ASSERT_NEAR(d.distance, ref, 1e-12 * std::max(ref, 1e-3)) << it;
  }
}

TEST(TriDistance, TouchingIsZero) {
  const Tri3 p = {Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 4, 0)};
  const Tri3 q = {Vec3(1, 1, 0), Vec3(1, 2, 1), Vec3(2, 1, 1)};
  const TriDistance d = kernel(p, q);
  EXPECT_TRUE(d.intersecting);
  EXPECT_EQ(d.distance, 0.0);
  EXPECT_LE((d.point_p - Vec3(1, 1, 0)).norm(), 1e-15);
  // Piercing: no vertex or edge pair is at distance 0, the common point must
  // still be found.
  const Tri3 r = {Vec3(1, 1, -1), Vec3(1, 1, 1), Vec3(9, 9, 9)};
  const TriDistance e = kernel(p, r);
  EXPECT_TRUE(e.intersecting);
  EXPECT_LE((e.point_p - Vec3(1, 1, 0)).norm(), 1e-15);
}

// edge_axes_reach against the kernel it lets the distance search skip: it may
// say yes only when the pair is at least `reach` apart, so the kernel's value
// is at least reach less the search's kernel slack (1e-13 big). Random pairs,
// edge-edge pairs built at a known distance (where one axis carries it all),
// degenerate triangles, 1.7e6 m offsets, reach just under and over the distance.
TEST(TriDistance, EdgeAxesNeverRejectACloserPair) {
  std::mt19937_64 rng(123);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double offsets[] = {0.0, 3.0, 1.7374e6};
  int said_yes = 0, edge_pairs_yes = 0, edge_pairs = 0;
  for (int it = 0; it < 60000; ++it) {
    const double off = offsets[it % 3];
    const Vec3 o(off * u(rng), off * u(rng), off * u(rng));
    Tri3 p, q;
    const int kind = it % 4;
    if (kind == 3) {
      // Edges a0a1 and b0b1 closest at interior points, h apart along n.
      const Vec3 e = Vec3(u(rng), u(rng), u(rng)).normalized();
      Vec3 f = Vec3(u(rng), u(rng), u(rng)).normalized();
      const Vec3 n = e.cross(f).normalized();
      const double h = std::pow(10.0, -6.0 + 6.0 * (u(rng) + 1.0) / 2.0);
      const Vec3 c = o + Vec3(u(rng), u(rng), u(rng));
      p = {c - e, c + e, c - n + 0.3 * u(rng) * e};
      q = {c + h * n - f, c + h * n + f, c + (h + 1.0) * n + 0.3 * u(rng) * f};
      ++edge_pairs;
    } else {
      const Vec3 shift = Vec3(u(rng), u(rng), u(rng)) * (kind == 0 ? 0.3 : 2.0);
      for (auto& v : p) v = o + Vec3(u(rng), u(rng), u(rng));
      for (auto& v : q) v = o + Vec3(u(rng), u(rng), u(rng)) + shift;
      if (kind == 2) q[2] = q[0] + 0.5 * (q[1] - q[0]);  // zero area
    }
    double a[9], b[9];
    flatten(p, a);
    flatten(q, b);
    if (tri_distance(a, b).intersecting) continue;
    Vec3 pp, qq;
    const double d = std::sqrt(tri_distance_disjoint2(a, b, pp, qq));
    const double ref = static_cast<double>(testing::reference_tri_distance(p.data(), q.data()));
    double big = 0.0;
    for (int k = 0; k < 9; ++k) big = std::max({big, std::abs(a[k]), std::abs(b[k])});
    for (double f : {0.5, 1.0 - 1e-6, 1.0 - 1e-12, 1.0, 1.0 + 1e-12, 1.0 + 1e-6, 2.0}) {
      const double reach = ref * f;
      if (!edge_axes_reach(a, b, reach, 1e-14 * big)) continue;
      ++said_yes;
      edge_pairs_yes += kind == 3 && f == 0.5;
      ASSERT_GE(d, reach - 1e-13 * big) << it << " reach " << reach << " kernel " << d;
      ASSERT_GE(ref, reach - 1e-15 * big) << it << " reach " << reach << " reference " << ref;
    }
  }
  // The test does work: most edge-edge pairs are proven half their distance apart.
  EXPECT_GT(said_yes, 10000);
  EXPECT_GT(edge_pairs_yes, edge_pairs / 2);
}

}  // namespace
}  // namespace plancheck
