// SPDX-License-Identifier: MIT
#include "kernels/tri_tri_overlap.h"

#include "support/brute_force.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>

namespace plancheck {
namespace {

using Tri3 = std::array<Vec3, 3>;

bool kernel(const Tri3& p, const Tri3& q) {
  return tri_tri_overlap(p[0].data(), p[1].data(), p[2].data(), q[0].data(), q[1].data(),
                         q[2].data());
}

bool reference(const Tri3& p, const Tri3& q) {
  return testing::exact_tri_tri_reference(p.data(), q.data());
}

// The kernel answer for every vertex order of both triangles and both
// argument orders; all must agree (exact predicates leave no room).
bool all_orders_agree(const Tri3& p, const Tri3& q, bool expected) {
  std::array<int, 3> pi = {0, 1, 2};
  do {
    std::array<int, 3> qi = {0, 1, 2};
    do {
      const Tri3 pp = {p[pi[0]], p[pi[1]], p[pi[2]]};
      const Tri3 qq = {q[qi[0]], q[qi[1]], q[qi[2]]};
      if (kernel(pp, qq) != expected || kernel(qq, pp) != expected) return false;
    } while (std::next_permutation(qi.begin(), qi.end()));
  } while (std::next_permutation(pi.begin(), pi.end()));
  return true;
}

void expect_case(const Tri3& p, const Tri3& q, bool expected, const char* what) {
  EXPECT_EQ(reference(p, q), expected) << what << " (reference)";
  EXPECT_TRUE(all_orders_agree(p, q, expected)) << what << " (kernel)";
}

Tri3 shifted(Tri3 t, const Vec3& d) {
  for (auto& v : t) v += d;
  return t;
}

TEST(TriTriOverlap, ConstructedContactsAreExact) {
  const Tri3 base = {Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 4, 0)};
  // Vertex on vertex, vertex on edge, vertex on face, from above.
  expect_case(base, {Vec3(0, 0, 0), Vec3(-1, -1, 1), Vec3(-2, 0, 3)}, true, "vertex-vertex");
  expect_case(base, {Vec3(2, 0, 0), Vec3(2, -1, 1), Vec3(3, -2, 3)}, true, "vertex on edge");
  expect_case(base, {Vec3(1, 1, 0), Vec3(1, 2, 1), Vec3(3, 1, 2)}, true, "vertex on face");
  // Edge crossing edge (non-coplanar): edge (2,-1,0)-(2,1,0) crosses x-axis edge.
  expect_case(base, {Vec3(2, -1, 0), Vec3(2, 1, 0), Vec3(2, 0, 5)}, true, "edge through edge");
  // Edge lying on the face, the rest above.
  expect_case(base, {Vec3(1, 1, 0), Vec3(2, 1, 0), Vec3(1, 1, 3)}, true, "edge on face");
  // Edge piercing the interior.
  expect_case(base, {Vec3(1, 1, -1), Vec3(1, 1, 1), Vec3(9, 9, 9)}, true, "piercing");
  // Shared edge, different planes (a hinge).
  expect_case(base, {Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(2, -3, 2)}, true, "hinge");
  // Same, but the other triangle is slid past the end of the edge.
  expect_case(base, {Vec3(5, 0, 0), Vec3(9, 0, 0), Vec3(7, -3, 2)}, false, "collinear edges apart");
  // Just outside: vertex near the hypotenuse, beyond it.
  expect_case(base, {Vec3(2, 2.0000000000000004, 0), Vec3(3, 3, 1), Vec3(5, 2, 3)}, false,
              "vertex just past hypotenuse");
  expect_case(base, {Vec3(2, 2, 0), Vec3(3, 3, 1), Vec3(5, 2, 3)}, true, "vertex on hypotenuse");
}

TEST(TriTriOverlap, CoplanarCases) {
  const Tri3 base = {Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 4, 0)};
  expect_case(base, {Vec3(1, 1, 0), Vec3(2, 1, 0), Vec3(1, 2, 0)}, true, "contained");
  expect_case(base, {Vec3(-1, -1, 0), Vec3(9, -1, 0), Vec3(-1, 9, 0)}, true, "containing");
  expect_case(base, {Vec3(3, 3, 0), Vec3(5, 3, 0), Vec3(3, 5, 0)}, false, "disjoint");
  expect_case(base, {Vec3(2, 2, 0), Vec3(5, 3, 0), Vec3(3, 5, 0)}, true, "touching at vertex");
  expect_case(base, {Vec3(4, 0, 0), Vec3(0, 4, 0), Vec3(4, 4, 0)}, true, "sharing an edge");
  expect_case(base, {Vec3(-1, 1, 0), Vec3(5, 1, 0), Vec3(2, 9, 0)}, true, "edges crossing");
  // A tilted plane with exactly representable points.
  const Tri3 t = {Vec3(0, 0, 0), Vec3(2, 0, 2), Vec3(0, 2, 2)};
  expect_case(t, {Vec3(1, 1, 2), Vec3(2, 2, 4), Vec3(1, 3, 4)}, true, "tilted, touching");
  expect_case(t, {Vec3(2, 2, 4), Vec3(3, 2, 5), Vec3(2, 3, 5)}, false, "tilted, apart");
}

