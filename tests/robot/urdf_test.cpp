// SPDX-License-Identifier: MIT
// Robots from URDF/SRDF (src/scene/robot_loader.h). The test arm in
// tests/data/robot/arm_description has every joint type, meshes in three
// formats reached three ways, primitives and a mimic joint. The same cell is
// written here by hand as a plain scene (a glTF node tree and actions with
// pivots and axes worked out on paper) and must give the same answers state
// by state; FCL on the URDF scene's geometry must agree too.
#include "src/base/error.h"
#include "src/scene/kinematics.h"
#include "src/geometry/motion_bound.h"
#include "src/scene/plan.h"
#include "src/scene/robot_loader.h"
#include "src/scene/scene_loader.h"
#include "src/checks/verify.h"
#include "bench/fcl_peer/fcl_peer.h"
#include "foundation/fixtures.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <initializer_list>
#include <random>
#include <fstream>
#include <iterator>
#include <set>
#include <sys/wait.h>

namespace plancheck {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;
using testing::expect_input_error;

const fs::path kPackage = fs::path(PLANCHECK_SOURCE_DIR) / "tests/data/robot/arm_description";
const fs::path kUrdf = kPackage / "urdf/arm.urdf";
const fs::path kSrdf = kPackage / "urdf/arm.srdf";
const fs::path kPlancheck = fs::path(PLANCHECK_BINARY_DIR) / "plancheck";

std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void write_text(const fs::path& file, const std::string& text) { std::ofstream(file, std::ios::binary) << text; }

int run_command(const std::string& command) {
  const int status = std::system(command.c_str());
  return status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

Scene load_arm() {
  SceneOptions o;
  o.srdf = kSrdf;
  return load_scene(kUrdf, o);
}

Mesh box(const Vec3& lo, const Vec3& hi) {
  Mesh m = box_tessellation(hi - lo);
  for (Vec3& v : m.vertices) v += (lo + hi) / 2;
  return m;
}

// One node of the hand-written glTF: name, parent, mesh given in the
// reference frame (every node transform is the identity; the tree only says
// what moves with what).
struct HandNode {
  std::string name;
  int parent;
  Mesh mesh;
};

void write_gltf(const fs::path& file, const std::vector<HandNode>& nodes) {
  std::vector<testing::MeshNode> out;
  for (const HandNode& n : nodes) out.push_back({n.name, n.parent, Vec3::Zero(), n.mesh});
  testing::write_mesh_gltf(file, out);
}

// The test arm at its zero pose, worked out from arm.urdf by hand: the elbow
// turns its frame by +90 degrees about x, so from the fore arm on a link's
// (x, y, z) is the reference frame's (x, -z, y).
fs::path write_hand_scene(const TempDir& dir) {
  double cylinder_dev = 0, sphere_dev = 0;
  Mesh column = cylinder_tessellation(0.05, 0.3, cylinder_dev);
  for (Vec3& v : column.vertices) v += Vec3(0, 0, 0.25);
  Mesh tool = sphere_tessellation(0.03, sphere_dev);
  for (Vec3& v : tool.vertices) v = Vec3(v.x(), -v.z(), v.y()) + Vec3(1.07, 0, 0.45);
  write_gltf(dir / "arm.gltf",
             {{"world", -1, {}},
              {"base_link", 0, box({-0.2, -0.2, 0}, {0.2, 0.2, 0.1})},
              {"column", 0, column},
              {"upper_frame", 0, {}},
              {"upper", 3, box({0, -0.04, 0.41}, {0.5, 0.04, 0.49})},
              {"fore_frame", 3, {}},
              {"fore", 5, box({0.52, -0.03, 0.43}, {0.92, 0.03, 0.47})},
              {"hand_frame", 5, {}},
              {"hand", 7, box({0.93, -0.04, 0.41}, {1.03, 0.04, 0.49})},
              {"tool_frame", 7, {}},
              {"tool", 9, tool},
              {"finger_l_frame", 9, {}},
              {"finger_l", 11, box({1.13, -0.01, 0.46}, {1.17, 0.01, 0.47})},
              {"finger_r_frame", 9, {}},
              {"finger_r", 13, box({1.13, -0.01, 0.43}, {1.17, 0.01, 0.44})}});
  return dir.write("hand.json", R"({"format": "plancheck-scene/1", "model": "arm.gltf",
    "length_unit": "m", "angle_unit": "rad",
    "actions": [
      {"name": "arm/shoulder", "node": "upper_frame", "type": "rotate", "pivot": [0, 0, 0.4], "axis": [0, 0, 1], "limits": [-3, 3]},
      {"name": "elbow", "node": "fore_frame", "type": "rotate", "pivot": [0.5, 0, 0.45], "axis": [0, -1, 0]},
      {"name": "slide", "node": "hand_frame", "type": "translate", "axis": [1, 0, 0], "limits": [0, 0.2]},
      {"name": "wrist/roll", "node": "tool_frame", "type": "rotate", "pivot": [1.03, 0, 0.45], "axis": [1, 0, 0], "limits": [-1.5, 1.5]},
      {"name": "finger_left", "node": "finger_l_frame", "type": "translate", "axis": [0, 0, 1], "limits": [0, 0.03]},
      {"name": "finger_right", "node": "finger_r_frame", "type": "translate", "axis": [0, 0, 1]}],
    "allowed_collisions": [["column", "upper"], ["tool", "finger_l"], ["tool", "finger_r"]]})");
}

std::set<std::pair<std::string, std::string>> pair_names(const Scene& s) {
  std::set<std::pair<std::string, std::string>> out;
  for (const CheckedPair& p : s.checked_pairs)
    out.insert(std::minmax(s.parts[p.a].name, s.parts[p.b].name));
  return out;
}

// Uniform within the limits (elbow: a whole turn and a bit either way).
std::vector<double> random_state(const Scene& s, std::mt19937_64& rng) {
  std::vector<double> q(s.parameter_names.size());
  for (const Action& a : s.actions) {
    if (a.parameter_count == 0) continue;
    const double lo = a.has_limits ? a.lower : -7.0, hi = a.has_limits ? a.upper : 7.0;
    q[a.first_parameter] = std::uniform_real_distribution<double>(lo, hi)(rng);
  }
  return q;
}

TEST(RobotLoader, ArmJointsBecomeActionsAndLinksParts) {
  const Scene s = load_arm();
  EXPECT_EQ(s.parameter_names, (std::vector<std::string>{"arm/shoulder", "elbow", "slide", "wrist/roll", "finger_left"}));
  ASSERT_EQ(s.actions.size(), 6u);
  ASSERT_EQ(s.parts.size(), 8u);  // tool0 has no geometry: a node, not a part
  auto action = [&](const std::string& name) -> const Action& {
    for (const Action& a : s.actions)
      if (a.name == name) return a;
    throw std::runtime_error("no action " + name);
  };
  EXPECT_EQ(action("elbow").type, ActionType::kRotate);
  EXPECT_FALSE(action("elbow").has_limits);  // continuous
  EXPECT_NEAR((action("elbow").axis - Vec3(0, -1, 0)).norm(), 0, 1e-15);
  EXPECT_NEAR((action("elbow").pivot - Vec3(0.5, 0, 0.45)).norm(), 0, 1e-15);
  EXPECT_EQ(action("slide").type, ActionType::kTranslateAxis);
  EXPECT_EQ(action("slide").lower, 0.0);
  EXPECT_EQ(action("slide").upper, 0.2);
  const Action& right = action("finger_right");
  EXPECT_EQ(right.parameter_count, 0);
  ASSERT_GE(right.mimic, 0);
  EXPECT_EQ(s.actions[right.mimic].name, "finger_left");
  EXPECT_EQ(right.multiplier, -1.0);
  // The fixed joint folds column into base_link's (empty) chain.
  EXPECT_EQ(s.parts[s.find_part("column")].chain, s.parts[s.find_part("base_link")].chain);
  ASSERT_TRUE(s.robot);
  EXPECT_EQ(s.robot->links, 9);
  EXPECT_EQ(s.robot->joints, 8);
  EXPECT_EQ(s.robot->cylinders, 1);
  EXPECT_EQ(s.robot->spheres, 1);
}

// Each mesh where the hand-written numbers put it: the STL by package://,
// the OBJ by a relative path with a space and scale="1 1 2", the DAE in
// millimetres with Z_UP (unit applied, no up-axis turn, as RViz shows it).
TEST(RobotLoader, MeshesLandWhereTheUrdfPutsThem) {
  const Scene s = load_arm();
  auto bounds = [&](const std::string& part) {
    Eigen::AlignedBox3d b;
    for (const Vec3& v : s.parts[s.find_part(part)].mesh.vertices) b.extend(v);
    return b;
  };
  auto expect_box = [&](const std::string& part, const Vec3& lo, const Vec3& hi) {
    const auto b = bounds(part);
    EXPECT_LT((b.min() - lo).norm(), 1e-6) << part << " min " << b.min().transpose();
    EXPECT_LT((b.max() - hi).norm(), 1e-6) << part << " max " << b.max().transpose();
  };
  expect_box("upper", {0, -0.04, 0.41}, {0.5, 0.04, 0.49});
  expect_box("fore", {0.52, -0.03, 0.43}, {0.92, 0.03, 0.47});
  expect_box("hand", {0.93, -0.04, 0.41}, {1.03, 0.04, 0.49});
  expect_box("finger_r", {1.13, -0.01, 0.43}, {1.17, 0.01, 0.44});
}

TEST(RobotLoader, HandWrittenSceneGivesIdenticalAnswersStateByState) {
  TempDir dir;
  const Scene urdf = load_arm();
  const Scene hand = load_scene(write_hand_scene(dir));
  EXPECT_EQ(pair_names(urdf), pair_names(hand));
  const Checker a(urdf, 1), b(hand, 1);
  std::mt19937_64 rng(19);
  int collisions = 0, compared = 0, near_contact = 0;
  for (int i = 0; i < 1500; ++i) {
    const std::vector<double> q = random_state(urdf, rng);
    std::vector<double> qh(q);
    qh.push_back(-q[4]);  // finger_right mimics finger_left with multiplier -1
    StateResult ra, rb;
    a.check_state(q, ra);
    b.check_state(qh, rb);
    // glTF and assimp hold float coordinates: within 1e-6 m of contact the
    // two models may differ; such states are counted, not compared.
    if (std::min(ra.min_distance, rb.min_distance) < 1e-6 && ra.collision != rb.collision) {
      ++near_contact;
      continue;
    }
    ++compared;
    ASSERT_EQ(ra.collision, rb.collision) << "state " << i;
    collisions += ra.collision;
    EXPECT_NEAR(ra.min_distance, rb.min_distance, 1e-6) << "state " << i;
    EXPECT_EQ(ra.limit_action >= 0, rb.limit_action >= 0) << "state " << i;
  }
  EXPECT_LE(near_contact, 3);
  EXPECT_GT(collisions, compared / 20);
  EXPECT_LT(collisions, compared - compared / 20);
}

TEST(RobotLoader, FclAgreesOnTheUrdfGeometry) {
  const Scene s = load_arm();
  const Checker checker(s, 1);
  std::vector<const Mesh*> meshes;
  for (const Part& p : s.parts) meshes.push_back(&p.mesh);
  const reference::FclPeer fcl(s, meshes, checker.pairs());
  std::mt19937_64 rng(2019);
  int collisions = 0;
  for (int i = 0; i < 800; ++i) {
    const std::vector<double> q = random_state(s, rng);
    StateResult ours;
    checker.check_state(q, ours);
    const auto ref = fcl.check(q);
    ASSERT_EQ(ours.collision, ref.collision) << "state " << i;
    collisions += ours.collision;
    if (!ours.collision) {
      EXPECT_NEAR(ours.min_distance, ref.distance, 1e-9) << "state " << i;
    }
  }
  EXPECT_GT(collisions, 40);
  EXPECT_LT(collisions, 760);
}

// The mimic finger follows its master: at finger_left = d, finger_r has moved by -d.
TEST(RobotLoader, MimicJointFollowsItsMaster) {
  const Scene s = load_arm();
  std::vector<double> q(s.parameter_names.size(), 0.0);
  q[4] = 0.02;
  const Affine left = part_transform(s, s.find_part("finger_l"), q);
  const Affine right = part_transform(s, s.find_part("finger_r"), q);
  EXPECT_LT((left.translation() - Vec3(0, 0, 0.02)).norm(), 1e-15);
  EXPECT_LT((right.translation() - Vec3(0, 0, -0.02)).norm(), 1e-15);
}

// The motion bound of a mimic link covers how far it really travels.
TEST(RobotLoader, MotionBoundCoversAMimicLink) {
  const Scene s = load_arm();
  const MotionBound bound(s);
  std::vector<double> qa(s.parameter_names.size(), 0.0), qb(qa);
  qb[4] = 0.03;
  const int right = s.find_part("finger_r");
  const double travelled = (part_transform(s, right, qb).translation() - part_transform(s, right, qa).translation()).norm();
  EXPECT_NEAR(travelled, 0.03, 1e-15);
  EXPECT_GE(bound.part_bound(right, qa, qb), travelled);
  EXPECT_LE(bound.part_bound(right, qa, qb), 0.03 * (1 + 1e-6));
}

TEST(RobotLoader, SrdfAllowsExactlyThoseLinkPairs) {
  const Scene with = load_arm();
  const Scene without = load_scene(kUrdf);
  const auto a = pair_names(with), b = pair_names(without);
  EXPECT_EQ(b.size(), a.size() + 3);
  EXPECT_FALSE(a.count({"column", "upper"}));
  EXPECT_TRUE(b.count({"column", "upper"}));
  // Not the subtree: column against the fore arm (upper's child) stays checked.
  EXPECT_TRUE(a.count({"column", "fore"}));
  EXPECT_FALSE(a.count({"finger_l", "tool"}));
  EXPECT_TRUE(a.count({"finger_l", "finger_r"}));
}

TEST(RobotLoader, AllowedCollisionsNamingALinkMeanExactlyThatLink) {
  TempDir dir;
  const fs::path scene = dir.write("s.json", R"({"format": "plancheck-scene/1", "angle_unit": "rad",
    "robot": {"urdf": ")" + kUrdf.string() + R"("}, "allowed_collisions": [["upper", "base_link"]]})");
  const auto p = pair_names(load_scene(scene));
  EXPECT_FALSE(p.count({"base_link", "upper"}));
  EXPECT_TRUE(p.count({"base_link", "fore"}));
}

