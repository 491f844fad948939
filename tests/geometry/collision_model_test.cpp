// SPDX-License-Identifier: MIT
#include "src/geometry/collision_model.h"

#include "kernels/tri_distance.h"
#include "kernels/tri_tri_overlap.h"
#include "support/brute_force.h"
#include "support/same_answer.h"
#include "src/base/parallel.h"
#include "support/sanitized.h"
#include "support/test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace plancheck {
namespace {

using testing::brute_force_collide;
using testing::brute_force_distance;
using testing::posed_vertices;

enum class PoseKind { kRigid, kScaleA, kScaleB, kScaleBoth };

using testing::make_box;
using testing::random_rigid;

Affine with_scale(const Affine& t, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> s(0.6, 1.6);
  return t * Eigen::Scaling(s(rng), s(rng), s(rng));
}

// Distance from x to the posed triangle tri of mesh m.
double point_to_triangle(const Vec3& x, const Mesh& m, const std::vector<Vec3>& v,
                         std::uint32_t tri) {
  const Vec3 t[3] = {v[m.triangles[tri][0]], v[m.triangles[tri][1]], v[m.triangles[tri][2]]};
  const Vec3 q[3] = {x, x, x};
  return static_cast<double>(testing::reference_tri_distance(t, q));
}

struct Stats {
  int colliding = 0, separate = 0;
};

// Runs collide() and distance() for one pose and checks them against brute force.
void check_pose(const Mesh& ma, const CollisionModel& a, const Affine& ta, const Mesh& mb,
                const CollisionModel& b, const Affine& tb, Stats& stats, const std::string& what) {
  SCOPED_TRACE(what);
  const auto va = posed_vertices(ma, ta);
  const auto vb = posed_vertices(mb, tb);
  const auto expected = brute_force_collide(ma, va, mb, vb);

  CollideResult all;
  collide(a, ta, b, tb, CollideRequest{1u << 30}, all);
  ASSERT_EQ(all.collide, !expected.empty());
  // With no limit the listed pairs are exactly the brute-force set.
  const std::set<std::pair<std::uint32_t, std::uint32_t>> got(all.triangle_pairs.begin(),
                                                              all.triangle_pairs.end());
  ASSERT_EQ(got.size(), all.triangle_pairs.size()) << "a pair listed twice";
  using PairSet = std::set<std::pair<std::uint32_t, std::uint32_t>>;
  const PairSet want(expected.begin(), expected.end());
  ASSERT_EQ(got, want);
  CollideResult first;
  collide(a, ta, b, tb, CollideRequest{0}, first);
  ASSERT_EQ(first.collide, all.collide);
  ASSERT_EQ(first.triangle_pairs.size(), first.collide ? 1u : 0u);
  // The contact answer a collision test can return equals what distance()
  // reports for the same pose, bit for bit, at every listing limit; a
  // pose that does not touch leaves it as it was.
  DistanceResult plain;
  distance(a, ta, b, tb, DistanceRequest{}, plain);
  for (std::size_t limit : {std::size_t{0}, std::size_t{3}, std::size_t{1} << 30}) {
    DistanceResult contact;
    contact.distance = -1.0;
    CollideResult c;
    CollideRequest request{limit};
    request.contact = &contact;
    collide(a, ta, b, tb, request, c);
    ASSERT_EQ(c.collide, all.collide);
    if (!c.collide) {
      ASSERT_EQ(contact.distance, -1.0);
      continue;
    }
    ASSERT_TRUE(contact.found);
    ASSERT_EQ(contact.distance, 0.0);
    ASSERT_TRUE(testing::same_answer(contact, plain));
    // The first pair listed is the one whose point is reported.
    ASSERT_EQ(c.triangle_pairs.front(), std::make_pair(contact.triangle_a, contact.triangle_b));
  }
  CollideResult some;
  collide(a, ta, b, tb, CollideRequest{3}, some);
  ASSERT_EQ(some.triangle_pairs.size(), std::min<std::size_t>(3, expected.size()));
  for (const auto& [i, j] : some.triangle_pairs) ASSERT_TRUE(got.count({i, j}));

  const auto bd = brute_force_distance(ma, va, mb, vb);
  DistanceResult d;
  distance(a, ta, b, tb, DistanceRequest{}, d);
  ASSERT_TRUE(d.found);
  if (expected.empty()) {
    ++stats.separate;
    ASSERT_GT(d.distance, 0.0);
    // The brute force rounds world coordinates (ulp 2.3e-10 at 1.7e6 m);
    // the query works in a part frame. Allow 1e-12 relative, or a few ulps of
    // the world coordinates where those dominate.
    const double scale = 1.0 + va[0].cwiseAbs().maxCoeff();
    ASSERT_NEAR(d.distance, bd.distance, std::max({1e-12 * bd.distance, 1e-15, 4e-15 * scale}));
    ASSERT_NEAR((d.point_a - d.point_b).norm(), d.distance, 1e-12 * scale);
    ASSERT_LE(point_to_triangle(d.point_a, ma, va, d.triangle_a), 1e-12 * scale);
    ASSERT_LE(point_to_triangle(d.point_b, mb, vb, d.triangle_b), 1e-12 * scale);
    // Pruning: the bound is strict, and a slightly larger one finds the same.
    DistanceResult at, above, below;
    distance(a, ta, b, tb, DistanceRequest{d.distance}, at);
    EXPECT_FALSE(at.found);
    distance(a, ta, b, tb, DistanceRequest{d.distance * (1 + 1e-9)}, above);
    ASSERT_TRUE(above.found);
    EXPECT_EQ(above.distance, d.distance);
    distance(a, ta, b, tb, DistanceRequest{d.distance * (1 - 1e-9)}, below);
    EXPECT_FALSE(below.found);
  } else {
    ++stats.colliding;
    ASSERT_EQ(bd.distance, 0.0);
    ASSERT_EQ(d.distance, 0.0);
    ASSERT_TRUE(got.count({d.triangle_a, d.triangle_b}));
    // A common point: on both reported triangles, to rounding.
    const double scale = 1.0 + va[0].cwiseAbs().maxCoeff();
    EXPECT_LE(point_to_triangle(d.point_a, ma, va, d.triangle_a), 1e-9 * scale);
    EXPECT_LE(point_to_triangle(d.point_b, mb, vb, d.triangle_b), 1e-9 * scale);
    DistanceResult bounded;
    distance(a, ta, b, tb, DistanceRequest{0.0}, bounded);
    EXPECT_FALSE(bounded.found);  // nothing is strictly below 0
  }
}

void run_poses(const Mesh& ma, const Mesh& mb, const Vec3& offset, double spread, int poses,
               std::uint64_t seed) {
  const CollisionModel a(ma), b(mb);
  EXPECT_EQ(a.triangle_count(), ma.triangles.size());
  // At least the corner indices and the slot -> mesh index map.
  EXPECT_GT(a.memory_bytes(), ma.triangles.size() * (12 + 4));
  std::mt19937_64 rng(seed);
  Stats stats;
  for (int i = 0; i < poses; ++i) {
    for (PoseKind kind :
         {PoseKind::kRigid, PoseKind::kScaleA, PoseKind::kScaleB, PoseKind::kScaleBoth}) {
      Affine ta = random_rigid(rng, offset, 0.0);
      Affine tb = random_rigid(rng, offset, spread);
      if (kind == PoseKind::kScaleA || kind == PoseKind::kScaleBoth) ta = with_scale(ta, rng);
      if (kind == PoseKind::kScaleB || kind == PoseKind::kScaleBoth) tb = with_scale(tb, rng);
      check_pose(ma, a, ta, mb, b, tb, stats,
                 "pose " + std::to_string(i) + " kind " + std::to_string(static_cast<int>(kind)));
      if (::testing::Test::HasFatalFailure()) return;
    }
  }
  // Both outcomes must occur for the comparison to cover both paths.
  EXPECT_GT(stats.colliding, 0);
  EXPECT_GT(stats.separate, 0);
}

TEST(CollisionModel, SphereVsTorusMatchesBruteForce) {
  run_poses(testing::make_sphere(Vec3(0.2, 0, 0), 1.0, 16, 24),
            testing::make_torus(Vec3(0, 0.1, 0), 1.2, 0.35, 24, 12), Vec3::Zero(), 2.0,
            testing::case_count(6, 2), 1);
}

TEST(CollisionModel, SoupsMatchBruteForce) {
  run_poses(testing::make_soup(11, 600, Vec3::Zero(), 1.0, 0.3),
            testing::make_soup(12, 500, Vec3::Zero(), 1.0, 0.3), Vec3::Zero(), 1.5, 5, 2);
}

TEST(CollisionModel, FarFromOriginMatchesBruteForce) {
  // Lunar-radius offsets: the parts' own frames are near the origin, the
  // poses put them 1.7374e6 m away.
  run_poses(testing::make_torus(Vec3::Zero(), 1.0, 0.3, 20, 10),
            testing::make_sphere(Vec3::Zero(), 0.8, 12, 20), Vec3(1.7374e6, -2.5e5, 3.1e5), 1.8,
            testing::case_count(5, 2), 3);
}

TEST(CollisionModel, IdentityPosesFindExactTouching) {
  // Two unit squares sharing an edge exactly: touching is a collision and
  // the distance is 0; moved apart by a tiny exact gap they are separate.
  Mesh sq;
  sq.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  sq.triangles = {{0, 1, 2}, {0, 2, 3}};
  Mesh other = sq;
  for (Vec3& v : other.vertices) v.x() += 1.0;  // shares the edge x = 1
  const CollisionModel a(sq), b(other);
  CollideResult c;
  collide(a, Affine::Identity(), b, Affine::Identity(), CollideRequest{}, c);
  EXPECT_TRUE(c.collide);
  DistanceResult d;
  distance(a, Affine::Identity(), b, Affine::Identity(), DistanceRequest{}, d);
  EXPECT_TRUE(d.found);
  EXPECT_EQ(d.distance, 0.0);
  for (Vec3& v : other.vertices) v.x() += 0x1p-40;
  const CollisionModel b2(other);
  collide(a, Affine::Identity(), b2, Affine::Identity(), CollideRequest{}, c);
  EXPECT_FALSE(c.collide);
  distance(a, Affine::Identity(), b2, Affine::Identity(), DistanceRequest{}, d);
  EXPECT_EQ(d.distance, 0x1p-40);
}

TEST(CollisionModel, NearTouchingRigidPosesMatchBruteForce) {
  // The rigid-rigid path (oriented boxes, children tested at the split and
  // the deeper overlap visited first) at poses moved to within a relative
  // 1e-9 and 1e-12 of touching, either side: the collision flag, the full
  // listing, the first contact and a short listing all against brute force.
  // (Not onto the touching pose itself: there the query's frame and the
  // brute force's world coordinates round differently, and each is exact
  // for its own.)
  const Mesh ma = testing::make_torus(Vec3::Zero(), 1.0, 0.3, 20, 10);
  const Mesh mb = testing::make_sphere(Vec3::Zero(), 0.5, 8, 12);
  const CollisionModel a(ma), b(mb);
  std::mt19937_64 rng(41);
  Stats stats;
  for (int i = 0; i < testing::case_count(12, 5); ++i) {
    const Affine ta = random_rigid(rng, Vec3(0.3, -0.2, 0.1), 0.0);
    Affine tb = random_rigid(rng, Vec3(0.3, -0.2, 0.1), 2.0);
    const auto va = posed_vertices(ma, ta), vb = posed_vertices(mb, tb);
    const auto bd = brute_force_distance(ma, va, mb, vb);
    if (!(bd.distance > 0.0)) continue;
    double p[9], q[9];
    for (int v = 0; v < 3; ++v)
      for (int k = 0; k < 3; ++k) {
        p[3 * v + k] = va[ma.triangles[bd.triangle_a][v]][k];
        q[3 * v + k] = vb[mb.triangles[bd.triangle_b][v]][k];
      }
    const TriDistance closest = tri_distance(p, q);
    const Vec3 u = (closest.point_p - closest.point_q) / closest.distance;  // moves b towards a
    for (double f : {1.0 - 1e-9, 1.0 - 1e-12, 1.0 + 1e-12, 1.0 + 1e-9}) {
      Affine moved = tb;
      moved.translation() += f * bd.distance * u;
      check_pose(ma, a, ta, mb, b, moved, stats, "pose " + std::to_string(i) + " f " + std::to_string(f));
      if (::testing::Test::HasFatalFailure()) return;
    }
  }
  EXPECT_GT(stats.colliding, 0);
  EXPECT_GT(stats.separate, 0);
}

// collide() as asked and with one cull switched off (`cull`, a flag of
// CollideRequest), at `limit` (and near_below, when > 0): the same flag,
// the same listing in the same order, the same contact bit for bit, the
// same near answer, never more node pairs. Gives both results; the caller
// checks HasFatalFailure.
void collide_with_and_without(const CollisionModel& a, const Affine& ta, const CollisionModel& b, const Affine& tb,
                              std::size_t limit, bool CollideRequest::*cull, CollideResult& rf, CollideResult& rs,
                              double near_below = 0.0) {
  DistanceResult contact_fast, contact_slow;
  CollideRequest fast{limit}, slow{limit};
  fast.contact = &contact_fast;
  slow.contact = &contact_slow;
  fast.near_below = slow.near_below = near_below;
  slow.*cull = false;
  collide(a, ta, b, tb, fast, rf);
  collide(a, ta, b, tb, slow, rs);
  ASSERT_EQ(rf.collide, rs.collide);
  ASSERT_EQ(rf.near, rs.near);
  ASSERT_EQ(rf.triangle_pairs, rs.triangle_pairs);
  ASSERT_LE(rf.node_pairs_visited, rs.node_pairs_visited);
  if (rf.collide) {
    ASSERT_TRUE(testing::same_answer(contact_fast, contact_slow));
  }
}

// distance() with request q and with q's `cull` off: the same answer bit
// for bit, never more node pairs with it. True when the cull dropped any.
bool distance_with_and_without(const CollisionModel& a, const Affine& ta, const CollisionModel& b, const Affine& tb,
                               const DistanceRequest& q, bool DistanceRequest::*cull) {
  DistanceRequest qs = q;
  qs.*cull = false;
  DistanceResult df, ds;
  distance(a, ta, b, tb, q, df);
  distance(a, ta, b, tb, qs, ds);
  EXPECT_TRUE(testing::same_answer(df, ds));
  EXPECT_LE(df.node_pairs_visited, ds.node_pairs_visited);
  return df.node_pairs_visited < ds.node_pairs_visited;
}

// The axis-aligned cull of the rigid-rigid descent (CollideRequest::box_cull)
// against the descent without it: the same flag, the same listing in the
// same order at every limit, the same contact bit for bit, never more node
// pairs, on interpenetrating, grazing and separate rigid poses; and, asked
// whether the sets come within a distance (near_below: the rounding
// guards' 4e-9 m of the verdict-only check, 1 mm, 5 cm), the same near
// answer. Poses moved to within a relative 1e-9 and 1e-12 of touching.
TEST(CollisionModel, BoxCullChangesNoListingOrContact) {
  struct Case {
    Mesh a, b;
    double spread;
  };
  const Case cases[] = {
      {testing::make_torus(Vec3::Zero(), 1.0, 0.3, 20, 10), testing::make_sphere(Vec3::Zero(), 0.5, 8, 12), 1.6},
      {testing::make_sphere(Vec3(0.2, 0, 0), 1.0, 16, 24), testing::make_torus(Vec3(0, 0.1, 0), 1.2, 0.35, 24, 12), 2.0},
      {testing::make_soup(11, 600, Vec3::Zero(), 1.0, 0.3), testing::make_soup(12, 500, Vec3::Zero(), 1.0, 0.3), 1.5},
  };
  std::mt19937_64 rng(77);
  int colliding = 0, culled = 0, poses = 0, near = 0, apart = 0, culled_near = 0;
  for (const Case& c : cases) {
    const CollisionModel a(c.a), b(c.b);
    for (int i = 0; i < testing::case_count(150, 30); ++i) {
      const Affine ta = random_rigid(rng, Vec3(0.3, -0.2, 0.1), 0.0);
      const Affine tb = random_rigid(rng, Vec3(0.3, -0.2, 0.1), c.spread);
      ++poses;
      std::vector<Affine> moved = {tb};
      DistanceResult d;
      distance(a, ta, b, tb, DistanceRequest{}, d);
      if (i % 5 == 0) {
        if (d.distance > 0.0) {
          const Vec3 u = (d.point_a - d.point_b) / d.distance;  // moves b towards a
          for (double f : {1.0 - 1e-9, 1.0 - 1e-12, 1.0 + 1e-12, 1.0 + 1e-9}) {
            Affine m = tb;
            m.translation() += f * d.distance * u;
            moved.push_back(m);
          }
        }
      }
      for (std::size_t m = 0; m < moved.size(); ++m) {
        for (std::size_t limit : {std::size_t{0}, std::size_t{1}, std::size_t{16}, std::size_t{1} << 30}) {
          SCOPED_TRACE("pose " + std::to_string(i) + "." + std::to_string(m) + " limit " + std::to_string(limit));
          CollideResult rf, rs;
          collide_with_and_without(a, ta, b, moved[m], limit, &CollideRequest::box_cull, rf, rs);
          if (::testing::Test::HasFatalFailure()) return;
          if (limit == 0 && m == 0) {
            colliding += rf.collide;
            culled += rf.node_pairs_visited < rs.node_pairs_visited;
          }
        }
        // The rounding guards' scale, two margins, and just past the
        // unmoved pose's own distance (a cull too keen on the widened
        // boxes drops the pairs that answer it).
        for (double near_below : {4.001e-9, 1e-3, 0.05, d.distance * (1.0 + 1e-9), d.distance * 1.2}) {
          if (!(near_below > 0.0)) continue;
          SCOPED_TRACE("pose " + std::to_string(i) + "." + std::to_string(m) + " near_below " +
                       std::to_string(near_below));
          CollideResult rf, rs;
          collide_with_and_without(a, ta, b, moved[m], 0, &CollideRequest::box_cull, rf, rs, near_below);
          if (::testing::Test::HasFatalFailure()) return;
          if (!rf.collide) ++(rf.near ? near : apart);
          culled_near += rf.node_pairs_visited < rs.node_pairs_visited;
        }
      }
    }
  }
  // Both outcomes, and the cull at work, for the comparison to mean something.
  EXPECT_GT(colliding, poses / 10);
  EXPECT_LT(colliding, poses);
  EXPECT_GT(culled, 0);
  EXPECT_GT(near, 0);
  EXPECT_GT(apart, 0);
  EXPECT_GT(culled_near, 0);
}


// The world-frame cull of the root boxes (CollideRequest::root_cull,
// DistanceRequest::root_cull, roots_apart) against collide() and distance()
// without it: the same flag, listing, contact and near answer, the same
// distance answer bit for bit below bounds either side of the pair's own
// distance (exact, within a factor of 2, yes or no, seeded), on
// interpenetrating, grazing and separate rigid
// poses, near the origin and at lunar-scale offsets (1e6 m), and for boxes
// whose faces are a relative 1e-12 to 1e-6 of a metre from touching, face
// to face, edge to edge and slightly turned. Wherever roots_apart says
// apart by `reach`, the exact distance is above reach. Scaled poses are
// never culled (their boxes are not rigidly posed). Fails with the
// oriented boxes' half extents halved or with reach ignored (the near
// answers); with the tolerance dropped it still passes (these poses round
// alike in both frames): the tolerance rests on the argument in
// collision_model.cpp.
TEST(CollisionModel, RootCullChangesNoAnswer) {
  struct Case {
    Mesh a, b;
    double spread;
  };
  const Case cases[] = {
      {testing::make_torus(Vec3::Zero(), 1.0, 0.3, 20, 10), testing::make_sphere(Vec3::Zero(), 0.5, 8, 12), 2.5},
      {testing::make_soup(11, 600, Vec3::Zero(), 1.0, 0.3), testing::make_soup(12, 500, Vec3::Zero(), 1.0, 0.3), 2.5},
      {make_box(Vec3(0.1, 0.2, -0.3), Vec3(0.5, 0.2, 0.1)), make_box(Vec3(-0.2, 0.0, 0.1), Vec3(0.3, 0.3, 0.05)), 1.5},
  };
  std::mt19937_64 rng(2026);
  int poses = 0, culled = 0, kept_apart = 0, colliding = 0, culled_near = 0, distance_culled = 0;
  auto one = [&](const CollisionModel& a, const Affine& ta, const CollisionModel& b, const Affine& tb,
                 const std::string& what) {
    SCOPED_TRACE(what);
    ++poses;
    DistanceResult d;
    distance(a, ta, b, tb, DistanceRequest{}, d);
    for (double reach : {0.0, 4.001e-9, 1e-3, 0.05}) {
      const bool cull = roots_apart(a, ta, b, tb, reach);
      if (cull) {
        ASSERT_GT(d.distance, reach) << "reach " << reach;
      }
      if (reach == 0.0) {
        culled += cull;
        kept_apart += !cull && d.distance > 0.0;
      } else {
        culled_near += cull;
      }
    }
    for (std::size_t limit : {std::size_t{0}, std::size_t{1} << 30}) {
      CollideResult rf, rs;
      collide_with_and_without(a, ta, b, tb, limit, &CollideRequest::root_cull, rf, rs);
      if (::testing::Test::HasFatalFailure()) return;
      colliding += limit == 0 && rf.collide;
    }
    for (double near_below : {4.001e-9, 1e-3, 0.05, d.distance * (1.0 - 1e-9), d.distance * (1.0 + 1e-9)}) {
      if (!(near_below > 0.0)) continue;
      CollideResult rf, rs;
      collide_with_and_without(a, ta, b, tb, 0, &CollideRequest::root_cull, rf, rs, near_below);
      if (::testing::Test::HasFatalFailure()) return;
    }
    // distance() below a bound: exact, within a factor, yes or no, seeded.
    for (double upper : {1e-3, 0.05, d.distance * 0.5, d.distance * (1.0 - 1e-9), d.distance * (1.0 + 1e-9),
                         d.distance * 2.0}) {
      if (!(upper > 0.0)) continue;
      for (double rel : {0.0, 1.0}) {
        for (int kind = 0; kind < 3; ++kind) {
          DistanceRequest q{upper, rel, 0.0};
          q.first_below = kind == 1;
          if (kind == 2 && d.found) {
            q.seed_slot_a = d.slot_a;
            q.seed_slot_b = d.slot_b;
          }
          DistanceResult r;
          distance(a, ta, b, tb, q, r);
          const bool cull = roots_apart(a, ta, b, tb, upper);
          if (cull) {
            ASSERT_FALSE(r.found);
            ASSERT_GE(d.distance, upper);
          }
          distance_culled += cull;
          distance_with_and_without(a, ta, b, tb, q, &DistanceRequest::root_cull);
          if (::testing::Test::HasFailure()) return;
        }
      }
    }
  };
  for (const Case& c : cases) {
    const CollisionModel a(c.a), b(c.b);
    for (const Vec3& offset : {Vec3(0.3, -0.2, 0.1), Vec3(1e6, -2e6, 3e5)}) {
      for (int i = 0; i < testing::case_count(60, 15); ++i) {
        const Affine ta = random_rigid(rng, offset, 0.0);
        const Affine tb = random_rigid(rng, offset, c.spread);
        one(a, ta, b, tb, "pose " + std::to_string(i));
        if (::testing::Test::HasFatalFailure()) return;
        // Scaled: never culled, answers as without the cull.
        const Affine sb = with_scale(tb, rng);
        EXPECT_FALSE(roots_apart(a, ta, b, sb, 0.0));
        CollideResult rf, rs;
        collide_with_and_without(a, ta, b, sb, 0, &CollideRequest::root_cull, rf, rs);
        if (::testing::Test::HasFatalFailure()) return;
      }
    }
  }
  // Boxes whose root boxes are their own faces: b's face a relative gap
  // from a's, face to face and turned about the gap's axis or tilted.
  {
    const Mesh ma = make_box(Vec3::Zero(), Vec3(0.5, 0.25, 0.125));
    const Mesh mb = make_box(Vec3::Zero(), Vec3(0.25, 0.25, 0.25));
    const CollisionModel a(ma), b(mb);
    for (const Vec3& offset : {Vec3(0.0, 0.0, 0.0), Vec3(1e6, -2e6, 3e5)}) {
      for (double gap : {-1e-6, -1e-12, 0.0, 1e-12, 1e-9, 1e-6, 1e-3}) {
        for (double turn : {0.0, 0.3, 1e-7}) {
          Affine ta = Affine::Identity();
          ta.translation() = offset;
          Affine tb = Affine::Identity();
          tb.linear() = Eigen::AngleAxisd(turn, Vec3::UnitX()).toRotationMatrix();
          // b's lowest point at a's top face (z = 0.125) plus the gap.
          const double low = 0.25 * (std::abs(std::cos(turn)) + std::abs(std::sin(turn)));
          tb.translation() = offset + Vec3(0.1, 0.0, 0.125 + low + gap);
          one(a, ta, b, tb, "gap " + std::to_string(gap) + " turn " + std::to_string(turn));
          if (::testing::Test::HasFatalFailure()) return;
        }
      }
    }
  }
  // Both outcomes, and the cull at work, for the comparison to mean something.
  EXPECT_GT(colliding, 0);
  EXPECT_GT(culled, poses / 10);
  EXPECT_GT(kept_apart, 0);
  EXPECT_GT(culled_near, 0);
  EXPECT_GT(distance_culled, 0);
}

// The cull of a leaf's triangles against the other side's node boxes
// (CollideRequest::leaf_cull, DistanceRequest::leaf_cull) against the
// descents without it: the same flag, the same listing in the same order at
// every limit, the same contact bit for bit; the same distance answer bit
// for bit with no bound (best-first), below a bound, with a tie tolerance
// and as a first-below question; never more node pairs. Coarse parts (a slab of 12 triangles, a
// sphere of few, large triangles) against fine ones, as either side (both
// ways through the cull), inside their hulls, crossing their faces and
// moved to within a relative 1e-9 and 1e-12 of touching them, near the
// origin and at lunar-radius offsets.
TEST(CollisionModel, LeafCullChangesNoListingOrContact) {
  struct Case {
    Mesh coarse, fine;
    Vec3 at;
    double spread;
  };
  const Vec3 moon(1.2e6, -0.9e6, 0.7e6);
  const Case cases[] = {
      {make_box(Vec3::Zero(), Vec3(1.0, 0.8, 0.15)), testing::make_sphere(Vec3::Zero(), 0.3, 16, 24), Vec3::Zero(), 1.0},
      {make_box(Vec3::Zero(), Vec3(1.0, 0.8, 0.15)), testing::make_torus(Vec3::Zero(), 0.3, 0.08, 24, 12), moon, 1.0},
      {testing::make_sphere(Vec3::Zero(), 1.5, 5, 7), testing::make_torus(Vec3::Zero(), 0.4, 0.1, 24, 12), Vec3::Zero(),
       1.8},
      {testing::make_sphere(Vec3::Zero(), 1.5, 5, 7), testing::make_soup(13, 600, Vec3::Zero(), 0.4, 0.1), moon, 1.8},
  };
  std::mt19937_64 rng(91);
  int colliding = 0, culled_a = 0, culled_b = 0, culled_distance = 0, grazing = 0, poses = 0;
  // Compares at every limit; counts the pose's flag and culls at limit 0.
  const auto compare = [&](const CollisionModel& a, const Affine& ta, const CollisionModel& b, const Affine& tb,
                           int* collided, int* culled) {
    for (std::size_t limit : {std::size_t{0}, std::size_t{1}, std::size_t{16}, std::size_t{1} << 30}) {
      SCOPED_TRACE("limit " + std::to_string(limit));
      CollideResult rf, rs;
      collide_with_and_without(a, ta, b, tb, limit, &CollideRequest::leaf_cull, rf, rs);
      if (::testing::Test::HasFatalFailure()) return;
      if (limit == 0 && collided) *collided += rf.collide;
      if (limit == 0 && culled) *culled += rf.node_pairs_visited < rs.node_pairs_visited;
    }
    for (int kind = 0; kind < 4; ++kind) {
      SCOPED_TRACE("distance kind " + std::to_string(kind));
      DistanceRequest qf;
      if (kind > 0) qf.upper_bound = 0.25;
      if (kind == 2) qf.abs_tolerance = 1e-6;
      qf.first_below = kind == 3;
      culled_distance += distance_with_and_without(a, ta, b, tb, qf, &DistanceRequest::leaf_cull);
      if (::testing::Test::HasFailure()) return;
    }
  };
  for (const Case& c : cases) {
    const CollisionModel coarse(c.coarse), fine(c.fine);
    for (int i = 0; i < testing::case_count(200, 30); ++i) {
      const Affine ta = random_rigid(rng, c.at, 0.0);
      const Affine tb = random_rigid(rng, c.at, c.spread);
      SCOPED_TRACE("pose " + std::to_string(i));
      ++poses;
      // The coarse part as a (its leaves against the fine part's nodes), then as b.
      compare(coarse, ta, fine, tb, &colliding, &culled_a);
      compare(fine, tb, coarse, ta, nullptr, &culled_b);
      if (::testing::Test::HasFatalFailure()) return;
      // Moved to within a hair of touching, either side.
      if (i % 4 != 0) continue;
      DistanceResult d;
      distance(coarse, ta, fine, tb, DistanceRequest{}, d);
      if (!(d.distance > 0.0)) continue;
      const Vec3 u = (d.point_a - d.point_b) / d.distance;  // moves the fine part towards the coarse one
      for (double f : {1.0 - 1e-9, 1.0 - 1e-12, 1.0 + 1e-12, 1.0 + 1e-9}) {
        SCOPED_TRACE("grazing " + std::to_string(f));
        Affine moved = tb;
        moved.translation() += f * d.distance * u;
        compare(coarse, ta, fine, moved, nullptr, nullptr);
        compare(fine, moved, coarse, ta, nullptr, nullptr);
        if (::testing::Test::HasFatalFailure()) return;
        ++grazing;
      }
    }
  }
  // Both outcomes, and the cull at work, for the comparison to mean something.
  EXPECT_GT(colliding, poses / 10);
  EXPECT_LT(colliding, poses);
  EXPECT_GT(culled_a, poses / 10);
  EXPECT_GT(culled_b, poses / 10);
  EXPECT_GT(culled_distance, poses / 10);
  EXPECT_GT(grazing, 0);
}

// An octagonal slab of radius r from z0 to z1, flat faces as fans of 8
// long triangles and sides of two each (32 triangles): a lander's deck.
Mesh make_octagonal_slab(double r, double z0, double z1) {
  Mesh m;
  m.vertices.push_back(Vec3(0, 0, z0));
  m.vertices.push_back(Vec3(0, 0, z1));
  for (int k = 0; k < 8; ++k) {
    const double t = (22.5 + 45.0 * k) * M_PI / 180.0;
    m.vertices.push_back(Vec3(r * std::cos(t), r * std::sin(t), z0));
    m.vertices.push_back(Vec3(r * std::cos(t), r * std::sin(t), z1));
  }
  for (std::uint32_t k = 0; k < 8; ++k) {
    const std::uint32_t lo = 2 + 2 * k, hi = lo + 1, lo2 = 2 + 2 * ((k + 1) % 8), hi2 = lo2 + 1;
    m.triangles.push_back({0, lo2, lo});
    m.triangles.push_back({1, hi, hi2});
    m.triangles.push_back({lo, lo2, hi2});
    m.triangles.push_back({lo, hi2, hi});
  }
  return m;
}

// The leaf cull beside the rim of long triangles (CollideRequest::leaf_cull,
// DistanceRequest::leaf_cull; the axis through a triangle's point nearest a
// small node's box, and the distance descent's cull of leaf pairs): a
// finely meshed wrist (a torus 4.5 cm across, or a sphere) placed just off
// an edge or corner of an octagonal deck slab, in the wedge outside both of
// the faces that meet there, where neither face's plane nor the small
// node's face axes separate them; gaps from 1 cm into the deck to 12 cm
// off it and within 1e-9 and 1e-12 (relative) of touching, near the origin
// and at lunar-radius offsets, either part as a. Against the descents
// without the cull: the same collision listing, order, contact and near
// answer; the same distance bit for bit with no bound, below the sweep's
// 5 cm, with a tie tolerance, as a first-below question and below a bound
// a hair above and below the distance itself. The cull must be at work:
// the bounded searches that prove the pair beyond 5 cm visit far fewer
// node pairs (before this axis the descent went down to the leaves there).
TEST(CollisionModel, LeafCullBesideARimChangesNoAnswer) {
  const Mesh deck = make_octagonal_slab(1.32, 0.0, 0.056);
  const Mesh wrists[] = {testing::make_torus(Vec3::Zero(), 0.03, 0.015, 48, 12),
                         testing::make_sphere(Vec3::Zero(), 0.045, 12, 24)};
  const Vec3 moon(1.2e6, -0.9e6, 0.7e6);
  const CollisionModel coarse(deck);
  std::mt19937_64 rng(33);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int poses = 0, colliding = 0, beyond = 0, beyond_culled = 0, grazing = 0;
  std::uint64_t nodes_fast = 0, nodes_slow = 0;
  for (const Mesh& wrist : wrists) {
    const CollisionModel fine(wrist);
    const double radius = 0.045;
    for (int i = 0; i < testing::case_count(240, 40); ++i) {
      SCOPED_TRACE("pose " + std::to_string(i));
      const Vec3 at = i % 2 == 0 ? Vec3::Zero() : moon;
      const Affine ta = random_rigid(rng, at, 0.0);
      // A rim point of side k (a top or bottom edge, or the corner's
      // vertical edge) and a way out of both faces that meet there.
      const int k = static_cast<int>(unit(rng) * 8) % 8;
      const double t0 = (22.5 + 45.0 * k) * M_PI / 180.0, t1 = t0 + M_PI / 4.0;
      const Vec3 c0(1.32 * std::cos(t0), 1.32 * std::sin(t0), 0.0), c1(1.32 * std::cos(t1), 1.32 * std::sin(t1), 0.0);
      const Vec3 side = Vec3(std::cos(t0 + M_PI / 8.0), std::sin(t0 + M_PI / 8.0), 0.0);
      Vec3 rim, out;
      const double phi = (0.05 + 0.9 * unit(rng)) * M_PI / 2.0;
      if (unit(rng) < 0.7) {  // a top or bottom edge
        const bool top = unit(rng) < 0.5;
        rim = c0 + unit(rng) * (c1 - c0) + Vec3(0, 0, top ? 0.056 : 0.0);
        out = std::cos(phi) * side + std::sin(phi) * Vec3(0, 0, top ? 1.0 : -1.0);
      } else {  // the corner's vertical edge, between the two side faces
        const Vec3 prev(std::cos(t0 - M_PI / 8.0), std::sin(t0 - M_PI / 8.0), 0.0);
        rim = c0 + Vec3(0, 0, 0.056 * unit(rng));
        out = (std::cos(phi) * side + std::sin(phi) * prev).normalized();
      }
      const double gap = -0.01 + 0.13 * unit(rng);
      Affine tb = random_rigid(rng, Vec3::Zero(), 0.0);
      tb.translation() = ta * (rim + (radius + gap) * out);
      ++poses;
      const auto compare = [&](const Affine& tf) {
        for (int order = 0; order < 2; ++order) {
          SCOPED_TRACE(order == 0 ? "deck as a" : "deck as b");
          const CollisionModel& a = order == 0 ? coarse : fine;
          const CollisionModel& b = order == 0 ? fine : coarse;
          const Affine& pa = order == 0 ? ta : tf;
          const Affine& pb = order == 0 ? tf : ta;
          for (std::size_t limit : {std::size_t{0}, std::size_t{1} << 30})
            for (double near_below : {0.0, 0.05}) {
              CollideResult rf, rs;
              collide_with_and_without(a, pa, b, pb, limit, &CollideRequest::leaf_cull, rf, rs, near_below);
              if (::testing::Test::HasFatalFailure()) return;
              if (order == 0 && limit == 0 && near_below == 0.0) colliding += rf.collide;
            }
          DistanceResult exact;
          distance(a, pa, b, pb, DistanceRequest{}, exact);
          for (int kind = 0; kind < 6; ++kind) {
            SCOPED_TRACE("distance kind " + std::to_string(kind));
            DistanceRequest q;
            if (kind >= 1 && kind <= 3) q.upper_bound = 0.05;
            if (kind == 2) q.abs_tolerance = 1e-12;
            q.first_below = kind == 3;
            if (kind == 4) q.upper_bound = exact.distance * (1.0 + 1e-12) + 1e-300;
            if (kind == 5) q.upper_bound = exact.distance * (1.0 - 1e-12);
            DistanceRequest qs = q;
            qs.leaf_cull = false;
            DistanceResult df, ds;
            distance(a, pa, b, pb, q, df);
            distance(a, pa, b, pb, qs, ds);
            ASSERT_TRUE(testing::same_answer(df, ds));
            ASSERT_LE(df.node_pairs_visited, ds.node_pairs_visited);
            if (kind == 1 && !ds.found) {
              ++beyond;
              beyond_culled += 2 * df.node_pairs_visited < ds.node_pairs_visited;
              nodes_fast += df.node_pairs_visited;
              nodes_slow += ds.node_pairs_visited;
            }
          }
        }
      };
      compare(tb);
      if (::testing::Test::HasFatalFailure()) return;
      // Moved to within a hair of touching the deck.
      if (i % 4 != 0) continue;
      DistanceResult d;
      distance(coarse, ta, fine, tb, DistanceRequest{}, d);
      if (!(d.distance > 0.0)) continue;
      const Vec3 u = (d.point_a - d.point_b) / d.distance;  // moves the wrist towards the deck
      for (double f : {1.0 - 1e-9, 1.0 - 1e-12, 1.0 + 1e-12, 1.0 + 1e-9}) {
        SCOPED_TRACE("grazing " + std::to_string(f));
        Affine moved = tb;
        moved.translation() += f * d.distance * u;
        compare(moved);
        if (::testing::Test::HasFatalFailure()) return;
        ++grazing;
      }
    }
  }
  // Both outcomes, and the cull at work where the pair is beyond 5 cm.
  EXPECT_GT(colliding, 0);
  EXPECT_LT(colliding, poses);
  EXPECT_GT(grazing, 0);
  EXPECT_GT(beyond, poses / 4);
  // (Before this axis: 72 of 540 such searches, 12,414 node pairs against
  // 20,124; with it 216, 2,350 against 19,702.)
  EXPECT_GT(beyond_culled, beyond / 4);
  EXPECT_LT(4 * nodes_fast, nodes_slow) << nodes_fast << " node pairs against " << nodes_slow;
}

// The leaf cull proves nothing from a NaN or an infinity: poses with one
// non-finite or huge entry (rotation or translation, either part) answer as
// the descent without the cull does. Such poses do not reach the cull today
// (a NaN rotation is no isometry, so no oriented boxes; a 1e308 translation
// makes obb_tol infinite), and box_clear_of_leaf refuses non-finite input
// itself besides. Upstream, a state's parameters must be finite, but a
// finite parameter far outside its limits can still overflow a transform,
// and the verdict is a safety claim either way.
TEST(CollisionModel, LeafCullDropsNothingOnNonFinitePoses) {
  const Mesh deck = make_box(Vec3::Zero(), Vec3(1.0, 0.8, 0.15));
  const CollisionModel coarse(deck), fine(testing::make_sphere(Vec3::Zero(), 0.3, 8, 12));
  const double bad[] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                        -std::numeric_limits<double>::infinity(), 1e308};
  std::mt19937_64 rng(17);
  const auto same_value = [](double x, double y) { return x == y || (std::isnan(x) && std::isnan(y)); };
  int slow_collides = 0, compared = 0;
  for (int it = 0; it < 96; ++it) {
    Affine ta = random_rigid(rng, Vec3::Zero(), 0.0);
    Affine tb = random_rigid(rng, Vec3::Zero(), 0.5);
    Affine& spoiled = it % 2 == 0 ? tb : ta;
    const int entry = (it / 2) % 12;  // 9 of the rotation, 3 of the translation
    const double v = bad[(it / 24) % 4];
    if (entry < 9)
      spoiled.linear()(entry / 3, entry % 3) = v;
    else
      spoiled.translation()[entry - 9] = v;
    SCOPED_TRACE("pose " + std::to_string(it) + " entry " + std::to_string(entry) + " value " + std::to_string(v));
    for (int order = 0; order < 2; ++order) {
      const CollisionModel& a = order == 0 ? coarse : fine;
      const CollisionModel& b = order == 0 ? fine : coarse;
      const Affine& pa = order == 0 ? ta : tb;
      const Affine& pb = order == 0 ? tb : ta;
      // Not collide_with_and_without: a contact's points and distance may be
      // NaN here (and equal as NaN), which same_answer counts as different.
      CollideRequest fast{std::size_t{1} << 30}, slow{std::size_t{1} << 30};
      slow.leaf_cull = false;
      CollideResult rf, rs;
      collide(a, pa, b, pb, fast, rf);
      collide(a, pa, b, pb, slow, rs);
      ASSERT_EQ(rf.collide, rs.collide);
      ASSERT_EQ(rf.triangle_pairs, rs.triangle_pairs);
      slow_collides += rs.collide;
      DistanceRequest qf;
      qf.upper_bound = 0.25;
      DistanceRequest qs = qf;
      qs.leaf_cull = false;
      DistanceResult df, ds;
      distance(a, pa, b, pb, qf, df);
      distance(a, pa, b, pb, qs, ds);
      ASSERT_EQ(df.found, ds.found);
      ASSERT_TRUE(same_value(df.distance, ds.distance)) << df.distance << " against " << ds.distance;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 192);
  // The descent without the cull reports contacts on some of these poses:
  // the comparison would see a cull that dropped them.
  EXPECT_GT(slow_collides, 0);
}

// A closed box of half extents h centred at c whose six faces are each an
// n x n grid of squares (two triangles each): flat faces of many triangles,
// so a face parallel to another at one distance ties n^2 triangle pairs.
Mesh make_grid_box(const Vec3& c, const Vec3& h, int n) {
  Mesh m;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = -1; side <= 1; side += 2) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const std::uint32_t first = static_cast<std::uint32_t>(m.vertices.size());
      for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
          Vec3 x = c;
          x[axis] += side * h[axis];
          x[u] += h[u] * (2.0 * i / n - 1.0);
          x[v] += h[v] * (2.0 * j / n - 1.0);
          m.vertices.push_back(x);
        }
      const auto at = [&](int i, int j) { return first + static_cast<std::uint32_t>(i * (n + 1) + j); };
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
          m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    }
  return m;
}