TEST(TriTriOverlap, DegenerateTriangles) {
  const Tri3 base = {Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 4, 0)};
  // Segments (collinear or repeated vertices) piercing, touching, missing.
  expect_case(base, {Vec3(1, 1, -1), Vec3(1, 1, 1), Vec3(1, 1, 0.5)}, true, "segment piercing");
  expect_case(base, {Vec3(1, 1, 1), Vec3(1, 1, 3), Vec3(1, 1, 1)}, false, "segment above");
  expect_case(base, {Vec3(1, 1, 0), Vec3(1, 1, 3), Vec3(1, 1, 3)}, true, "segment touching");
  expect_case(base, {Vec3(-1, 1, 0), Vec3(5, 1, 0), Vec3(2, 1, 0)}, true, "segment in plane");
  expect_case(base, {Vec3(3, 3, 0), Vec3(5, 3, 0), Vec3(4, 3, 0)}, false, "segment in plane apart");
  // Points.
  expect_case(base, {Vec3(1, 1, 0), Vec3(1, 1, 0), Vec3(1, 1, 0)}, true, "point on face");
  expect_case(base, {Vec3(2, 2, 0), Vec3(2, 2, 0), Vec3(2, 2, 0)}, true, "point on edge");
  expect_case(base, {Vec3(1, 1, 1e-300), Vec3(1, 1, 1e-300), Vec3(1, 1, 1e-300)}, false,
              "point a hair above");
  // Both degenerate.
  const Tri3 seg = {Vec3(0, 0, 0), Vec3(2, 2, 2), Vec3(1, 1, 1)};
  expect_case(seg, {Vec3(0, 2, 0), Vec3(2, 0, 2), Vec3(2, 0, 2)}, true, "segments crossing");
  expect_case(seg, {Vec3(0, 2, 0), Vec3(2, 0, 2.5), Vec3(2, 0, 2.5)}, false, "segments skew");
  expect_case(seg, {Vec3(2, 2, 2), Vec3(3, 3, 3), Vec3(3, 3, 3)}, true, "collinear touching");
  expect_case(seg, {Vec3(3, 3, 3), Vec3(4, 4, 4), Vec3(3, 3, 3)}, false, "collinear apart");
  expect_case(seg, {Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1)}, true, "point on segment");
  expect_case(seg, {Vec3(1, 1, 1.5), Vec3(1, 1, 1.5), Vec3(1, 1, 1.5)}, false, "point off segment");
  const Tri3 pt = {Vec3(1, 2, 3), Vec3(1, 2, 3), Vec3(1, 2, 3)};
  expect_case(pt, pt, true, "same point");
  expect_case(pt, shifted(pt, Vec3(0, 0, 1e-15)), false, "different points");
}

