// SPDX-License-Identifier: MIT
// Static triangles beyond every moving part's reach are left out at build
// time: the count is reported, results do not change, and contact triangle
// indices still name the scene mesh's triangles.
#include "src/scene/scene_loader.h"
#include "src/checks/verify.h"
#include "src/checks/probes.h"
#include "support/fixtures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace plancheck {
namespace {

using testing::TempDir;

constexpr double kPi = 3.14159265358979323846;

Mesh concat(const Mesh& a, const Mesh& b) {
  Mesh m = a;
  const auto base = static_cast<std::uint32_t>(a.vertices.size());
  m.vertices.insert(m.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (Tri t : b.triangles) m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  return m;
}

// verify_test's bar over a slab, with a far block (x in [40, 41], z in
// [5, 6]) stored first in the slab's own mesh, so the slab's triangles have
// mesh indices 12..23 and dropping the block shifts the model's indices.
struct Scene3 {
  TempDir dir{"prune"};
  Scene scene;
  Scene3() {
    const Mesh far = testing::box_mesh({40, -1, 5}, {41, 1, 6});
    const Mesh slab = testing::box_mesh({-3, -1, -1}, {3, 1, 0});
    testing::write_obj(dir / "model.obj", {{"Slab", concat(far, slab)},
                                           {"Bar", testing::box_mesh({0, -0.1, 0.9}, {2, 0.1, 1.1})}});
    testing::write_text(dir / "scene.json", R"({
  "format": "plancheck-scene/1", "model": "model.obj", "length_unit": "m", "angle_unit": "deg",
  "actions": [{"name": "J1", "node": "Bar", "type": "rotate", "pivot": [0, 0, 1], "axis": [0, 1, 0], "limits": [-90, 30]}],
  "safety_margin": 0.05
})");
    scene = load_scene(dir / "scene.json");
  }
};

TEST(Prune, FarStaticTrianglesAreLeftOutAndCounted) {
  Scene3 s;
  const Checker checker(s.scene);
  EXPECT_EQ(checker.left_out_static_triangles(), 12u);
  EXPECT_EQ(checker.triangle_count(), 24u + 12u - 12u);
}

TEST(Prune, DistancesAndContactIndicesUnchanged) {
  Scene3 s;
  const Checker checker(s.scene);
  const int slab = s.scene.find_part("Slab");
  ASSERT_GE(slab, 0);
  const Mesh& mesh = s.scene.parts[static_cast<std::size_t>(slab)].mesh;
  // Safe: the closed form of verify_test (bar's underside is float(0.9)).
  for (double deg : {0.0, 10.0, 20.0}) {
    StateResult r;
    checker.check_state({deg}, r);  // as written, in the scene's degrees
    const double a = deg * kPi / 180.0;
    const double h = 1.0 - static_cast<double>(0.9f);
    EXPECT_FALSE(r.collision);
    EXPECT_NEAR(r.min_distance, 1.0 - 2.0 * std::sin(a) - h * std::cos(a), 1e-12) << deg;
  }
  // Colliding: the bar's tip goes through the slab's top; every listed slab
  // triangle is a top-face triangle of the slab (z = 0), not of the block.
  StateResult r;
  checker.check_state({35.0}, r);
  ASSERT_TRUE(r.collision);
  ASSERT_FALSE(r.contacts.empty());
  for (const PairContact& c : r.contacts) {
    const bool slab_is_b = c.part_b == slab;
    ASSERT_TRUE(slab_is_b || c.part_a == slab);
    for (const auto& [ta, tb] : c.triangles) {
      const std::uint32_t t = slab_is_b ? tb : ta;
      ASSERT_LT(t, mesh.triangles.size());
      EXPECT_GE(t, 12u);
      double zmax = -1e9;
      for (std::uint32_t v : mesh.triangles[t]) zmax = std::max(zmax, mesh.vertices[v].z());
      EXPECT_EQ(zmax, 0.0);
    }
  }
}


// `count` static parts S0, S1, ..., each two boxes: one near the sweep of
// the tests' bar (pivot at height 1, turning about y), one maybe far (every
// third within 30 m, the others within 3 m).
std::vector<std::pair<std::string, Mesh>> static_parts_around_bar(std::mt19937_64& rng, int count) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<std::pair<std::string, Mesh>> parts;
  for (int k = 0; k < count; ++k) {
    const double reach = k % 3 == 0 ? 30.0 : 3.0;
    const Vec3 c1(reach * u(rng), 2 * u(rng), reach * u(rng)), c2(3 * u(rng), 2 * u(rng), -1.5 + 0.3 * u(rng));
    const Vec3 h(0.2 + 0.1 * u(rng), 0.2, 0.2 + 0.1 * u(rng));
    parts.emplace_back("S" + std::to_string(k),
                       concat(testing::box_mesh(c1 - h, c1 + h), testing::box_mesh(c2 - h, c2 + h)));
  }
  return parts;
}