// The cull of node pairs whose triangle pairs the leaves' triangle-box test
// would all skip (DistanceRequest::tie_cull) against the search without it:
// the same answer bit for bit (distance, triangles, slots, points), never
// more node pairs. Ties of parallel faces, as the arm's base over the deck:
// a block over a slab, both of finely gridded faces, turned about the
// slab's normal and slid over it at gaps of 0.11 m to 1e-3 m, the pair
// placed at random (near the origin and at lunar-radius offsets), either
// part as a; searched with no bound, with the tie tolerance, seeded from
// the answer at a nearby turn (as a plan's states seed each other), below
// an upper bound just above the distance (within the tie tolerance: a
// search that has found nothing must not drop what its probe would
// settle), as a first-below question and as the coarse pass asks. Then
// curved parts at random poses, where the cull has little to do.
TEST(CollisionModel, TieCullChangesNoDistance) {
  const Vec3 moon(1.2e6, -0.9e6, 0.7e6);
  // Dyadic coordinates: exact in float, as a 3DS model's are, so the node
  // boxes (rounded outward to float) are the faces' own planes, and the cull
  // can settle the ties (a float box rounded out by up to 6e-8 of a
  // coordinate proves nothing at the scale of the tie tolerance).
  const Mesh slab = make_grid_box(Vec3::Zero(), Vec3(1.25, 0.875, 0.0625), 16);
  const Mesh block = make_grid_box(Vec3(0.125, -0.0625, 0.0), Vec3(0.15625, 0.125, 0.1875), 8);
  const CollisionModel deck(slab), arm(block);
  std::mt19937_64 rng(33);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int searches = 0, culled = 0, ties = 0;
  const auto compare = [&](const CollisionModel& a, const Affine& ta, const CollisionModel& b, const Affine& tb,
                           const DistanceRequest& q) {
    culled += distance_with_and_without(a, ta, b, tb, q, &DistanceRequest::tie_cull);
    ++searches;
  };
  // All the requests above for one pose; `seed` from a nearby pose.
  const auto requests = [&](const CollisionModel& a, const Affine& ta, const CollisionModel& b, const Affine& tb,
                            const DistanceResult& seed) {
    DistanceResult exact;
    distance(a, ta, b, tb, DistanceRequest{}, exact);
    ASSERT_TRUE(exact.found);
    for (int kind = 0; kind < 7; ++kind) {
      SCOPED_TRACE("request kind " + std::to_string(kind));
      DistanceRequest q;
      if (kind >= 1) q.abs_tolerance = 1e-12;
      if (kind == 2 || kind == 3) {
        q.seed_slot_a = seed.slot_a;
        q.seed_slot_b = seed.slot_b;
      }
      if (kind == 3) q.upper_bound = exact.distance * 1.5;
      if (kind == 4) q.upper_bound = exact.distance + 0.5e-12;
      if (kind == 5) {
        q.upper_bound = exact.distance * 1.001;
        q.first_below = true;
      }
      if (kind == 6) q.rel_tolerance = 4.0;
      compare(a, ta, b, tb, q);
      if (::testing::Test::HasFailure()) return;
    }
  };
  for (int i = 0; i < testing::case_count(40, 8); ++i) {
    const Affine world = random_rigid(rng, i % 2 == 0 ? Vec3::Zero() : moon, 0.0);
    const double gap = i % 3 == 0 ? 0.11 : i % 3 == 1 ? 0.05 : 1e-3;
    const Vec3 slide(0.6 * u(rng), 0.5 * u(rng), 0.0625 + gap + 0.1875);
    const double turn = 3.14159 * u(rng);
    const auto placed = [&](double angle) {
      Affine t = Affine::Identity();
      t.linear() = Eigen::AngleAxisd(angle, Vec3::UnitZ()).toRotationMatrix();
      t.translation() = slide;
      return world * t;
    };
    const Affine tb = placed(turn);
    for (int order = 0; order < 2; ++order) {
      SCOPED_TRACE("pose " + std::to_string(i) + " order " + std::to_string(order));
      const CollisionModel& a = order == 0 ? deck : arm;
      const CollisionModel& b = order == 0 ? arm : deck;
      const Affine& pa = order == 0 ? world : tb;
      const Affine& pb = order == 0 ? tb : world;
      // The seed: the answer at a slightly smaller turn.
      DistanceResult seed;
      DistanceRequest tie;
      tie.abs_tolerance = 1e-12;
      if (order == 0)
        distance(a, world, b, placed(turn - 1e-3), tie, seed);
      else
        distance(a, placed(turn - 1e-3), b, world, tie, seed);
      requests(a, pa, b, pb, seed);
      if (::testing::Test::HasFailure()) return;
      ++ties;
    }
  }
  const Mesh sphere = testing::make_sphere(Vec3::Zero(), 0.5, 12, 18);
  const Mesh torus = testing::make_torus(Vec3::Zero(), 0.8, 0.2, 24, 12);
  const CollisionModel ball(sphere), ring(torus);
  for (int i = 0; i < testing::case_count(60, 12); ++i) {
    SCOPED_TRACE("curved pose " + std::to_string(i));
    const Affine ta = random_rigid(rng, i % 2 == 0 ? Vec3::Zero() : moon, 0.0);
    const Affine tb = random_rigid(rng, i % 2 == 0 ? Vec3::Zero() : moon, 2.5);
    DistanceResult seed;
    distance(ball, ta, ring, random_rigid(rng, i % 2 == 0 ? Vec3::Zero() : moon, 2.5), DistanceRequest{}, seed);
    DistanceResult probe;
    distance(ball, ta, ring, tb, DistanceRequest{}, probe);
    if (!(probe.distance > 0.0)) continue;  // touching: nothing to search
    requests(ball, ta, ring, tb, seed);
    if (::testing::Test::HasFailure()) return;
  }
  // The cull at work, for the comparison to mean something.
  EXPECT_EQ(ties, 2 * testing::case_count(40, 8));
  EXPECT_GT(culled, searches / 4);
}

