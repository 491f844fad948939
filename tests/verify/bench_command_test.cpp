// SPDX-License-Identifier: MIT
// `plancheck bench` runs plancheck_bench table3, which checks every state
// against FCL before timing: on a small scene it must agree (exit 0) and
// write its JSON; bad input exits 2. Timings are printed, never asserted.
#include "support/fixtures.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>

namespace plancheck {
namespace {

using testing::run_command;
using testing::TempDir;
using testing::write_text;

const std::string kPlancheck = std::string(PLANCHECK_BINARY_DIR) + "/plancheck";
const std::string kBench = std::string(PLANCHECK_BINARY_DIR) + "/plancheck_bench";

TEST(BenchCommand, SmallSceneAgreesWithFclAndWritesJson) {
  if (!std::filesystem::exists(kBench)) GTEST_SKIP() << "plancheck_bench not built";
  TempDir dir("bench");
  testing::write_obj(dir / "model.obj", {{"Slab", testing::box_mesh({-3, -1, -1}, {3, 1, 0})},
                                         {"Bar", testing::box_mesh({0, -0.1, 0.9}, {2, 0.1, 1.1})}});
  write_text(dir / "scene.json", R"({
  "format": "plancheck-scene/1", "model": "model.obj", "length_unit": "m", "angle_unit": "deg",
  "actions": [{"name": "J1", "node": "Bar", "type": "rotate", "pivot": [0, 0, 1], "axis": [0, 1, 0], "limits": [-90, 30]}],
  "safety_margin": 0.05
})");
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

TEST(BenchCommand, MissingSceneExitsTwo) {
  if (!std::filesystem::exists(kBench)) GTEST_SKIP() << "plancheck_bench not built";
  EXPECT_EQ(run_command(kPlancheck + " bench /nonexistent/scene.json >/dev/null 2>&1"), 2);
}

}  // namespace
}  // namespace plancheck