// prune_static runs its passes over parts in parallel (--threads): on random
// scenes of many static parts around a moving bar, a build on 2 threads
// leaves out exactly what a build on 1 thread does, and answers the same.
TEST(Prune, ParallelPruningEqualsSerial) {
  std::mt19937_64 rng(1126);
  for (int trial = 0; trial < 6; ++trial) {
    TempDir dir{"prune-parallel"};
    std::vector<std::pair<std::string, Mesh>> parts = static_parts_around_bar(rng, 12);
    parts.emplace_back("Bar", testing::box_mesh({0, -0.1, 0.9}, {2, 0.1, 1.1}));
    testing::write_obj(dir / "model.obj", parts);
    testing::write_text(dir / "scene.json", R"({
  "format": "plancheck-scene/1", "model": "model.obj", "length_unit": "m", "angle_unit": "deg",
  "actions": [{"name": "J1", "node": "Bar", "type": "rotate", "pivot": [0, 0, 1], "axis": [0, 1, 0], "limits": [-90, 30]}],
  "safety_margin": 0.05
})");
    const Scene scene = load_scene(dir / "scene.json");
    const Checker serial(scene, 1), parallel(scene, 2);
    SCOPED_TRACE(trial);
    EXPECT_GT(serial.left_out_static_triangles(), 0u);
    EXPECT_EQ(parallel.left_out_static_triangles(), serial.left_out_static_triangles());
    EXPECT_EQ(parallel.triangle_count(), serial.triangle_count());
    EXPECT_EQ(parallel.memory_bytes(), serial.memory_bytes());
    for (double deg = -90.0; deg <= 30.0; deg += 7.5) {
      StateResult a, b;
      serial.check_state({deg}, a);
      parallel.check_state({deg}, b);
      EXPECT_EQ(a.collision, b.collision) << deg;
      EXPECT_EQ(a.min_distance, b.min_distance) << deg;
      ASSERT_EQ(a.contacts.size(), b.contacts.size()) << deg;
      for (std::size_t i = 0; i < a.contacts.size(); ++i) {
        EXPECT_EQ(a.contacts[i].part_a, b.contacts[i].part_a);
        EXPECT_EQ(a.contacts[i].part_b, b.contacts[i].part_b);
        EXPECT_EQ(a.contacts[i].triangles, b.contacts[i].triangles);
      }
    }
  }
}

// With probes and a second thread the structures are one queue of jobs: the
// probes' ray scene, the pruning beside it, then the parts (static ones
// waiting for the pruning). Built so on 2 threads, the checker leaves out,
// answers and reads its probes exactly as built on 1 thread.
TEST(Prune, QueuedBuildOnTwoThreadsEqualsOneThread) {
  std::mt19937_64 rng(2611);
  for (int trial = 0; trial < 4; ++trial) {
    TempDir dir{"prune-queue"};
    std::vector<std::pair<std::string, Mesh>> parts = static_parts_around_bar(rng, 10);
    parts.emplace_back("Bar", testing::box_mesh({0, -0.1, 0.9}, {2, 0.1, 1.1}));
    parts.emplace_back("Tip", testing::box_mesh({2, -0.05, 0.95}, {2.2, 0.05, 1.05}));
    testing::write_obj(dir / "model.obj", parts);
    testing::write_text(dir / "scene.json", R"({
  "format": "plancheck-scene/1", "model": "model.obj", "length_unit": "m", "angle_unit": "deg",
  "actions": [{"name": "J1", "node": "Bar", "type": "rotate", "pivot": [0, 0, 1], "axis": [0, 1, 0], "limits": [-90, 30]},
              {"name": "J2", "node": "Tip", "type": "rotate", "pivot": [0, 0, 1], "axis": [0, 1, 0], "limits": [-90, 30]}],
  "safety_margin": 0.05,
  "probes": [{"name": "down", "part": "Bar", "origin": [1.5, 0, 0.85], "direction": [0, 0, -1], "max_range": 5.0},
             {"name": "fan", "part": "Tip", "origin": [2.1, 0, 0.9], "direction": [0, 0, -1],
              "fan": {"count": 8, "half_angle": 30}, "max_range": 5.0}]
})");
    const Scene scene = load_scene(dir / "scene.json");
    const Checker serial(scene, 1), queued(scene, 2);
    SCOPED_TRACE(trial);
    EXPECT_GT(serial.left_out_static_triangles(), 0u);
    EXPECT_EQ(queued.left_out_static_triangles(), serial.left_out_static_triangles());
    EXPECT_EQ(queued.triangle_count(), serial.triangle_count());
    EXPECT_EQ(queued.memory_bytes(), serial.memory_bytes());
    ASSERT_NE(serial.probe_caster(), nullptr);
    ASSERT_NE(queued.probe_caster(), nullptr);
    int hits = 0;
    for (double deg = -90.0; deg <= 30.0; deg += 7.5) {
      const std::vector<double> params{deg, -0.5 * deg};
      StateResult a, b;
      serial.check_state(params, a);
      queued.check_state(params, b);
      EXPECT_EQ(a.collision, b.collision) << deg;
      EXPECT_EQ(a.min_distance, b.min_distance) << deg;
      EXPECT_EQ(a.part_a, b.part_a) << deg;
      EXPECT_EQ(a.part_b, b.part_b) << deg;
      ASSERT_EQ(a.contacts.size(), b.contacts.size()) << deg;
      for (std::size_t i = 0; i < a.contacts.size(); ++i) EXPECT_EQ(a.contacts[i].triangles, b.contacts[i].triangles);
      std::vector<ProbeReading> pa, pb;
      serial.probe_caster()->cast_state(params, pa);
      queued.probe_caster()->cast_state(params, pb);
      ASSERT_EQ(pa.size(), 2u);
      ASSERT_EQ(pb.size(), pa.size());
      for (std::size_t q = 0; q < pa.size(); ++q) {
        EXPECT_EQ(pa[q].distance, pb[q].distance) << deg;
        EXPECT_EQ(pa[q].hit, pb[q].hit) << deg;
        hits += pa[q].hit >= 0 ? 1 : 0;
      }
    }
    EXPECT_GT(hits, 0);  // the probes see static parts
  }
}

}  // namespace
}  // namespace plancheck
