// SPDX-License-Identifier: MIT
// verify --continuous in a digging scene: the motion between states s and
// s + 1 meets the terrain as dug through state s. A Foot passing through the
// rim an earlier dig raised, between two safe states, is a collision; one
// moving inside the pit, below the undisturbed ground, is safe; with
// --dig-carry the next plan meets the rim too. A dense oracle (2,000 exact
// sub-steps per segment against a heightfield built afresh from the grid dug
// through the segment's first state) agrees on random plans.
#include "src/checks/continuous.h"
#include "src/checks/dig.h"
#include "src/scene/plan.h"
#include "src/scene/scene_loader.h"
#include "src/checks/verify.h"
#include "support/fixtures.h"
#include "support/sanitized.h"

#include <gtest/gtest.h>

#include <random>

namespace plancheck {
namespace {

using testing::TempDir;

constexpr double kMargin = 0.002;

// Flat ground at z = 0.1 (40 x 40 samples, 1 cm apart). The Scoop's bottom
// point M is (0.2, 0.2, 0.3); pushed down 0.25 it digs a pit 5 cm deep, soil
// within 7 cm of M lowered to 0.05, and a rim 7 to 10 cm from M up to 12.5 mm
// high (template 0.25 x 5 cm, peak at 8.5 cm). Foot, a 1 cm cube, hovers 5 mm
// over the ground with its x extent [0.28, 0.29] (over the rim's peak) at
// rest. Parameters: S.x, S.y, S.z, F.x, F.y, F.z.
Scene write_scene(const TempDir& dir) {
  std::string dem = "ncols 40\nnrows 40\nxllcorner 0\nyllcorner 0\ncellsize 0.01\n";
  for (int r = 0; r < 40; ++r) {
    for (int c = 0; c < 40; ++c) dem += c ? " 0.1" : "0.1";
    dem += "\n";
  }
  testing::write_text(dir / "site.asc", dem);
  testing::write_obj(dir / "m.obj",
                     {{"Scoop", testing::box_mesh(Vec3(0.19, 0.19, 0.3), Vec3(0.21, 0.21, 0.35))},
                      {"Foot", testing::box_mesh(Vec3(0.28, 0.195, 0.105), Vec3(0.29, 0.205, 0.115))}});
  testing::write_text(dir / "s.json", R"({"format": "plancheck-scene/1", "model": "m.obj",
      "actions": [{"name": "S", "node": "Scoop", "type": "translate"},
                  {"name": "F", "node": "Foot", "type": "translate"}],
      "allowed_collisions": [["Scoop", "terrain"]],
      "safety_margin": 0.002,
      "terrain": {"dem": "site.asc", "origin": [0, 0, 0], "collide": true},
      "scoop": {"part": "Scoop", "bottom_point": [0.2, 0.2, 0.3], "width": 0.1,
                "template": {"pit": -1.0, "rim": 0.25, "rim_start": 0.7}, "capacity": 1, "bulk_density": 1240}})");
  return load_scene(dir / "s.json");
}

using State = std::vector<double>;
const State kPark{0, 0, 0, 0.05, 0, 0};   // Foot 13 cm and more from M, 5 mm over flat ground
const State kDig{0, 0, -0.25, 0.05, 0, 0};  // the Scoop digs, Foot parked

Plan make_plan(const std::string& name, std::vector<State> states) {
  Plan p;
  p.name = name;
  p.states = std::move(states);
  return p;
}

std::vector<PlanResult> run(const Checker& checker, const Scene& scene, const std::vector<Plan>& plans, bool carry,
                            int threads = 2) {
  auto results = verify_plans(checker, scene, plans, VerifyOptions{threads, carry});
  ContinuousOptions options;
  options.threads = threads;
  options.dig_carry = carry;
  verify_segments(checker, scene, plans, results, options);
  return results;
}

// Two segment results equal, field by field (bit for bit).
void expect_same_segment(const SegmentResult& a, const SegmentResult& b) {
  EXPECT_EQ(a.collision, b.collision);
  EXPECT_EQ(a.clearance, b.clearance);
  EXPECT_EQ(a.lower_bound, b.lower_bound);
  EXPECT_EQ(a.min_sampled, b.min_sampled);
  EXPECT_EQ(a.part_a, b.part_a);
  EXPECT_EQ(a.part_b, b.part_b);
  EXPECT_EQ(a.witness_t, b.witness_t);
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(a.unresolved, b.unresolved);
}

// Random plans: the Scoop digs at a few places (some twice), Foot wanders
// around the pits and rims at heights from under the undisturbed ground to a
// few centimetres over it; with `beside`, every other state Foot is lifted
// beside the Scoop instead (1 to 6 cm off in x, 15 cm and more over the
// ground: the Scoop is then its closest).
std::vector<Plan> random_dig_plans(std::uint64_t seed, int states_per_plan, bool beside) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Plan> plans;
  for (int i = 0; i < 3; ++i) {
    std::vector<State> states;
    double sx = 0.0, sy = 0.0;
    for (int k = 0; k < states_per_plan; ++k) {
      if (k % 4 == 0) sx = 0.08 * u(rng) - 0.04, sy = 0.08 * u(rng) - 0.04;  // a new dig site now and then
      const double sz = k % 4 == 1 ? -0.22 - 0.03 * u(rng) : 0.0;            // in the soil, or lifted
      // Foot within 15 cm of the site, from 2 cm under the ground to 3 cm over it.
      const bool lifted = beside && k % 2 == 0;
      const double fx = lifted ? sx - 0.06 + 0.04 * u(rng) : sx - 0.08 + 0.3 * u(rng) - 0.15;
      const double fy = lifted ? sy : sy + 0.3 * u(rng) - 0.15;
      const double fz = lifted ? 0.15 + 0.1 * u(rng) : sz < 0.0 ? 0.05 : 0.05 * u(rng) - 0.025;
      states.push_back({sx, sy, sz, fx, fy, fz});
    }
    plans.push_back(make_plan((beside ? "e" : "r") + std::to_string(i), states));
  }
  return plans;
}

