// SPDX-License-Identifier: MIT
// load_scene: units, actions, chains, checked pairs, optional blocks, and
// every error path with the file and key path in the message.
#include "src/scene/scene_loader.h"

#include "tests/foundation/fixtures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <utility>

namespace plancheck {
namespace {

constexpr double kPi = 3.14159265358979323846;

class SceneLoaderTest : public ::testing::Test {
 protected:
  void SetUp() override { testing::write_arm_model(dir_ / "arm.gltf"); }

  // A scene with the given body after "format" and "model".
  std::filesystem::path scene(const std::string& body, const std::string& name = "s.json") {
    return dir_.write(name, "{\"format\": \"plancheck-scene/1\", \"model\": \"arm.gltf\"" +
                                (body.empty() ? std::string() : ", " + body) + "}");
  }

  void expect_error(const std::string& body, std::initializer_list<std::string> parts) {
    const auto file = scene(body, "bad.json");
    testing::expect_input_error([&] { load_scene(file); }, parts);
  }

  static std::set<std::pair<std::string, std::string>> pair_names(const Scene& s) {
    std::set<std::pair<std::string, std::string>> out;
    for (const CheckedPair& c : s.checked_pairs) {
      EXPECT_LT(c.a, c.b);
      std::string a = s.parts[c.a].name, b = s.parts[c.b].name;
      if (b < a) std::swap(a, b);
      out.emplace(a, b);
    }
    return out;
  }

  testing::TempDir dir_;
};

const std::string kTwoJoints =
    R"("actions": [
      {"name": "J1", "node": "arm1", "type": "rotate", "pivot": [0, 0, 0], "axis": [0, 0, 2], "limits": [-90, 90]},
      {"name": "J2", "node": "arm2", "type": "rotate", "pivot": [1, 0, 0], "axis": [0, 1, 0]}])";

// Geometry in SI; driving parameters and limits stay as written (plan units),
// with the conversion each action's pose applies.
TEST_F(SceneLoaderTest, ActionsKeepLimitsAsWrittenAndGeometryInSi) {
  const Scene s = load_scene(scene(kTwoJoints));
  ASSERT_EQ(s.actions.size(), 2u);
  const Action& j1 = s.actions[0];
  EXPECT_EQ(j1.type, ActionType::kRotate);
  EXPECT_EQ(j1.node_name, "arm1");
  EXPECT_EQ(s.nodes[j1.node].name, "arm1");
  EXPECT_EQ(j1.axis, Vec3(0, 0, 1));  // normalised
  EXPECT_TRUE(j1.has_limits);
  EXPECT_EQ(j1.lower, -90.0);
  EXPECT_EQ(j1.upper, 90.0);
  EXPECT_DOUBLE_EQ(j1.unit_to_si, kPi / 180);
  EXPECT_EQ(j1.whole_turn, 360.0);
  EXPECT_FALSE(s.actions[1].has_limits);
  EXPECT_EQ(s.parameter_names, (std::vector<std::string>{"J1", "J2"}));
  EXPECT_EQ(s.reference_parameters, (std::vector<double>{0, 0}));
  EXPECT_EQ(s.nodes[s.parts[s.find_part("tip")].node].path, "/world/arm1/arm2/tip");
}

TEST_F(SceneLoaderTest, ChainsRootFirstAndShared) {
  const Scene s = load_scene(scene(kTwoJoints));
  auto chain = [&](const char* part) { return s.parts[s.find_part(part)].chain; };
  EXPECT_EQ(chain("base"), std::vector<int>{});
  EXPECT_EQ(chain("arm1"), std::vector<int>{0});
  EXPECT_EQ(chain("arm1b"), std::vector<int>{0});
  EXPECT_EQ(chain("arm2"), (std::vector<int>{0, 1}));
  EXPECT_EQ(chain("tip"), (std::vector<int>{0, 1}));
  EXPECT_EQ(s.chains.size(), 3u);
  for (const Part& p : s.parts) EXPECT_EQ(s.chains[p.chain_id], p.chain) << p.name;
  EXPECT_EQ(s.parts[s.find_part("arm2")].chain_id, s.parts[s.find_part("tip")].chain_id);
  EXPECT_NE(s.parts[s.find_part("arm2")].chain_id, s.parts[s.find_part("arm1")].chain_id);
  EXPECT_FALSE(s.parts[s.find_part("mast")].moving());
  EXPECT_TRUE(s.parts[s.find_part("tip")].moving());
}

