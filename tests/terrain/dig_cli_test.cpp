// SPDX-License-Identifier: MIT
// The command line on the default dataset: `plancheck dig` files, the scoop
// and probe columns of `verify`, report.json's scoop and probe fields, and
// results that do not depend on the thread count.
#include "src/scene/terrain.h"

#include "tests/support/fixtures.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <sstream>
#include <string>

namespace plancheck {
namespace {

namespace fs = std::filesystem;

const fs::path kData = fs::path(PLANCHECK_SOURCE_DIR) / "datasets/change5";
const fs::path kExe = fs::path(PLANCHECK_BINARY_DIR) / "plancheck";

TEST(DigCommand, WritesBeforeAfterGridsAndAPng) {
  if (!fs::exists(kData / "scene.json")) GTEST_SKIP() << "run build/generate_change5 " << kData;
  testing::TempDir dir("dig_cli");
  ASSERT_EQ(testing::run_command(kExe.string() + " dig " + (kData / "scene.json").string() + " " +
                                 (kData / "plans/plan01.csv").string() + " --out " + dir.path().string() + " > " +
                                 (dir / "out.txt").string()),
            0);
  const Dem site = load_dem(kData / "site.asc", 1.0);
  const Dem before = load_dem(dir / "before.asc", 1.0);
  const Dem after = load_dem(dir / "after.asc", 1.0);
  ASSERT_EQ(before.z.size(), site.z.size());
  for (std::size_t i = 0; i < site.z.size(); ++i) ASSERT_DOUBLE_EQ(before.z[i], site.z[i]);
  double lowest = 0.0;
  for (std::size_t i = 0; i < site.z.size(); ++i) lowest = std::min(lowest, after.z[i] - before.z[i]);
  EXPECT_LT(lowest, -0.02);  // a pit of about 3 cm
  const std::string png = testing::read_text(dir / "dig.png");
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  EXPECT_NE(testing::read_text(dir / "out.txt").find("deepest 0.03"), std::string::npos);
}

TEST(DigCommand, VerifyReportsScoopAndProbesIndependentlyOfThreads) {
  if (!fs::exists(kData / "scene.json")) GTEST_SKIP() << "run build/generate_change5 " << kData;
  testing::TempDir dir("verify_cli");
  const std::string plans = (kData / "plans/plan01.csv").string() + " " + (kData / "plans/plan10.csv").string();
  for (int threads : {1, 2})
    ASSERT_EQ(testing::run_command(kExe.string() + " verify " + (kData / "scene.json").string() + " " + plans +
                                   " --threads " + std::to_string(threads) + " --out " +
                                   (dir / ("t" + std::to_string(threads))).string() + " > /dev/null 2>&1"),
              0);
  const std::string csv = testing::read_text(dir / "t1/plan01.csv");
  EXPECT_EQ(csv, testing::read_text(dir / "t2/plan01.csv"));
  const std::string header = csv.substr(0, csv.find('\n'));
  EXPECT_NE(header.find(",probe:scoop_down,probe:scoop_down:hit,probe:elbow_fan,probe:elbow_fan:hit,scoop_depth,scoop_volume"),
            std::string::npos);
  const auto report = nlohmann::json::parse(testing::read_text(dir / "t1/report.json"));
  const auto& p1 = report["plans"][0];
  EXPECT_EQ(p1["scoop"]["model"], "template");
  EXPECT_TRUE(p1["scoop"]["dug"].get<bool>());
  EXPECT_NEAR(p1["scoop"]["deepest"]["depth"].get<double>(), 0.03, 0.005);
  EXPECT_GT(p1["scoop"]["collected_mass_kg"].get<double>(), 0.1);
  EXPECT_LE(p1["scoop"]["collected_volume"].get<double>(), p1["scoop"]["capacity"].get<double>());
  ASSERT_EQ(p1["probes"].size(), 2u);
  EXPECT_EQ(p1["probes"][0]["name"], "scoop_down");
  // The scoop's down probe starts 1 mm over M; in the soil it reads the terrain within millimetres.
  EXPECT_LT(p1["probes"][0]["min_distance"].get<double>(), 0.01);
  EXPECT_EQ(p1["probes"][0]["hit"], "terrain");
  EXPECT_FALSE(report["plans"][1]["scoop"]["dug"].get<bool>());
}

TEST(DigCommand, DigCarryStartsEachPlanWhereThePreviousLeftTheGround) {
  if (!fs::exists(kData / "scene.json")) GTEST_SKIP() << "run build/generate_change5 " << kData;
  testing::TempDir dir("carry_cli");
  const std::string plan = (kData / "plans/plan01.csv").string();
  // The same plan again under another name: two plans of one name would
  // write one CSV, which verify refuses.
  std::string again = testing::read_text(plan);
  ASSERT_EQ(again.rfind("# name: plan01\n", 0), 0u);
  again.replace(0, 15, "# name: again\n");
  testing::write_text(dir / "again.csv", again);
  auto dug = [&](const std::string& flag, const std::string& out) {
    EXPECT_EQ(testing::run_command(kExe.string() + " verify " + (kData / "scene.json").string() + " " + plan + " " +
                                   (dir / "again.csv").string() + flag + " --out " + (dir / out).string() + " > /dev/null 2>&1"),
              0);
    const auto report = nlohmann::json::parse(testing::read_text(dir / out / "report.json"));
    return std::pair{report["plans"][0]["scoop"]["dug_volume"].get<double>(),
                     report["plans"][1]["scoop"]["dug_volume"].get<double>()};
  };
  const auto [a1, a2] = dug("", "fresh");
  EXPECT_EQ(a1, a2);  // each plan starts from the undisturbed site
  const auto [b1, b2] = dug(" --dig-carry", "carry");
  EXPECT_EQ(b1, a1);
  EXPECT_LT(b2, 0.5 * b1);  // the same scoop in its own pit finds little new soil
}

}  // namespace
}  // namespace plancheck
