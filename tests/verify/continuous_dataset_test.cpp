// SPDX-License-Identifier: MIT
// verify --continuous on the default dataset (datasets/change5): the designed
// violations move to the segments that lead into them, safe plans stay safe
// with a certificate, and grazing paths built through the colliding and
// too-close states of plan04 and plan07 (ends pushed apart until both are
// safe, some by large J1 swings) are caught; dense sampling (1,000 exact
// sub-steps) agrees on the closest segments and on the grazing ones.
#include "src/checks/continuous.h"
#include "src/scene/plan.h"
#include "src/scene/scene_loader.h"
#include "src/checks/verify.h"
#include "support/sanitized.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

namespace plancheck {
namespace {

const std::filesystem::path kDir = std::filesystem::path(PLANCHECK_SOURCE_DIR) / "datasets/change5";

double distance_at(const Checker& checker, const std::vector<double>& q) {
  StateResult r;
  checker.check_state(q, r);
  return r.collision ? 0.0 : r.min_distance;
}

struct Segment {
  std::vector<double> qa, qb;
};

// Through q_mid along direction u: the smallest of 1, 2, 4, ... 64 degrees
// (times u) at which both ends are at least margin + 5 mm clear.
std::optional<Segment> graze_through(const Checker& checker, double margin, const std::vector<double>& mid,
                                     const std::vector<double>& u) {
  // States are in plan units: the default scene's joints in degrees.
  for (double a = 1.0; a <= 64.0; a *= 2.0) {
    Segment s{mid, mid};
    for (std::size_t j = 0; j < mid.size(); ++j) {
      s.qa[j] -= a * u[j];
      s.qb[j] += a * u[j];
    }
    if (distance_at(checker, s.qa) >= margin + 0.005 && distance_at(checker, s.qb) >= margin + 0.005) return s;
  }
  return std::nullopt;
}

struct Fixture {
  Scene scene;
  std::vector<Plan> plans;
  std::unique_ptr<Checker> checker;
  std::vector<PlanResult> discrete, results;
};

const Fixture& fixture() {
  static const Fixture f = [] {
    Fixture x;
    x.scene = load_scene(kDir / "scene.json");
    for (int i = 1; i <= 10; ++i) {
      char name[32];
      std::snprintf(name, sizeof name, "plans/plan%02d.csv", i);
      x.plans.push_back(load_plan(x.scene, kDir / name));
    }
    x.checker = std::make_unique<Checker>(x.scene);
    x.discrete = verify_plans(*x.checker, x.scene, x.plans, VerifyOptions{0, false, false});
    x.results = x.discrete;
    verify_segments(*x.checker, x.scene, x.plans, x.results, ContinuousOptions{});
    return x;
  }();
  return f;
}

// The dense oracle of one segment against the certified answer.
void expect_dense_agrees(const Checker& checker, const SegmentChecker& seg, double margin, const Segment& s,
                         const SegmentResult& g, int n) {
  bool collision = false;
  double min_sampled = std::numeric_limits<double>::infinity(), lower = min_sampled, prev_d = 0.0;
  std::vector<double> prev_q;
  for (int j = 0; j <= n; ++j) {
    std::vector<double> q(s.qa.size());
    for (std::size_t i = 0; i < q.size(); ++i)
      q[i] = j == n ? s.qb[i] : s.qa[i] + static_cast<double>(j) / n * (s.qb[i] - s.qa[i]);
    StateResult r;
    checker.check_state(q, r);
    const double d = r.collision ? 0.0 : r.min_distance;
    collision |= r.collision;
    min_sampled = std::min(min_sampled, d);
    if (j > 0) lower = std::min(lower, std::min({prev_d, d, 0.5 * (prev_d + d - seg.pair_bound(prev_q, q))}));
    prev_q = q;
    prev_d = d;
  }
  if (collision) {
    EXPECT_TRUE(g.collision);
  }
  if (min_sampled < margin) {
    EXPECT_TRUE(g.collision || g.clearance);
  }
  if (lower >= margin + seg.options().tolerance) {
    EXPECT_FALSE(g.collision || g.clearance);
  }
  EXPECT_LE(g.lower_bound, min_sampled);
}

TEST(ContinuousDataset, DesignedViolationsStartBetweenStatesAndSafePlansAreCertified) {
  ASSERT_TRUE(std::filesystem::exists(kDir / "scene.json")) << "run `make dataset` first";
  const Fixture& f = fixture();
  for (std::size_t p = 0; p < f.plans.size(); ++p) {
    SCOPED_TRACE(f.plans[p].name);
    const PlanResult& r = f.results[p];
    if (f.plans[p].name == "plan04") {
      ASSERT_TRUE(r.first_violation);
      EXPECT_EQ(r.first_violation->state, 138u);  // state 139 collides: the collision starts on the way there
      EXPECT_EQ(r.first_violation->kind, Verdict::kCollision);
      EXPECT_TRUE(r.first_violation->between);
      EXPECT_TRUE(r.segments[150].collision);  // and ends on the way out of 150
    } else if (f.plans[p].name == "plan07") {
      ASSERT_TRUE(r.first_violation);
      EXPECT_EQ(r.first_violation->state, 167u);
      EXPECT_EQ(r.first_violation->kind, Verdict::kClearance);
      EXPECT_TRUE(r.first_violation->between);
    } else {
      EXPECT_EQ(r.verdict, f.discrete[p].verdict);
    }
    if (f.discrete[p].verdict == Verdict::kSafe || f.discrete[p].verdict == Verdict::kLimits) {
      for (std::size_t s = 0; s + 1 < r.segments.size(); ++s) {
        EXPECT_FALSE(r.segments[s].collision || r.segments[s].clearance) << s;
        EXPECT_GE(r.segments[s].lower_bound, f.scene.safety_margin) << s;
      }
    }
  }
}

TEST(ContinuousDataset, GrazingPathsThroughBadStatesAreCaughtAndDenseSamplingAgrees) {
  const Fixture& f = fixture();
  const double margin = f.scene.safety_margin;
  const SegmentChecker seg(*f.checker, f.scene, ContinuousOptions{});
  std::mt19937_64 rng(11);
  std::normal_distribution<double> normal;
  std::vector<std::pair<Segment, bool>> grazes;  // (segment, its middle collides)
  for (std::size_t p = 0; p < f.plans.size(); ++p)
    for (std::size_t s = 0; s < f.plans[p].states.size(); ++s) {
      const StateResult& st = f.discrete[p].states[s];
      if (!st.collision && !(st.min_distance < margin)) continue;
      const std::size_t n = f.plans[p].states[s].size();
      std::vector<std::vector<double>> dirs{std::vector<double>(n, 0.0)};
      dirs[0][0] = 1.0;  // a J1 swing
      for (int k = 0; k < 6; ++k) {
        std::vector<double> u(n);
        double norm = 0.0;
        for (double& x : u) {
          x = normal(rng);
          norm += x * x;
        }
        for (double& x : u) x /= std::sqrt(norm);
        dirs.push_back(u);
      }
      for (const auto& u : dirs)
        if (auto g = graze_through(*f.checker, margin, f.plans[p].states[s], u)) grazes.emplace_back(*g, st.collision);
    }
  ASSERT_GE(grazes.size(), 20u);
  int dense_checked = 0;
  for (std::size_t i = 0; i < grazes.size(); ++i) {
    SCOPED_TRACE("graze " + std::to_string(i));
    const auto& [s, collides] = grazes[i];
    StateResult a, b;
    f.checker->check_state(s.qa, a);
    f.checker->check_state(s.qb, b);
    const SegmentResult g = seg.check(s.qa, s.qb, a, b);
    if (collides) {
      EXPECT_TRUE(g.collision);
    }
    EXPECT_TRUE(g.collision || g.clearance);
    if (i % 5 == 0 && dense_checked < testing::case_count(8, 3)) {
      expect_dense_agrees(*f.checker, seg, margin, s, g, 1000);
      ++dense_checked;
    }
  }
  // The dataset's own closest segments (by their least sampled distance).
  std::vector<std::tuple<double, std::size_t, std::size_t>> closest;
  for (std::size_t p = 0; p < f.plans.size(); ++p)
    for (std::size_t s = 0; s + 1 < f.plans[p].states.size(); ++s)
      closest.emplace_back(f.results[p].segments[s].min_sampled, p, s);
  std::sort(closest.begin(), closest.end());
  for (int k = 0; k < testing::case_count(8, 3); ++k) {
    const auto [d, p, s] = closest[static_cast<std::size_t>(k)];
    SCOPED_TRACE(f.plans[p].name + " segment " + std::to_string(s));
    expect_dense_agrees(*f.checker, seg, margin, Segment{f.plans[p].states[s], f.plans[p].states[s + 1]},
                        f.results[p].segments[s], 1000);
  }
}

}  // namespace
}  // namespace plancheck
