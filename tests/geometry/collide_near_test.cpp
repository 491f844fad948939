// SPDX-License-Identifier: MIT
// collide() asked whether the sets come within a distance as well
// (CollideRequest::near_below, the verdict-only check's one traversal for a
// pair whose boxes meet): against the same collide() without it (the flag,
// the listing in its order and the contact, bit for bit) and against
// distance() below that bound, the exact search it stands in for: near is
// false exactly when the sets are apart and distance() finds nothing below
// near_below, that is when every triangle pair's kernel distance is at least
// near_below. Random rigid and scaled poses of curved meshes and soups; poses
// moved to within a relative 1e-9 and 1e-12 of the distance asked about, and
// that distance asked about to the ulp; coplanar flat grids side by side
// (touching, 1e-9 m and 1e-6 m apart) and parallel faces 1e-9 m apart.
#include "src/geometry/collision_model.h"

#include "kernels/tri_distance.h"
#include "support/brute_force.h"
#include "support/same_answer.h"
#include "support/sanitized.h"
#include "support/test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace plancheck {
namespace {

struct Tally {
  int colliding = 0, near = 0, apart = 0;
};

// One pose, one near_below: every claim of the header comment.
void expect_near_answer(const CollisionModel& a, const Affine& ta, const CollisionModel& b, const Affine& tb,
                        double near_below, const std::string& what, Tally& tally) {
  const std::string at = what + " near_below " + std::to_string(near_below);
  for (std::size_t limit : {std::size_t{0}, std::size_t{16}}) {
    DistanceResult contact_plain, contact_near;
    CollideRequest plain{limit}, asked{limit};
    plain.contact = &contact_plain;
    asked.contact = &contact_near;
    asked.near_below = near_below;
    CollideResult rp, rn;
    collide(a, ta, b, tb, plain, rp);
    collide(a, ta, b, tb, asked, rn);
    ASSERT_EQ(rn.collide, rp.collide) << at;
    ASSERT_EQ(rn.triangle_pairs, rp.triangle_pairs) << at << " limit " << limit;
    if (rp.collide) {
      ASSERT_TRUE(testing::same_answer(contact_near, contact_plain)) << at;
      ASSERT_TRUE(rn.near) << at;
      if (limit == 0) ++tally.colliding;
      continue;
    }
    // The exact search below near_below, as the verdict-only check would
    // have run it after the collision test.
    DistanceRequest q{near_below};
    q.known_disjoint = true;
    DistanceResult d;
    distance(a, ta, b, tb, q, d);
    ASSERT_EQ(rn.near, d.found) << at << " distance " << d.distance;
    if (limit == 0) ++(rn.near ? tally.near : tally.apart);
  }
}

// near_below values around a pose's distance d (when finite and positive):
// on it, an ulp either side, 1e-12 and 1e-9 relative either side; and some
// fixed ones from the rounding-guard scale to far beyond.
std::vector<double> bounds_around(double d) {
  std::vector<double> v = {1e-11, 1e-6, 1e-3, 0.05, 0.4};
  if (std::isfinite(d) && d > 0.0) {
    v.push_back(d);
    v.push_back(std::nextafter(d, 0.0));
    v.push_back(std::nextafter(d, 1e300));
    for (double f : {1e-12, 1e-9}) {
      v.push_back(d * (1.0 - f));
      v.push_back(d * (1.0 + f));
    }
  }
  return v;
}

Affine random_pose(std::mt19937_64& rng, double spread, bool scaled) {
  Affine t = testing::random_rigid(rng, Vec3::Zero(), spread);
  if (scaled) {
    std::uniform_real_distribution<double> s(0.6, 1.6);
    t = t * Eigen::Scaling(s(rng), s(rng), s(rng));
  }
  return t;
}

void run_random(const Mesh& ma, const Mesh& mb, double spread, int poses, std::uint64_t seed) {
  const CollisionModel a(ma), b(mb);
  std::mt19937_64 rng(seed);
  Tally tally;
  for (int i = 0; i < poses; ++i) {
    const bool scaled = i % 4 == 3;
    const Affine ta = random_pose(rng, 0.0, scaled && i % 8 == 3);
    Affine tb = random_pose(rng, spread, scaled);
    DistanceResult d;
    distance(a, ta, b, tb, DistanceRequest{}, d);
    std::vector<Affine> moved = {tb};
    if (d.found && d.distance > 0.0) {
      // b moved towards a so the closest pair comes within a relative 1e-9
      // and 1e-12 of touching, either side.
      const Vec3 u = (d.point_a - d.point_b) / d.distance;
      for (double f : {1.0 - 1e-9, 1.0 - 1e-12, 1.0 + 1e-12, 1.0 + 1e-9}) {
        Affine m = tb;
        m.translation() += f * d.distance * u;
        moved.push_back(m);
      }
    }
    for (std::size_t k = 0; k < moved.size(); ++k) {
      DistanceResult dk;
      distance(a, ta, b, moved[k], DistanceRequest{}, dk);
      for (double nb : bounds_around(dk.distance)) {
        expect_near_answer(a, ta, b, moved[k], nb, "pose " + std::to_string(i) + "." + std::to_string(k), tally);
        if (::testing::Test::HasFatalFailure()) return;
      }
    }
  }
  // Each answer occurred, so the comparison is not vacuous.
  EXPECT_GT(tally.colliding, 0);
  EXPECT_GT(tally.near, 0);
  EXPECT_GT(tally.apart, 0);
}

TEST(CollideNear, CurvedMeshesAtRandomAndNearTouchingPoses) {
  run_random(testing::make_torus(Vec3::Zero(), 1.0, 0.3, 20, 10), testing::make_sphere(Vec3::Zero(), 0.5, 8, 12), 1.6,
             testing::case_count(24, 6), 7);
}

TEST(CollideNear, SoupsAtRandomAndNearTouchingPoses) {
  run_random(testing::make_soup(21, 400, Vec3::Zero(), 1.0, 0.3), testing::make_soup(22, 300, Vec3::Zero(), 1.0, 0.3),
             1.5, 12, 8);  // all 12 under the sanitizers too: the first 3 all collide
}

// An n x n grid of squares (two triangles each) over [x0, x0 + w] x [0, w]
// at height z.
Mesh flat_grid(double x0, double w, double z, int n) {
  Mesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.vertices.push_back(Vec3(x0 + w * i / n, w * j / n, z));
  const auto at = [n](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return m;
}

TEST(CollideNear, CoplanarAndParallelGridsTouchingAndJustApart) {
  Tally tally;
  for (double gap : {0.0, 1e-9, 1e-6}) {
    // Side by side in one plane: the left grid ends at x = 1, the right
    // one starts at 1 + gap (touching along an edge when 0).
    const CollisionModel left(flat_grid(0.0, 1.0, 0.0, 8)), right(flat_grid(1.0 + gap, 1.0, 0.0, 8));
    // Face to face: the same grid raised by the gap (coplanar when 0).
    const CollisionModel below(flat_grid(0.0, 1.0, 0.0, 8)), above(flat_grid(0.25, 1.0, gap, 8));
    // The same pairs posed rigidly away from the identity (a turn and a
    // shift applied to both), so the working frame maps b.
    Affine turn = Affine::Identity();
    turn.linear() = Eigen::AngleAxisd(0.7, Vec3(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
    turn.translation() = Vec3(0.4, -1.3, 2.2);
    for (const Affine& t : {Affine(Affine::Identity()), turn}) {
      for (double nb : {1e-11, 0.5e-9, 1e-9, std::nextafter(1e-9, 1.0), 2e-9, 0.5e-6, 1e-6, 2e-6, 1e-3}) {
        const std::string what = "gap " + std::to_string(gap);
        expect_near_answer(left, t, right, t, nb, what + " side by side", tally);
        expect_near_answer(below, t, above, t, nb, what + " face to face", tally);
        if (HasFatalFailure()) return;
      }
    }
  }
  EXPECT_GT(tally.colliding, 0);
  EXPECT_GT(tally.near, 0);
  EXPECT_GT(tally.apart, 0);
}

TEST(CollideNear, NotAskedAnswersNotNear) {
  // near_below 0 asks nothing: near stays false even where the sets come
  // close; a non-finite bound proves nothing: near is true.
  const CollisionModel a(flat_grid(0.0, 1.0, 0.0, 2)), b(flat_grid(1.0 + 1e-6, 1.0, 0.0, 2));
  CollideResult r;
  collide(a, Affine::Identity(), b, Affine::Identity(), CollideRequest{}, r);
  EXPECT_FALSE(r.collide);
  EXPECT_FALSE(r.near);
  for (double nb : {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()}) {
    CollideRequest q;
    q.near_below = nb;
    collide(a, Affine::Identity(), b, Affine::Identity(), q, r);
    EXPECT_FALSE(r.collide);
    EXPECT_TRUE(r.near) << nb;
  }
}

}  // namespace
}  // namespace plancheck
