// SPDX-License-Identifier: MIT
// End to end on a scene whose distance has a closed form: a 2 m bar pitching
// about a horizontal axis 1 m above a wide slab. Every verdict kind, the exit
// status, the report files and thread-count invariance.
#include "support/bar_scene.h"
#include "support/fixtures.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <sstream>

namespace plancheck {
namespace {

using testing::run_command;
using testing::TempDir;
using testing::read_text;
using testing::write_text;

const std::string kPlancheck = std::string(PLANCHECK_BINARY_DIR) + "/plancheck";

// The bar-on-slab scene and its closed-form distance: tests/support/bar_scene.h.
using testing::bar_distance;
void write_scene(const TempDir& dir) { testing::write_bar_scene(dir); }

std::string plan_text(const std::string& name, const std::vector<double>& angles, const std::string& extra = "") {
  std::ostringstream s;
  s << "# name: " << name << "\n" << extra << "J1\n";
  s.precision(17);
  for (double a : angles) s << a << "\n";
  return s.str();
}

nlohmann::json run_verify(const TempDir& dir, const std::vector<std::string>& plans, int threads, int* status,
                          const std::string& out = "out") {
  std::string cmd = kPlancheck + " verify " + (dir / "scene.json").string();
  for (const auto& p : plans) cmd += " " + (dir / p).string();
  cmd += " --out " + (dir / out).string() + " --threads " + std::to_string(threads) + " >/dev/null 2>&1";
  *status = run_command(cmd);
  if (!std::filesystem::exists(dir / out / "report.json")) return nullptr;
  return nlohmann::json::parse(read_text(dir / out / "report.json"));
}

const nlohmann::json& plan_named(const nlohmann::json& report, const std::string& name) {
  for (const auto& p : report["plans"])
    if (p["name"] == name) return p;
  static const nlohmann::json none;
  return none;
}

TEST(Verify, EveryVerdictKindOnTheAnalyticScene) {
  TempDir dir("verify");
  write_scene(dir);
  write_text(dir / "safe.csv", plan_text("safe", {0, 5, 10, 5, 0}, "# target: 0, 0, 0\n# tolerance: 0.001\n"));
  write_text(dir / "collide.csv", plan_text("collide", {0, 10, 35, 10}));
  write_text(dir / "near.csv", plan_text("near", {0, 10, 26, 10}));
  write_text(dir / "limits.csv", plan_text("limits", {0, -60, -95, 0}));
  write_text(dir / "target.csv", plan_text("target", {0, 10, 0}, "# target: 1, 0, 0\n# tolerance: 0.02\n"));
  int status = -1;
  const auto report = run_verify(dir, {"safe.csv", "collide.csv", "near.csv", "limits.csv", "target.csv"}, 2, &status);
  ASSERT_FALSE(report.is_null());
  EXPECT_EQ(status, 1);
  EXPECT_EQ(report["format"], "plancheck-report/1");

  const auto& safe = plan_named(report, "safe");
  EXPECT_EQ(safe["verdict"], "safe");
  EXPECT_TRUE(safe["first_violation"].is_null());
  EXPECT_EQ(safe["min_distance_state"], 2);
  EXPECT_NEAR(safe["min_distance"].get<double>(), bar_distance(10), 1e-12);
  EXPECT_EQ(safe["min_distance_parts"], nlohmann::json::array({"Bar", "Slab"}));
  EXPECT_NEAR(safe["target_error"].get<double>(), 0.0, 1e-12);

  const auto& collide = plan_named(report, "collide");
  EXPECT_EQ(collide["verdict"], "collision");
  EXPECT_EQ(collide["first_violation"]["state"], 2);
  EXPECT_EQ(collide["first_violation"]["kind"], "collision");
  ASSERT_EQ(collide["collisions"].size(), 1u);
  EXPECT_EQ(collide["collisions"][0]["state"], 2);
  EXPECT_FALSE(collide["collisions"][0]["pairs"][0]["triangles"].empty());
  EXPECT_EQ(collide["min_distance"].get<double>(), 0.0);

  const auto& near = plan_named(report, "near");
  EXPECT_GT(bar_distance(26), 0.0);
  EXPECT_LT(bar_distance(26), 0.05);
  EXPECT_EQ(near["verdict"], "clearance");
  EXPECT_EQ(near["first_violation"]["state"], 2);
  EXPECT_NEAR(near["min_distance"].get<double>(), bar_distance(26), 1e-12);

  const auto& limits = plan_named(report, "limits");
  EXPECT_EQ(limits["verdict"], "limits");
  EXPECT_EQ(limits["first_violation"]["state"], 2);
  EXPECT_EQ(limits["first_violation"]["action"], "J1");

  const auto& target = plan_named(report, "target");
  EXPECT_EQ(target["verdict"], "target");
  EXPECT_NEAR(target["target_error"].get<double>(), 1.0, 1e-12);
}

TEST(Verify, CsvRowsMatchTheClosedFormDistance) {
  TempDir dir("verify-csv");
  write_scene(dir);
  std::vector<double> angles;
  for (int i = 0; i <= 100; ++i) angles.push_back(-80.0 + 1.08 * i);  // up to 28 deg: first contact near 27.1
  write_text(dir / "sweep.csv", plan_text("sweep", angles));
  int status = -1;
  ASSERT_FALSE(run_verify(dir, {"sweep.csv"}, 1, &status).is_null());
  EXPECT_EQ(status, 1);
  std::istringstream csv(read_text(dir / "out/sweep.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line.rfind("state,collision,min_distance,part_a,part_b,ax,ay,az,bx,by,bz", 0), 0u);
  int rows = 0, collisions = 0;
  while (std::getline(csv, line)) {
    std::vector<std::string> f;
    std::stringstream ls(line);
    for (std::string x; std::getline(ls, x, ',');) f.push_back(x);
    ASSERT_GE(f.size(), 11u) << line;
    const double expected = bar_distance(angles[static_cast<std::size_t>(rows)]);
    const bool collide = f[1] == "1";
    EXPECT_EQ(collide, expected <= 0.0) << line;
    if (collide) ++collisions;
    else EXPECT_NEAR(std::stod(f[2]), expected, 1e-11) << line;  // printed with 12 digits
    ++rows;
  }
  EXPECT_EQ(rows, 101);
  EXPECT_GT(collisions, 0);
}

TEST(Verify, OneAndTwoThreadsWriteIdenticalReports) {
  TempDir dir("verify-threads");
  write_scene(dir);
  std::vector<double> a, b;
  for (int i = 0; i < 400; ++i) {
    a.push_back(-60.0 + 45.0 * (1.0 - std::cos(i * 0.05)));
    b.push_back(20.0 * std::sin(i * 0.031));
  }
  write_text(dir / "a.csv", plan_text("a", a));
  write_text(dir / "b.csv", plan_text("b", b));
  int s1 = -1, s2 = -1;
  auto r1 = run_verify(dir, {"a.csv", "b.csv"}, 1, &s1, "out1");
  auto r2 = run_verify(dir, {"a.csv", "b.csv"}, 2, &s2, "out2");
  ASSERT_FALSE(r1.is_null());
  ASSERT_FALSE(r2.is_null());
  EXPECT_EQ(s1, s2);
  for (auto* r : {&r1, &r2}) {
    r->erase("seconds");
    r->erase("threads");
    for (auto& p : (*r)["plans"]) p.erase("seconds");
  }
  EXPECT_EQ(r1, r2);
  EXPECT_EQ(read_text(dir / "out1/a.csv"), read_text(dir / "out2/a.csv"));
  EXPECT_EQ(read_text(dir / "out1/b.csv"), read_text(dir / "out2/b.csv"));
}

TEST(Verify, BadPlanExitsTwoAndLeavesNoReport) {
  TempDir dir("verify-bad");
  write_scene(dir);
  write_text(dir / "good.csv", plan_text("good", {0, 1}));
  write_text(dir / "bad.csv", "J1\n0\nfive\n");
  // A report from an earlier run in the same folder must not survive.
  int status = -1;
  ASSERT_FALSE(run_verify(dir, {"good.csv"}, 1, &status).is_null());
  EXPECT_EQ(status, 0);
  const std::string cmd = kPlancheck + " verify " + (dir / "scene.json").string() + " " + (dir / "good.csv").string() +
                          " " + (dir / "bad.csv").string() + " --out " + (dir / "out").string() + " 2>" +
                          (dir / "err.txt").string() + " >/dev/null";
  EXPECT_EQ(run_command(cmd), 2);
  EXPECT_FALSE(std::filesystem::exists(dir / "out/report.json"));
  const std::string err = read_text(dir / "err.txt");
  EXPECT_NE(err.find("bad.csv:3"), std::string::npos) << err;
}

}  // namespace
}  // namespace plancheck