// An exact search with nothing to start from runs best-first until its
// first bound, one with a bound depth-first (kernels/pair_traversal.h);
// both settle a leaf's nearest float-bounded pair first until they find
// one. The same minimum, bit for
// bit (the smallest of the same kernel values in the same frame), against
// brute force, on far, grazing and separate poses of rigid and scaled parts,
// near the origin and at lunar-radius offsets; in all, fewer node pairs
// expanded than depth-first from no bound.
TEST(CollisionModel, BestFirstAndDepthFirstFindTheSameMinimum) {
  struct Case {
    Mesh a, b;
    Vec3 at;
    double spread;
  };
  const Case cases[] = {
      {testing::make_torus(Vec3::Zero(), 1.0, 0.3, 20, 10), testing::make_sphere(Vec3::Zero(), 0.5, 8, 12),
       Vec3(0.3, -0.2, 0.1), 3.0},
      {testing::make_soup(11, 600, Vec3::Zero(), 1.0, 0.3), testing::make_soup(12, 500, Vec3::Zero(), 1.0, 0.3),
       Vec3::Zero(), 2.5},
      {testing::make_torus(Vec3::Zero(), 1.0, 0.3, 20, 10), testing::make_sphere(Vec3::Zero(), 0.8, 12, 20),
       Vec3(1.7374e6, -2.5e5, 3.1e5), 3.0},
  };
  std::mt19937_64 rng(1127);
  const int poses = testing::case_count(30, 6);
  int compared = 0;
  std::size_t bf_pairs = 0, df_pairs = 0;
  for (const Case& c : cases) {
    const CollisionModel a(c.a), b(c.b);
    for (int i = 0; i < poses; ++i) {
      const Affine ta = random_rigid(rng, c.at, 0.0);
      Affine tb = random_rigid(rng, c.at, c.spread);
      if (i % 3 == 1) tb = with_scale(tb, rng);
      SCOPED_TRACE("pose " + std::to_string(i));
      CollideResult touch;
      collide(a, ta, b, tb, CollideRequest{0}, touch);
      if (touch.collide) continue;
      DistanceRequest best_first;  // no bound, no seed
      best_first.known_disjoint = true;
      DistanceRequest depth_first = best_first;
      depth_first.upper_bound = std::numeric_limits<double>::max();
      DistanceResult bf, df;
      distance(a, ta, b, tb, best_first, bf);
      distance(a, ta, b, tb, depth_first, df);
      ASSERT_TRUE(bf.found);
      ASSERT_TRUE(df.found);
      ASSERT_EQ(bf.distance, df.distance);
      bf_pairs += bf.node_pairs_visited;
      df_pairs += df.node_pairs_visited;
      const auto va = posed_vertices(c.a, ta), vb = posed_vertices(c.b, tb);
      const auto bd = brute_force_distance(c.a, va, c.b, vb);
      const double scale = 1.0 + va[0].cwiseAbs().maxCoeff();
      ASSERT_NEAR(bf.distance, bd.distance, std::max({1e-12 * bd.distance, 1e-15, 4e-15 * scale}));
      EXPECT_LE(point_to_triangle(bf.point_a, c.a, va, bf.triangle_a), 1e-12 * scale);
      EXPECT_LE(point_to_triangle(bf.point_b, c.b, vb, bf.triangle_b), 1e-12 * scale);
      ++compared;
    }
  }
  // Most poses apart (a third may collide), at every size of the run.
  EXPECT_GT(compared, 3 * poses / 2);
  // Best-first until the first bound expands fewer node pairs in all (not
  // at every pose: the depth-first rest may wander where pure best-first
  // would not).
  EXPECT_LT(bf_pairs, df_pairs);
}

