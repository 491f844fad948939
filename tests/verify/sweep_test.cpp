// SPDX-License-Identifier: MIT
// `plancheck sweep`: the grid, the row order and units, the verdict of every
// configuration (against a closed form, and against `verify` on a plan made
// of the same configurations), thread-count invariance and bad input.
#include "support/bar_scene.h"
#include "support/fixtures.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

namespace plancheck {
namespace {

using testing::bar_distance;
using testing::read_text;
using testing::run_command;
using testing::TempDir;
using testing::write_text;

const std::string kPlancheck = std::string(PLANCHECK_BINARY_DIR) + "/plancheck";
const std::filesystem::path kChange5 = std::filesystem::path(PLANCHECK_SOURCE_DIR) / "datasets/change5";

std::vector<std::vector<std::string>> read_csv(const std::filesystem::path& file) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(read_text(file));
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> f;
    std::stringstream ls(line);
    for (std::string x; std::getline(ls, x, ',');) f.push_back(x);
    if (!line.empty() && line.back() == ',') f.emplace_back();
    rows.push_back(f);
  }
  return rows;
}

// A .npy file as written: its descr and shape text and the raw data.
struct Npy {
  std::string descr, shape, data;
};

Npy read_npy(const std::filesystem::path& file) {
  const std::string b = read_text(file);
  Npy out;
  if (b.size() < 10 || b.compare(0, 6, "\x93NUMPY") != 0) {
    ADD_FAILURE() << file << ": not a .npy file";
    return out;
  }
  const std::size_t len = static_cast<unsigned char>(b[8]) | static_cast<std::size_t>(static_cast<unsigned char>(b[9])) << 8;
  const std::string header = b.substr(10, len);
  EXPECT_EQ((10 + len) % 64, 0u) << file;
  const auto field = [&](const std::string& key, char open, char close) {
    const std::size_t k = header.find(key);
    const std::size_t a = header.find(open, k + key.size());
    const std::size_t e = header.find(close, a + 1);
    return header.substr(a, e - a + 1);
  };
  out.descr = field("'descr'", '\'', '\'');
  out.descr = out.descr.substr(1, out.descr.size() - 2);
  out.shape = field("'shape'", '(', ')');
  out.data = b.substr(10 + len);
  return out;
}

int sweep(const std::string& scene, const std::string& options, const std::filesystem::path& out,
          const std::filesystem::path& err = "/dev/null") {
  return run_command(kPlancheck + " sweep " + scene + " " + options + " --out " + out.string() + " >/dev/null 2>" +
                     err.string());
}

TEST(Sweep, GridRowsMatchTheClosedForm) {
  TempDir dir("sweep-bar");
  testing::write_bar_scene(dir);
  ASSERT_EQ(sweep((dir / "scene.json").string(), "--grid 'J1=-80:28:0.25' --threads 2 --csv", dir / "out"), 0);
  const auto rows = read_csv(dir / "out/sweep.csv");
  ASSERT_EQ(rows.size(), 1u + 433u);  // -80, -79.75, ..., 28 (the decimal step lands on TO)
  EXPECT_EQ(rows[0], (std::vector<std::string>{"J1", "verdict", "collision", "min_distance", "part_a", "part_b",
                                               "target_x", "target_y", "target_z"}));
  int collisions = 0, clearance = 0, safe = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const auto& f = rows[i];
    ASSERT_EQ(f.size(), 9u);
    const double deg = -80.0 + 0.25 * static_cast<double>(i - 1);
    EXPECT_NEAR(std::stod(f[0]), deg, 1e-9);
    const double d = bar_distance(deg);
    if (d <= 0.0) {
      EXPECT_EQ(f[1], "collision") << deg;
      EXPECT_EQ(f[2], "1");
      ++collisions;
    } else {
      EXPECT_EQ(f[2], "0") << deg;
      EXPECT_NEAR(std::stod(f[3]), d, 1e-11) << deg;
      EXPECT_EQ(f[4], "Bar");
      EXPECT_EQ(f[5], "Slab");
      EXPECT_EQ(f[1], d < 0.05 ? "clearance" : "safe") << deg;
      (d < 0.05 ? clearance : safe)++;
    }
  }
  EXPECT_GT(collisions, 0);
  EXPECT_GT(clearance, 0);
  EXPECT_GT(safe, 0);
  const auto summary = nlohmann::json::parse(read_text(dir / "out/sweep.json"));
  EXPECT_EQ(summary["format"], "plancheck-sweep/1");
  EXPECT_EQ(summary["configurations"], 433);
  EXPECT_EQ(summary["counts"]["safe"], safe);
  EXPECT_EQ(summary["counts"]["collision"], collisions);
  EXPECT_EQ(summary["counts"]["clearance"], clearance);
  EXPECT_EQ(summary["colliding_pairs"][0]["parts"], nlohmann::json::array({"Bar", "Slab"}));
  EXPECT_EQ(summary["colliding_pairs"][0]["configurations"], collisions);
}