TEST(ContinuousDig, PassingThroughTheRimBetweenTwoSafeStatesIsACollision) {
  TempDir dir("continuous_dig");
  const Scene scene = write_scene(dir);
  const Checker checker(scene, 2);
  ASSERT_TRUE(checker.terrain_is_dug());
  // Dig, lift, then Foot slides at 5 mm over the ground from beyond the rim
  // into the pit (x extent [0.16, 0.17], 3 to 4 cm from M).
  const Plan plan = make_plan("rim", {kPark, kDig, kPark, {0, 0, 0, -0.12, 0, 0}});
  for (bool carry : {false, true}) {
    SCOPED_TRACE(carry);
    const auto results = run(checker, scene, {plan}, carry);
    const PlanResult& r = results[0];
    for (const StateResult& s : r.states) {
      EXPECT_FALSE(s.collision);
      EXPECT_GE(s.min_distance, kMargin + 0.001);  // every state is safe on the dug terrain
    }
    ASSERT_TRUE(r.segments[2].checked);
    EXPECT_TRUE(r.segments[2].collision);
    EXPECT_EQ(r.segments[2].lower_bound, 0.0);
    EXPECT_EQ(checker.part_name(r.segments[2].part_a), "Foot");
    EXPECT_EQ(checker.part_name(r.segments[2].part_b), "terrain");
    EXPECT_GT(r.segments[2].witness_t, 0.0);
    EXPECT_LT(r.segments[2].witness_t, 1.0);
    for (std::size_t s : {0u, 1u}) EXPECT_FALSE(r.segments[s].collision || r.segments[s].clearance) << s;
    EXPECT_EQ(r.verdict, Verdict::kCollision);
    ASSERT_TRUE(r.first_violation);
    EXPECT_TRUE(r.first_violation->between);
    EXPECT_EQ(r.first_violation->state, 2u);
    EXPECT_EQ(checker.part_name(r.first_violation->part_a), "Foot");
    EXPECT_EQ(checker.part_name(r.first_violation->part_b), "terrain");

    // What the check did before segments saw the dug terrain: against the
    // undisturbed ground (5 mm under Foot all the way) the same segment,
    // between the same two end results, is certified safe.
    const SegmentChecker seg(checker, scene, ContinuousOptions{});
    const SegmentResult old = seg.check(plan.states[2], plan.states[3], r.states[2], r.states[3]);
    EXPECT_FALSE(old.collision || old.clearance);
    EXPECT_GE(old.lower_bound, kMargin);
  }
}