TEST_F(SceneLoaderTest, ActionsOfOneNodeKeepFileOrderInTheChain) {
  const Scene s = load_scene(scene(R"("actions": [
      {"name": "S", "node": "tip", "type": "scale", "fixed_point": [2, 0, 0]},
      {"name": "J1", "node": "arm1", "type": "rotate", "pivot": [0, 0, 0], "axis": [0, 0, 1]},
      {"name": "E", "node": "tip", "type": "translate", "axis": [1, 0, 0]}])"));
  // Ancestors first (J1 on arm1), then tip's own actions as listed: S, E.
  EXPECT_EQ(s.parts[s.find_part("tip")].chain, (std::vector<int>{1, 0, 2}));
  EXPECT_EQ(s.parameter_names, (std::vector<std::string>{"S.x", "S.y", "S.z", "J1", "E"}));
  EXPECT_EQ(s.reference_parameters, (std::vector<double>{1, 1, 1, 0, 0}));
  EXPECT_EQ(s.actions[0].first_parameter, 0);
  EXPECT_EQ(s.actions[1].first_parameter, 3);
  EXPECT_EQ(s.actions[2].first_parameter, 4);
  EXPECT_EQ(s.actions[0].parameter_count, 3);
}

TEST_F(SceneLoaderTest, CheckedPairsFollowTheContract) {
  const Scene s = load_scene(scene(kTwoJoints));
  // moving x static: 4 x 2; moving x moving with different chains: arm1/arm1b x arm2/tip.
  // Never: base-mast (static-static), arm1-arm1b and arm2-tip (same chain).
  const std::set<std::pair<std::string, std::string>> expected = {
      {"arm1", "base"}, {"arm1", "mast"}, {"arm1b", "base"}, {"arm1b", "mast"},
      {"arm2", "base"}, {"arm2", "mast"}, {"base", "tip"},  {"mast", "tip"},
      {"arm1", "arm2"}, {"arm1", "tip"},  {"arm1b", "arm2"}, {"arm1b", "tip"}};
  EXPECT_EQ(pair_names(s), expected);
  EXPECT_EQ(s.checked_pairs.size(), expected.size());
}

TEST_F(SceneLoaderTest, AllowedCollisionsCoverWholeSubtrees) {
  const Scene s = load_scene(scene(kTwoJoints + R"(, "allowed_collisions": [["arm2", "arm1"], ["base", "arm2"]])"));
  // [arm2, arm1]: arm2's subtree {arm2, tip} against arm1's {arm1, arm1b, arm2, tip}.
  // [base, arm2]: base against arm2 and tip.
  const std::set<std::pair<std::string, std::string>> expected = {
      {"arm1", "base"}, {"arm1", "mast"}, {"arm1b", "base"}, {"arm1b", "mast"}, {"arm2", "mast"}, {"mast", "tip"}};
  EXPECT_EQ(pair_names(s), expected);
}

TEST_F(SceneLoaderTest, NoActionsNoPairs) {
  const Scene s = load_scene(scene(""));
  EXPECT_TRUE(s.checked_pairs.empty());
  EXPECT_EQ(s.parts.size(), 6u);
  EXPECT_EQ(s.chains.size(), 1u);
  EXPECT_DOUBLE_EQ(s.safety_margin, 0.0);
  EXPECT_EQ(s.length_unit, "m");
  EXPECT_EQ(s.angle_unit, "deg");
}

