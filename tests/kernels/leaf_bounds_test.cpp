// SPDX-License-Identifier: MIT
// The SIMD leaf-pair prefilters (kernels/leaf_bounds.h) against the exact
// double kernels, and every wide instruction set against the scalar
// instantiation, on random and adversarial leaves: touching vertices, edges
// and faces, gaps down to 1e-12, coplanar pairs, zero-area triangles and
// slivers, offsets up to 1.7e6, all vertex orders, rigid and scaled maps.
#include "kernels/leaf_bounds.h"
#include "kernels/tri_distance.h"
#include "kernels/tri_tri_overlap.h"
#include "src/geometry/bvh.h"
#include "support/sanitized.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <utility>
#include <vector>

namespace plancheck {
namespace {

using Tri9 = std::array<double, 9>;

// One side: a leaf's triangles in its own frame, stored as a model would
// (node box rounded outward, SoA with padding), and its working-frame map.
struct Side {
  std::vector<Tri9> own;      // own frame
  std::vector<Tri9> working;  // working frame, as the queries compute it
  float lo[3], hi[3];
  std::vector<float> soa;
  std::size_t stride = 0;
  bool identity = true;
  double l[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, t[3] = {0, 0, 0};

  void finish() {
    const std::size_t n = own.size();
    double blo[3] = {1e300, 1e300, 1e300}, bhi[3] = {-1e300, -1e300, -1e300}, max_abs = 0.0;
    for (const Tri9& tri : own)
      for (int c = 0; c < 9; ++c) {
        blo[c % 3] = std::min(blo[c % 3], tri[c]);
        bhi[c % 3] = std::max(bhi[c % 3], tri[c]);
        max_abs = std::max(max_abs, std::abs(tri[c]));
      }
    for (int k = 0; k < 3; ++k) {
      lo[k] = round_down(blo[k]);
      hi[k] = round_up(bhi[k]);
    }
    stride = n + kSoaPadding;
    soa.assign(9 * stride, 0.0f);
    store_leaf_soa(soa.data(), stride, 0, static_cast<int>(n), lo, hi,
                   [&](std::uint32_t s, int v) { return own[s].data() + 3 * v; });
    working.resize(n);
    for (std::size_t s = 0; s < n; ++s)
      for (int v = 0; v < 3; ++v) {
        const double* x = own[s].data() + 3 * v;
        for (int r = 0; r < 3; ++r)
          working[s][3 * v + r] =
              identity ? x[r] : l[3 * r] * x[0] + l[3 * r + 1] * x[1] + l[3 * r + 2] * x[2] + t[r];
      }
    size_ = 0.0;
    for (int r = 0; r < 3; ++r) {
      double row = identity ? max_abs : std::abs(t[r]);
      if (!identity)
        for (int c = 0; c < 3; ++c) row += std::abs(l[3 * r + c]) * max_abs;
      size_ = std::max(size_, row);
    }
  }

  LeafSide leaf_side() const {
    return make_leaf_side(soa.data(), stride, identity ? nullptr : l, identity ? nullptr : t,
                          size_ * (1.0 + 1e-6));
  }

  double size_ = 0.0;
};

// Sets b's map to the inverse of (l, t) applied to working-frame triangles,
// so b's own-frame vertices map (up to rounding) onto `wanted`.
void place(Side& b, const std::vector<Tri9>& wanted, const Eigen::Matrix3d& rot,
           const Eigen::Vector3d& shift) {
  b.identity = false;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) b.l[3 * r + c] = rot(r, c);
    b.t[r] = shift[r];
  }
  b.own.clear();
  for (const Tri9& w : wanted) {
    Tri9 o;
    for (int v = 0; v < 3; ++v) {
      const Eigen::Vector3d x(w[3 * v], w[3 * v + 1], w[3 * v + 2]);
      const Eigen::Vector3d y = rot.inverse() * (x - shift);
      for (int k = 0; k < 3; ++k) o[3 * v + k] = y[k];
    }
    b.own.push_back(o);
  }
}

struct Totals {
  std::uint64_t pairs = 0, touching = 0, proven_apart = 0, with_bound = 0;
};

// Runs every available instruction set on the pair and checks it.
void check_pair(const Side& a, const Side& b, Totals& totals) {
  LeafPairInput in;
  make_leaf_pair(a.leaf_side(), 0, static_cast<int>(a.own.size()), a.lo, a.hi, b.leaf_side(), 0,
                 static_cast<int>(b.own.size()), b.lo, b.hi, in);
  const LeafKernels* scalar = leaf_kernels_for(Isa::kScalar);
  ASSERT_NE(scalar, nullptr);
  std::uint32_t touch_ref[kLeafLanes];
  LeafPairBounds lb_ref;
  scalar->touch_masks(in, touch_ref);
  scalar->lower_bounds(in, 1e30f, lb_ref);
  // The row and column pre-pass changes no bit, at any width.
  for (int k = 0; k < kIsaCount; ++k) {
    const LeafKernels* isa = leaf_kernels_for(static_cast<Isa>(k));
    if (isa == nullptr) continue;
    std::uint32_t fast[kLeafLanes], all[kLeafLanes];
    isa->touch_masks(in, fast);
    isa->touch_masks_all(in, all);
    for (std::size_t i = 0; i < a.own.size(); ++i)
      ASSERT_EQ(fast[i], all[i]) << isa->name << " pre-pass changed row " << i;
  }
  const std::size_t na = a.own.size(), nb = b.own.size();
  double big = 0.0;
  for (const auto* side : {&a.working, &b.working})
    for (const Tri9& tri : *side)
      for (double x : tri) big = std::max(big, std::abs(x));
  for (std::size_t i = 0; i < na; ++i)
    for (std::size_t j = 0; j < nb; ++j) {
      const double* p = a.working[i].data();
      const double* q = b.working[j].data();
      const bool touching = tri_tri_overlap(p, p + 3, p + 6, q, q + 3, q + 6);
      const bool may_touch = (touch_ref[i] >> j) & 1u;
      ++totals.pairs;
      totals.touching += touching;
      totals.proven_apart += !may_touch;
      ASSERT_TRUE(may_touch || !touching) << "prefilter rejected a touching pair " << i << "," << j;
      const float l2 = lb_ref.lower2[i][j];
      ASSERT_GE(l2, 0.0f);
      if (l2 > 0.0f) {
        ++totals.with_bound;
        ASSERT_FALSE(touching) << "positive distance bound on a touching pair";
        // The double kernel's closest points lie within a few ulps of big
        // of the triangles, so its value is the exact distance to 1e-14 big.
        const double d = tri_distance(p, q).distance;
        ASSERT_LE(std::sqrt(static_cast<double>(l2)), d + 1e-13 * big)
            << "lower bound above the distance, pair " << i << "," << j;
      }
    }
  for (int k = 1; k < kIsaCount; ++k) {
    const LeafKernels* wide = leaf_kernels_for(static_cast<Isa>(k));
    if (wide == nullptr) continue;
    std::uint32_t touch[kLeafLanes];
    LeafPairBounds lb;
    wide->touch_masks(in, touch);
    wide->lower_bounds(in, 1e30f, lb);
    for (std::size_t i = 0; i < na; ++i) {
      ASSERT_EQ(touch[i], touch_ref[i]) << wide->name << " touch mask differs from scalar";
      ASSERT_EQ(lb.candidates[i], lb_ref.candidates[i]) << wide->name;
      for (std::size_t j = 0; j < nb; ++j)
        ASSERT_EQ(std::bit_cast<std::uint32_t>(lb.lower2[i][j]),
                  std::bit_cast<std::uint32_t>(lb_ref.lower2[i][j]))
            << wide->name << " lower bound differs from scalar at " << i << "," << j;
    }
    // Candidates against a cut: exactly the lanes whose bound is below it.
    const float cut2 = lb_ref.lower2[0][0] > 0.0f ? lb_ref.lower2[0][0] : 1e-6f;
    wide->lower_bounds(in, cut2, lb);
    for (std::size_t i = 0; i < na; ++i)
      for (std::size_t j = 0; j < nb; ++j)
        ASSERT_EQ((lb.candidates[i] >> j) & 1u, lb.lower2[i][j] < cut2 ? 1u : 0u) << wide->name;
  }
}

Eigen::Matrix3d random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
  q.normalize();
  return q.toRotationMatrix();
}