TEST(ContinuousDig, MovingInsideThePitThroughTheUndisturbedGroundLevelIsSafe) {
  TempDir dir("continuous_dig");
  const Scene scene = write_scene(dir);
  const Checker checker(scene, 2);
  // Dig, lift; Foot rises, goes over the pit, down into it to where its
  // extent [0.095, 0.105] straddles the undisturbed ground (4.5 cm over the
  // pit floor) and 8 cm along it, never farther than 4.6 cm from M.
  const Plan plan = make_plan("pit", {kPark, kDig, kPark, {0, 0, 0, 0.05, 0, 0.05}, {0, 0, 0, -0.08, 0, 0.05},
                                      {0, 0, 0, -0.08, -0.04, -0.01}, {0, 0, 0, -0.08, 0.04, -0.01}});
  for (bool carry : {false, true}) {
    SCOPED_TRACE(carry);
    const auto results = run(checker, scene, {plan}, carry);
    const PlanResult& r = results[0];
    EXPECT_EQ(r.verdict, Verdict::kSafe);
    EXPECT_FALSE(r.first_violation.has_value());
    for (std::size_t s = 0; s + 1 < plan.states.size(); ++s) {
      const SegmentResult& g = r.segments[s];
      ASSERT_TRUE(g.checked) << s;
      EXPECT_FALSE(g.collision || g.clearance) << s;
      EXPECT_GE(g.lower_bound, kMargin) << s;
    }
    // The undisturbed ground would have been hit at the end of the descent
    // and all along the pit; the check before segments saw the dug terrain
    // (ends from the dug terrain, samples between on the undisturbed one)
    // flagged the motion along the pit as a collision.
    for (std::size_t s : {5u, 6u}) {
      StateResult undisturbed;
      checker.check_state(plan.states[s], undisturbed);
      EXPECT_TRUE(undisturbed.collision) << s;
    }
    const SegmentChecker seg(checker, scene, ContinuousOptions{});
    const SegmentResult old = seg.check(plan.states[5], plan.states[6], r.states[5], r.states[6]);
    EXPECT_TRUE(old.collision);
  }
}

TEST(ContinuousDig, WithDigCarryTheNextPlanMeetsTheRim) {
  TempDir dir("continuous_dig");
  const Scene scene = write_scene(dir);
  const Checker checker(scene, 2);
  const std::vector<Plan> plans{make_plan("dig", {kPark, kDig, kPark}),
                                make_plan("slide", {kPark, {0, 0, 0, -0.12, 0, 0}})};
  const auto carried = run(checker, scene, plans, true);
  EXPECT_EQ(carried[0].verdict, Verdict::kSafe);
  EXPECT_EQ(carried[1].verdict, Verdict::kCollision);
  ASSERT_TRUE(carried[1].first_violation);
  EXPECT_TRUE(carried[1].first_violation->between);
  EXPECT_EQ(carried[1].first_violation->state, 0u);
  // Without carrying, the second plan starts on undisturbed ground: safe.
  const auto fresh = run(checker, scene, plans, false);
  EXPECT_EQ(fresh[0].verdict, Verdict::kSafe);
  EXPECT_EQ(fresh[1].verdict, Verdict::kSafe);
}

