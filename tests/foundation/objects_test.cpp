// SPDX-License-Identifier: MIT
// The scene file's `objects` (scene-format.md "World objects"): shapes and
// poses in the scene's units, parents (a model node, a robot link), their
// place among the parts and pairs, and every bad input named by file and
// objects[i].field.
#include "src/scene/kinematics.h"
#include "src/scene/objects.h"
#include "src/scene/scene_loader.h"

#include "tests/foundation/fixtures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace plancheck {
namespace {

class ObjectsTest : public ::testing::Test {
 protected:
  void SetUp() override { testing::write_arm_model(dir_ / "arm.gltf"); }

  std::filesystem::path scene(const std::string& objects, const std::string& more = "", const std::string& name = "s.json") {
    return dir_.write(name, R"({"format": "plancheck-scene/1", "model": "arm.gltf", "length_unit": "mm", "angle_unit": "deg",
      "actions": [{"name": "J1", "node": "arm1", "type": "rotate", "pivot": [0, 0, 0], "axis": [0, 0, 1]}], "objects": )" +
                                objects + more + "}");
  }

  void expect_error(const std::string& objects, std::initializer_list<std::string> parts) {
    const auto file = scene(objects, "", "bad.json");
    testing::expect_input_error([&] { load_scene(file); }, parts);
  }

  testing::TempDir dir_;
};

constexpr double kPi = 3.14159265358979323846;

// A box in millimetres and degrees: 12 triangles, full edge lengths centred
// at the pose, rpy about fixed x, y, z; a static part checked against the arm.
TEST_F(ObjectsTest, BoxPosedInTheScenesUnits) {
  const Scene s = load_scene(scene(R"([{"name": "Rock", "box": [200, 400, 600], "pose": {"xyz": [3000, 0, 500], "rpy": [0, 0, 90]}}])"));
  const int p = s.find_part("Rock");
  ASSERT_GE(p, 0);
  const Part& rock = s.parts[static_cast<std::size_t>(p)];
  EXPECT_FALSE(rock.moving());
  EXPECT_EQ(rock.mesh.triangles.size(), 12u);
  Vec3 lo = Vec3::Constant(INFINITY), hi = -lo;
  for (const Vec3& v : rock.mesh.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  // Yaw 90: x and y extents swap.
  EXPECT_NEAR(lo.x(), 2.8, 1e-12);
  EXPECT_NEAR(hi.x(), 3.2, 1e-12);
  EXPECT_NEAR(lo.y(), -0.1, 1e-12);
  EXPECT_NEAR(hi.y(), 0.1, 1e-12);
  EXPECT_NEAR(lo.z(), 0.2, 1e-12);
  EXPECT_NEAR(hi.z(), 0.8, 1e-12);
  bool paired = false;
  for (const CheckedPair& c : s.checked_pairs) paired |= s.parts[c.a].name == "Rock" || s.parts[c.b].name == "Rock";
  EXPECT_TRUE(paired);
  ASSERT_EQ(s.objects.size(), 1u);
  EXPECT_EQ(s.objects[0].name, "Rock");
}

// Cylinder and sphere contain the true shape (every face at least the radius
// from the axis or centre), as the URDF loader's primitives.
TEST_F(ObjectsTest, CylinderAndSphereContainTheTrueShape) {
  const Scene s = load_scene(scene(R"([{"name": "Pole", "cylinder": {"radius": 50, "length": 1200}, "pose": {"xyz": [1000, 1000, 600]}},
                                       {"name": "Ball", "sphere": 100, "pose": {"xyz": [500, -1000, 400]}}])"));
  const Part& pole = s.parts[static_cast<std::size_t>(s.find_part("Pole"))];
  const Part& ball = s.parts[static_cast<std::size_t>(s.find_part("Ball"))];
  for (const Tri& t : pole.mesh.triangles) {
    const Vec3 a = pole.mesh.vertices[t[0]], b = pole.mesh.vertices[t[1]], c = pole.mesh.vertices[t[2]];
    const Vec3 n = (b - a).cross(c - a).normalized();
    if (std::abs(n.z()) > 0.5) continue;  // a cap
    EXPECT_GE(std::abs(n.dot(a - Vec3(1, 1, 0))), 0.05);
  }
  for (const Tri& t : ball.mesh.triangles) {
    const Vec3 a = ball.mesh.vertices[t[0]], b = ball.mesh.vertices[t[1]], c = ball.mesh.vertices[t[2]];
    EXPECT_GE(std::abs((b - a).cross(c - a).normalized().dot(a - Vec3(0.5, -1, 0.4))), 0.1);
  }
}

// An object on a model node moves with it (its chain is the node's).
TEST_F(ObjectsTest, ObjectOnANodeMovesWithIt) {
  const Scene s = load_scene(scene(R"([{"name": "Bag", "box": [50, 50, 80], "parent": "arm2", "pose": {"xyz": [1500, 0, 100]}}])"));
  const int bag = s.find_part("Bag"), arm2 = s.find_part("arm2");
  EXPECT_EQ(s.parts[static_cast<std::size_t>(bag)].chain, s.parts[static_cast<std::size_t>(arm2)].chain);
  const std::vector<double> q = {37.0};
  EXPECT_TRUE(part_transform(s, bag, q).isApprox(part_transform(s, arm2, q)));
  EXPECT_FALSE(part_transform(s, bag, q).isApprox(Affine::Identity()));
}

// An object on a robot link: posed in the link's frame (axes included) and
// moving with the link. In arm.urdf, link `fore` stands at (0.5, 0, 0.45)
// rolled 90 degrees about x, so its y axis is the world's z.
TEST_F(ObjectsTest, ObjectOnARobotLinkUsesTheLinksFrame) {
  const std::filesystem::path robot = std::filesystem::path(PLANCHECK_SOURCE_DIR) / "tests/data/robot/arm_description/urdf/arm.urdf";
  const auto file = dir_.write("r.json", R"({"format": "plancheck-scene/1", "length_unit": "m", "angle_unit": "rad",
      "robot": {"urdf": ")" + robot.string() + R"("},
      "objects": [{"name": "Held", "box": [0.02, 0.02, 0.02], "parent": "fore", "pose": {"xyz": [0, 0.1, 0]}}]})");
  const Scene s = load_scene(file);
  const int held = s.find_part("Held"), fore = s.find_part("fore");
  ASSERT_GE(held, 0);
  ASSERT_GE(fore, 0);
  Vec3 centre = Vec3::Zero();
  for (const Vec3& v : s.parts[static_cast<std::size_t>(held)].mesh.vertices) centre += v / 8.0;
  EXPECT_NEAR((centre - Vec3(0.5, 0, 0.55)).norm(), 0, 1e-12);
  EXPECT_EQ(s.parts[static_cast<std::size_t>(held)].chain, s.parts[static_cast<std::size_t>(fore)].chain);
  std::vector<double> q(s.parameter_names.size());
  for (std::size_t i = 0; i < q.size(); ++i) q[i] = 0.3 + 0.1 * static_cast<double>(i);
  EXPECT_TRUE(part_transform(s, held, q).isApprox(part_transform(s, fore, q)));
}

