// SPDX-License-Identifier: MIT
// Checker::pose_parts for a list of parts (the motion checks' samples pose
// only a pair's two parts, and the longer chain of two arm parts continues
// the shorter's product) and pose_parts_moving (the same with the moving
// part's velocity field) against the whole scene posed at once: the same
// transforms and boxes bit for bit, for every pair of parts of the default
// arm and of the URDF arm, at random states.
#include "src/checks/verify.h"
#include "src/scene/kinematics.h"
#include "src/scene/scene_loader.h"
#include "foundation/fixtures.h"
#include "tests/verify/arm_scenes.h"

#include <gtest/gtest.h>

#include <cstring>
#include <vector>

namespace plancheck {
namespace {

using testing::ArmSegments;
using testing::TempDir;

bool same_bits(const Affine& a, const Affine& b) {
  return std::memcmp(a.matrix().data(), b.matrix().data(), sizeof(double) * 16) == 0;
}

bool same_bits(const Vec3& a, const Vec3& b) { return std::memcmp(a.data(), b.data(), sizeof(double) * 3) == 0; }

// A branching arm: J1 turns A, on it J2 turns B and J3 turns C (chains
// [J1, J2] and [J1, J3]: neither begins the other), with a scale on D
// below B and a static base.
std::filesystem::path branching_scene(const TempDir& dir) {
  testing::write_box_gltf(dir / "branch.gltf",
                          {{.name = "world"},
                           {.name = "Base", .parent = 0, .box = true, .lo = {-1, -1, -0.5}, .hi = {1, 1, 0}},
                           {.name = "A", .parent = 0, .box = true, .lo = {0, -0.1, 0}, .hi = {1, 0.1, 0.2}},
                           {.name = "B", .parent = 2, .box = true, .lo = {1, -0.1, 0}, .hi = {2, 0.1, 0.2}},
                           {.name = "C", .parent = 2, .box = true, .lo = {0, 0.2, 0}, .hi = {0.5, 0.6, 0.2}},
                           {.name = "D", .parent = 3, .box = true, .lo = {2, -0.1, 0}, .hi = {2.3, 0.1, 0.2}}});
  testing::write_text(dir / "branch.json", R"({"format": "plancheck-scene/1", "model": "branch.gltf",
  "length_unit": "m", "angle_unit": "deg", "actions": [
    {"name": "J1", "node": "A", "type": "rotate", "pivot": [0, 0, 0], "axis": [0, 0, 1], "limits": [-170, 170]},
    {"name": "J2", "node": "B", "type": "rotate", "pivot": [1, 0, 0], "axis": [0, 1, 0], "limits": [-90, 90]},
    {"name": "J3", "node": "C", "type": "rotate", "pivot": [0, 0.2, 0], "axis": [1, 0, 0], "limits": [-90, 90]},
    {"name": "G", "node": "D", "type": "scale", "fixed_point": [2, 0, 0]}]})");
  return dir / "branch.json";
}

// scene: 0 the default arm, 1 the URDF arm, 2 the branching arm.
void listed_poses_equal_the_whole(int which) {
  const bool urdf = which == 1;
  TempDir dir("pose-parts");
  const Scene scene = load_scene(which == 2 ? branching_scene(dir) : testing::arm_scene(dir, urdf));
  const Checker checker(scene, 1);
  ArmSegments random(scene, 5 + static_cast<std::uint64_t>(which));
  const int n = static_cast<int>(scene.parts.size());
  std::vector<double> q, unused, rates;
  PosedParts whole, listed;
  int pairs = 0, continued = 0, velocities = 0;
  for (int state = 0; state < 8; ++state) {
    random.next(1.0, q, unused);
    rates.assign(q.size(), 0.0);
    for (std::size_t k = 0; k < q.size(); ++k) rates[k] = unused[k] - q[k];
    checker.pose_parts(q, whole);
    for (int a = 0; a < n; ++a) {
      for (int b = 0; b < n; ++b) {
        if (a == b) continue;
        const int two[2] = {a, b};
        for (int moving : {-1, a}) {
          Vec3 w, u;
          const bool known = moving < 0 ? false : checker.pose_parts_moving(q, listed, two, moving, rates, w, u);
          if (moving < 0) checker.pose_parts(q, listed, two);
          for (int x : two) {
            const std::size_t i = static_cast<std::size_t>(x);
            ASSERT_TRUE(same_bits(*listed.pose[i], *whole.pose[i]))
                << scene.parts[i].name << " posed with " << scene.parts[static_cast<std::size_t>(x == a ? b : a)].name;
            ASSERT_TRUE(same_bits(listed.box[i].first, whole.box[i].first));
            ASSERT_TRUE(same_bits(listed.box[i].second, whole.box[i].second));
          }
          if (moving >= 0) {
            const auto& part = scene.parts[static_cast<std::size_t>(moving)];
            bool scaled = false;
            for (int x : part.chain) scaled = scaled || scene.actions[static_cast<std::size_t>(x)].type == ActionType::kScale;
            EXPECT_EQ(known, part.moving() && !scaled);
            if (known) {
              Affine t;
              Vec3 w2, u2;
              ASSERT_TRUE(part_transform_velocity(scene, moving, q, rates, t, w2, u2));
              EXPECT_TRUE(same_bits(w, w2) && same_bits(u, u2));
              ++velocities;
            }
          }
        }
        ++pairs;
        const auto& ca = scene.parts[static_cast<std::size_t>(a)].chain;
        const auto& cb = scene.parts[static_cast<std::size_t>(b)].chain;
        continued += !ca.empty() && ca.size() < cb.size() && std::equal(ca.begin(), ca.end(), cb.begin());
      }
    }
  }
  std::printf("[ %s ] %d pairs posed, %d with one chain continuing the other, %d velocity fields\n",
              which == 2 ? "branching arm" : urdf ? "URDF arm" : "default arm", pairs, continued, velocities);
  EXPECT_GT(continued, 8);
  EXPECT_GT(velocities, 8);
}

TEST(PoseParts, ListedPartsEqualTheWholeSceneDefaultArm) { listed_poses_equal_the_whole(0); }

TEST(PoseParts, ListedPartsEqualTheWholeSceneUrdfArm) { listed_poses_equal_the_whole(1); }

TEST(PoseParts, ListedPartsEqualTheWholeSceneBranchingArm) { listed_poses_equal_the_whole(2); }

}  // namespace
}  // namespace plancheck