// The robot stands on a node of a model and moves with that node's action.
TEST(RobotLoader, RobotBesideAModelMovesWithItsParent) {
  TempDir dir;
  testing::write_box_gltf(dir / "cell.gltf", {{.name = "world"},
                                              {.name = "ground", .parent = 0, .box = true, .lo = {-2, -2, -0.1}, .hi = {2, 2, 0}},
                                              {.name = "Deck", .parent = 0},
                                              {.name = "deck_plate", .parent = 2, .box = true, .lo = {-0.3, -0.3, 0.9}, .hi = {0.3, 0.3, 1}}});
  const fs::path file = dir.write("s.json", R"({"format": "plancheck-scene/1", "model": "cell.gltf",
    "length_unit": "m", "angle_unit": "rad",
    "actions": [{"name": "lift", "node": "Deck", "type": "translate", "axis": [0, 0, 1], "limits": [0, 1]}],
    "robot": {"urdf": ")" + kUrdf.string() + R"(", "parent": "Deck", "origin": {"xyz": [0, 0, 1], "rpy": [0, 0, 1.5707963267948966]}},
    "allowed_collisions": [["deck_plate", "base_link"]]})");
  const Scene s = load_scene(file);
  ASSERT_GE(s.find_part("upper"), 0);
  // rpy yaw 90 degrees: the upper arm (x 0..0.5 in the robot) now lies along +y, 1 m up.
  Eigen::AlignedBox3d b;
  for (const Vec3& v : s.parts[s.find_part("upper")].mesh.vertices) b.extend(v);
  EXPECT_LT((b.min() - Vec3(-0.04, 0, 1.41)).norm(), 1e-6);
  EXPECT_LT((b.max() - Vec3(0.04, 0.5, 1.49)).norm(), 1e-6);
  std::vector<double> q(s.parameter_names.size(), 0.0);
  const auto lift = std::find(s.parameter_names.begin(), s.parameter_names.end(), "lift");
  ASSERT_NE(lift, s.parameter_names.end());
  q[lift - s.parameter_names.begin()] = 0.5;
  const Affine t = part_transform(s, s.find_part("base_link"), q);
  EXPECT_LT((t.translation() - Vec3(0, 0, 0.5)).norm(), 1e-15);
  EXPECT_LT((t.linear() - Mat3::Identity()).norm(), 1e-15);
  // The base stands on the plate (allowed) but is checked against the ground.
  const auto p = pair_names(s);
  EXPECT_FALSE(p.count({"base_link", "deck_plate"}));
  EXPECT_TRUE(p.count({"base_link", "ground"}));
}