// Parts of one leaf each: every search is a single leaf pair, where the
// first search settles the pair with the smallest float bound before the
// others (DistanceQuery::leaves) and then skips it. Against brute force
// over every triangle pair, from no bound (best-first) and from a bound
// (depth-first), on soups close enough that most pairs' float bounds are 0.
TEST(CollisionModel, SingleLeafPairsMatchBruteForce) {
  std::mt19937_64 rng(27);
  int compared = 0;
  for (int m = 0; m < testing::case_count(40, 8); ++m) {
    const Mesh ma = testing::make_soup(100 + m, 16, Vec3::Zero(), 0.5, 0.3);
    const Mesh mb = testing::make_soup(200 + m, 16, Vec3::Zero(), 0.5, 0.3);
    const CollisionModel a(ma), b(mb);
    for (int i = 0; i < 25; ++i) {
      const Affine ta = random_rigid(rng, Vec3::Zero(), 0.0);
      const Affine tb = random_rigid(rng, Vec3::Zero(), 1.2);
      CollideResult touch;
      collide(a, ta, b, tb, CollideRequest{0}, touch);
      if (touch.collide) continue;
      const auto va = posed_vertices(ma, ta), vb = posed_vertices(mb, tb);
      const auto bd = brute_force_distance(ma, va, mb, vb);
      for (const double bound : {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::max()}) {
        DistanceRequest q{bound};
        q.known_disjoint = true;
        DistanceResult d;
        distance(a, ta, b, tb, q, d);
        ASSERT_TRUE(d.found) << m << " " << i;
        ASSERT_NEAR(d.distance, bd.distance, std::max(1e-12 * bd.distance, 1e-15)) << m << " " << i;
      }
      ++compared;
    }
  }
  EXPECT_GT(compared, testing::case_count(40, 8) * 5);
}

