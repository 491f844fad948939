// SPDX-License-Identifier: MIT
// The verdict-only check (verify --verdict-only, CheckRequest::exact_below,
// verdict_only_request) against the full check, state by state: the same
// verdict at every margin tried, the same first colliding pair, the exact
// distance wherever it is below the margin, and otherwise a lower bound that
// really is one. Margins are placed on and around each state's own distance
// (within ulps, the 1e-9 m guard, the tie tolerance), where a shortcut that
// mis-settles a comparison would show; on the default scene's cold states
// (random configurations within limits and some beyond), along the default
// plans (digging, so the dug-terrain pairs too), on a bar on a slab at the
// origin and at the lunar radius (where the guard grows with coordinates).
#include "src/checks/verify.h"
#include "src/scene/plan.h"
#include "src/scene/scene_loader.h"
#include "stability/stability_scene.h"
#include "support/fixtures.h"
#include "support/sanitized.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace plancheck {
namespace {

namespace fs = std::filesystem;

const fs::path kDataset = fs::path(PLANCHECK_SOURCE_DIR) / "datasets/change5";

struct Tally {
  int states = 0, collision = 0, clearance = 0, bound = 0, exact = 0;
};

// Margins around a distance d: on it, an ulp either side, within and beyond
// the guard and the tie tolerance, and far either side.
std::vector<double> margins_around(double d) {
  std::vector<double> m = {0.0};
  if (!std::isfinite(d)) return m;
  for (double e : {0.0, 1e-13, 1e-12, 5e-10, 1e-9, 1.5e-9, 3e-9, 1e-6, 1e-3})
    for (double sign : {-1.0, 1.0}) m.push_back(d + sign * e);
  m.push_back(std::nextafter(d, 0.0));
  m.push_back(std::nextafter(d, 1e300));
  m.push_back(2.0 * d + 0.01);
  m.push_back(0.5 * d);
  std::vector<double> out;
  for (double x : m)
    if (x >= 0.0) out.push_back(x);
  return out;
}

// One state at one margin: the verdict-only answer against the full one.
void expect_same(const Checker& c, const std::vector<double>& state, const StateResult& full, double margin,
                 const std::string& what, Tally& tally) {
  StateResult vo;
  c.check_state(state, vo, verdict_only_request(margin));
  const std::string at = what + " margin " + std::to_string(margin);
  ++tally.states;
  ASSERT_EQ(verdict_name(state_verdict(vo, margin)), verdict_name(state_verdict(full, margin))) << at;
  ASSERT_EQ(vo.collision, full.collision) << at;
  EXPECT_EQ(vo.limit_action, full.limit_action) << at;
  if (full.collision) {
    ++tally.collision;
    // The first colliding pair in checked-pair order, one triangle pair.
    ASSERT_EQ(vo.contacts.size(), 1u) << at;
    EXPECT_EQ(vo.contacts[0].part_a, full.contacts[0].part_a) << at;
    EXPECT_EQ(vo.contacts[0].part_b, full.contacts[0].part_b) << at;
    EXPECT_EQ(vo.contacts[0].triangles.size(), 1u) << at;
    EXPECT_EQ(vo.min_distance, 0.0) << at;
    return;
  }
  if (vo.distance_is_bound) {
    ++tally.bound;
    // A certified lower bound, above the margin and its guard, no pair named.
    EXPECT_LE(vo.min_distance, full.min_distance + kDistanceTieTolerance) << at;
    EXPECT_GE(vo.min_distance, margin + full.distance_tolerance) << at;
    EXPECT_EQ(vo.part_a, -1) << at;
    return;
  }
  if (full.part_a < 0) {  // no checked pair at all
    EXPECT_EQ(vo.part_a, -1) << at;
    return;
  }
  ++tally.exact;
  if (state_verdict(full, margin) == Verdict::kClearance) ++tally.clearance;
  // Exact: the full check's minimum, to within the tie tolerance both searches allow.
  EXPECT_NEAR(vo.min_distance, full.min_distance, 2.0 * kDistanceTieTolerance) << at;
  EXPECT_GE(vo.part_a, 0) << at;
  EXPECT_EQ(vo.distance_tolerance, full.distance_tolerance) << at;
}

void expect_same_around(const Checker& c, const std::vector<double>& state, double scene_margin,
                        const std::string& what, Tally& tally) {
  StateResult full;
  c.check_state(state, full);
  std::vector<double> margins = margins_around(full.min_distance);
  margins.push_back(scene_margin);
  for (double m : margins) {
    expect_same(c, state, full, m, what, tally);
    if (::testing::Test::HasFatalFailure()) return;
  }
}

TEST(VerdictOnly, ColdStatesOfTheDefaultSceneAgreeAtMarginsAroundEachDistance) {
  const Scene scene = load_scene(kDataset / "scene.json");
  const Checker checker(scene);
  std::mt19937_64 rng(20261126);
  Tally tally;
  const int n = testing::case_count(300, 40);
  for (int i = 0; i < n; ++i) {
    // Within limits, and every fifth state up to 20% beyond them.
    const std::vector<double> p = testing::random_state(scene, rng, i % 5 == 0 ? 0.2 : 0.0);
    expect_same_around(checker, p, scene.safety_margin, "cold state " + std::to_string(i), tally);
    if (HasFatalFailure()) return;
  }
  // Every outcome occurred: the comparison above is not vacuous.
  EXPECT_GT(tally.collision, 0);
  EXPECT_GT(tally.clearance, 0);
  EXPECT_GT(tally.bound, 0);
  EXPECT_GT(tally.exact, 0);
  std::cout << "cold states: " << n << ", comparisons " << tally.states << " (collision " << tally.collision
            << ", clearance " << tally.clearance << ", exact " << tally.exact << ", bound " << tally.bound << ")\n";
}

TEST(VerdictOnly, BarNearTheMarginAtTheOriginAndAtTheLunarRadius) {
  stability::BarScene s;
  // Angles lifting the bar's far end through contact, the margin and away.
  std::vector<std::string> degrees = {"0", "1e-9", "-1e-9", "-0.001", "0.001", "-1", "-1.4", "-1.43", "-1.432",
                                      "-1.4324", "-2", "-5", "-30", "10"};
  const auto states = s.states(degrees);
  const Checker near(s.scene);
  const Scene far_scene = stability::translated(s.scene, stability::kLunarRadius * Vec3(0.48, -0.6, 0.64));
  const Checker far(far_scene);
  Tally tally;
  for (std::size_t i = 0; i < states.size(); ++i) {
    expect_same_around(near, states[i], 0.05, "origin, J1 " + degrees[i], tally);
    if (HasFatalFailure()) return;
    expect_same_around(far, states[i], 0.05, "lunar radius, J1 " + degrees[i], tally);
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(tally.collision, 0);
  EXPECT_GT(tally.clearance, 0);
  EXPECT_GT(tally.bound, 0);
}

// The same answer, bit for bit (NaN and the sign of zero included).
void expect_identical(const StateResult& x, const StateResult& y, const std::string& at) {
  auto bits = [](double v) { return std::bit_cast<std::uint64_t>(v); };
  ASSERT_EQ(x.collision, y.collision) << at;
  ASSERT_EQ(x.contacts.size(), y.contacts.size()) << at;
  for (std::size_t i = 0; i < x.contacts.size(); ++i) {
    EXPECT_EQ(x.contacts[i].part_a, y.contacts[i].part_a) << at;
    EXPECT_EQ(x.contacts[i].part_b, y.contacts[i].part_b) << at;
    EXPECT_EQ(x.contacts[i].triangles, y.contacts[i].triangles) << at;
  }
  EXPECT_EQ(bits(x.min_distance), bits(y.min_distance)) << at << ": " << x.min_distance << " vs " << y.min_distance;
  EXPECT_EQ(x.distance_is_bound, y.distance_is_bound) << at;
  EXPECT_EQ(x.part_a, y.part_a) << at;
  EXPECT_EQ(x.part_b, y.part_b) << at;
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(bits(x.point_a[k]), bits(y.point_a[k])) << at;
    EXPECT_EQ(bits(x.point_b[k]), bits(y.point_b[k])) << at;
  }
  EXPECT_EQ(x.limit_action, y.limit_action) << at;
  EXPECT_EQ(bits(x.distance_tolerance), bits(y.distance_tolerance)) << at;
}

// Margins that put the verdict-only cutoff (margin + 4 G + the tie
// tolerance, G the state's largest guard) within a few ulps of each checked
// pair's box gap at this state, either side: the gaps as check_pairs
// computes them, from the posed part boxes, less 4 G for every G the guard
// can take here (kDistanceTolerance on a scene of metres, 64 eps times the
// largest coordinate far from the origin).
std::vector<double> margins_at_box_gaps(const Checker& c, const std::vector<double>& state) {
  PosedParts posed;
  c.pose_parts(state, posed);
  double magnitude = 0.0;
  for (const auto& [lo, hi] : posed.box)
    if (lo.allFinite() && hi.allFinite()) magnitude = std::max({magnitude, lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()});
  std::vector<double> guards = {kDistanceTolerance};
  const double g = 64.0 * std::numeric_limits<double>::epsilon() * magnitude;
  if (g > kDistanceTolerance)
    for (double f : {1.0, 1.0 + 1e-6, 1.0 + 1e-3}) guards.push_back(g * f);
  // The nearest pairs' gaps (the cutoff lies near them at margins that matter).
  std::vector<double> gaps;
  for (const auto& [a, b] : c.pairs()) {
    if (static_cast<std::size_t>(b) >= posed.box.size()) continue;  // the terrain: its box is not posed here
    const auto& x = posed.box[static_cast<std::size_t>(a)];
    const auto& y = posed.box[static_cast<std::size_t>(b)];
    double g2 = 0.0;
    for (int i = 0; i < 3; ++i) {
      const double g = std::max(std::max(x.first[i] - y.second[i], y.first[i] - x.second[i]), 0.0);
      g2 += g * g;
    }
    if (g2 > 0.0 && std::isfinite(g2)) gaps.push_back(std::sqrt(g2));
  }
  std::sort(gaps.begin(), gaps.end());
  gaps.resize(std::min<std::size_t>(gaps.size(), 8));
  std::vector<double> out;
  for (double gap : gaps)
    for (double guard : guards) {
      double m = gap - 4.0 * guard - kDistanceTieTolerance;
      for (int step = 0; step < 2; ++step) m = std::nextafter(m, 0.0);
      for (int step = 0; step < 5; ++step, m = std::nextafter(m, 1e300))
        if (m >= 0.0) out.push_back(m);
    }
  return out;
}

// A check without a seed skips the square root of box gaps beyond the
// cutoff (check_pairs' `lazy`); with one it takes every root. An empty seed
// changes nothing else, so both must answer the same bit for bit: on cold
// states of the default scene (its terrain too, whole and as the dug
// path's separate pass) and on the bar near the origin and at the lunar
// radius, at the scene's margin, around each state's distance, and at
// margins that put the cutoff within ulps of a box gap.
TEST(VerdictOnly, UnseededStatesAnswerAsSeededOnesBitForBit) {
  struct Case {
    const Checker* checker;
    std::vector<double> state;
    double margin;
    std::string what;
  };
  const Scene scene = load_scene(kDataset / "scene.json");
  const Checker checker(scene);
  stability::BarScene bar;
  const Checker near(bar.scene);
  const Scene far_scene = stability::translated(bar.scene, stability::kLunarRadius * Vec3(0.48, -0.6, 0.64));
  const Checker far(far_scene);
  std::vector<Case> cases;
  std::mt19937_64 rng(16);
  const int n = testing::case_count(60, 10);
  for (int i = 0; i < n; ++i)
    cases.push_back({&checker, testing::random_state(scene, rng, i % 5 == 0 ? 0.2 : 0.0), scene.safety_margin,
                     "cold state " + std::to_string(i)});
  const std::vector<std::string> degrees = {"0", "-0.001", "-1", "-1.4324", "-2", "-5", "-30", "10"};
  const auto bar_states = bar.states(degrees);
  for (std::size_t i = 0; i < bar_states.size(); ++i) {
    cases.push_back({&near, bar_states[i], 0.05, "bar at the origin, J1 " + degrees[i]});
    cases.push_back({&far, bar_states[i], 0.05, "bar at the lunar radius, J1 " + degrees[i]});
  }
  int compared = 0, bounds = 0;
  for (const Case& c : cases) {
    StateResult full;
    c.checker->check_state(c.state, full);
    std::vector<double> margins = margins_around(full.min_distance);
    margins.push_back(c.margin);
    for (double m : margins_at_box_gaps(*c.checker, c.state)) margins.push_back(m);
    for (double m : margins) {
      const CheckRequest request = verdict_only_request(m);
      const std::string at = c.what + " margin " + std::to_string(m);
      StateResult lazy, rooted;
      StateSeed empty;
      c.checker->check_state(c.state, lazy, request);
      c.checker->check_state(c.state, rooted, request, &empty);
      expect_identical(lazy, rooted, at);
      ++compared;
      bounds += lazy.distance_is_bound ? 1 : 0;
      // The terrain in its own pass (the dug path), after the other pairs.
      if (c.checker->terrain()) {
        StateSeed empty_a, empty_b;
        c.checker->check_state_without_terrain(c.state, lazy, request);
        c.checker->check_terrain(c.state, *c.checker->terrain(), lazy, nullptr, request);
        c.checker->check_state_without_terrain(c.state, rooted, request, &empty_a);
        c.checker->check_terrain(c.state, *c.checker->terrain(), rooted, &empty_b, request);
        expect_identical(lazy, rooted, at + " (terrain apart)");
      }
      if (HasFailure()) return;
    }
  }
  EXPECT_GT(bounds, 0);
  std::cout << "compared " << compared << " answers, " << bounds << " of them bounds\n";
}

// Along the default plans, dug terrain included: per state the same verdict,
// per plan the same verdict and first violation; the plan's minimum exact
// when below the margin.
TEST(VerdictOnly, DefaultPlansGiveTheFullVerdictsStateByState) {
  const Scene scene = load_scene(kDataset / "scene.json");
  const Checker checker(scene, 2);
  std::vector<Plan> plans;
  for (const auto& entry : fs::directory_iterator(kDataset / "plans")) plans.push_back(load_plan(scene, entry.path()));
  std::sort(plans.begin(), plans.end(), [](const Plan& a, const Plan& b) { return a.name < b.name; });
  VerifyOptions full_options;
  full_options.threads = 2;
  VerifyOptions vo_options = full_options;
  vo_options.verdict_only = true;
  const auto full = verify_plans(checker, scene, plans, full_options);
  const auto vo = verify_plans(checker, scene, plans, vo_options);
  ASSERT_EQ(full.size(), vo.size());
  int bounds = 0, violations = 0;
  for (std::size_t p = 0; p < full.size(); ++p) {
    const std::string name = plans[p].name;
    EXPECT_EQ(verdict_name(vo[p].verdict), verdict_name(full[p].verdict)) << name;
    ASSERT_EQ(vo[p].first_violation.has_value(), full[p].first_violation.has_value()) << name;
    if (full[p].first_violation) {
      ++violations;
      EXPECT_EQ(vo[p].first_violation->state, full[p].first_violation->state) << name;
      EXPECT_EQ(vo[p].first_violation->part_a, full[p].first_violation->part_a) << name;
      EXPECT_EQ(vo[p].first_violation->part_b, full[p].first_violation->part_b) << name;
    }
    if (full[p].min_distance < scene.safety_margin) {
      EXPECT_NEAR(vo[p].min_distance, full[p].min_distance, 2.0 * kDistanceTieTolerance) << name;
    } else {
      EXPECT_LE(vo[p].min_distance, full[p].min_distance + kDistanceTieTolerance) << name;
    }
    for (std::size_t s = 0; s < full[p].states.size(); ++s) {
      const StateResult& a = full[p].states[s];
      const StateResult& b = vo[p].states[s];
      ASSERT_EQ(verdict_name(state_verdict(b, scene.safety_margin)), verdict_name(state_verdict(a, scene.safety_margin)))
          << name << " state " << s;
      if (b.distance_is_bound) {
        ++bounds;
        EXPECT_LE(b.min_distance, a.min_distance + kDistanceTieTolerance) << name << " state " << s;
      }
    }
    // Digging and probes do not depend on the kind of check.
    ASSERT_EQ(vo[p].dig_steps.size(), full[p].dig_steps.size());
    for (std::size_t s = 0; s < full[p].dig_steps.size(); ++s)
      EXPECT_EQ(vo[p].dig_steps[s].volume, full[p].dig_steps[s].volume) << name << " state " << s;
  }
  EXPECT_GT(bounds, 0);
  EXPECT_GT(violations, 0);
}

// The command line: a verdict column equal to the full run's state verdicts,
// report.json saying it is a verdict-only run, and the same exit status.
TEST(VerdictOnly, CommandLineWritesTheVerdictColumn) {
  testing::TempDir dir("verdict-only-cli");
  const std::string exe = std::string(PLANCHECK_BINARY_DIR) + "/plancheck";
  const std::string plans = (kDataset / "plans/plan04.csv").string() + "\" \"" + (kDataset / "plans/plan07.csv").string() +
                            "\" \"" + (kDataset / "plans/plan01.csv").string();
  const std::string common = "\"" + exe + "\" verify \"" + (kDataset / "scene.json").string() + "\" \"" + plans +
                             "\" --quiet --threads 2 --out ";
  const int full_status = testing::run_command(common + "\"" + (dir / "full").string() + "\" > /dev/null");
  const int vo_status = testing::run_command(common + "\"" + (dir / "vo").string() + "\" --verdict-only > /dev/null");
  EXPECT_EQ(full_status, 1);  // plan04 collides, plan07 is too close
  EXPECT_EQ(vo_status, full_status);

  const Scene scene = load_scene(kDataset / "scene.json");
  for (const char* name : {"plan04", "plan07", "plan01"}) {
    std::ifstream full_csv(dir / "full" / (std::string(name) + ".csv")), vo_csv(dir / "vo" / (std::string(name) + ".csv"));
    std::string full_header, vo_header;
    std::getline(full_csv, full_header);
    std::getline(vo_csv, vo_header);
    ASSERT_EQ(vo_header, full_header + ",verdict") << name;
    std::string a, b;
    int rows = 0;
    while (std::getline(full_csv, a)) {
      ASSERT_TRUE(static_cast<bool>(std::getline(vo_csv, b))) << name;
      // The full row's verdict from its own columns: collision, distance
      // against the margin (these rows are far from the guard), limits.
      std::vector<std::string> f;
      std::stringstream ss(a);
      for (std::string field; std::getline(ss, field, ',');) f.push_back(field);
      std::string expected = "safe";
      if (f[1] == "1") expected = "collision";
      else if (!f[2].empty() && std::stod(f[2]) < scene.safety_margin) expected = "clearance";
      else if (f.size() > 11 && !f[11].empty()) expected = "limits";
      EXPECT_EQ(b.substr(b.rfind(',') + 1), expected) << name << ": " << b;
      EXPECT_EQ(b.substr(0, b.find(',', b.find(',') + 1)), a.substr(0, a.find(',', a.find(',') + 1))) << name;
      ++rows;
    }
    EXPECT_GT(rows, 100) << name;
  }
  const auto full_json = nlohmann::json::parse(testing::read_text(dir / "full" / "report.json"));
  const auto vo_json = nlohmann::json::parse(testing::read_text(dir / "vo" / "report.json"));
  EXPECT_EQ(vo_json.value("verdict_only", false), true);
  EXPECT_FALSE(full_json.contains("verdict_only"));
  for (std::size_t p = 0; p < 3; ++p) {
    EXPECT_EQ(vo_json["plans"][p]["verdict"], full_json["plans"][p]["verdict"]);
    EXPECT_EQ(vo_json["plans"][p]["first_violation"], full_json["plans"][p]["first_violation"]);
  }
}

}  // namespace
}  // namespace plancheck