TEST(Sweep, StepsSpanTheLimitsWithExactEnds) {
  TempDir dir("sweep-steps");
  testing::write_bar_scene(dir);
  ASSERT_EQ(sweep((dir / "scene.json").string(), "--steps 5 --csv", dir / "out"), 0);
  const auto rows = read_csv(dir / "out/sweep.csv");
  ASSERT_EQ(rows.size(), 6u);
  const double expected[] = {-90, -60, -30, 0, 30};
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_NEAR(std::stod(rows[i + 1][0]), expected[i], 1e-9);
    // The ends are the limits themselves: never a limits violation.
    EXPECT_NE(rows[i + 1][1], "limits");
  }
  EXPECT_EQ(rows[5][1], "collision");  // 30 deg: the bar's end is in the slab
}

// Grid values are plan values: kept and echoed as written, checked against
// the limits as written (330 poses like -30 but is past the 30-degree limit).
TEST(Sweep, GridValuesAreEchoedAndLimitedAsWritten) {
  TempDir dir("sweep-written");
  testing::write_bar_scene(dir);
  ASSERT_EQ(sweep((dir / "scene.json").string(), "--grid J1=-450:330:390 --csv", dir / "out"), 0);
  const auto rows = read_csv(dir / "out/sweep.csv");
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[1][0], "-450");
  EXPECT_EQ(rows[2][0], "-60");
  EXPECT_EQ(rows[3][0], "330");
  EXPECT_EQ(rows[1][1], "limits");  // poses like -90, on the lower limit
  EXPECT_EQ(rows[2][1], "safe");
  EXPECT_EQ(rows[3][1], "limits");  // poses like -30, safe there
  const auto summary = nlohmann::json::parse(read_text(dir / "out/sweep.json"));
  EXPECT_EQ(summary["axes"][0]["values"], nlohmann::json::array({-450.0, -60.0, 330.0}));
  EXPECT_EQ(summary["counts"]["limits"], 2);
}

TEST(Sweep, OneAndTwoThreadsWriteTheSameRows) {
  TempDir dir("sweep-threads");
  testing::write_bar_scene(dir);
  ASSERT_EQ(sweep((dir / "scene.json").string(), "--grid J1=-90:30:0.05 --threads 1 --csv", dir / "one"), 0);
  ASSERT_EQ(sweep((dir / "scene.json").string(), "--grid J1=-90:30:0.05 --threads 2 --csv", dir / "two"), 0);
  for (const char* file : {"sweep.csv", "verdict.npy", "distance.npy"})
    EXPECT_EQ(read_text(dir / "one" / file), read_text(dir / "two" / file)) << file;
}

