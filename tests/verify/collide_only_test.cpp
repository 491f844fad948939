// SPDX-License-Identifier: MIT
// The pair pass of check_state against the pair-by-pair test. A state's
// pass finds the pairs whose boxes meet from every pair's box gap at once
// (the touching ones listed without branches, then sorted into pair order)
// and, collision only, only from the pairs in clusters whose union box
// meets the moving box; the static parts' poses and boxes stay in a
// per-thread scratch between states, keyed by the checker. The reference:
// Checker::pair_collides on every checked pair (its own box test, then
// the exact collision test), and for a part that only translates on a grid
// of eighths (exact arithmetic) every triangle pair by the kernel.
#include "src/checks/verify.h"
#include "src/scene/kinematics.h"
#include "src/scene/scene_loader.h"
#include "support/brute_force.h"
#include "support/fixtures.h"
#include "support/sanitized.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace plancheck {
namespace {

// `statics` static boxes and 4 box objects on a grid of eighths (exact in
// float, as the OBJ reader keeps them), many touching or overlapping; a
// Probe box translating freely, an Arm bar turning about z through the
// origin. (40 partners a moving part: 12 clusters of even counts; 41: 13
// clusters, the last of 3, so both paddings of the cluster pass.)
Scene write_scene(const testing::TempDir& dir, int statics = 36) {
  std::mt19937_64 rng(33051);
  std::uniform_int_distribution<int> centre(-24, 24), half(1, 5);
  const auto eighths = [](int k) { return k / 8.0; };
  std::vector<std::pair<std::string, Mesh>> parts;
  for (int i = 0; i < statics; ++i) {
    const Vec3 c(eighths(centre(rng)), eighths(centre(rng)), eighths(centre(rng)));
    const Vec3 h(eighths(half(rng)), eighths(half(rng)), eighths(half(rng)));
    parts.emplace_back("S" + std::to_string(i), testing::box_mesh(c - h, c + h));
  }
  parts.emplace_back("Probe", testing::box_mesh(Vec3::Constant(-0.25), Vec3::Constant(0.25)));
  parts.emplace_back("Arm", testing::box_mesh({0, -0.125, -0.125}, {2, 0.125, 0.125}));
  testing::write_obj(dir / "model.obj", parts);
  std::string objects;
  for (int i = 0; i < 4; ++i) {
    objects += std::string(i ? ", " : "") + R"({"name": "Rock)" + std::to_string(i) + R"(", "box": [0.5, 0.25, 0.75], "pose": {"xyz": [)" +
               std::to_string(eighths(centre(rng))) + ", " + std::to_string(eighths(centre(rng))) + ", " +
               std::to_string(eighths(centre(rng))) + "]}}";
  }
  testing::write_text(dir / "scene.json", R"({
  "format": "plancheck-scene/1", "model": "model.obj", "length_unit": "m", "angle_unit": "deg",
  "actions": [{"name": "P", "node": "Probe", "type": "translate", "limits": [-3.5, 3.5]},
              {"name": "J", "node": "Arm", "type": "rotate", "pivot": [0, 0, 0], "axis": [0, 0, 1], "limits": [-180, 180]}],
  "objects": [)" + objects + R"(],
  "safety_margin": 0.05
})");
  return load_scene(dir / "scene.json");
}

// The pairs in contact, in checked-pair order, by pair_collides.
std::vector<std::pair<int, int>> reference_contacts(const Checker& checker, const std::vector<double>& state) {
  PosedParts posed;
  checker.pose_parts(state, posed);
  const auto pairs = checker.pairs();
  std::vector<std::pair<int, int>> out;
  for (std::size_t k = 0; k < pairs.size(); ++k)
    if (checker.pair_collides(posed, k)) out.push_back(pairs[k]);
  return out;
}

std::vector<std::pair<int, int>> contact_pairs(const StateResult& r) {
  std::vector<std::pair<int, int>> out;
  for (const PairContact& c : r.contacts) out.emplace_back(c.part_a, c.part_b);
  return out;
}