TEST(CollisionModel, EmptyMeshes) {
  const CollisionModel empty{Mesh{}};
  const CollisionModel sphere(testing::make_sphere(Vec3::Zero(), 1, 8, 8));
  CollideResult c;
  collide(empty, Affine::Identity(), sphere, Affine::Identity(), CollideRequest{}, c);
  EXPECT_FALSE(c.collide);
  DistanceResult d;
  distance(sphere, Affine::Identity(), empty, Affine::Identity(), DistanceRequest{}, d);
  EXPECT_FALSE(d.found);
}

}  // namespace
}  // namespace plancheck

namespace plancheck {
namespace {

TEST(CollisionModel, ConcurrentQueriesMatchSerialOnes) {
  const CollisionModel a(testing::make_torus(Vec3::Zero(), 1.0, 0.3, 40, 20));
  const CollisionModel b(testing::make_sphere(Vec3::Zero(), 0.7, 16, 24));
  std::mt19937_64 rng(8);
  const int n = 64;
  std::vector<Affine> poses;
  for (int i = 0; i < n; ++i) poses.push_back(random_rigid(rng, Vec3::Zero(), 1.6));
  std::vector<CollideResult> c_serial(n), c_par(n);
  std::vector<DistanceResult> d_serial(n), d_par(n);
  for (int i = 0; i < n; ++i) {
    collide(a, Affine::Identity(), b, poses[i], CollideRequest{}, c_serial[i]);
    distance(a, Affine::Identity(), b, poses[i], DistanceRequest{}, d_serial[i]);
  }
  parallel_for(n, 2, 1, [&](std::size_t begin, std::size_t end, int) {
    for (std::size_t i = begin; i < end; ++i) {
      collide(a, Affine::Identity(), b, poses[i], CollideRequest{}, c_par[i]);
      distance(a, Affine::Identity(), b, poses[i], DistanceRequest{}, d_par[i]);
    }
  });
  for (int i = 0; i < n; ++i) {
    EXPECT_EQ(c_par[i].triangle_pairs, c_serial[i].triangle_pairs) << i;
    EXPECT_EQ(d_par[i].distance, d_serial[i].distance) << i;
    EXPECT_EQ(d_par[i].triangle_a, d_serial[i].triangle_a) << i;
  }
}

}  // namespace
}  // namespace plancheck