// --- Tessellations contain the true shape, by at most the stated deviation.

// Convex mesh: inside when on the inner side of every face plane.
double outside_by(const Mesh& m, const Vec3& p) {
  double worst = -1e300;
  for (const Tri& t : m.triangles) {
    const Vec3 n = (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).normalized();
    worst = std::max(worst, n.dot(p - m.vertices[t[0]]));
  }
  return worst;
}

TEST(Tessellation, CylinderContainsTheTrueCylinder) {
  double dev = 0;
  const double r = 0.37, l = 1.3;
  const Mesh m = cylinder_tessellation(r, l, dev);
  EXPECT_LE(dev / r, 0.00121);
  EXPECT_GE(dev / r, 0.00120);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 2 * 3.14159265358979323846);
  for (int i = 0; i < 20000; ++i) {
    const double a = i < 128 ? 3.14159265358979323846 * i / 64 + 3.14159265358979323846 / 64 : u(rng);
    const double z = std::uniform_real_distribution<double>(-l / 2, l / 2)(rng);
    ASSERT_LE(outside_by(m, Vec3(r * std::cos(a), r * std::sin(a), z)), 0.0) << a;
  }
  double far = 0;
  for (const Vec3& v : m.vertices) far = std::max(far, std::hypot(v.x(), v.y()));
  EXPECT_NEAR(far - r, dev, 1e-15);
}