// An end state whose own dig changes the ground under the moving part: the
// motion reaches it before the dig, so the segment is judged on the terrain
// before it. Foot comes down beside the pit-to-be to 1 mm over the
// undisturbed ground as the Scoop arrives and digs: state 1 itself, over the
// pit its own dig made, is clear, but on the way in Foot comes within the
// 2 mm margin of the ground still standing there.
TEST(ContinuousDig, TheEndStatesOwnDigIsNotPartOfTheMotionIntoIt) {
  TempDir dir("continuous_dig");
  const Scene scene = write_scene(dir);
  const Checker checker(scene, 2);
  const Plan plan = make_plan("end", {{0, 0, 0, -0.12, 0, 0.04}, {0, 0, -0.25, -0.12, 0, -0.004}});
  const auto results = run(checker, scene, {plan}, false);
  const PlanResult& r = results[0];
  ASSERT_FALSE(r.states[1].collision);
  EXPECT_GE(r.states[1].min_distance, kMargin);  // over the pit its own dig made
  EXPECT_TRUE(r.segments[0].clearance);
  EXPECT_FALSE(r.segments[0].collision);
  EXPECT_LT(r.segments[0].lower_bound, kMargin);
  EXPECT_EQ(r.verdict, Verdict::kClearance);
  ASSERT_TRUE(r.first_violation);
  EXPECT_TRUE(r.first_violation->between);
  EXPECT_EQ(checker.part_name(r.first_violation->part_b), "terrain");
}

TEST(ContinuousDig, ResultsDoNotDependOnTheThreadCount) {
  TempDir dir("continuous_dig");
  const Scene scene = write_scene(dir);
  const Checker checker(scene, 2);
  std::vector<Plan> plans;
  for (int i = 0; i < 4; ++i)
    plans.push_back(make_plan("p" + std::to_string(i),
                              {kPark, kDig, kPark, {0, 0, 0, -0.12, 0.01 * i, 0.002 * i}, {0, 0, 0, 0.05, 0, 0.01}}));
  for (bool carry : {false, true}) {
    const auto one = run(checker, scene, plans, carry, 1);
    const auto two = run(checker, scene, plans, carry, 2);
    for (std::size_t p = 0; p < plans.size(); ++p)
      for (std::size_t s = 0; s + 1 < plans[p].states.size(); ++s) {
        expect_same_segment(one[p].segments[s], two[p].segments[s]);
      }
  }
}

// Random plans (random_dig_plans, Foot wandering). Each segment against 2,000 exact sub-steps (600
// under the sanitizers) on a heightfield built afresh from the grid dug
// through its first state.
TEST(ContinuousDig, DenseSamplingOnTheDugTerrainAgrees) {
  TempDir dir("continuous_dig");
  const Scene scene = write_scene(dir);
  const Checker checker(scene, 2);
  const Digger digger(scene);
  const std::vector<Plan> plans = random_dig_plans(11, 10, false);
  const auto results = run(checker, scene, plans, false);
  const SegmentChecker seg(checker, scene, ContinuousOptions{});
  const double tol = ContinuousOptions{}.tolerance;
  // Fewer sub-steps under the sanitizers: the certified `lower` below stays a
  // lower bound at any step (it is built from the motion bound), only looser.
  constexpr int kSteps = testing::case_count(2000, 600);
  int flagged = 0, safe = 0;
  for (std::size_t p = 0; p < plans.size(); ++p) {
    Dem grid = digger.undisturbed();
    std::vector<DigStep> steps;
    const auto& st = plans[p].states;
    digger.dig_plan(st, grid, steps, [&](std::size_t s, const Dem& now, const SampleRect&) {
      if (s + 1 >= st.size()) return;
      SCOPED_TRACE("plan " + std::to_string(p) + " segment " + std::to_string(s));
      const Heightfield field(now, digger.origin());
      const SegmentResult& g = results[p].segments[s];
      ASSERT_TRUE(g.checked);
      bool collision = false;
      double min_sampled = std::numeric_limits<double>::infinity(), lower = min_sampled, prev_d = 0.0;
      std::vector<double> prev_q;
      for (int j = 0; j <= kSteps; ++j) {
        const double t = static_cast<double>(j) / kSteps;
        std::vector<double> q(st[s].size());
        for (std::size_t i = 0; i < q.size(); ++i) q[i] = j == kSteps ? st[s + 1][i] : st[s][i] + t * (st[s + 1][i] - st[s][i]);
        StateResult r;
        checker.check_state_without_terrain(q, r);
        checker.check_terrain(q, field, r);
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
      if (min_sampled < kMargin) {
        EXPECT_TRUE(g.clearance || g.collision) << min_sampled;
      }
      if (lower >= kMargin + tol) {
        EXPECT_FALSE(g.clearance || g.collision) << lower;
      }
      if (!collision && lower > ContinuousOptions{}.contact_tolerance) {
        EXPECT_FALSE(g.collision);
      }
      EXPECT_LE(g.lower_bound, min_sampled);
      EXPECT_GE(g.min_sampled, lower - 1e-12);
      (g.clearance || g.collision ? flagged : safe) += 1;
    });
  }
  // Both outcomes are exercised.
  EXPECT_GT(flagged, 3);
  EXPECT_GT(safe, 3);
}

}  // namespace
}  // namespace plancheck