// On the default scene: every configuration of a small 3-joint grid has the
// verdict, pair and distance that `verify` gives the same configuration as a
// plan state, and the rows come in odometer order (last joint fastest).
TEST(Sweep, AgreesWithVerifyOnTheDefaultScene) {
  ASSERT_TRUE(std::filesystem::exists(kChange5 / "scene.json")) << "run `make dataset` first";
  TempDir dir("sweep-change5");
  const std::string grid = "J1=-40:40:40,J2=-20:40:15,J3=-150:-30:30";
  ASSERT_EQ(sweep((kChange5 / "scene.json").string(), "--grid " + grid + " --csv", dir / "out"), 0);
  const auto rows = read_csv(dir / "out/sweep.csv");
  ASSERT_EQ(rows.size(), 1u + 3u * 5u * 5u);
  const Npy verdicts = read_npy(dir / "out/verdict.npy"), distances = read_npy(dir / "out/distance.npy");
  EXPECT_EQ(verdicts.descr, "|u1");
  EXPECT_EQ(distances.descr, "<f4");
  EXPECT_EQ(verdicts.shape, "(3, 5, 5)");
  EXPECT_EQ(distances.shape, "(3, 5, 5)");
  ASSERT_EQ(verdicts.data.size(), 75u);
  ASSERT_EQ(distances.data.size(), 75u * 4u);
  std::ostringstream plan;
  plan << "J1,J2,J3\n";
  std::size_t i = 1;
  for (int j1 = -40; j1 <= 40; j1 += 40)
    for (int j2 = -20; j2 <= 40; j2 += 15)
      for (int j3 = -150; j3 <= -30; j3 += 30, ++i) {
        ASSERT_EQ(rows[i][0], std::to_string(j1));
        ASSERT_EQ(rows[i][1], std::to_string(j2));
        ASSERT_EQ(rows[i][2], std::to_string(j3));
        plan << j1 << "," << j2 << "," << j3 << "\n";
      }
  write_text(dir / "grid.csv", plan.str());
  const int status = run_command(kPlancheck + " verify " + (kChange5 / "scene.json").string() + " " +
                                 (dir / "grid.csv").string() + " --out " + (dir / "v").string() + " >/dev/null 2>&1");
  ASSERT_LE(status, 1);
  const auto states = read_csv(dir / "v/grid.csv");
  ASSERT_EQ(states.size(), rows.size());
  int kinds[3] = {0, 0, 0};
  for (std::size_t r = 1; r < rows.size(); ++r) {
    const auto& s = rows[r];  // J1,J2,J3,verdict,collision,min_distance,part_a,part_b,...
    const auto& v = states[r];  // state,collision,min_distance,part_a,part_b,...
    EXPECT_EQ(s[4], v[1]) << "row " << r;
    // verdict.npy's code and distance.npy's float32 lower bound of verify's distance.
    const int code = static_cast<unsigned char>(verdicts.data[r - 1]);
    EXPECT_EQ(code, s[3] == "safe" ? 0 : s[3] == "clearance" ? 1 : s[3] == "collision" ? 2 : 3) << "row " << r;
    float f;
    std::memcpy(&f, distances.data.data() + 4 * (r - 1), 4);
    if (v[1] == "1") {
      EXPECT_EQ(f, 0.0f) << "row " << r;
    } else {
      const double exact = std::stod(v[2]);  // 12 significant digits
      EXPECT_LE(f, exact * (1 + 1e-11)) << "row " << r;
      EXPECT_GE(f, exact * (1 - 1.2e-7)) << "row " << r;  // within a float's rounding toward zero
    }
    if (v[1] == "1") {
      EXPECT_EQ(s[3], "collision");
      ++kinds[0];
      continue;
    }
    EXPECT_EQ(s[5], v[2]) << "row " << r;
    EXPECT_EQ(s[6], v[3]) << "row " << r;
    EXPECT_EQ(s[7], v[4]) << "row " << r;
    const bool too_close = std::stod(v[2]) < 0.05;
    EXPECT_EQ(s[3], too_close ? "clearance" : "safe") << "row " << r;
    ++kinds[too_close ? 1 : 2];
  }
  EXPECT_GT(kinds[0], 0);  // the grid reaches into the lander
  EXPECT_GT(kinds[2], 0);
}