TEST(Tessellation, SphereContainsTheTrueSphere) {
  double dev = 0;
  const double r = 0.21;
  const Mesh m = sphere_tessellation(r, dev);
  EXPECT_LE(dev / r, 0.00242);
  std::mt19937_64 rng(6);
  std::normal_distribution<double> g;
  for (int i = 0; i < 20000; ++i) {
    Vec3 p(g(rng), g(rng), g(rng));
    ASSERT_LE(outside_by(m, p.normalized() * r), 0.0) << p.transpose();
  }
  // The face centres are where the surface comes nearest: still outside it.
  for (const Tri& t : m.triangles) {
    const Vec3 c = (m.vertices[t[0]] + m.vertices[t[1]] + m.vertices[t[2]]) / 3;
    ASSERT_LE(outside_by(m, c.normalized() * r), 0.0);
  }
  double far = 0;
  for (const Vec3& v : m.vertices) far = std::max(far, v.norm());
  EXPECT_NEAR(far - r, dev, 1e-15);
}

// --- MoveIt's padding and scale.

TEST(PaddingAndScale, PrimitivesGrowAsMoveItGrowsThem) {
  TempDir dir;
  const fs::path urdf = dir.write("p.urdf", R"(<robot name="p">
    <link name="a"><collision><geometry><box size="0.2 0.4 0.6"/></geometry></collision></link>
    <joint name="j" type="revolute"><parent link="a"/><child link="b"/><origin xyz="2 0 0"/><axis xyz="0 0 1"/>
      <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    <link name="b"><collision><geometry><sphere radius="0.1"/></geometry></collision></link></robot>)");
  const fs::path scene = dir.write("s.json", R"({"format": "plancheck-scene/1", "angle_unit": "rad",
    "robot": {"urdf": "p.urdf", "padding": 0.01, "scale": 2}})");
  const Scene s = load_scene(scene);
  Eigen::AlignedBox3d a;
  for (const Vec3& v : s.parts[s.find_part("a")].mesh.vertices) a.extend(v);
  EXPECT_LT((a.max() - Vec3(0.21, 0.41, 0.61)).norm(), 1e-15);  // size * 2 + 2 * 0.01, halved
  double nearest = 1e300;
  const Mesh& b = s.parts[s.find_part("b")].mesh;
  for (const Tri& t : b.triangles) {
    const Vec3 c = (b.vertices[t[0]] + b.vertices[t[1]] + b.vertices[t[2]]) / 3 - Vec3(2, 0, 0);
    nearest = std::min(nearest, c.norm());
  }
  EXPECT_GE(nearest, 0.21 * (1 - 1e-3));  // radius 0.1 * 2 + 0.01, contained
}