TEST_F(SceneLoaderTest, OptionalBlocksInMillimetres) {
  testing::write_arm_model(dir_ / "arm.gltf", 1000.0);
  dir_.write("site.asc", "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n0 0\n0 0\n");
  const Scene s = load_scene(scene(R"("length_unit": "mm", "angle_unit": "deg", "safety_margin": 50,
      "actions": [{"name": "J1", "node": "arm1", "type": "rotate", "pivot": [0, 0, 0], "axis": [0, 0, 1]},
                  {"name": "Ext", "node": "tip", "type": "translate", "axis": [0, 0, 3], "limits": [0, 250]}],
      "allowed_collisions": [["terrain", "arm2"]],
      "terrain": {"dem": "site.asc", "origin": [-1500, 500, -50]},
      "scoop": {"part": "tip", "bottom_point": [2100, 0, 0], "width": 100, "capacity": 400000,
                "bulk_density": 1240, "repose_angle": 35, "template": {"pit": -0.5}},
      "probes": [{"name": "down", "part": "tip", "origin": [2100, 0, 0], "direction": [0, 0, -2], "max_range": 3000,
                  "fan": {"count": 8, "half_angle": 45}}])"));
  EXPECT_DOUBLE_EQ(s.length_scale, 0.001);
  EXPECT_DOUBLE_EQ(s.safety_margin, 0.05);
  EXPECT_EQ(s.actions[1].upper, 250.0);  // as written, in mm
  EXPECT_DOUBLE_EQ(s.actions[1].unit_to_si, 0.001);
  EXPECT_EQ(s.actions[1].whole_turn, 0.0);
  EXPECT_EQ(s.actions[1].axis, Vec3(0, 0, 1));
  // Vertices too: arm1's box ends at x = 1 m.
  double max_x = 0;
  for (const Vec3& v : s.parts[s.find_part("arm1")].mesh.vertices) max_x = std::max(max_x, v.x());
  EXPECT_NEAR(max_x, 1.0, 1e-12);
  ASSERT_TRUE(s.terrain.has_value());
  EXPECT_EQ(s.terrain->dem, dir_.path() / "site.asc");
  EXPECT_TRUE(s.terrain->collide);
  EXPECT_TRUE(s.terrain->origin.isApprox(Vec3(-1.5, 0.5, -0.05)));
  std::vector<int> allowed = {s.find_part("arm2"), s.find_part("tip")};
  std::sort(allowed.begin(), allowed.end());
  EXPECT_EQ(s.terrain_allowed_parts, allowed);
  ASSERT_TRUE(s.scoop.has_value());
  EXPECT_EQ(s.scoop->part_index, s.find_part("tip"));
  EXPECT_TRUE(s.scoop->bottom_point.isApprox(Vec3(2.1, 0, 0)));
  EXPECT_DOUBLE_EQ(s.scoop->width, 0.1);
  EXPECT_NEAR(s.scoop->capacity, 4e-4, 1e-15);
  EXPECT_NEAR(s.scoop->repose_angle, 35 * kPi / 180, 1e-15);
  EXPECT_DOUBLE_EQ(s.scoop->templ.pit, -0.5);
  EXPECT_DOUBLE_EQ(s.scoop->templ.rim, ScoopTemplate{}.rim);
  ASSERT_EQ(s.probes.size(), 1u);
  EXPECT_EQ(s.probes[0].direction, Vec3(0, 0, -1));
  EXPECT_DOUBLE_EQ(s.probes[0].max_range, 3.0);
  EXPECT_EQ(s.probes[0].fan_count, 8);
  EXPECT_NEAR(s.probes[0].fan_half_angle, kPi / 4, 1e-15);
}

TEST_F(SceneLoaderTest, BadJsonGivesLineAndColumn) {
  const auto file = dir_.write("broken.json", "{\n  \"format\": \"plancheck-scene/1\",\n  \"model\": \"arm.gltf\",\n  oops\n}\n");
  testing::expect_input_error([&] { load_scene(file); }, {"broken.json:4:3: invalid JSON"});
  const auto truncated = dir_.write("truncated.json", "{\"format\": \"plancheck-scene/1\",\n \"model\": ");
  testing::expect_input_error([&] { load_scene(truncated); }, {"truncated.json:2:", "invalid JSON"});
}

TEST_F(SceneLoaderTest, UnknownKeysNameTheirPath) {
  expect_error(R"("modle": "x")", {"bad.json: modle: unknown key"});
  expect_error(R"("actions": [
      {"name": "J1", "node": "arm1", "type": "rotate", "pivot": [0, 0, 0], "axis": [0, 0, 1]},
      {"name": "J2", "node": "arm2", "type": "rotate", "pivot": [0, 0, 0], "axis": [0, 0, 1]},
      {"name": "J3", "node": "tip", "type": "rotate", "pivto": [0, 0, 0], "axis": [0, 0, 1]}])",
               {"bad.json: actions[2].pivto: unknown key"});
  dir_.write("site.asc", "ncols 1\n");
  expect_error(R"("terrain": {"dem": "site.asc", "colide": false})", {"bad.json: terrain.colide: unknown key"});
  expect_error(R"("format": "plancheck-scene/1")", {"bad.json: format: key given twice"});
}