// Without --csv: the NumPy arrays and the summary only; sweep.json counts
// what they hold and how many configurations got an exact distance.
TEST(Sweep, WithoutCsvWritesTheArraysAndTheSummary) {
  TempDir dir("sweep-npy");
  testing::write_bar_scene(dir);
  ASSERT_EQ(sweep((dir / "scene.json").string(), "--grid J1=-90:30:0.5", dir / "out"), 0);
  EXPECT_FALSE(std::filesystem::exists(dir / "out/sweep.csv"));
  const Npy verdicts = read_npy(dir / "out/verdict.npy");
  EXPECT_EQ(verdicts.shape, "(241,)");
  const auto summary = nlohmann::json::parse(read_text(dir / "out/sweep.json"));
  EXPECT_EQ(summary["configurations"], 241);
  // The certified sweep gives exact distances near the slab only.
  EXPECT_GT(summary["checked"].get<int>(), 0);
  EXPECT_LT(summary["checked"].get<int>(), 241);
  std::size_t counts[4] = {};
  for (char c : verdicts.data) ++counts[static_cast<unsigned char>(c)];
  EXPECT_EQ(counts[0], summary["counts"]["safe"]);
  EXPECT_EQ(counts[1], summary["counts"]["clearance"]);
  EXPECT_EQ(counts[2], summary["counts"]["collision"]);
  EXPECT_EQ(counts[3], summary["counts"]["limits"]);
  // An earlier run's CSV does not survive a run without --csv.
  ASSERT_EQ(sweep((dir / "scene.json").string(), "--grid J1=-90:30:0.5 --csv", dir / "out"), 0);
  ASSERT_EQ(sweep((dir / "scene.json").string(), "--grid J1=-90:30:1", dir / "out"), 0);
  EXPECT_FALSE(std::filesystem::exists(dir / "out/sweep.csv"));
}

TEST(Sweep, GridsBeyondTwoBillionConfigurationsExitTwo) {
  TempDir dir("sweep-big");
  // 360,001 x 155,001 values: 5.6e10 configurations.
  EXPECT_EQ(sweep((kChange5 / "scene.json").string(), "--grid 'J1=-180:180:0.001,J2=-20:135:0.001'", dir / "out",
                  dir / "err.txt"),
            2);
  EXPECT_NE(read_text(dir / "err.txt").find("more than 2000000000 configurations"), std::string::npos)
      << read_text(dir / "err.txt");
  EXPECT_FALSE(std::filesystem::exists(dir / "out/verdict.npy"));
}

TEST(Sweep, BadGridsExitTwoNamingTheItem) {
  TempDir dir("sweep-bad");
  testing::write_bar_scene(dir);
  const std::string scene = (dir / "scene.json").string();
  const std::pair<std::string, std::string> cases[] = {
      {"--grid 'J9=0:1:1'", "'J9' is not a driving parameter"},
      {"--grid 'J1=0:10:0'", "STEP must be positive"},
      {"--grid 'J1=10:0:1'", "TO is below FROM"},
      {"--grid 'J1=0:x:1'", "TO 'x' is not a finite number"},
      {"--grid 'J1=0:1'", "expected FROM:TO:STEP"},
      {"--grid 'J1=0:1:1,J1=0:2:1'", "given twice"},
      {"--grid 'J1=0:1e9:1e-9'", "more than"},
      {"--steps 1", "below 2"},
      {"--steps 3 --grid J1=0:1:1", "excludes"},
  };
  for (const auto& [options, message] : cases) {
    EXPECT_EQ(sweep(scene, options, dir / "out", dir / "err.txt"), 2) << options;
    const std::string err = read_text(dir / "err.txt");
    EXPECT_NE(err.find(message), std::string::npos) << options << ": " << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n') - (err.find("loading") != std::string::npos ? 1 : 0), 1)
        << options << ": " << err;
    EXPECT_FALSE(std::filesystem::exists(dir / "out/sweep.json")) << options;
  }
}

}  // namespace
}  // namespace plancheck
