// SPDX-License-Identifier: MIT
// Configurations the doubles cannot pose: the checker refuses them at once
// (NaN in a pose defeats every pruning test, so a search would visit every
// triangle pair: a hang, or a "safe" with no distance), and a motion between
// two written values as far apart as doubles go (1e308 to -1e308 degrees)
// interpolates finitely and ends as an uncertified violation.
#include "src/base/error.h"
#include "src/checks/verify.h"
#include "src/scene/scene_loader.h"
#include "support/bar_scene.h"
#include "support/fixtures.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace plancheck {
namespace {

TEST(NonFinite, CheckerRefusesAPoseItCannotSettle) {
  testing::TempDir dir("non-finite");
  testing::write_bar_scene(dir);
  const Scene scene = load_scene(dir / "scene.json");
  const Checker checker(scene);
  CheckRequest collide_only;
  collide_only.distance = false;
  CheckRequest verdict_only;
  verdict_only.exact_below = 0.05;
  for (double v : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                   -std::numeric_limits<double>::infinity()}) {
    std::vector<double> q = scene.reference_parameters;
    q[0] = v;
    for (const CheckRequest& request : {CheckRequest{}, collide_only, verdict_only}) {
      StateResult r;
      try {
        checker.check_state(q, r, request);
        ADD_FAILURE() << "no error for " << v;
      } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("poses part 'Bar' beyond the range of doubles"), std::string::npos)
            << e.what();
      }
    }
  }
  // A finite angle, however large, poses (its sine is taken of the reduced value).
  std::vector<double> q = scene.reference_parameters;
  q[0] = 1e308;
  StateResult r;
  checker.check_state(q, r);
  EXPECT_TRUE(std::isfinite(r.min_distance));
}

TEST(NonFinite, MotionAcrossTheRangeOfADoubleIsAnUncertifiedViolation) {
  testing::TempDir dir("non-finite-motion");
  testing::write_bar_scene(dir);
  testing::write_text(dir / "far.csv", "J1\n1e308\n-1e308\n");
  const std::string cmd = std::string(PLANCHECK_BINARY_DIR) + "/plancheck verify " + (dir / "scene.json").string() +
                          " " + (dir / "far.csv").string() + " --continuous --threads 1 --out " +
                          (dir / "out").string() + " >/dev/null 2>&1";
  // 1: a violation (the states violate J1's limits; the motion between them
  // turns through everything and cannot be certified).
  ASSERT_EQ(testing::run_command(cmd), 1);
  const nlohmann::json report = nlohmann::json::parse(testing::read_text(dir / "out/report.json"));
  EXPECT_NE(report["plans"][0]["verdict"], "safe");
  // The segment's columns in state 0's row: a violation, not a certified pass.
  std::istringstream csv(testing::read_text(dir / "out/far.csv"));
  std::string header, row;
  ASSERT_TRUE(std::getline(csv, header) && std::getline(csv, row));
  auto field = [](const std::string& line, std::size_t k) {
    std::istringstream in(line);
    std::string f;
    for (std::size_t i = 0; i <= k; ++i) std::getline(in, f, ',');
    return f;
  };
  auto column = [&](const std::string& name) {
    std::istringstream in(header);
    std::string f;
    for (std::size_t i = 0; std::getline(in, f, ','); ++i)
      if (f == name) return i;
    ADD_FAILURE() << "no column " << name << " in " << header;
    return std::size_t{0};
  };
  EXPECT_TRUE(field(row, column("segment_collision")) == "1" || field(row, column("segment_clearance")) == "1")
      << header << "\n" << row;
}

}  // namespace
}  // namespace plancheck