TEST_F(SceneLoaderTest, FormatModelAndUnits) {
  const auto no_format = dir_.write("nf.json", R"({"model": "arm.gltf"})");
  testing::expect_input_error([&] { load_scene(no_format); }, {"nf.json: format: missing"});
  const auto wrong = dir_.write("wf.json", R"({"format": "plancheck-scene/2", "model": "arm.gltf"})");
  testing::expect_input_error([&] { load_scene(wrong); }, {"wf.json: format: unsupported format"});
  const auto no_model = dir_.write("nm.json", R"({"format": "plancheck-scene/1"})");
  testing::expect_input_error([&] { load_scene(no_model); }, {"nm.json: model: missing"});
  const auto missing_model = dir_.write("mm.json", R"({"format": "plancheck-scene/1", "model": "none.3ds"})");
  testing::expect_input_error([&] { load_scene(missing_model); }, {"none.3ds", "cannot open"});
  expect_error(R"("length_unit": "inch")", {"bad.json: length_unit: unknown unit 'inch'"});
  expect_error(R"("angle_unit": "grad")", {"bad.json: angle_unit: unknown unit 'grad'"});
  expect_error(R"("length_unit": 1)", {"bad.json: length_unit: expected a string"});
  expect_error(R"("safety_margin": -0.1)", {"bad.json: safety_margin: must not be negative"});
  expect_error(R"("safety_margin": "big")", {"bad.json: safety_margin: expected a number"});
  testing::expect_input_error([&] { load_scene(dir_ / "absent.json"); }, {"absent.json", "cannot open"});
}

TEST_F(SceneLoaderTest, ActionErrors) {
  auto rotate = [](const std::string& extra) {
    return R"("actions": [{"name": "J1", "node": "arm1", "type": "rotate", )" + extra + "}]";
  };
  expect_error(rotate(R"("pivot": [0, 0, 0], "axis": [0, 0, 0])"), {"bad.json: actions[0].axis: zero-length axis"});
  // nlohmann refuses 1e999 while parsing: the message places it by line and column.
  expect_error(rotate(R"("pivot": [0, 1e999, 0], "axis": [0, 0, 1])"), {"bad.json:1:", "'1e999' is not a finite number"});
  expect_error(rotate(R"("pivot": [0, 0, 0], "axis": [0, 0, 1], "limits": [10, -10])"),
               {"bad.json: actions[0].limits: lower limit is above the upper limit"});
  expect_error(rotate(R"("pivot": [0, 0], "axis": [0, 0, 1])"), {"bad.json: actions[0].pivot: expected an array of 3 numbers"});
  expect_error(rotate(R"("axis": [0, 0, 1])"), {"bad.json: actions[0].pivot: missing"});
  expect_error(rotate(R"("pivot": [0, 0, 0], "axis": [0, 0, 1], "fixed_point": [0, 0, 0])"),
               {"bad.json: actions[0].fixed_point: not allowed"});
  expect_error(R"("actions": [{"name": "J1", "node": "elbow", "type": "rotate", "pivot": [0, 0, 0], "axis": [0, 0, 1]}])",
               {"bad.json: actions[0].node: node 'elbow' not found in arm.gltf"});
  expect_error(R"("actions": [{"name": "J1", "node": "arm1", "type": "twist"}])",
               {"bad.json: actions[0].type: unknown action type 'twist'"});
  expect_error(R"("actions": [{"name": "J1", "node": "arm1", "type": "rotate", "pivot": [0, 0, 0], "axis": [0, 0, 1]},
                              {"name": "J1", "node": "arm2", "type": "rotate", "pivot": [0, 0, 0], "axis": [0, 0, 1]}])",
               {"bad.json: actions[1].name: two actions named 'J1'"});
  expect_error(R"("actions": [{"name": "J1", "node": "arm1", "type": "rotate", "pivot": [0, 0, 0], "axis": [0, 0, 1]},
                              {"name": "J2", "node": "arm1", "type": "rotate", "pivot": [0, 0, 0], "axis": [1, 0, 0]}])",
               {"bad.json: actions[1].node: node 'arm1' already carries a rotate action ('J1')"});
  expect_error(R"("actions": [{"name": "T1", "node": "arm1", "type": "translate", "axis": [1, 0, 0]},
                              {"name": "T2", "node": "arm1", "type": "translate"}])",
               {"bad.json: actions[1].node: node 'arm1' already carries a translate action"});
  expect_error(R"("actions": [{"name": "S", "node": "arm1", "type": "scale"}])", {"bad.json: actions[0].fixed_point: missing"});
  expect_error(R"("actions": [{"name": "S", "node": "arm1", "type": "scale", "fixed_point": [0, 0, 0], "limits": [0, 2]}])",
               {"bad.json: actions[0].limits: scale factors must be positive"});
  expect_error(R"("actions": [{"name": "T", "node": "arm1", "type": "translate"},
                              {"name": "T.x", "node": "arm2", "type": "translate", "axis": [1, 0, 0]}])",
               {"bad.json: actions: two driving parameters named 'T.x'"});
  expect_error(R"("actions": {"name": "J1"})", {"bad.json: actions: expected an array"});
}

