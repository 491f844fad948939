// SPDX-License-Identifier: MIT
// The triangle distance in double lanes (kernels/tri_distance_lanes.h), at
// every instruction-set width this CPU has, against the scalar kernel
// tri_distance_disjoint2: the squared distance and both closest points
// bitwise equal, on random pairs and on pairs built to reach every branch of
// the scalar kernel (each Voronoi region of a point on a triangle, clamped
// and unclamped segment parameters, parallel and zero-length edges,
// zero-area triangles, shared vertices and edges, equal candidates, gaps
// down to 1e-12, offsets to 1e6, intersecting and coincident triangles).
#include "kernels/leaf_bounds.h"
#include "kernels/tri_distance.h"

#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace plancheck {
namespace {

using Tri9 = std::array<double, 9>;

std::vector<const LeafKernels*> every_width() {
  std::vector<const LeafKernels*> all{&leaf_kernels_none()};
  for (int k = 0; k < kIsaCount; ++k)
    if (const LeafKernels* t = leaf_kernels_for(static_cast<Isa>(k))) all.push_back(t);
  return all;
}

bool same_bits(double x, double y) { return std::memcmp(&x, &y, sizeof x) == 0; }

// Which of the scalar kernel's candidates won (for the coverage count).
struct Reach {
  int compared = 0;
};

void expect_same(const LeafKernels& k, const Tri9& p, const Tri9& q, Reach& reach) {
  Eigen::Vector3d pa, qa;
  const double want = tri_distance_disjoint2(p.data(), q.data(), pa, qa);
  double pb[3], qb[3];
  const double got = k.tri_distance2(p.data(), q.data(), pb, qb);
  ++reach.compared;
  bool same = same_bits(want, got);
  for (int x = 0; x < 3; ++x) same = same && same_bits(pa[x], pb[x]) && same_bits(qa[x], qb[x]);
  if (same) return;
  std::string text;
  for (double v : p) text += std::to_string(v) + " ";
  text += "| ";
  for (double v : q) text += std::to_string(v) + " ";
  ADD_FAILURE() << k.name << ": " << std::hexfloat << got << " vs scalar " << want << " on " << text;
}

Tri9 random_tri(std::mt19937_64& rng, double scale, double offset) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Tri9 t;
  for (double& x : t) x = offset + scale * u(rng);
  return t;
}

// Adversarial shapes: vertices shared, edges shared, degenerate triangles,
// parallel edges and faces, tiny gaps.
std::vector<std::pair<Tri9, Tri9>> adversarial(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<std::pair<Tri9, Tri9>> out;
  const double gaps[] = {0.0, 1e-12, 1e-6, 0.1, 3.0};
  const double offsets[] = {0.0, 1e3, -1e6};
  for (int n = 0; n < 400; ++n) {
    for (double off : offsets)
      for (double gap : gaps) {
        Tri9 p = random_tri(rng, 1.0, off), q = random_tri(rng, 1.0, off);
        switch (n % 10) {
          case 0:  // q a copy of p lifted by gap along z: parallel faces, equal candidates
            q = p;
            for (int v = 0; v < 3; ++v) q[3 * v + 2] += gap;
            break;
          case 1:  // a shared vertex
            for (int k = 0; k < 3; ++k) q[k] = p[k];
            break;
          case 2:  // a shared edge
            for (int k = 0; k < 6; ++k) q[k] = p[k];
            break;
          case 3:  // p a segment (zero area), q a point
            for (int k = 0; k < 3; ++k) p[6 + k] = p[3 + k];
            for (int k = 0; k < 6; ++k) q[3 + k] = q[k % 3];
            break;
          case 4:  // both points
            for (int k = 3; k < 9; ++k) p[k] = p[k % 3], q[k] = q[k % 3];
            break;
          case 5:  // p's edge parallel to q's edge, offset by gap
            for (int k = 0; k < 3; ++k) {
              q[k] = p[k] + (k == 2 ? gap : 0.0) + (k == 0 ? 0.3 : 0.0);
              q[3 + k] = p[3 + k] + (k == 2 ? gap : 0.0) + (k == 0 ? 0.3 : 0.0);
            }
            break;
          case 6:  // q above p's interior (face region), axis-aligned
            p = {off, off, off, off + 1, off, off, off, off + 1, off};
            q = {off + 0.2, off + 0.2, off + gap, off + 0.3 + u(rng) * 0.1, off + 0.2, off + 1 + gap,
                 off + 0.2, off + 0.3, off + 2 + gap};
            break;
          case 7:  // coplanar triangles side by side
            for (int v = 0; v < 3; ++v) p[3 * v + 2] = q[3 * v + 2] = off;
            for (int v = 0; v < 3; ++v) q[3 * v] += 2.0 + gap;
            break;
          case 8:  // a zero-area triangle with three collinear distinct points
            for (int k = 0; k < 3; ++k) p[6 + k] = 0.5 * (p[k] + p[3 + k]);
            break;
          default:  // small triangles far apart along one axis
            for (int v = 0; v < 3; ++v) q[3 * v] += 10.0 + gap;
            break;
        }
        out.emplace_back(p, q);
      }
  }
  return out;
}