namespace plancheck {
namespace {

Mesh unit_cube() {
  Mesh m;
  for (int i = 0; i < 8; ++i) m.vertices.push_back(Vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
  m.triangles = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1},
                 {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
  return m;
}

// Rigid poses with exactly representable matrices (quarter turns, dyadic
// shifts), so the working-frame coordinates are exact and face, edge and
// vertex contacts are known exactly: culling must never drop them.
TEST(CollisionModel, ExactContactsUnderQuarterTurns) {
  const Mesh cube = unit_cube();
  const CollisionModel a(cube), b(cube);
  Affine turn = Affine::Identity();
  turn.linear() << 0, -1, 0, 1, 0, 0, 0, 0, 1;  // quarter turn about z
  const Vec3 offsets[] = {Vec3(2, 0, 0.5), Vec3(2, 1, 1), Vec3(2, 1, 0.25), Vec3(2, -1, -1)};
  // The turned cube spans x in [-1, 0] before the shift: shifted by 2 in x
  // its face x = 1 meets a's face x = 1.
  for (const Vec3& o : offsets) {
    for (double gap : {0.0, 0x1p-30, 0x1p-50}) {
      Affine tb = turn;
      tb.translation() = o + Vec3(gap, 0, 0);
      const bool touching = gap == 0.0;
      CollideResult c;
      collide(a, Affine::Identity(), b, tb, CollideRequest{}, c);
      EXPECT_EQ(c.collide, touching) << o.transpose() << " gap " << gap;
      const auto brute = testing::brute_force_collide(cube, cube.vertices, cube,
                                                      testing::posed_vertices(cube, tb));
      EXPECT_EQ(!brute.empty(), touching);
      DistanceResult d;
      distance(a, Affine::Identity(), b, tb, DistanceRequest{}, d);
      ASSERT_TRUE(d.found);
      EXPECT_EQ(d.distance, gap) << o.transpose();
      // The same with a rotated (non-identity) frame for a.
      Affine ta = turn;
      CollideResult c2;
      collide(a, ta, b, ta * tb, CollideRequest{}, c2);
      EXPECT_EQ(c2.collide, touching);
    }
  }
}

}  // namespace
}  // namespace plancheck
