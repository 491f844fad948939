// SPDX-License-Identifier: MIT
// Measurements, not tests: disabled by default; timings never decide a test.
// Run: build/tests/plancheck_geometry_tests --gtest_also_run_disabled_tests
//        --gtest_filter='GeometryMeasure.*'
// Every timed answer is first checked against FCL (OBBRSS) on the same poses.
#include "src/geometry/bvh.h"
#include "src/geometry/collision_model.h"

#include "support/test_meshes.h"

#include <fcl/fcl.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

namespace plancheck {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> fcl_model(const Mesh& m) {
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  std::vector<fcl::Vector3d> v(m.vertices.begin(), m.vertices.end());
  std::vector<fcl::Triangle> t;
  for (const Tri& tri : m.triangles) t.emplace_back(tri[0], tri[1], tri[2]);
  model->beginModel();
  model->addSubModel(v, t);
  model->endModel();
  return model;
}

// A bumpy sphere (so BVH nodes are not all alike), about 2 * rings * segments triangles.
Mesh bumpy_sphere(double radius, int rings, int segments) {
  Mesh m = testing::make_sphere(Vec3::Zero(), radius, rings, segments);
  for (Vec3& v : m.vertices) {
    const double bump = 1.0 + 0.03 * std::sin(7 * v.x()) * std::cos(5 * v.y() + 3 * v.z());
    v *= bump;
  }
  return m;
}

TEST(GeometryMeasure, DISABLED_BuildAndQueryTimes) {
  const Mesh body = bumpy_sphere(1.5, 400, 500);               // ~400k triangles
  const Mesh arm = testing::make_torus(Vec3::Zero(), 0.5, 0.12, 150, 100);  // 30k
  auto t0 = std::chrono::steady_clock::now();
  const CollisionModel body_model(body);
  const double build_body = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  const CollisionModel arm_model(arm);
  const double build_arm = seconds_since(t0);
  std::printf("build: body %zu tris %.3f s (%.1f MB), arm %zu tris %.3f s\n",
              body.triangles.size(), build_body, body_model.memory_bytes() / 1e6,
              arm.triangles.size(), build_arm);
  {
    // Share of the oriented boxes in the build: recompute them on a copy.
    CollisionModelData copy = body_model.data();
    t0 = std::chrono::steady_clock::now();
    compute_node_obbs(copy);
    std::printf("  of which oriented boxes: %.3f s; nodes %zu\n", seconds_since(t0),
                copy.bvh.nodes.size());
  }
  t0 = std::chrono::steady_clock::now();
  auto fb = fcl_model(body);
  auto fa = fcl_model(arm);
  std::printf("fcl OBBRSS build (both): %.3f s\n", seconds_since(t0));

  // Poses of the arm: far, near (clearances 0.2, 0.01, 0.001 m), intersecting.
  struct Pose {
    const char* name;
    double gap;  // arm centre at radius 1.5 + 0.62 + gap along a tilted axis
  };
  const Pose poses[] = {{"far 1 m", 1.0},     {"near 0.2 m", 0.2}, {"near 1 cm", 0.01},
                        {"near 1 mm", 0.001}, {"in 1 mm", -0.001}, {"in 5 cm", -0.05}};
  for (const Pose& pose : poses) {
    const Vec3 axis = Vec3(0.3, -0.5, 0.8).normalized();
    Affine tb = Affine::Identity();
    // Arm standing on its rim, outer edge toward the body.
    tb.linear() = Eigen::AngleAxisd(0.7, Vec3(1, 2, 0.5).normalized()).toRotationMatrix();
    tb.translation() = axis * 3.0;
    const Affine ta = Affine::Identity();
    // Slide the arm along the axis until the clearance is the wanted one
    // (negative: pushed in that far past first contact).
    for (int it = 0; it < 6; ++it) {
      DistanceResult d0;
      distance(body_model, ta, arm_model, tb, DistanceRequest{}, d0);
      const double target = std::max(pose.gap, 0.0);
      if (d0.distance == 0.0) break;
      tb.translation() -= axis * (d0.distance - target * (it < 5 ? 1.0 : 1.0));
    }
    if (pose.gap < 0) tb.translation() += axis * pose.gap;

    fcl::CollisionObjectd oa(fb, fcl::Transform3d(ta.matrix()));
    fcl::CollisionObjectd ob(fa, fcl::Transform3d(tb.matrix()));
    const int reps = 10;
    fcl::CollisionResultd fcr;
    fcl::CollisionRequestd fcq;
    t0 = std::chrono::steady_clock::now();
    for (int r = 0; r < reps; ++r) {
      fcr.clear();
      fcl::collide(&oa, &ob, fcq, fcr);
    }
    const double fcl_collide = seconds_since(t0) / reps;
    fcl::DistanceRequestd fdq(true);
    fcl::DistanceResultd fdr;
    t0 = std::chrono::steady_clock::now();
    for (int r = 0; r < reps; ++r) {
      fdr.clear();
      fcl::distance(&oa, &ob, fdq, fdr);
    }
    const double fcl_distance = seconds_since(t0) / reps;

    CollideResult cr;
    t0 = std::chrono::steady_clock::now();
    for (int r = 0; r < reps; ++r) collide(body_model, ta, arm_model, tb, CollideRequest{0}, cr);
    const double our_collide = seconds_since(t0) / reps;
    DistanceResult dr;
    t0 = std::chrono::steady_clock::now();
    for (int r = 0; r < reps; ++r) distance(body_model, ta, arm_model, tb, DistanceRequest{}, dr);
    const double our_distance = seconds_since(t0) / reps;


    EXPECT_EQ(cr.collide, fcr.isCollision()) << pose.name;
    if (!cr.collide) {
      EXPECT_NEAR(dr.distance, fdr.min_distance, 1e-9) << pose.name;
    }
    std::printf(
        "%-11s collide=%d distance=%.6g | plancheck collide %8.1f us (%llu node pairs, %llu tri) distance "
        "%8.1f us (%llu node pairs, %llu tri pairs) | fcl collide %8.1f us distance %8.1f us\n",
        pose.name, cr.collide, dr.distance, our_collide * 1e6,
        static_cast<unsigned long long>(cr.node_pairs_visited),
        static_cast<unsigned long long>(cr.triangle_pairs_tested), our_distance * 1e6,
        static_cast<unsigned long long>(dr.node_pairs_visited),
        static_cast<unsigned long long>(dr.triangle_pairs_tested), fcl_collide * 1e6,
        fcl_distance * 1e6);
  }
}

}  // namespace
}  // namespace plancheck