TEST(TriTriOverlap, TinyGapsAreSeen) {
  // Vertex of q above an interior point of p at heights 1e-3 .. 1e-12, and
  // edge-edge near misses, at the origin and far from it.
  for (double offset : {0.0, 1.7374e6}) {
    const Vec3 o(offset, -offset, offset);
    const Tri3 p = shifted({Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 4, 0)}, o);
    for (double gap = 1e-3; gap >= 1e-12; gap /= 10) {
      const Tri3 q = shifted({Vec3(1, 1, gap), Vec3(1, 2, 1), Vec3(2, 1, 1)}, o);
      const bool expected = reference(p, q);
      EXPECT_TRUE(all_orders_agree(p, q, expected)) << gap;
      if (offset == 0.0) {
        EXPECT_FALSE(expected) << gap;  // exact at the origin
      }
      const Tri3 e = shifted({Vec3(2, -1, gap), Vec3(2, 1, gap), Vec3(2, 0, 3)}, o);
      const bool expected_e = reference(p, e);
      EXPECT_TRUE(all_orders_agree(p, e, expected_e)) << gap;
      if (offset == 0.0) {
        EXPECT_FALSE(expected_e) << gap;
      }
    }
    EXPECT_TRUE(all_orders_agree(p, shifted({Vec3(1, 1, 0), Vec3(1, 2, 1), Vec3(2, 1, 1)}, o),
                                 true));
  }
}

// Random triangles on a small integer grid: plenty of exact coplanarity,
// collinearity, shared points and touching, at several scales and offsets.
TEST(TriTriOverlap, GridCasesMatchExactReference) {
  std::mt19937_64 rng(12345);
  std::uniform_int_distribution<int> coord(0, 3);
  int hits = 0, total = 0;
  const unsigned long long fallbacks_before = exact_fallback_count();
  for (double offset : {0.0, 1.7374e6, -3.25e3}) {
    for (double scale : {1.0, 0x1p-20, 0x1p+10}) {
      for (int it = 0; it < 1500; ++it) {
        Tri3 p, q;
        for (auto* t : {&p, &q})
          for (auto& v : *t)
            v = Vec3(coord(rng), coord(rng), coord(rng)) * scale + Vec3::Constant(offset);
        const bool expected = reference(p, q);
        hits += expected;
        ++total;
        ASSERT_EQ(kernel(p, q), expected) << "case " << it;
        if (it % 10 == 0) {
          ASSERT_TRUE(all_orders_agree(p, q, expected)) << "case " << it;
        }
      }
    }
  }
  // Both answers must be well represented for the comparison to mean much,
  // and the exact fallback must have been exercised (zero determinants).
  EXPECT_GT(hits, total / 10);
  EXPECT_LT(hits, total * 9 / 10);
  EXPECT_GT(exact_fallback_count(), fallbacks_before);
}

TEST(TriTriOverlap, RandomCasesMatchExactReference) {
  std::mt19937_64 rng(777);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int hits = 0;
  const int n = 8000;
  for (int it = 0; it < n; ++it) {
    Tri3 p, q;
    const double offset = it % 2 ? 1.7374e6 : 0.0;
    for (auto* t : {&p, &q})
      for (auto& v : *t) v = Vec3(u(rng), u(rng), u(rng)) + Vec3::Constant(offset);
    // Every fourth case: q shares a vertex with p, or has a vertex on p's edge.
    if (it % 4 == 1) q[0] = p[1];
    if (it % 4 == 3) q[0] = p[0] + 0.5 * (p[1] - p[0]);
    const bool expected = reference(p, q);
    hits += expected;
    ASSERT_EQ(kernel(p, q), expected) << "case " << it;
    if (it % 50 == 0) {
      ASSERT_TRUE(all_orders_agree(p, q, expected)) << "case " << it;
    }
  }
  EXPECT_GT(hits, n / 10);
  EXPECT_LT(hits, n * 9 / 10);
}

}  // namespace
}  // namespace plancheck