// On a regular octahedron every vertex normal points away from the centre,
// so MoveIt's padding moves each vertex straight out by the padding.
TEST(PaddingAndScale, MeshVerticesMoveAlongTheirNormals) {
  Mesh m;
  m.vertices = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (Vec3& v : m.vertices) v += Vec3(3, 4, 5);
  m.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  const Mesh out = scale_and_pad(m, 1.5, 0.1);
  ASSERT_EQ(out.vertices.size(), 6u);
  for (std::size_t i = 0; i < 6; ++i)
    EXPECT_LT((out.vertices[i] - (Vec3(3, 4, 5) + (m.vertices[i] - Vec3(3, 4, 5)) * 1.6)).norm(), 1e-15);
}

// --- Mesh lookup.

// A copy of the test package elsewhere, reached by the package map, by
// ROS_PACKAGE_PATH and by its package.xml above the URDF; plain and file://.
TEST(MeshLookup, PackageMapRosPackagePathAndPackageXml) {
  TempDir dir;
  fs::create_directories(dir / "src");
  fs::copy(kPackage, dir / "src/arm_description", fs::copy_options::recursive);
  const fs::path copied = dir / "src/arm_description/urdf/arm.urdf";
  EXPECT_EQ(load_scene(copied).parts.size(), 8u);  // package.xml above the URDF
  // Elsewhere, without a package.xml above: the map, then ROS_PACKAGE_PATH.
  const fs::path lone = dir / "lone/arm.urdf";
  fs::create_directories(lone.parent_path());
  std::string text = read_text(copied);
  const std::string rel = "../meshes/fore arm.obj";
  text.replace(text.find(rel), rel.size(), "file://" + (dir / "src/arm_description/meshes/fore%20arm.obj").string());
  write_text(lone, text);
  expect_input_error([&] { load_scene(lone); }, {"arm.urdf", "link 'upper'", "package 'arm_description' not found"});
  SceneOptions o;
  o.packages["arm_description"] = dir / "src/arm_description";
  EXPECT_EQ(load_scene(lone, o).parts.size(), 8u);
  ::setenv("ROS_PACKAGE_PATH", (dir / "nothing").string().append(":").append((dir / "src").string()).c_str(), 1);
  const std::size_t parts = load_scene(lone).parts.size();
  ::unsetenv("ROS_PACKAGE_PATH");
  EXPECT_EQ(parts, 8u);
}

