// SPDX-License-Identifier: MIT
// Model-level stability (issue 6, part 2): collide() and distance() on two
// box meshes built in double through the API, against the exact CGAL
// reference over all triangle pairs. Contacts at a face, an edge and a
// corner, gaps 1e-3 .. 1e-12 m and a 1e-9 m penetration, for a 1 m box
// beside a 1 m box and beside a 1 mm box; each also placed 1,737.4 km from
// the origin through the transforms (the relative frame must give the same
// flags and distances) and through the vertices themselves (flags exact for
// the translated doubles, distances within 1e-6 m of the near ones); and
// turned by whole turns in radians about the small box's centre.
#include "src/geometry/collision_model.h"
#include "stability/exact_reference.h"
#include "support/fixtures.h"
#include "support/sanitized.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace plancheck {
namespace {

using stability::ExactAnswer;
using stability::exact_mesh_mesh;

constexpr double kLunarRadius = 1737400.0;
constexpr double kBound = 16.0;  // distance bound, eps * M (as the kernel suite)

struct Pair {
  std::string name;
  Mesh a, b;
};

double magnitude(const Mesh& a, const Mesh& b) {
  double m = 0;
  for (const Mesh* mesh : {&a, &b})
    for (const Vec3& v : mesh->vertices) m = std::max(m, v.cwiseAbs().maxCoeff());
  return m;
}

Mesh moved(const Mesh& m, const Vec3& t) {
  Mesh out = m;
  for (Vec3& v : out.vertices) v += t;
  return out;
}

// Every gap in Release; under the sanitizers (the exact CGAL reference is
// most of the time there) contact, the widest, the narrowest and a
// penetration, at every spot and scale.
const std::vector<double> kGaps = testing::kSanitized
    ? std::vector<double>{0.0, 1e-3, 1e-9, 1e-12, -1e-9}
    : std::vector<double>{0.0, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, -1e-9};

std::vector<Pair> pairs() {
  std::vector<Pair> out;
  for (double big : {1.0})
    for (double s : {1.0, 1e-3}) {
      const Mesh a = testing::box_mesh({0, 0, 0}, {big, big, big});
      struct Spot {
        const char* name;
        double x, y;
      };
      for (const Spot spot : {Spot{"face", 0.25, 0.25}, Spot{"edge", big, 0.25}, Spot{"corner", big, big}})
        for (double g : kGaps) {
          char name[96];
          std::snprintf(name, sizeof name, "%g m box, %g m box at its %s, gap %g", big, s, spot.name, g);
          out.push_back({name, a, testing::box_mesh({spot.x, spot.y, big + g}, {spot.x + s, spot.y + s, big + g + s})});
        }
    }
  return out;
}

struct Answer {
  bool collide = false;
  double distance = 0;
};

Answer query(const Mesh& a, const Affine& ta, const Mesh& b, const Affine& tb) {
  const CollisionModel ma(a), mb(b);
  CollideResult c;
  collide(ma, ta, mb, tb, CollideRequest{}, c);
  DistanceResult d;
  distance(ma, ta, mb, tb, DistanceRequest{}, d);
  EXPECT_TRUE(d.found);
  EXPECT_EQ(c.collide, d.distance == 0.0);
  return {c.collide, d.distance};
}

TEST(ModelStability, ContactsGapsAndTheLunarRadius) {
  std::size_t cases = 0, wrong = 0;
  double max_err = 0, max_far = 0;
  const Vec3 generic = Vec3(0.48, -0.6, 0.64);
  for (const Pair& p : pairs()) {
    ++cases;
    const ExactAnswer exact = exact_mesh_mesh(p.a, Affine::Identity(), p.b, Affine::Identity());
    const Answer near = query(p.a, Affine::Identity(), p.b, Affine::Identity());
    wrong += near.collide != exact.overlap;
    EXPECT_EQ(near.collide, exact.overlap) << p.name;
    const double err = std::abs(near.distance - exact.distance);
    max_err = std::max(max_err, err);
    EXPECT_LE(err, kBound * DBL_EPSILON * magnitude(p.a, p.b)) << p.name;
    for (const Vec3& dir : {Vec3(Vec3::UnitX()), generic}) {
      const Vec3 t = kLunarRadius * dir;
      // Through the transforms: the relative frame is exactly the near one.
      const Affine far_t{Eigen::Translation3d(t)};
      const Answer via_t = query(p.a, far_t, p.b, far_t);
      EXPECT_EQ(via_t.collide, near.collide) << p.name;
      EXPECT_NEAR(via_t.distance, near.distance, 1e-6) << p.name;
      // Through the vertices: the translated doubles are the question now
      // (a 1e-12 m gap is not representable 1,737 km out); flags exact for
      // them, distances within 1e-6 m of the near ones.
      const Mesh fa = moved(p.a, t), fb = moved(p.b, t);
      const ExactAnswer far_exact = exact_mesh_mesh(fa, Affine::Identity(), fb, Affine::Identity());
      const Answer via_v = query(fa, Affine::Identity(), fb, Affine::Identity());
      wrong += via_v.collide != far_exact.overlap;
      EXPECT_EQ(via_v.collide, far_exact.overlap) << p.name << " (vertices moved)";
      EXPECT_LE(std::abs(via_v.distance - far_exact.distance), kBound * DBL_EPSILON * magnitude(fa, fb)) << p.name;
      EXPECT_NEAR(via_v.distance, near.distance, 1e-6) << p.name;
      max_far = std::max({max_far, std::abs(via_v.distance - near.distance), std::abs(via_t.distance - near.distance)});
    }
  }
  std::printf("[stability] model: %zu box pairs (x3 placements), wrong flags %zu, max |d - exact| %.2g m, "
              "max |d far - d| %.2g m\n", cases, wrong, max_err, max_far);
}

TEST(ModelStability, WholeTurnsInRadiansMoveByRoundingOnly) {
  // Radians are used as given: 2 pi k is not a double, so a whole turn is a
  // rotation by fl(2 pi k) - 2 pi k (~1e-16 k rad). Flags are unchanged for
  // gaps above that rounding, distances move by at most |angle| eps * r.
  for (const Pair& p : pairs()) {
    const Answer ref = query(p.a, Affine::Identity(), p.b, Affine::Identity());
    const Vec3 centre = 0.5 * (p.b.vertices[0] + p.b.vertices[7]);
    for (double k : {1.0, -3.0, 1000.0, 1e6}) {
      const double angle = 2 * M_PI * k;
      Affine tb = Affine::Identity();
      tb.translate(centre).rotate(Eigen::AngleAxisd(angle, Vec3(1, 2, 2).normalized())).translate(-centre);
      const Answer r = query(p.a, Affine::Identity(), p.b, tb);
      const double slack = 8 * std::abs(angle) * DBL_EPSILON * 4.0;  // radius <= 4 m here
      EXPECT_NEAR(r.distance, ref.distance, slack) << p.name << " k " << k;
      if (ref.distance > slack && !ref.collide) {
        EXPECT_FALSE(r.collide) << p.name;
      }
    }
  }
}

}  // namespace
}  // namespace plancheck