namespace plancheck {
namespace {

// What a dug segment's check reads of its end state qb: qb against the
// terrain as dug through qa. When qb's own state (which saw its dig) has a
// closest pair that is not a terrain pair, the check takes its other pairs
// from that state and checks only the terrain pairs again; otherwise it
// checks the whole state again. Either way the segment's result is, bit for
// bit, that of the check given the state checked afresh (the whole state
// without the terrain, then the terrain pairs against the dug terrain), and
// both ways occur here. Also: every pair's box gap and guard at once
// (Checker::pair_gaps) are pair_distance's answers to need 0.
TEST(ContinuousDig, EndStateTakenFromItsDigEqualsTheStateCheckedAfresh) {
  TempDir dir("continuous_dig");
  const Scene scene = write_scene(dir);
  const Checker checker(scene, 2);
  const Digger digger(scene);
  std::vector<Plan> plans = random_dig_plans(23, 12, true);
  // A dig that raises its rim into Foot at rest (5 mm over the ground
  // before it, in the rim after): qb's own state collides, the motion up to
  // it does not.
  plans.push_back(make_plan("rim", {kPark, {0, 0, -0.25, 0, 0, 0}, kPark}));
  const auto results = verify_plans(checker, scene, plans, VerifyOptions{1, false});
  const SegmentChecker seg(checker, scene, ContinuousOptions{});
  const int terrain = checker.terrain_index();
  int taken = 0, again = 0, gaps = 0;

  auto expect_gaps = [&](const std::vector<double>& q, const Heightfield* field) {
    PosedParts posed;
    posed.terrain = field;
    checker.pose_parts(q, posed);
    std::vector<double> gap, guard;
    checker.pair_gaps(posed, gap, guard);
    ASSERT_EQ(gap.size(), checker.pairs().size());
    for (std::size_t k = 0; k < gap.size(); ++k) {
      PairAnswer one;
      checker.pair_distance(posed, k, 0.0, one);
      EXPECT_EQ(gap[k], one.distance) << k;
      EXPECT_EQ(guard[k], one.guard) << k;
      ++gaps;
    }
  };
  for (std::size_t p = 0; p < plans.size(); ++p) {
    Dem grid = digger.undisturbed();
    std::vector<DigStep> steps;
    const auto& st = plans[p].states;
    const auto& rs = results[p].states;
    digger.dig_plan(st, grid, steps, [&](std::size_t s, const Dem& now, const SampleRect&) {
      if (s + 1 >= st.size()) return;
      SCOPED_TRACE("plan " + std::to_string(p) + " segment " + std::to_string(s));
      const Heightfield field(now, digger.origin());
      const StateResult& sb = rs[s + 1];
      StateResult fresh;
      checker.check_state_without_terrain(st[s + 1], fresh, row_request());
      checker.check_terrain(st[s + 1], field, fresh);
      expect_same_segment(seg.check(st[s], st[s + 1], rs[s], sb, &field, false),
                          seg.check(st[s], st[s + 1], rs[s], fresh, &field, true));
      const bool other = !sb.collision && sb.part_a >= 0 && sb.part_a != terrain && sb.part_b != terrain;
      (other ? taken : again) += 1;
      expect_gaps(st[s], &field);
      expect_gaps(st[s], nullptr);
    });
  }
  EXPECT_GT(taken, 3);
  EXPECT_GT(again, 3);
  EXPECT_GT(gaps, 0);
}

}  // namespace
}  // namespace plancheck