// b made of `wanted` as given (as_is) or turned by a random rotation and
// moved by a random shift within `offset`, then checked against a.
void check_against(const Side& a, const std::vector<Tri9>& wanted, bool as_is, double offset,
                   std::mt19937_64& rng, std::uniform_real_distribution<double>& u, Totals& totals) {
  Side b;
  if (as_is) {
    b.own = wanted;
  } else {
    const Eigen::Vector3d shift(offset * u(rng), offset * u(rng), offset * u(rng));
    place(b, wanted, random_rotation(rng), shift);
  }
  b.finish();
  check_pair(a, b, totals);
}

Tri9 permuted(const Tri9& t, int perm) {
  static const int orders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  Tri9 r;
  for (int v = 0; v < 3; ++v)
    for (int k = 0; k < 3; ++k) r[3 * v + k] = t[3 * orders[perm][v] + k];
  return r;
}

// A random triangle near c of size s; kind 1: zero area (collinear), 2: a
// point, 3: a sliver.
Tri9 random_triangle(std::mt19937_64& rng, const double* c, double s, int kind) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Tri9 t;
  for (int k = 0; k < 9; ++k) t[k] = c[k % 3] + s * u(rng);
  if (kind == 1) {
    const double w = 0.5 * (u(rng) + 1.0);
    for (int k = 0; k < 3; ++k) t[6 + k] = t[k] + w * (t[3 + k] - t[k]);
  } else if (kind == 2) {
    for (int k = 0; k < 3; ++k) t[3 + k] = t[6 + k] = t[k];
  } else if (kind == 3) {
    for (int k = 0; k < 3; ++k) t[6 + k] = 0.5 * (t[k] + t[3 + k]) + 1e-9 * s * u(rng);
  }
  return t;
}