// allowed_collisions may name an object (and a node's subtree holds the
// objects on it); probes may be fixed to one.
TEST_F(ObjectsTest, AllowedCollisionsAndProbesNameObjects) {
  const auto count = [](const Scene& s, const std::string& name) {
    int n = 0;
    for (const CheckedPair& c : s.checked_pairs) n += s.parts[c.a].name == name || s.parts[c.b].name == name;
    return n;
  };
  const std::string objects = R"([{"name": "Rock", "box": [100, 100, 100], "pose": {"xyz": [3000, 0, 0]}},
                                  {"name": "Bag", "box": [50, 50, 50], "parent": "arm2", "pose": {"xyz": [1500, 0, 300]}}])";
  const Scene all = load_scene(scene(objects));
  const Scene some = load_scene(scene(objects, R"(, "allowed_collisions": [["Rock", "arm1"], ["arm2", "base"]],
      "probes": [{"name": "down", "part": "Bag", "origin": [1500, 0, 300], "direction": [0, 0, -1], "max_range": 1000}])", "t.json"));
  EXPECT_EQ(count(all, "Rock"), 5);   // against every moving part: arm1, arm1b, arm2, tip, Bag
  EXPECT_EQ(count(some, "Rock"), 0);  // arm1's subtree is every moving part (Bag included)
  EXPECT_EQ(count(all, "Bag"), 3);    // base, mast, Rock
  EXPECT_EQ(count(some, "Bag"), 1);   // mast: [arm2, base] holds Bag in arm2's subtree, [Rock, arm1] too
  EXPECT_EQ(some.probes[0].part_index, some.find_part("Bag"));
}