TEST_F(SceneLoaderTest, AmbiguousNodeNamesBothPaths) {
  testing::write_box_gltf(dir_ / "arm.gltf", {{.name = "world"},
                                              {.name = "left", .parent = 0},
                                              {.name = "joint", .parent = 1},
                                              {.name = "a", .parent = 2, .box = true},
                                              {.name = "joint", .parent = 0},
                                              {.name = "b", .parent = 4, .box = true}});
  expect_error(R"("actions": [{"name": "J1", "node": "joint", "type": "translate"}])",
               {"bad.json: actions[0].node: node name 'joint' is not unique", "/world/left/joint", "/world/joint"});
}

TEST_F(SceneLoaderTest, AllowedCollisionErrors) {
  expect_error(R"("allowed_collisions": [["arm1", "nowhere"]])",
               {"bad.json: allowed_collisions[0][1]: node 'nowhere' not found"});
  expect_error(R"("allowed_collisions": [["arm1"]])", {"bad.json: allowed_collisions[0]: expected a pair"});
  // Without a terrain block, "terrain" is an ordinary (here missing) node name.
  expect_error(R"("allowed_collisions": [["terrain", "arm1"]])", {"node 'terrain' not found"});
}

TEST_F(SceneLoaderTest, OptionalBlockErrors) {
  dir_.write("site.asc", "ncols 1\n");
  const std::string terrain = R"("terrain": {"dem": "site.asc"}, )";
  expect_error(R"("terrain": {"dem": "missing.asc"})", {"bad.json: terrain.dem: cannot open"});
  expect_error(R"("scoop": {"part": "tip", "bottom_point": [0, 0, 0], "width": 0.1})",
               {"bad.json: scoop: a scoop needs a terrain block"});
  expect_error(terrain + R"("scoop": {"part": "shovel", "bottom_point": [0, 0, 0], "width": 0.1})",
               {"bad.json: scoop.part: part 'shovel' not found"});
  expect_error(terrain + R"("scoop": {"part": "tip", "bottom_point": [0, 0, 0], "width": 0.1, "model": "magic"})",
               {"bad.json: scoop.model: unknown model 'magic'"});
  expect_error(terrain + R"("scoop": {"part": "tip", "bottom_point": [0, 0, 0], "width": 0})",
               {"bad.json: scoop.width: must be positive"});
  expect_error(R"("probes": [{"name": "p", "part": "tip", "origin": [0, 0, 0], "direction": [0, 0, 0], "max_range": 1}])",
               {"bad.json: probes[0].direction: zero-length direction"});
  expect_error(R"("probes": [{"name": "p", "part": "tip", "origin": [0, 0, 0], "direction": [0, 0, 1], "max_range": 0}])",
               {"bad.json: probes[0].max_range: must be positive"});
  expect_error(R"("probes": [{"name": "p", "part": "tip", "origin": [0, 0, 0], "direction": [0, 0, 1], "max_range": 1},
                             {"name": "p", "part": "arm1", "origin": [0, 0, 0], "direction": [0, 0, 1], "max_range": 1}])",
               {"bad.json: probes[1].name: two probes named 'p'"});
  expect_error(R"("probes": [{"name": "p", "part": "tip", "origin": [0, 0, 0], "direction": [0, 0, 1], "max_range": 1,
                              "fan": {"count": 0, "half_angle": 10}}])",
               {"bad.json: probes[0].fan.count"});
}

}  // namespace
}  // namespace plancheck