TEST(MeshLookup, MissingMeshNamesFileLinkAndPath) {
  TempDir dir;
  const fs::path u = dir.write("m.urdf", R"(<robot name="m"><link name="a">
    <collision><geometry><mesh filename="meshes/none.stl"/></geometry></collision></link></robot>)");
  expect_input_error([&] { load_scene(u); }, {"m.urdf", "link 'a' (line 1) collision[0]", "none.stl", "not found"});
}

// --- Errors: exit 2 naming the file and the element.

TEST(RobotErrors, XmlThatDoesNotParse) {
  TempDir dir;
  const fs::path u = dir.write("bad.urdf", "<robot name=\"x\">\n  <link name=\"a\">\n</robot>\n");
  expect_input_error([&] { load_scene(u); }, {"bad.urdf:", "XML does not parse"});
  const fs::path s = dir.write("bad.srdf", "<robot><disable_collisions link1=\"a\"</robot>");
  const fs::path ok = dir.write("ok.urdf", R"(<robot name="o"><link name="a"><collision><geometry><box size="1 1 1"/></geometry></collision></link></robot>)");
  SceneOptions o;
  o.srdf = s;
  expect_input_error([&] { load_scene(ok, o); }, {"bad.srdf:1", "XML does not parse"});
}

TEST(RobotErrors, NotAValidUrdf) {
  TempDir dir;
  const fs::path u = dir.write("j.urdf", R"(<robot name="j"><link name="a"/>
    <joint name="j1" type="revolute"><parent link="a"/><child link="ghost"/><axis xyz="0 0 1"/>
    <limit lower="0" upper="1" effort="1" velocity="1"/></joint></robot>)");
  expect_input_error([&] { load_scene(u); }, {"j.urdf", "not a valid URDF", "ghost"});
}

TEST(RobotErrors, JointCycleAndTwoRoots) {
  TempDir dir;
  const std::string links = R"(<link name="a"/><link name="b"/><link name="c"/>)";
  auto joint = [](const char* name, const char* parent, const char* child) {
    return std::string("<joint name=\"") + name + "\" type=\"fixed\"><parent link=\"" + parent +
           "\"/><child link=\"" + child + "\"/></joint>\n";
  };
  const fs::path cycle = dir.write("cycle.urdf", "<robot name=\"c\">" + links + "\n" + joint("ab", "a", "b") +
                                                     joint("bc", "b", "c") + joint("cb", "c", "b") + "</robot>");
  expect_input_error([&] { load_scene(cycle); }, {"cycle.urdf", "link 'b' is the child of two joints", "cycle"});
  const fs::path loop = dir.write("loop.urdf", "<robot name=\"c\">" + links + "\n" + joint("bc", "b", "c") +
                                                   joint("cb", "c", "b") + "</robot>");
  expect_input_error([&] { load_scene(loop); }, {"loop.urdf", "joint cycle"});
  // Every link in the cycle: no root at all (refused before urdfdom sees it).
  const fs::path ring = dir.write("ring.urdf", "<robot name=\"c\"><link name=\"b\"/><link name=\"c\"/>\n" +
                                                   joint("bc", "b", "c") + joint("cb", "c", "b") + "</robot>");
  expect_input_error([&] { load_scene(ring); }, {"ring.urdf", "no root link", "joint cycle"});
  // A joint from a link to itself, under a root: refused before urdfdom too
  // (which leaked the link that holds itself; found by fuzz_urdf).
  const fs::path self = dir.write("self.urdf", "<robot name=\"c\">" + links + "\n" + joint("ab", "a", "b") +
                                                   joint("cc", "c", "c") + "</robot>");
  expect_input_error([&] { load_scene(self); }, {"self.urdf", "joint 'cc' (line 3) joins link 'c' to itself"});
  const fs::path roots = dir.write("roots.urdf", "<robot name=\"r\">" + links + "\n" + joint("ab", "a", "b") + "</robot>");
  expect_input_error([&] { load_scene(roots); }, {"roots.urdf", "Two root links"});
}