// Triangles built from a's working triangles so that they touch, nearly
// touch or are coplanar with them (working-frame coordinates).
Tri9 adversarial(std::mt19937_64& rng, const Tri9& p, int mode) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Eigen::Vector3d p0(p[0], p[1], p[2]), p1(p[3], p[4], p[5]), p2(p[6], p[7], p[8]);
  Eigen::Vector3d n = (p1 - p0).cross(p2 - p0);
  const double size = (p1 - p0).norm() + (p2 - p0).norm() + 1e-30;
  n = n.norm() > 0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d(0, 0, 1);
  Eigen::Vector3d other = n.unitOrthogonal();
  const double gaps[] = {0.0, 1e-12, 1e-9, 1e-6, 1e-3};
  const double gap = gaps[rng() % 5] * size;
  const double side = (rng() & 1) ? 1.0 : -1.0;
  Eigen::Vector3d q0, q1, q2;
  switch (mode) {
    case 0:  // shares a vertex, rest on one side (plus a gap)
      q0 = p0 + side * gap * n;
      q1 = p0 + side * size * (n + u(rng) * other);
      q2 = p0 + side * size * (n - u(rng) * other) + 0.3 * size * (p1 - p0).normalized();
      break;
    case 1:  // shares (part of) an edge
      q0 = p0 + side * gap * n;
      q1 = p1 + side * gap * n;
      q2 = 0.5 * (p0 + p1) + side * size * n;
      break;
    case 2: {  // vertex on the face
      const double w0 = u(rng), w1 = (1 - w0) * u(rng);
      const Eigen::Vector3d x = p0 + w0 * (p1 - p0) + w1 * (p2 - p0);
      q0 = x + side * gap * n;
      q1 = x + side * size * (n + other);
      q2 = x + side * size * (n - other);
      break;
    }
    case 3:  // coplanar (shifted in the plane, plus a gap off it)
      q0 = p0 + (u(rng) - 0.5) * size * other + side * gap * n;
      q1 = p1 + (u(rng) - 0.5) * size * other + side * gap * n;
      q2 = p2 + (u(rng) - 0.5) * size * other + side * gap * n;
      break;
    default:  // the same triangle
      q0 = p0;
      q1 = p1;
      q2 = p2;
  }
  return {q0[0], q0[1], q0[2], q1[0], q1[1], q1[2], q2[0], q2[1], q2[2]};
}

