// SPDX-License-Identifier: MIT
// The part-scale contact witness (src/geometry/solid_witness.h): whenever
// it certifies two meshes for moves of their points, every such rigid move
// leaves them in contact by brute force over all triangle pairs with the
// exact test (kernels/tri_tri_overlap.h); a piece wholly inside a solid
// (no surface contact), an open piece and shallow crossings are refused.
#include "src/geometry/solid_witness.h"

#include "kernels/tri_tri_overlap.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace plancheck {
namespace {

// A prism of n sides about the z axis, radius r (to the corners), from z0
// to z1, outward triangles; `split` cuts each side into that many strips
// (coplanar triangles, as the default lander's panels are).
void prism(Mesh& m, int n, double r, double z0, double z1, int split = 1, bool open = false) {
  const std::uint32_t base = static_cast<std::uint32_t>(m.vertices.size());
  const int rows = split + 1;
  for (int k = 0; k < rows; ++k)
    for (int i = 0; i < n; ++i) {
      const double a = 2.0 * M_PI * i / n;
      m.vertices.emplace_back(r * std::cos(a), r * std::sin(a), z0 + (z1 - z0) * k / split);
    }
  auto at = [&](int row, int i) { return base + static_cast<std::uint32_t>(row * n + (i % n)); };
  for (int k = 0; k + 1 < rows; ++k)
    for (int i = 0; i < n; ++i) {
      m.triangles.push_back({at(k, i), at(k, i + 1), at(k + 1, i + 1)});
      m.triangles.push_back({at(k, i), at(k + 1, i + 1), at(k + 1, i)});
    }
  for (int i = 1; i + 1 < n; ++i) {
    m.triangles.push_back({at(split, 0), at(split, i), at(split, i + 1)});  // top, normal +z
    if (!(open && i == 1)) m.triangles.push_back({at(0, 0), at(0, i + 1), at(0, i)});  // bottom, -z
  }
}

// A box bar along x from x0 to x1, half sides h.
void bar(Mesh& m, double x0, double x1, double h) {
  const std::uint32_t b = static_cast<std::uint32_t>(m.vertices.size());
  for (int i = 0; i < 8; ++i)
    m.vertices.emplace_back(i & 1 ? x1 : x0, i & 2 ? h : -h, i & 4 ? h : -h);
  const int f[12][3] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                        {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  for (const auto& t : f)
    m.triangles.push_back({b + static_cast<std::uint32_t>(t[0]), b + static_cast<std::uint32_t>(t[1]),
                           b + static_cast<std::uint32_t>(t[2])});
}

bool touch(const Mesh& a, const Affine& pa, const Mesh& b, const Affine& pb) {
  for (const Tri& s : a.triangles) {
    const Vec3 x0 = pa * a.vertices[s[0]], x1 = pa * a.vertices[s[1]], x2 = pa * a.vertices[s[2]];
    for (const Tri& t : b.triangles) {
      const Vec3 y0 = pb * b.vertices[t[0]], y1 = pb * b.vertices[t[1]], y2 = pb * b.vertices[t[2]];
      if (tri_tri_overlap(x0.data(), x1.data(), x2.data(), y0.data(), y1.data(), y2.data())) return true;
    }
  }
  return false;
}

// A rigid move of a mesh's points by at most `reach` (m): a turn about a
// point of the mesh's box and a shift, shared out at random.
Affine jiggle(const Mesh& m, double reach, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), f(0.0, 1.0);
  Vec3 lo = m.vertices[0], hi = lo;
  for (const Vec3& v : m.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const Vec3 c = 0.5 * (lo + hi);
  const double radius = 0.5 * (hi - lo).norm();
  const double share = f(rng);
  Vec3 axis(u(rng), u(rng), u(rng));
  if (axis.norm() < 1e-3) axis = Vec3::UnitZ();
  Vec3 shift(u(rng), u(rng), u(rng));
  if (shift.norm() > 0.0) shift *= (1.0 - share) * reach / shift.norm();
  // Every point is within `radius` of c: a turn by angle t moves it by at
  // most t radius; f(rng) puts the extremes in too.
  const double angle = radius > 0.0 ? share * reach / radius * (f(rng) < 0.2 ? 1.0 : f(rng)) : 0.0;
  Affine t = Affine::Identity();
  t.translate(c + shift).rotate(Eigen::AngleAxisd(angle, axis.normalized())).translate(-c);
  return t;
}

TEST(SolidWitness, PiecesAndClosedPiecesAreFound) {
  Mesh m;
  prism(m, 8, 1.0, 0.0, 1.0, 3);
  bar(m, 3.0, 4.0, 0.1);
  const SolidPieces s = solid_pieces(m);
  ASSERT_EQ(s.pieces.size(), 2u);
  ASSERT_EQ(s.solids.size(), 2u);
  // Three strips on each side are one plane: 8 sides and 2 caps.
  std::size_t planes = s.solids[0].planes.size() + s.solids[1].planes.size();
  EXPECT_EQ(planes, 10u + 6u);
  EXPECT_EQ(s.deepest, 0.5);  // half the least side of its box (1 m tall)

  // Corners repeated at equal positions still join one piece.
  Mesh loose;
  bar(loose, 0.0, 1.0, 0.1);
  for (Tri& t : loose.triangles)
    for (std::uint32_t& v : t) {
      loose.vertices.push_back(loose.vertices[v]);
      v = static_cast<std::uint32_t>(loose.vertices.size() - 1);
    }
  const SolidPieces l = solid_pieces(loose);
  EXPECT_EQ(l.pieces.size(), 1u);
  EXPECT_EQ(l.solids.size(), 1u);

  // A missing triangle: a piece, not a solid.
  Mesh open;
  prism(open, 8, 1.0, 0.0, 1.0, 1, /*open=*/true);
  const SolidPieces o = solid_pieces(open);
  EXPECT_EQ(o.pieces.size(), 1u);
  EXPECT_EQ(o.solids.size(), 0u);
  EXPECT_EQ(o.deepest, 0.0);
}

TEST(SolidWitness, CertifiedPairsTouchUnderEveryMove) {
  Mesh solid, rod;
  prism(solid, 8, 1.0, 0.0, 1.0, 2);
  bar(rod, 0.0, 1.6, 0.05);
  const SolidPieces ss = solid_pieces(solid), sr = solid_pieces(rod);
  std::mt19937_64 rng(20261128);
  std::uniform_real_distribution<double> u(-1.0, 1.0), f(0.0, 1.0);
  int certified = 0, refused_touching = 0;
  for (int trial = 0; trial < 1500; ++trial) {
    // The rod through or near the prism, at a random angle.
    Affine pr = Affine::Identity();
    pr.translate(Vec3(1.2 * u(rng), 1.2 * u(rng), 0.5 + 0.8 * u(rng)));
    pr.rotate(Eigen::AngleAxisd(M_PI * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized()));
    const Affine ps = Affine::Identity();
    SolidMoves moves;
    moves.whole_a = 0.3 * f(rng) * f(rng);
    moves.whole_b = 0.1 * f(rng) * f(rng);
    moves.pad = 1e-12;
    SolidHint hint;
    const bool yes = solid_crossing(rod, sr, pr, solid, ss, ps, moves, hint);
    if (!yes) {
      if (touch(rod, pr, solid, ps)) ++refused_touching;
      continue;
    }
    ++certified;
    ASSERT_TRUE(touch(rod, pr, solid, ps)) << "trial " << trial;
    for (int j = 0; j < 12; ++j) {
      const Affine ma = jiggle(rod, moves.whole_a, rng) * pr;
      const Affine mb = jiggle(solid, moves.whole_b, rng) * ps;
      ASSERT_TRUE(touch(rod, ma, solid, mb)) << "trial " << trial << " move " << j;
    }
    // The same hint again answers the same.
    EXPECT_TRUE(solid_crossing(rod, sr, pr, solid, ss, ps, moves, hint));
  }
  // Both outcomes occur: the test sees certificates and refusals of touching pairs.
  EXPECT_GT(certified, 100);
  EXPECT_GT(refused_touching, 50);
}

TEST(SolidWitness, NoSurfaceContactOrTooShallowIsRefused) {
  Mesh solid, rod;
  prism(solid, 8, 1.0, 0.0, 1.0);
  bar(rod, -0.3, 0.3, 0.05);
  const SolidPieces ss = solid_pieces(solid), sr = solid_pieces(rod);
  const Affine ps = Affine::Identity();
  SolidMoves none;
  SolidHint hint;
  // Wholly inside: deep, but no vertex outside, and no contact.
  Affine inside = Affine::Identity();
  inside.translate(Vec3(0.0, 0.0, 0.5));
  ASSERT_FALSE(touch(rod, inside, solid, ps));
  EXPECT_FALSE(solid_crossing(rod, sr, inside, solid, ss, ps, none, hint));
  // Poking out of the top: the rod's lower end 0.2 inside (depth 0.2 below
  // the top), its upper end 0.4 above.
  Affine poke = Affine::Identity();
  poke.translate(Vec3(0.0, 0.0, 1.1)).rotate(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitY()));
  ASSERT_TRUE(touch(rod, poke, solid, ps));
  SolidMoves m;
  m.whole_a = 0.1;
  EXPECT_TRUE(solid_crossing(rod, sr, poke, solid, ss, ps, m, hint));
  m.whole_a = 0.2;  // the lower end's depth is 0.2 less the rod's half side
  EXPECT_FALSE(solid_crossing(rod, sr, poke, solid, ss, ps, m, hint));
  m.whole_a = 0.0;
  m.whole_b = 0.2;
  EXPECT_FALSE(solid_crossing(rod, sr, poke, solid, ss, ps, m, hint));
  // A scale in a pose is not rigid: nothing certified.
  Affine scaled = poke;
  scaled.scale(1.001);
  m.whole_b = 0.0;
  EXPECT_FALSE(solid_crossing(rod, sr, scaled, solid, ss, ps, m, hint));
  // An open solid certifies nothing.
  Mesh open;
  prism(open, 8, 1.0, 0.0, 1.0, 1, /*open=*/true);
  const SolidPieces so = solid_pieces(open);
  SolidHint fresh;
  EXPECT_FALSE(solid_crossing(rod, sr, poke, open, so, ps, m, fresh));
}

}  // namespace
}  // namespace plancheck
