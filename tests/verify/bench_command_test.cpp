// SPDX-License-Identifier: MIT
// `plancheck bench` runs plancheck_bench table3 (plans or --random cold
// states) or two_mesh (--two-mesh), which check every answer against FCL
// before timing: they must agree (exit 0) and write their JSON; bad input
// exits 2. Timings are printed, never asserted.
#include "support/fixtures.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

namespace plancheck {
namespace {

using testing::run_command;
using testing::TempDir;
using testing::write_text;

const std::string kPlancheck = std::string(PLANCHECK_BINARY_DIR) + "/plancheck";
const std::string kBench = std::string(PLANCHECK_BINARY_DIR) + "/plancheck_bench";

// A bar turning about a pivot 1 m above a slab (scene.json, model.obj).
void write_bar_over_slab(const std::filesystem::path& dir) {
  testing::write_obj(dir / "model.obj", {{"Slab", testing::box_mesh({-3, -1, -1}, {3, 1, 0})},
                                         {"Bar", testing::box_mesh({0, -0.1, 0.9}, {2, 0.1, 1.1})}});
  write_text(dir / "scene.json", R"({
  "format": "plancheck-scene/1", "model": "model.obj", "length_unit": "m", "angle_unit": "deg",
  "actions": [{"name": "J1", "node": "Bar", "type": "rotate", "pivot": [0, 0, 1], "axis": [0, 1, 0], "limits": [-90, 30]}],
  "safety_margin": 0.05
})");
}

TEST(BenchCommand, SmallSceneAgreesWithFclAndWritesJson) {
  if (!std::filesystem::exists(kBench)) GTEST_SKIP() << "plancheck_bench not built";
  TempDir dir("bench");
  write_bar_over_slab(dir.path());
  // Safe states, then through the slab (colliding), so both answers are checked.
  write_text(dir / "p.csv", "# name: p\nJ1\n0\n5\n10\n20\n26\n30\n35\n");
  const std::string cmd = kPlancheck + " bench " + (dir / "scene.json").string() + " " + (dir / "p.csv").string() +
                          " --fcl --repetitions 1 --tolerances 0 0.1 --json " + (dir / "t.json").string() +
                          " >/dev/null 2>&1";
  ASSERT_EQ(run_command(cmd), 0);
  const auto j = nlohmann::json::parse(testing::read_text(dir / "t.json"));
  EXPECT_EQ(j["total"]["states"], 7);
  EXPECT_EQ(j["total"]["colliding_states"], 2);  // 30 and 35 degrees
  EXPECT_TRUE(j["answers_checked_against_fcl"].get<bool>());
  EXPECT_LE(j["max_distance_difference_vs_fcl"].get<double>(), 1e-9);
  // The tolerance table's errors stay within their bound (the bench exits 3 otherwise).
  ASSERT_EQ(j["tolerance"].size(), 2u);
  EXPECT_EQ(j["tolerance"][0]["max_abs_error"].get<double>(), 0.0);
}

// --random: cold states drawn within the limits go through the same answer
// check against FCL (and verdict-only verdicts against the full check's)
// and write the spec's `total` keys.
TEST(BenchCommand, RandomColdStatesAgreeWithFclAndWriteTheKeys) {
  if (!std::filesystem::exists(kBench)) GTEST_SKIP() << "plancheck_bench not built";
  TempDir dir("bench_random");
  testing::write_obj(dir / "model.obj", {{"Slab", testing::box_mesh({-3, -1, -1}, {3, 1, 0})},
                                         {"Bar", testing::box_mesh({0, -0.1, 0.9}, {2, 0.1, 1.1})}});
  write_text(dir / "scene.json", R"({
  "format": "plancheck-scene/1", "model": "model.obj", "length_unit": "m", "angle_unit": "deg",
  "actions": [{"name": "J1", "node": "Bar", "type": "rotate", "pivot": [0, 0, 1], "axis": [0, 1, 0], "limits": [-10, 60]}],
  "safety_margin": 0.05
})");
  const std::string json = (dir / "r.json").string();
  const std::string cmd = kPlancheck + " bench " + (dir / "scene.json").string() +
                          " --random 50 --seed 3 --fcl --repetitions 1 --tolerances 0 --json " + json +
                          " >/dev/null 2>&1";
  ASSERT_EQ(run_command(cmd), 0);
  const auto j = nlohmann::json::parse(testing::read_text(json));
  EXPECT_EQ(j["mode"], "random");
  EXPECT_EQ(j["seed"], 3);
  EXPECT_EQ(j["drawn_parameters"], nlohmann::json::array({"J1"}));
  EXPECT_TRUE(j["answers_checked_against_fcl"].get<bool>());
  EXPECT_LE(j["max_distance_difference_vs_fcl"].get<double>(), 1e-9);
  const auto& t = j["total"];
  EXPECT_EQ(t["states"], 50);
  // J1 beyond about 27 degrees takes the bar into the slab: both answers occur.
  EXPECT_GT(t["colliding_states"].get<int>(), 0);
  EXPECT_LT(t["colliding_states"].get<int>(), 50);
  for (const char* key : {"plancheck_seconds_1_thread", "plancheck_seconds_2_threads", "fcl_seconds",
                          "fcl_collide_seconds", "plancheck_collide_seconds_1_thread", "fcl_over_plancheck_1_thread",
                          "plancheck_verdict_only_seconds_1_thread", "fcl_collide_over_plancheck_verdict_only"})
    EXPECT_TRUE(t.contains(key) && t[key].is_number()) << key;
  // The same seed draws the same states.
  ASSERT_EQ(run_command(cmd), 0);
  EXPECT_EQ(nlohmann::json::parse(testing::read_text(json))["total"]["colliding_states"], t["colliding_states"]);
  // Plans and --random together are refused.
  write_text(dir / "p.csv", "J1\n0\n");
  EXPECT_EQ(run_command(kPlancheck + " bench " + (dir / "scene.json").string() + " " + (dir / "p.csv").string() +
                        " --random 5 >/dev/null 2>&1"),
            2);
}