const double kOffsets[] = {0.0, 3.0, 1.7e3, 1.7e6};

TEST(LeafBounds, InstructionSetsAreDetected) {
  const LeafKernels* scalar = leaf_kernels_for(Isa::kScalar);
  ASSERT_NE(scalar, nullptr);
  EXPECT_EQ(scalar->width, 1);
  int widths[kIsaCount] = {1, 4, 8, 16};
  std::printf("leaf kernels in use: %s; available:", leaf_kernels().name);
  for (int k = 0; k < kIsaCount; ++k)
    if (const LeafKernels* t = leaf_kernels_for(static_cast<Isa>(k))) {
      EXPECT_EQ(t->width, widths[k]);
      std::printf(" %s", t->name);
    }
  std::printf("\n");
}

TEST(LeafBounds, RandomLeavesNeverRejectTouchingPairs) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Totals totals;
  const int rounds = testing::case_count(14000, 4000);
  for (int round = 0; round < rounds; ++round) {
    const double offset = kOffsets[round % 4];
    const double c[3] = {offset * u(rng), offset * u(rng), offset * u(rng)};
    const double s = std::pow(10.0, -3.0 + 3.0 * (u(rng) + 1.0) / 2.0);
    Side a;
    const int na = 1 + static_cast<int>(rng() % 16), nb = 1 + static_cast<int>(rng() % 16);
    for (int i = 0; i < na; ++i) a.own.push_back(random_triangle(rng, c, s, static_cast<int>(rng() % 8)));
    a.finish();
    std::vector<Tri9> wanted;
    const double spread = s * (rng() % 3);  // overlapping, adjacent or apart leaves
    const double cb[3] = {c[0] + spread * u(rng), c[1] + spread * u(rng), c[2] + spread * u(rng)};
    for (int j = 0; j < nb; ++j) wanted.push_back(random_triangle(rng, cb, s, static_cast<int>(rng() % 8)));
    check_against(a, wanted, round % 2 == 0, offset, rng, u, totals);
    if (HasFatalFailure()) return;
  }
  std::printf("pairs %llu, touching %llu, proven apart %llu, with a bound %llu\n",
              static_cast<unsigned long long>(totals.pairs),
              static_cast<unsigned long long>(totals.touching),
              static_cast<unsigned long long>(totals.proven_apart),
              static_cast<unsigned long long>(totals.with_bound));
  EXPECT_GT(totals.pairs, 64u * rounds);  // 72 on average
  EXPECT_GT(totals.touching, 1000u * rounds / 14000);
  EXPECT_GT(totals.proven_apart, totals.pairs / 4);  // the filter does work
}