// Every request's contacts are the reference's, for random states of the
// Probe on the grid (exact contacts at faces, edges and corners abound) and
// of the Arm; the Probe's pairs also against every triangle pair.
TEST(CollideOnly, PairPassFindsEveryPairThePairTestFinds) {
  for (const int statics : {36, 37}) {
    SCOPED_TRACE(std::to_string(statics) + " static boxes");
    testing::TempDir dir("collide-only");
    const Scene scene = write_scene(dir, statics);
    const Checker checker(scene, 1);
    const int probe = scene.find_part("Probe");
    const auto pairs = checker.pairs();
    CheckRequest collide;  // the bench's collide row
    collide.distance = false;
    collide.max_triangle_pairs = 0;
    CheckRequest listed;  // every triangle pair listed, no distance
    listed.distance = false;
    CheckRequest first = collide;  // the first contact only
    first.all_contacts = false;
    std::mt19937_64 rng(33052);
    std::uniform_int_distribution<int> grid(-28, 28);
    std::uniform_real_distribution<double> angle(-180.0, 180.0);
    const int kStates = testing::case_count(1500, 200);
    int colliding = 0, several = 0, probe_contacts = 0;
    for (int i = 0; i < kStates; ++i) {
      const std::vector<double> state = {grid(rng) / 8.0, grid(rng) / 8.0, grid(rng) / 8.0, angle(rng)};
      const std::string what = "state " + std::to_string(i);
      const auto want = reference_contacts(checker, state);
      StateResult full, a, b, c;
      checker.check_state(state, full);
      checker.check_state(state, a, collide);
      checker.check_state(state, b, listed);
      checker.check_state(state, c, first);
      ASSERT_EQ(contact_pairs(full), want) << what;
      ASSERT_EQ(contact_pairs(a), want) << what;
      ASSERT_EQ(contact_pairs(b), want) << what;
      ASSERT_EQ(c.collision, !want.empty()) << what;
      if (!want.empty()) {
        ASSERT_EQ(contact_pairs(c), decltype(want){want.front()}) << what;
      }
      for (std::size_t k = 0; k < b.contacts.size(); ++k)
        EXPECT_EQ(b.contacts[k].triangles, full.contacts[k].triangles) << what;
      colliding += !want.empty();
      several += want.size() > 1;
      // The Probe only translates by eighths: its posed vertices are exact,
      // and every triangle pair decides its pairs.
      const Affine tp = part_transform(scene, probe, state);
      const std::vector<Vec3> vp = testing::posed_vertices(scene.parts[static_cast<std::size_t>(probe)].mesh, tp);
      for (const auto& [pa, pb] : pairs) {
        if (pa != probe || scene.parts[static_cast<std::size_t>(pb)].moving()) continue;
        const Mesh& mb = scene.parts[static_cast<std::size_t>(pb)].mesh;
        const bool touch = !testing::brute_force_collide(scene.parts[static_cast<std::size_t>(probe)].mesh, vp, mb,
                                                         testing::posed_vertices(mb, Affine::Identity()), true)
                                .empty();
        const bool found = std::find(want.begin(), want.end(), std::pair<int, int>{pa, pb}) != want.end();
        EXPECT_EQ(found, touch) << what << " Probe-" << scene.parts[static_cast<std::size_t>(pb)].name;
        probe_contacts += touch;
      }
    }
    std::cout << "[ collide-only ] " << kStates << " states, " << colliding << " colliding, " << several
              << " with several pairs, " << probe_contacts << " Probe contacts\n";
    EXPECT_GE(colliding, kStates / 5);
    EXPECT_GE(several, kStates / 30);
  }
}

// A checker and its copy with a world object moved (with_placement) checked
// in turn on one thread: each sees its own static boxes, never the other's
// left in the scratch.
TEST(CollideOnly, CheckersTakingTurnsOnAThreadSeeTheirOwnStaticParts) {
  testing::TempDir dir("collide-only-turns");
  const Scene scene = write_scene(dir);
  const Checker checker(scene, 1);
  const int rock = scene.find_part("Rock0");
  CheckRequest collide;
  collide.distance = false;
  collide.max_triangle_pairs = 0;
  std::mt19937_64 rng(33053);
  std::uniform_int_distribution<int> grid(-28, 28);
  int moved_in = 0, moved_out = 0;
  for (int i = 0; i < testing::case_count(200, 40); ++i) {
    const std::vector<double> state = {grid(rng) / 8.0, grid(rng) / 8.0, grid(rng) / 8.0, 0.0};
    // The rock moved onto the Probe, and the Probe's state unchanged.
    Affine onto = Affine::Identity();
    onto.translation() = Vec3(state[0], state[1], state[2]) - scene.parts[static_cast<std::size_t>(rock)].mesh.vertices[0];
    const auto moved = checker.with_placement(rock, onto);
    for (int turn = 0; turn < 2; ++turn)
      for (const Checker* c : {&checker, moved.get()}) {
        StateResult r;
        c->check_state(state, r, collide);
        const auto want = reference_contacts(*c, state);
        ASSERT_EQ(contact_pairs(r), want) << "state " << i << (c == &checker ? " (as built)" : " (rock moved)");
        const bool rock_hit = std::any_of(want.begin(), want.end(), [&](const auto& p) { return p.second == rock; });
        (c == &checker ? moved_out : moved_in) += rock_hit;
      }
  }
  EXPECT_EQ(moved_in, 2 * testing::case_count(200, 40));  // a corner of the rock on the Probe's centre
  EXPECT_LT(moved_out, moved_in / 4);
}

}  // namespace
}  // namespace plancheck