TEST_F(ObjectsTest, BadObjectsNameFileAndField) {
  expect_error(R"({})", {"bad.json", "objects: expected an array"});
  std::string many = "[";
  for (std::size_t i = 0; i <= kMaxObjects; ++i) many += (i ? ", " : "") + std::string(R"({"name": "o)") + std::to_string(i) + R"(", "box": [1, 1, 1]})";
  expect_error(many + "]", {"bad.json", "objects: more than 4096 objects"});
  expect_error(R"([{"box": [1, 1, 1]}])", {"bad.json", "objects[0].name: missing"});
  expect_error(R"([{"name": "A", "box": [1, 1, 1]}, {"name": "A", "sphere": 1}])",
               {"bad.json", "objects[1].name: 'A' is already the name of an object"});
  expect_error(R"([{"name": "base", "box": [1, 1, 1]}])", {"bad.json", "objects[0].name: 'base' is already the name of the part"});
  expect_error(R"([{"name": "A", "box": [1, 0, 1]}])", {"bad.json", "objects[0].box[1]: must be a positive finite number"});
  expect_error(R"([{"name": "A", "box": [1, -2, 1]}])", {"objects[0].box[1]: must be a positive"});
  expect_error(R"([{"name": "A", "box": [1, 1]}])", {"objects[0].box: expected an array of 3 numbers"});
  expect_error(R"([{"name": "A", "sphere": 0}])", {"objects[0].sphere: must be a positive"});
  expect_error(R"([{"name": "A", "cylinder": {"radius": 1}}])", {"objects[0].cylinder.length: missing"});
  expect_error(R"([{"name": "A", "cylinder": {"radius": -1, "length": 1}}])", {"objects[0].cylinder.radius: must be a positive"});
  expect_error(R"([{"name": "A"}])", {"objects[0]: no shape"});
  expect_error(R"([{"name": "A", "box": [1, 1, 1], "sphere": 1}])", {"objects[0]: more than one shape"});
  expect_error(R"([{"name": "A", "cone": 1}])", {"objects[0].cone: unknown key"});
  expect_error(R"([{"name": "A", "box": [1, 1, 1], "pose": {"xyz": [0, 0, 0], "quat": [0, 0, 0, 1]}}])",
               {"objects[0].pose.quat: unknown key"});
  expect_error(R"([{"name": "A", "box": [1, 1, 1], "parent": "nowhere"}])",
               {"bad.json", "objects[0].parent: no node or link named 'nowhere'"});
  expect_error(R"([{"name": "A", "box": [1, 1, 1]}, {"name": "B", "box": [1, 1, 1], "parent": "A"}])",
               {"objects[1].parent: 'A' is a world object"});
  expect_error(R"([{"name": "A", "mesh": "missing.stl"}])", {"bad.json", "objects[0].mesh: cannot open", "missing.stl"});
  expect_error(R"([{"name": "A", "box": [1, 1, 1], "scale": [1, 1, 1]}])", {"objects[0].scale: only a mesh has a scale"});
  expect_error(R"([{"name": "A", "mesh": "arm.gltf", "scale": [1, 0, 1]}])", {"objects[0].scale[1]: must be a positive"});
}

// A mesh object: every triangle of the file, times scale and length_unit.
TEST_F(ObjectsTest, MeshObjectReadsAnyModelFile) {
  const Scene s = load_scene(scene(R"([{"name": "Copy", "mesh": "arm.gltf", "scale": [2, 1, 1], "pose": {"xyz": [0, 0, 5000]}}])"));
  const Part& copy = s.parts[static_cast<std::size_t>(s.find_part("Copy"))];
  std::size_t model = 0;
  for (const Part& p : s.parts)
    if (p.name != "Copy") model += p.mesh.triangles.size();
  EXPECT_EQ(copy.mesh.triangles.size(), model);
  double top = -INFINITY, far = -INFINITY;
  for (const Vec3& v : copy.mesh.vertices) {
    top = std::max(top, v.z());
    far = std::max(far, v.x());
  }
  EXPECT_NEAR(top, 5.0 + 0.002, 1e-9);  // the mast's top (2 mm in the file) 5 m up
  EXPECT_NEAR(far, 2 * 2.25 * 0.001, 1e-12);
  (void)kPi;
}

}  // namespace
}  // namespace plancheck