// --two-mesh: the random-pose case agrees with FCL (exit 0) and writes its keys.
TEST(BenchCommand, TwoMeshAgreesWithFclAndWritesJson) {
  if (!std::filesystem::exists(kBench)) GTEST_SKIP() << "plancheck_bench not built";
  TempDir dir("bench_two_mesh");
  const std::string json = (dir / "m.json").string();
  ASSERT_EQ(run_command(kPlancheck + " bench --two-mesh --poses 100 --repetitions 1 --fcl-repetitions 1 --json " +
                        json + " >/dev/null 2>&1"),
            0);
  const auto j = nlohmann::json::parse(testing::read_text(json));
  EXPECT_EQ(j["triangles"]["environment"], 2000);
  EXPECT_EQ(j["triangles"]["object"], 192);
  EXPECT_LE(j["max_distance_difference_vs_fcl"].get<double>(), 1e-9);
  const auto& t = j["total"];
  EXPECT_EQ(t["poses"], 100);
  EXPECT_GT(t["colliding_poses"].get<int>(), 0);
  EXPECT_LT(t["colliding_poses"].get<int>(), 100);
  for (const char* key : {"plancheck_seconds_1_thread", "plancheck_collide_seconds_1_thread", "fcl_seconds",
                          "fcl_collide_seconds", "fcl_over_plancheck_1_thread", "fcl_over_plancheck_collide"})
    EXPECT_TRUE(t.contains(key) && t[key].is_number()) << key;
}

TEST(BenchCommand, MissingSceneExitsTwo) {
  if (!std::filesystem::exists(kBench)) GTEST_SKIP() << "plancheck_bench not built";
  EXPECT_EQ(run_command(kPlancheck + " bench /nonexistent/scene.json >/dev/null 2>&1"), 2);
}

// plancheck_motion_replay: edges through the slab and beside it, checked
// certified and discretely (its answer check: every certified edge passes
// the discrete states), then timed; malformed edges exit 2 naming the line.
TEST(BenchCommand, MotionReplayChecksItsAnswersAndRejectsBadEdges) {
  const std::string replay = std::string(PLANCHECK_BINARY_DIR) + "/plancheck_motion_replay";
  if (!std::filesystem::exists(replay)) GTEST_SKIP() << "plancheck_motion_replay not built";
  TempDir dir("motion_replay");
  write_bar_over_slab(dir.path());
  write_text(dir / "edges.csv", "0,10\n-45,-10\n10,20\n20,30\n0,29.9\n");
  const std::string base = replay + " " + (dir / "scene.json").string() + " ";
  const std::string out = (dir / "out.txt").string();
  ASSERT_EQ(run_command(base + (dir / "edges.csv").string() + " --passes 1 --threads 1 >" + out + " 2>&1"), 0);
  // The bar's far corner comes within the margin of the slab between 20
  // and 30 degrees: the three edges up to 20 degrees are certified, the
  // two that reach 29.9 and 30 degrees are not.
  EXPECT_NE(testing::read_text(out).find("5 edges, 3 certified safe"), std::string::npos) << testing::read_text(out);
  // --per-edge: a header, then one row an edge (its discrete states and
  // whether it was certified), then the summary.
  ASSERT_EQ(run_command(base + (dir / "edges.csv").string() + " --passes 1 --threads 1 --per-edge >" + out + " 2>&1"), 0);
  {
    std::istringstream lines(testing::read_text(out));
    std::string line;
    std::getline(lines, line);
    EXPECT_EQ(line, "edge,length,states,certified,motion_us,discrete_us");
    std::vector<std::string> rows;
    while (std::getline(lines, line) && line.find("edges,") == std::string::npos) rows.push_back(line);
    ASSERT_EQ(rows.size(), 5u) << testing::read_text(out);
    // Edge 0 (0 -> 10 degrees) is certified, edge 4 (0 -> 29.9) is not.
    EXPECT_EQ(rows[0].rfind("0,10,", 0), 0u) << rows[0];
    EXPECT_NE(rows[0].find(",1,"), std::string::npos) << rows[0];
    EXPECT_EQ(rows[4].rfind("4,29.9,", 0), 0u) << rows[4];
    EXPECT_NE(rows[4].find(",0,"), std::string::npos) << rows[4];
    EXPECT_NE(line.find("5 edges, 3 certified safe"), std::string::npos) << line;
  }
  write_text(dir / "bad.csv", "0,10\n0,abc\n");
  EXPECT_EQ(run_command(base + (dir / "bad.csv").string() + " >" + out + " 2>&1"), 2);
  EXPECT_NE(testing::read_text(out).find("bad.csv:2: not a finite number"), std::string::npos) << testing::read_text(out);
  write_text(dir / "short.csv", "0,10\n5\n");
  EXPECT_EQ(run_command(base + (dir / "short.csv").string() + " >" + out + " 2>&1"), 2);
  EXPECT_NE(testing::read_text(out).find("short.csv:2: 1 values, expected 2"), std::string::npos);
}

}  // namespace
}  // namespace plancheck