TEST(LeafBounds, AdversarialLeavesNeverRejectTouchingPairs) {
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Totals totals;
  const int rounds = testing::case_count(12000, 3500);
  for (int round = 0; round < rounds; ++round) {
    const double offset = kOffsets[round % 4];
    const double c[3] = {offset * u(rng), offset * u(rng), offset * u(rng)};
    const double s = std::pow(10.0, -2.0 + 2.0 * (u(rng) + 1.0) / 2.0);
    Side a, b;
    const int na = 1 + static_cast<int>(rng() % 16), nb = 1 + static_cast<int>(rng() % 16);
    for (int i = 0; i < na; ++i) a.own.push_back(random_triangle(rng, c, s, static_cast<int>(rng() % 6)));
    // Rigid or scaled a-side maps put a in a non-trivial working frame too.
    if (round % 5 == 4) {
      a.identity = false;
      const Eigen::Matrix3d rot = random_rotation(rng) * (0.5 + u(rng) * 0.25);
      for (int r = 0; r < 3; ++r) {
        for (int k = 0; k < 3; ++k) a.l[3 * r + k] = rot(r, k);
        a.t[r] = offset * u(rng);
      }
    }
    a.finish();
    std::vector<Tri9> wanted;
    for (int j = 0; j < nb; ++j) {
      const Tri9& p = a.working[rng() % a.working.size()];
      wanted.push_back(permuted(adversarial(rng, permuted(p, static_cast<int>(rng() % 6)),
                                            static_cast<int>(rng() % 5)),
                                static_cast<int>(rng() % 6)));
    }
    if (round % 3 != 2) {
      b.own = wanted;  // identity: the touching configurations stay exact
    } else {
      const Eigen::Vector3d shift(offset * u(rng), offset * u(rng), offset * u(rng));
      place(b, wanted, random_rotation(rng), shift);
    }
    b.finish();
    check_pair(a, b, totals);
    if (HasFatalFailure()) return;
  }
  std::printf("pairs %llu, touching %llu, proven apart %llu, with a bound %llu\n",
              static_cast<unsigned long long>(totals.pairs),
              static_cast<unsigned long long>(totals.touching),
              static_cast<unsigned long long>(totals.proven_apart),
              static_cast<unsigned long long>(totals.with_bound));
  EXPECT_GT(totals.pairs, 58u * rounds);  // 72 on average
  EXPECT_GT(totals.touching, 10000u * rounds / 12000);
}

// Leaf pairs where only a few triangles of one side come near the other
// leaf: touch_masks then tests the pairs column by column (few of b's
// triangles left) or row by row over the rows near those columns only, and
// must give the bits of the plain row-by-row reference at every width. The
// near triangles touch, nearly touch or lie in the plane of a's (as in
// AdversarialLeaves); the rest are moved out of the other leaf's box.
TEST(LeafBounds, FewNearColumnsOrRowsKeepEveryBit) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Totals totals;
  const int rounds = testing::case_count(8000, 2500);
  for (int round = 0; round < rounds; ++round) {
    const double offset = kOffsets[round % 4];
    const double c[3] = {offset * u(rng), offset * u(rng), offset * u(rng)};
    const double s = std::pow(10.0, -2.0 + 2.0 * (u(rng) + 1.0) / 2.0);
    const int na = 1 + static_cast<int>(rng() % 16), nb = 1 + static_cast<int>(rng() % 16);
    const int near = 1 + static_cast<int>(rng() % 4);
    std::vector<Tri9> big, few;
    for (int i = 0; i < na; ++i) big.push_back(random_triangle(rng, c, s, static_cast<int>(rng() % 6)));
    for (int j = 0; j < nb; ++j) {
      if (j < near || rng() % 8 == 0) {
        const Tri9& p = big[rng() % big.size()];
        few.push_back(permuted(adversarial(rng, permuted(p, static_cast<int>(rng() % 6)),
                                           static_cast<int>(rng() % 5)),
                               static_cast<int>(rng() % 6)));
      } else {
        // Beyond a's box along one axis (by 0 to 2 sizes more).
        Tri9 t = random_triangle(rng, c, s, static_cast<int>(rng() % 4));
        const int k = static_cast<int>(rng() % 3);
        const double shift = (rng() & 1 ? 1.0 : -1.0) * s * (2.5 + u(rng) + 1.0);
        for (int v = 0; v < 3; ++v) t[3 * v + k] += shift;
        few.push_back(t);
      }
    }
    std::shuffle(few.begin(), few.end(), rng);
    // Few near columns (b = few) or few near rows (a = few).
    const bool few_rows = round % 2 == 1;
    Side a;
    a.own = few_rows ? few : big;
    a.finish();
    const std::vector<Tri9>& wanted = few_rows ? big : few;
    check_against(a, wanted, round % 3 != 2, offset, rng, u, totals);
    if (HasFatalFailure()) return;
  }
  std::printf("pairs %llu, touching %llu, proven apart %llu\n",
              static_cast<unsigned long long>(totals.pairs),
              static_cast<unsigned long long>(totals.touching),
              static_cast<unsigned long long>(totals.proven_apart));
  EXPECT_GT(totals.touching, 5000u * rounds / 8000);
  EXPECT_GT(totals.proven_apart, totals.pairs / 2);
}