TEST(TriDistanceLanes, RandomPairsEqualTheScalarKernelBitwise) {
  const auto widths = every_width();
  ASSERT_GE(widths.size(), 2u);  // none (the scalar kernel itself) and scalar lanes at least
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Reach reach;
  for (int n = 0; n < 40000; ++n) {
    const double scale = n % 3 == 0 ? 1e-3 : 1.0;
    Tri9 p = random_tri(rng, scale, 0.0), q = random_tri(rng, scale, 0.0);
    // Spread the pairs from overlapping to far apart.
    const double shift = 3.0 * scale * u(rng);
    for (int v = 0; v < 3; ++v) q[3 * v + n % 3] += shift;
    for (const LeafKernels* k : widths) expect_same(*k, p, q, reach);
  }
  EXPECT_EQ(reach.compared, 40000 * static_cast<int>(widths.size()));
}

TEST(TriDistanceLanes, AdversarialPairsEqualTheScalarKernelBitwise) {
  std::mt19937_64 rng(22);
  const auto pairs = adversarial(rng);
  Reach reach;
  for (const LeafKernels* k : every_width())
    for (const auto& [p, q] : pairs) {
      expect_same(*k, p, q, reach);
      expect_same(*k, q, p, reach);
    }
  EXPECT_GT(reach.compared, 0);
}

// Small integer coordinates: every dot product is exact, so points fall
// exactly on the boundaries of the scalar kernel's Voronoi regions (a test
// that is <= there against < here shows), and candidates tie exactly.
TEST(TriDistanceLanes, GridPairsOnRegionBoundariesEqualTheScalarKernelBitwise) {
  std::mt19937_64 rng(24);
  std::uniform_int_distribution<int> g(-2, 2);
  Reach reach;
  const auto widths = every_width();
  for (int n = 0; n < 30000; ++n) {
    Tri9 p, q;
    for (double& x : p) x = 0.5 * g(rng);
    for (double& x : q) x = 0.5 * g(rng);
    for (int v = 0; v < 3; ++v) q[3 * v + n % 3] += 0.5 * (n % 5);
    for (const LeafKernels* k : widths) expect_same(*k, p, q, reach);
  }
  EXPECT_EQ(reach.compared, 30000 * static_cast<int>(widths.size()));
}

// Every one of the 15 candidates wins somewhere in these sets, so no lane
// path goes untested: counted with the scalar kernel's own winner.
TEST(TriDistanceLanes, EveryCandidateWinsSomewhere) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<int> wins(15, 0);
  auto winner = [](const Tri9& p, const Tri9& q) {
    using namespace tri_distance_detail;
    const V pv[3] = {V(p[0], p[1], p[2]), V(p[3], p[4], p[5]), V(p[6], p[7], p[8])};
    const V qv[3] = {V(q[0], q[1], q[2]), V(q[3], q[4], q[5]), V(q[6], q[7], q[8])};
    double best = std::numeric_limits<double>::infinity();
    int at = -1;
    V c1, c2;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const double d = segment_segment(pv[i], pv[(i + 1) % 3], qv[j], qv[(j + 1) % 3], c1, c2);
        if (d < best) best = d, at = 3 * i + j;
      }
    for (int i = 0; i < 3; ++i) {
      if (point_triangle(pv[i], qv[0], qv[1], qv[2], c2) && (pv[i] - c2).squaredNorm() < best)
        best = (pv[i] - c2).squaredNorm(), at = 9 + 2 * i;
      if (point_triangle(qv[i], pv[0], pv[1], pv[2], c1) && (qv[i] - c1).squaredNorm() < best)
        best = (qv[i] - c1).squaredNorm(), at = 10 + 2 * i;
    }
    return at;
  };
  for (int n = 0; n < 20000; ++n) {
    Tri9 p = random_tri(rng, 1.0, 0.0), q = random_tri(rng, 1.0, 0.0);
    for (int v = 0; v < 3; ++v) q[3 * v + n % 3] += 2.5 * u(rng);
    const int w = winner(p, q);
    if (w >= 0) ++wins[static_cast<std::size_t>(w)];
  }
  for (int k = 0; k < 15; ++k) EXPECT_GT(wins[static_cast<std::size_t>(k)], 0) << "candidate " << k;
}

}  // namespace
}  // namespace plancheck