TEST(RobotErrors, MimicOfAMissingJoint) {
  TempDir dir;
  std::string text = read_text(kUrdf);
  const std::string master = "<mimic joint=\"finger_left\"";
  text.replace(text.find(master), master.size(), "<mimic joint=\"finger_lft\"");
  fs::copy(kPackage, dir / "pkg", fs::copy_options::recursive);
  write_text(dir / "pkg/urdf/arm.urdf", text);
  expect_input_error([&] { load_scene(dir / "pkg/urdf/arm.urdf"); },
                     {"arm.urdf", "joint 'finger_right' (line", "mimics joint 'finger_lft', which does not exist"});
}

TEST(RobotErrors, UnitsOtherThanMetresAndRadians) {
  TempDir dir;
  const std::string robot = R"("robot": {"urdf": ")" + kUrdf.string() + R"("})";
  expect_input_error([&] { load_scene(dir.write("a.json", R"({"format": "plancheck-scene/1", )" + robot + "}")); },
                     {"a.json", "angle_unit: must be rad with a robot", "(the default)"});
  expect_input_error(
      [&] { load_scene(dir.write("b.json", R"({"format": "plancheck-scene/1", "length_unit": "mm", "angle_unit": "rad", )" + robot + "}")); },
      {"b.json", "length_unit: must be m with a robot"});
  expect_input_error(
      [&] { load_scene(dir.write("c.json", R"({"format": "plancheck-scene/1", "angle_unit": "deg", )" + robot + "}")); },
      {"c.json", "angle_unit: must be rad"});
}

TEST(RobotErrors, PlanColumnNamingNoMovableJoint) {
  TempDir dir;
  const Scene s = load_arm();
  for (const char* column : {"base_fixed", "finger_right", "no_such_joint"}) {
    const fs::path plan = dir.write("p.csv", std::string("elbow,") + column + "\n0,0\n");
    expect_input_error([&] { load_plan(s, plan); }, {"p.csv:1:2", std::string("'") + column + "'"});
  }
}

TEST(RobotErrors, PlanColumnNamingAMimicJointSaysSo) {
  TempDir dir;
  const Scene s = load_arm();
  const fs::path plan = dir.write("p.csv", "elbow,finger_right\n0,0\n");
  expect_input_error([&] { load_plan(s, plan); },
                     {"p.csv:1:2", "'finger_right' names a mimic joint", "follows joint 'finger_left'"});
}

// package://NAME/.. would reach files beside the package, not in it.
TEST(RobotErrors, PackagePathsStayInsideThePackage) {
  TempDir dir;
  fs::create_directories(dir / "pkg/meshes");
  write_text(dir / "pkg/package.xml", "<package><name>pkg</name></package>");
  fs::copy_file(kPackage / "meshes/upper.stl", dir / "outside.stl");
  fs::copy_file(kPackage / "meshes/upper.stl", dir / "pkg/meshes/inside.stl");
  const std::string head = R"(<robot name="m"><link name="a"><collision><geometry><mesh filename=")";
  const std::string tail = R"("/></geometry></collision></link></robot>)";
  EXPECT_EQ(load_scene(dir.write("pkg/ok.urdf", head + "package://pkg/meshes/inside.stl" + tail)).parts.size(), 1u);
  for (const char* uri : {"package://pkg/../outside.stl", "package://pkg/meshes/../../outside.stl",
                          "package://pkg/%2e%2e/outside.stl"}) {
    const fs::path u = dir.write("pkg/up.urdf", head + uri + tail);
    expect_input_error([&] { load_scene(u); }, {"up.urdf", "link 'a'", "leaves the package's folder"});
  }
}

TEST(RobotErrors, SrdfNamingAnUnknownLink) {
  TempDir dir;
  SceneOptions o;
  o.srdf = dir.write("x.srdf", "<robot name=\"test_arm\">\n<disable_collisions link1=\"tool\" link2=\"thumb\"/>\n</robot>");
  expect_input_error([&] { load_scene(kUrdf, o); }, {"x.srdf:2", "link 'thumb' is not a link of arm.urdf"});
}

// --- The command line on a bare .urdf.