// make_leaf_pair as it was before make_leaf_side (the float map and the row
// sum per leaf pair, float rounding up by nextafter): the reference the
// per-query constants must reproduce bit for bit.
double reference_view(const LeafSide& s, std::uint32_t first, int count, const float* lo, const float* hi,
                      const double* w, const double* origin, LeafView& v) {
  constexpr double kU = 0x1p-24;
  auto amax = [](const double* x) { return std::max({std::abs(x[0]), std::abs(x[1]), std::abs(x[2])}); };
  auto up = [](double x) {
    float f = static_cast<float>(x);
    if (static_cast<double>(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
    return f;
  };
  v.soa = s.soa + first;
  v.stride = s.stride;
  v.count = count;
  double radius = 0.0, big = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double h = 0.5 * (static_cast<double>(hi[k]) - static_cast<double>(lo[k]));
    radius = h > radius ? h : radius;
    const double a = std::fabs(static_cast<double>(lo[k])) + std::fabs(static_cast<double>(hi[k]));
    big = a > big ? a : big;
  }
  radius = radius * (1.0 + 1e-15) + 1e-15 * big + 1e-300;
  double row = 1.0;
  if (s.l != nullptr) {
    row = 0.0;
    for (int r = 0; r < 3; ++r) {
      const double sum = std::fabs(s.l[3 * r]) + std::fabs(s.l[3 * r + 1]) + std::fabs(s.l[3 * r + 2]);
      row = sum > row ? sum : row;
    }
  }
  double off[3];
  for (int k = 0; k < 3; ++k) off[k] = w[k] - origin[k];
  for (int c = 0; c < 9; ++c)
    v.map[c] = s.l == nullptr ? (c % 4 == 0 ? 1.0f : 0.0f) : static_cast<float>(s.l[c]);
  for (int k = 0; k < 3; ++k) v.map[9 + k] = static_cast<float>(off[k]);
  const double off_max = amax(off);
  const double p = kU * (6.1 * row * radius + 5.1 * off_max) + 2e-15 * (s.size + amax(origin)) + 1e-300;
  v.perturb = up(p);
  return up((row * radius * (1.0 + 1e-6) + off_max + p) * (1.0 + 1e-6));
}

void expect_same_view(const LeafView& x, const LeafView& y) {
  EXPECT_EQ(x.soa, y.soa);
  EXPECT_EQ(x.stride, y.stride);
  EXPECT_EQ(x.count, y.count);
  for (int c = 0; c < 12; ++c) EXPECT_EQ(std::bit_cast<std::uint32_t>(x.map[c]), std::bit_cast<std::uint32_t>(y.map[c])) << c;
  EXPECT_EQ(std::bit_cast<std::uint32_t>(x.perturb), std::bit_cast<std::uint32_t>(y.perturb));
}

// The side's constants computed once a query give the very input the per
// pair computation gave, for identity, rigid and scaled maps, leaves from
// tiny to far off (offsets up to 1e6).
TEST(LeafBounds, PerQuerySideGivesThePerPairInput) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0), pos(0.0, 1.0);
  for (int n = 0; n < 20000; ++n) {
    Side a, b;
    const double scale = std::pow(10.0, -4.0 + 6.0 * pos(rng));
    const double offset = std::pow(10.0, 6.0 * pos(rng));
    for (Side* side : {&a, &b}) {
      const double c[3] = {offset * u(rng), offset * u(rng), offset * u(rng)};
      const int count = 1 + static_cast<int>(pos(rng) * 16.0) % 16;
      for (int t = 0; t < count; ++t) {
        Tri9 tri;
        for (int k = 0; k < 9; ++k) tri[k] = c[k % 3] + scale * u(rng);
        side->own.push_back(tri);
      }
    }
    if (n % 3 != 0) {
      const Eigen::Matrix3d rot = random_rotation(rng) * (n % 3 == 2 ? 0.5 + pos(rng) : 1.0);
      b.identity = false;
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) b.l[3 * r + c] = rot(r, c);
        b.t[r] = offset * u(rng);
      }
    }
    a.finish();
    b.finish();
    const int na = static_cast<int>(a.own.size()), nb = static_cast<int>(b.own.size());
    LeafPairInput in;
    make_leaf_pair(a.leaf_side(), 0, na, a.lo, a.hi, b.leaf_side(), 0, nb, b.lo, b.hi, in);
    // The reference on sides carrying only soa, stride, l, t and size.
    LeafSide ra, rb;
    for (auto [from, to] : {std::pair{&a, &ra}, std::pair{&b, &rb}}) {
      const LeafSide made = from->leaf_side();
      to->soa = made.soa;
      to->stride = made.stride;
      to->l = made.l;
      to->t = made.t;
      to->size = made.size;
    }
    double oa[3], ob[3], wa[3], wb[3];
    leaf_origin(a.lo, a.hi, oa);
    leaf_origin(b.lo, b.hi, ob);
    for (int r = 0; r < 3; ++r) {
      wa[r] = oa[r];
      wb[r] = b.identity ? ob[r] : b.l[3 * r] * ob[0] + b.l[3 * r + 1] * ob[1] + b.l[3 * r + 2] * ob[2] + b.t[r];
    }
    LeafPairInput ref;
    const float ea = reference_view(ra, 0, na, a.lo, a.hi, wa, wa, ref.a);
    const float eb = reference_view(rb, 0, nb, b.lo, b.hi, wb, wa, ref.b);
    ASSERT_NO_FATAL_FAILURE(expect_same_view(in.a, ref.a));
    ASSERT_NO_FATAL_FAILURE(expect_same_view(in.b, ref.b));
    ASSERT_EQ(std::bit_cast<std::uint32_t>(in.extent), std::bit_cast<std::uint32_t>(std::max(ea, eb))) << n;
    for (int k = 0; k < 3; ++k) ASSERT_EQ(in.axis[k], ref.b.map[9 + k]);
  }
}

// Far beyond the float range the kernels prove nothing rather than overflow.
TEST(LeafBounds, HugeExtentsProveNothing) {
  Side a, b;
  a.own.push_back({0, 0, 0, 1, 0, 0, 0, 1, 0});
  b.own.push_back({3e12, 0, 0, 3e12 + 1, 0, 0, 3e12, 1, 0});
  a.finish();
  b.finish();
  LeafPairInput in;
  make_leaf_pair(a.leaf_side(), 0, 1, a.lo, a.hi, b.leaf_side(), 0, 1, b.lo, b.hi, in);
  for (int k = 0; k < kIsaCount; ++k)
    if (const LeafKernels* t = leaf_kernels_for(static_cast<Isa>(k))) {
      std::uint32_t touch[kLeafLanes];
      LeafPairBounds lb;
      t->touch_masks(in, touch);
      t->lower_bounds(in, 1.0f, lb);
      EXPECT_EQ(touch[0], 1u) << t->name;
      EXPECT_EQ(lb.lower2[0][0], 0.0f) << t->name;
      EXPECT_EQ(lb.candidates[0], 1u) << t->name;
    }
}

}  // namespace
}  // namespace plancheck
