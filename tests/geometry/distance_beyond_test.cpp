// SPDX-License-Identifier: MIT
// DistanceResult::beyond: where a search below a bound finds nothing, the
// lower bound it proved on its way (the root boxes that ended it, or the
// node pairs its descent dropped). The motion checks take it as a sample's
// bound, so it must never exceed the true distance: checked against
// all-pairs brute force, for two meshes and for a mesh over a heightfield,
// at bounds from far below the distance to just under it, exact and within
// a factor, seeded or not, with and without the root cull.
#include "src/geometry/collision_model.h"
#include "src/geometry/heightfield.h"
#include "src/scene/terrain.h"

#include "tests/support/brute_force.h"
#include "tests/support/sanitized.h"
#include "tests/support/test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace plancheck {
namespace {

using testing::brute_force_distance;
using testing::make_box;
using testing::posed_vertices;
using testing::random_rigid;

// Counts over all requests that found nothing: how often beyond proved more
// than the request's tolerance alone (upper / (1 + rel)), and by how much.
struct Tally {
  int nothing = 0, more = 0, culled = 0;
};

// One request that found nothing, against the brute-force distance `truth`.
// The slack covers the brute force's own rounding (a few ulps of the
// coordinates), not any looseness of beyond.
void check_beyond(const DistanceRequest& q, const DistanceResult& r, double truth, double scale, Tally& tally,
                  const std::string& what) {
  SCOPED_TRACE(what);
  if (r.found) {
    EXPECT_EQ(r.beyond, 0.0);
    return;
  }
  ++tally.nothing;
  ASSERT_GE(r.beyond, 0.0);
  ASSERT_LE(r.beyond, truth + 1e-12 * scale) << "upper " << q.upper_bound << " rel " << q.rel_tolerance;
  if (r.beyond > q.upper_bound / (1.0 + q.rel_tolerance) * (1.0 + 1e-9)) ++tally.more;
}

TEST(DistanceBeyond, NeverAboveTheTrueDistanceOfTwoMeshes) {
  struct Case {
    Mesh a, b;
    double spread;
  };
  const Case cases[] = {
      {testing::make_torus(Vec3::Zero(), 1.0, 0.3, 20, 10), testing::make_sphere(Vec3::Zero(), 0.5, 8, 12), 3.0},
      {testing::make_soup(21, 300, Vec3::Zero(), 1.0, 0.3), testing::make_soup(22, 250, Vec3::Zero(), 1.0, 0.3), 3.0},
      {make_box(Vec3(0.1, 0.2, -0.3), Vec3(0.5, 0.2, 0.1)), make_box(Vec3(-0.2, 0.0, 0.1), Vec3(0.3, 0.3, 0.05)), 2.0},
      // A deck (one leaf of long triangles) beside a fine sphere: the
      // descent drops leaf-against-node pairs by the leaf's planes there
      // (cull_leaf), a drop that proves only the cut.
      {make_box(Vec3::Zero(), Vec3(1.2, 0.9, 0.1)), testing::make_sphere(Vec3::Zero(), 0.2, 16, 24), 1.0},
  };
  std::mt19937_64 rng(1203);
  Tally tally;
  for (const Case& c : cases) {
    const CollisionModel a(c.a), b(c.b);
    for (const Vec3& offset : {Vec3(0.3, -0.2, 0.1), Vec3(1e5, -2e5, 3e4)}) {
      for (int i = 0; i < testing::case_count(40, 10); ++i) {
        const Affine ta = random_rigid(rng, offset, 0.0);
        const Affine tb = random_rigid(rng, offset, c.spread);
        const double truth = brute_force_distance(c.a, posed_vertices(c.a, ta), c.b, posed_vertices(c.b, tb)).distance;
        if (!(truth > 0.0)) continue;
        const double scale = offset.norm() + 10.0;
        for (double upper : {1e-3, 0.05, truth * 0.25, truth * 0.5, truth * 0.9, truth * (1.0 - 1e-7)}) {
          if (upper > truth * (1.0 - 1e-7)) continue;
          for (double rel : {0.0, 0.35, 1.0}) {
            for (int kind = 0; kind < 3; ++kind) {
              DistanceRequest q{upper, rel, 1e-12};
              q.known_disjoint = kind != 1;
              q.root_cull = kind != 2;
              DistanceResult r;
              {
                // Not asked: nothing spent on it, and it says nothing.
                DistanceResult plain;
                distance(a, ta, b, tb, q, plain);
                EXPECT_EQ(plain.beyond, 0.0);
              }
              q.beyond = true;
              distance(a, ta, b, tb, q, r);
              ASSERT_FALSE(r.found) << "nothing lies below a bound under the distance: upper " << upper << " truth " << truth << " found " << r.distance << " kind " << kind << " rel " << rel;
              const bool cull = roots_apart(a, ta, b, tb, upper);
              if (cull && q.root_cull) {
                ++tally.culled;
                EXPECT_GE(r.beyond, upper);
              }
              check_beyond(q, r, truth, scale, tally, "pose " + std::to_string(i) + " kind " + std::to_string(kind));
              if (::testing::Test::HasFatalFailure()) return;
            }
          }
        }
        // Something found: beyond says nothing.
        DistanceRequest q{truth * 1.5 + 1e-9, 0.0, 0.0};
        q.beyond = true;
        DistanceResult r;
        distance(a, ta, b, tb, q, r);
        ASSERT_TRUE(r.found);
        EXPECT_EQ(r.beyond, 0.0);
      }
    }
  }
  // Both ways of proving more are exercised, and they prove more often.
  EXPECT_GT(tally.culled, 100);
  EXPECT_GT(tally.more, tally.nothing / 4);
}

TEST(DistanceBeyond, NeverAboveTheTrueDistanceOverAHeightfield) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Dem d;
  d.ncols = 23;
  d.nrows = 19;
  d.cellsize = 0.1;
  d.x0 = d.y0 = 0.05;
  d.z.resize(static_cast<std::size_t>(d.ncols) * d.nrows);
  d.valid.assign(d.z.size(), 1);
  for (double& z : d.z) z = 0.3 * u(rng);
  d.valid[static_cast<std::size_t>(5) * d.ncols + 7] = 0;  // a hole
  const Vec3 origin(-0.3, 0.2, 0.05);
  const Heightfield hf(d, origin);
  const Mesh terrain = dem_mesh(d, origin);
  const Mesh ball = testing::make_sphere(Vec3::Zero(), 0.15, 6, 9);
  const Mesh soup = testing::make_soup(5, 60, Vec3::Zero(), 0.25, 0.15);
  Tally tally;
  for (const Mesh* m : {&ball, &soup}) {
    const CollisionModel model(*m);
    for (int k = 0; k < testing::case_count(60, 15); ++k) {
      const Vec3 axis = Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized();
      Affine pose = Affine::Identity();
      pose.linear() = Eigen::AngleAxisd(6.3 * u(rng), axis).toRotationMatrix();
      pose.translation() = origin + Vec3(u(rng) * 2.4, u(rng) * 2.0, 0.2 + 1.2 * u(rng));
      const double truth = brute_force_distance(*m, posed_vertices(*m, pose), terrain, terrain.vertices).distance;
      if (!(truth > 0.0)) continue;
      for (double upper : {1e-3, truth * 0.25, truth * 0.5, truth * 0.9, truth * (1.0 - 1e-7)}) {
        if (upper > truth * (1.0 - 1e-7)) continue;
        for (double rel : {0.0, 0.35, 1.0}) {
          DistanceRequest q{upper, rel, 1e-12};
          q.known_disjoint = true;
          q.beyond = true;
          DistanceResult r;
          distance(model, pose, hf, q, r);
          ASSERT_FALSE(r.found);
          check_beyond(q, r, truth, 10.0, tally, "pose " + std::to_string(k));
          if (::testing::Test::HasFatalFailure()) return;
        }
      }
    }
  }
  EXPECT_GT(tally.more, tally.nothing / 4);
}

}  // namespace
}  // namespace plancheck