TEST(RobotCli, VerifyAndSceneOnABareUrdf) {
  TempDir dir;
  const fs::path safe = dir.write("safe.csv", "arm/shoulder,elbow,slide,wrist/roll,finger_left\n0,0,0,0,0\n0.5,0.3,0.1,1,0.02\n");
  const fs::path crash = dir.write("crash.csv", "elbow\n0\n3.3\n");  // the fore arm folds onto the upper arm
  const std::string base = kPlancheck.string() + " verify " + kUrdf.string() + " --srdf " + kSrdf.string() +
                           " --out " + (dir / "out").string() + " ";
  EXPECT_EQ(run_command(base + safe.string() + " > /dev/null 2>&1"), 0);
  EXPECT_EQ(run_command(base + crash.string() + " > /dev/null 2>&1"), 1);
  EXPECT_EQ(run_command(base + dir.write("bad.csv", "base_fixed\n0\n").string() + " > /dev/null 2>&1"), 2);
  // Without the package (copied away from its package.xml), --package finds the meshes.
  fs::create_directories(dir / "alone");
  fs::copy_file(kUrdf, dir / "alone/arm.urdf");
  fs::create_directories(dir / "meshes");
  fs::copy_file(kPackage / "meshes/fore arm.obj", dir / "meshes/fore arm.obj");
  const std::string scene = kPlancheck.string() + " scene " + (dir / "alone/arm.urdf").string();
  EXPECT_EQ(run_command(scene + " > /dev/null 2>&1"), 2);
  EXPECT_EQ(run_command(scene + " --package arm_description=" + kPackage.string() + " > " +
                                 (dir / "scene.txt").string() + " 2>&1"),
            0);
  const std::string out = read_text(dir / "scene.txt");
  EXPECT_NE(out.find("primitives: 3 boxes (exact), 1 cylinders, 1 spheres"), std::string::npos) << out;
  EXPECT_NE(out.find("finger_right  translate (axis)  node finger_r  limits none; mimics finger_left"),
            std::string::npos) << out;
}

// Options stand anywhere among the arguments: --package takes one value, so
// the plan after it stays a plan.
TEST(RobotCli, OptionsBeforeAndBetweenThePositionalArguments) {
  TempDir dir;
  const fs::path safe = dir.write("safe.csv", "elbow\n0\n0.5\n");
  const std::string out = " --out " + (dir / "out").string();
  const std::string plancheck = kPlancheck.string() + " verify " + kUrdf.string();
  EXPECT_EQ(run_command(plancheck + " --srdf " + kSrdf.string() + " --package arm_description=" + kPackage.string() +
                        " " + safe.string() + out + " > /dev/null 2>&1"),
            0);
  EXPECT_EQ(run_command(plancheck + " --package arm_description=" + kPackage.string() + " --package other=" +
                        dir.path().string() + " " + safe.string() + " --srdf " + kSrdf.string() + out +
                        " > /dev/null 2>&1"),
            0);
  EXPECT_TRUE(fs::exists(dir / "out/safe.csv"));
}

// Links in contact at the zero pose come out as lines to paste into an SRDF.
TEST(RobotCli, SceneListsContactsAsDisableCollisions) {
  TempDir dir;
  const fs::path u = dir.write("touch.urdf", R"(<robot name="t">
    <link name="a"><collision><origin xyz="0 0 0.5"/><geometry><box size="1 1 1"/></geometry></collision></link>
    <joint name="j" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0 0 1"/><axis xyz="0 0 1"/>
      <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    <link name="b"><collision><origin xyz="0 0 0.25"/><geometry><cylinder radius="0.2" length="0.5"/></geometry></collision></link>
    <joint name="k" type="revolute"><parent link="b"/><child link="c"/><origin xyz="0 0 0.5"/><axis xyz="1 0 0"/>
      <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    <link name="c"><collision><origin xyz="0 0 -1.2"/><geometry><sphere radius="0.3"/></geometry></collision></link>
  </robot>)");
  ASSERT_EQ(run_command(kPlancheck.string() + " scene " + u.string() + " > " + (dir / "o.txt").string()), 0);
  const std::string out = read_text(dir / "o.txt");
  EXPECT_NE(out.find("<disable_collisions link1=\"a\" link2=\"b\" reason=\"Adjacent\"/>"), std::string::npos) << out;
  EXPECT_NE(out.find("<disable_collisions link1=\"a\" link2=\"c\" reason=\"Default\"/>"), std::string::npos) << out;
  EXPECT_EQ(out.find("link1=\"b\" link2=\"c\""), std::string::npos) << out;

  // Names that XML must escape come out escaped, ready to paste.
  std::string text = read_text(u);
  for (std::size_t at; (at = text.find("\"a\"")) != std::string::npos;) text.replace(at, 3, "\"a&amp;&quot;x&lt;\"");
  const fs::path v = dir.write("touch2.urdf", text);
  ASSERT_EQ(run_command(kPlancheck.string() + " scene " + v.string() + " > " + (dir / "o2.txt").string()), 0);
  const std::string escaped = read_text(dir / "o2.txt");
  EXPECT_NE(escaped.find("<disable_collisions link1=\"a&amp;&quot;x&lt;\" link2=\"b\" reason=\"Adjacent\"/>"),
            std::string::npos) << escaped;
}

}  // namespace
}  // namespace plancheck
