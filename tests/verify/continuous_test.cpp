// SPDX-License-Identifier: MIT
// verify --continuous on synthetic scenes: a bar slewing about a vertical
// axis (with a telescoping boom and a scale on its chain) past posts. Paths
// that graze a post between two safe states, fast large-angle swings, and a
// dense-sampling oracle (2,000 exact sub-steps per segment).
#include "src/checks/continuous.h"
#include "src/scene/kinematics.h"
#include "src/scene/plan.h"
#include "src/scene/scene_loader.h"
#include "src/checks/verify.h"
#include "foundation/fixtures.h"
#include "support/fixtures.h"
#include "support/sanitized.h"
#include "tests/verify/bar_scene.h"
#include "tests/verify/dense_sampling.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <random>
#include <sstream>

namespace plancheck {
namespace {

using testing::Dense;
using testing::TempDir;
using testing::write_text;

constexpr double kMargin = 0.05;
const std::string kPlancheck = std::string(PLANCHECK_BINARY_DIR) + "/plancheck";

// The slewing bar past posts (bar_scene.h).
void write_scene(const TempDir& dir, const std::vector<std::pair<Vec3, Vec3>>& posts) {
  testing::write_bar_scene(dir, posts);
}

// Plan rows: Slew (deg), Boom (m), Grow.x (the other factors stay 1).
std::string plan_text(const std::vector<std::array<double, 3>>& rows) {
  std::ostringstream s;
  s.precision(17);
  s << "Slew,Boom,Grow.x\n";
  for (const auto& r : rows) s << r[0] << "," << r[1] << "," << r[2] << "\n";
  return s.str();
}

struct Run {
  Scene scene;
  std::vector<Plan> plans;
  std::unique_ptr<Checker> checker;
  std::vector<PlanResult> results;
};

std::unique_ptr<Run> run(const TempDir& dir, const std::vector<std::vector<std::array<double, 3>>>& plans,
                         int threads = 2, ContinuousOptions options = {}) {
  auto r = std::make_unique<Run>();
  r->scene = load_scene(dir / "scene.json");
  for (std::size_t i = 0; i < plans.size(); ++i) {
    const auto file = dir / ("p" + std::to_string(i) + ".csv");
    write_text(file, plan_text(plans[i]));
    r->plans.push_back(load_plan(r->scene, file));
  }
  r->checker = std::make_unique<Checker>(r->scene, threads);
  r->results = verify_plans(*r->checker, r->scene, r->plans, VerifyOptions{threads, false, false});
  options.threads = threads;
  verify_segments(*r->checker, r->scene, r->plans, r->results, options);
  return r;
}

// Every segment of every plan against dense sampling: nothing the samples
// find is missed; nothing is flagged that the samples prove to be farther
// than the tolerance from the margin; the certified bound is a lower bound.
void expect_agrees_with_dense(const Run& r, int n, int* flagged = nullptr) {
  const SegmentChecker seg(*r.checker, r.scene, ContinuousOptions{});
  const double tol = ContinuousOptions{}.tolerance;
  for (std::size_t p = 0; p < r.plans.size(); ++p)
    for (std::size_t s = 0; s + 1 < r.plans[p].states.size(); ++s) {
      SCOPED_TRACE("plan " + std::to_string(p) + " segment " + std::to_string(s));
      const SegmentResult& g = r.results[p].segments[s];
      ASSERT_TRUE(g.checked);
      const Dense d = testing::dense(*r.checker, seg, r.plans[p].states[s], r.plans[p].states[s + 1], n);
      if (d.collision) {
        EXPECT_TRUE(g.collision);
      }
      if (d.min_sampled < kMargin) {
        EXPECT_TRUE(g.clearance || g.collision);
      }
      if (d.lower >= kMargin + tol) {
        EXPECT_FALSE(g.clearance || g.collision) << d.lower;
      }
      if (!d.collision && d.lower > ContinuousOptions{}.contact_tolerance) {
        EXPECT_FALSE(g.collision);
      }
      EXPECT_LE(g.lower_bound, d.min_sampled);
      EXPECT_GE(g.min_sampled, d.lower - 1e-12);
      if (flagged && (g.clearance || g.collision)) ++*flagged;
    }
}

TEST(Continuous, SwingThroughAPostBetweenTwoSafeStatesIsACollision) {
  TempDir dir("continuous");
  write_scene(dir, {{{-0.1, 1.2, 0}, {0.1, 1.4, 2}}});  // a post at azimuth 90 degrees
  const auto r = run(dir, {{{0, 0, 1}, {180, 0, 1}}});
  const PlanResult& p = r->results[0];
  ASSERT_FALSE(p.states[0].collision);
  ASSERT_FALSE(p.states[1].collision);
  ASSERT_GT(p.states[0].min_distance, 1.0);  // both states far from the post
  ASSERT_GT(p.states[1].min_distance, 1.0);
  ASSERT_TRUE(p.segments[0].collision);
  EXPECT_EQ(p.verdict, Verdict::kCollision);
  ASSERT_TRUE(p.first_violation.has_value());
  EXPECT_TRUE(p.first_violation->between);
  EXPECT_EQ(p.first_violation->state, 0u);
  EXPECT_EQ(r->checker->part_name(p.first_violation->part_b), "Post0");
  EXPECT_EQ(p.segments[0].lower_bound, 0.0);
  EXPECT_FALSE(p.segments[1].checked);  // the last state has no segment
  expect_agrees_with_dense(*r, 2000);
}

TEST(Continuous, FastLargeAngleSwingsGoTheWayTheParametersGo) {
  TempDir dir("continuous");
  // Posts at azimuth 0 and 180 degrees, just beyond the bar's reach at rest
  // for the second; a -170 -> 170 swing goes through 0 (linear in the
  // parameter), never past 180.
  write_scene(dir, {{{1.2, -0.1, 0}, {1.4, 0.1, 2}}, {{-2.5, -0.1, 0}, {-2.3, 0.1, 2}}});
  const auto r = run(dir, {{{-170, -0.5, 1}, {170, -0.5, 1}},  // through 0: hits post 0 (reach 1.5)
                           {{-170, 0, 0.5}, {170, 0, 0.5}},     // shrunk to reach 1.0: clears post 0
                           {{170, 0.45, 1}, {-170, 0.45, 1}},   // reach 2.45: hits post 0 at 0
                           {{-179, 0.2, 1}, {179, 0.2, 1}}});   // 358 degrees, not 2, past post 0
  for (const PlanResult& p : r->results) {
    ASSERT_FALSE(p.states[0].collision);
    ASSERT_GT(p.states[1].min_distance, kMargin);
  }
  EXPECT_TRUE(r->results[0].segments[0].collision);
  EXPECT_FALSE(r->results[1].segments[0].collision || r->results[1].segments[0].clearance);
  EXPECT_TRUE(r->results[2].segments[0].collision);
  EXPECT_TRUE(r->results[3].segments[0].collision);
  expect_agrees_with_dense(*r, 2000);
}

// A post at azimuth `deg` (degrees), radius 1.3 m: the bar (reach 2 m)
// sweeps through it, and both ends stay clear of it when 20+ degrees away.
std::pair<Vec3, Vec3> post_at(double deg) {
  const double a = deg * std::acos(-1.0) / 180, x = 1.3 * std::cos(a), y = 1.3 * std::sin(a);
  return {{x - 0.1, y - 0.1, 0}, {x + 0.1, y + 0.1, 2}};
}

// The motion between two states runs from the value as written to the value
// as written: steps of more than half a turn, several turns, and steps whose
// written values straddle +-180 go the way they are written (before, values
// were reduced into (-180, 180] when read and the motion took the reduced
// way: 0 -> 200 and 0 -> 720 passed as safe). The same end poses written the
// other way round miss the post and stay safe.
TEST(Continuous, StepsMoveAsWrittenNotTheShortWay) {
  struct Case {
    double post;  // azimuth, degrees
    double from, to;
    bool collision;
  };
  for (const Case c : {Case{100, 0, 200, true}, Case{100, 0, -160, false},    // 200 poses like -160
                       Case{100, 0, 720, true}, Case{100, 720, 0, true},      // two turns, not none
                       Case{100, 360, 360, false}, Case{100, -30, 330, true}, // one turn through 100
                       Case{180, 160, 200, true}, Case{180, 160, -160, false},  // across 180 vs through 0
                       Case{0, 170, -170, true}, Case{0, 170, 190, false},
                       Case{-100, 0, -200, true}, Case{-100, 0, 160, false},
                       Case{-100, 1e4 + 60, 1e4 + 120, false}, Case{-100, -1e4, -1e4 + 360, true}}) {
    SCOPED_TRACE("post at " + std::to_string(c.post) + ", " + std::to_string(c.from) + " -> " + std::to_string(c.to));
    TempDir dir("continuous");
    write_scene(dir, {post_at(c.post)});
    const auto r = run(dir, {{{c.from, 0, 1}, {c.to, 0, 1}}});
    const PlanResult& p = r->results[0];
    ASSERT_GT(p.states[0].min_distance, 0.2);  // both states well clear
    ASSERT_GT(p.states[1].min_distance, 0.2);
    EXPECT_EQ(r->plans[0].states[1][0], c.to);  // as written
    EXPECT_EQ(p.segments[0].collision, c.collision);
    EXPECT_EQ(p.verdict, c.collision ? Verdict::kCollision : Verdict::kSafe);
    expect_agrees_with_dense(*r, 4000);
  }
}

// Post face at y = face, the bar's far corners sweep radius rho: on a slew
// through 90 degrees the minimum distance is face - rho exactly (corner to
// face), with the OBJ's single-precision coordinates.
TEST(Continuous, GrazingWithinAndBeyondTheToleranceOfTheMargin) {
  const double rho = std::hypot(2.0, static_cast<double>(0.05f));
  const double tol = ContinuousOptions{}.tolerance;
  struct Case {
    double gap;
    bool flagged;
  };
  for (const Case c : {Case{kMargin - 2e-5, true}, Case{kMargin + 3 * tol, false}, Case{kMargin - 0.02, true},
                       Case{0.5 * kMargin, true}, Case{-1e-3, true}}) {
    SCOPED_TRACE("gap " + std::to_string(c.gap));
    TempDir dir("continuous");
    const double face = static_cast<double>(static_cast<float>(rho + c.gap));
    write_scene(dir, {{{-0.1, face, 0}, {0.1, face + 0.2, 2}}});
    const auto r = run(dir, {{{60, 0, 1}, {120, 0, 1}}, {{0, 0, 1}, {180, 0, 1}}});
    for (const PlanResult& p : r->results) {
      ASSERT_GT(p.states[0].min_distance, kMargin + 0.01);
      ASSERT_GT(p.states[1].min_distance, kMargin + 0.01);
      const SegmentResult& g = p.segments[0];
      EXPECT_EQ(g.clearance || g.collision, c.flagged);
      EXPECT_EQ(g.collision, face - rho < 0.0);
      EXPECT_LE(g.lower_bound, std::max(0.0, face - rho) + 1e-9);
      if (c.flagged) {
        EXPECT_TRUE(p.first_violation && p.first_violation->between);
        EXPECT_LT(g.min_sampled, kMargin + tol);  // the witness
      } else {
        EXPECT_GE(g.lower_bound, kMargin);
        EXPECT_EQ(p.verdict, Verdict::kSafe);
      }
    }
    expect_agrees_with_dense(*r, 2000);
  }
}

TEST(Continuous, RandomPlansAgreeWithDenseSampling) {
  TempDir dir("continuous");
  write_scene(dir, {{{-0.1, 1.2, 0}, {0.1, 1.4, 2}},
                    {{1.9, -0.3, 0.5}, {2.1, 0.3, 0.92}},     // under the bar's path at reach 2
                    {{-2.6, -0.1, 0.98}, {-2.4, 0.1, 1.2}}});  // hit only when boomed out
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> slew(-180, 180), boom(-0.6, 0.7), grow(0.5, 1.4);
  std::vector<std::vector<std::array<double, 3>>> plans(testing::case_count(6, 2));
  for (auto& p : plans)
    for (int s = 0; s < 12; ++s) p.push_back({slew(rng), boom(rng), grow(rng)});
  const auto r = run(dir, plans);
  int flagged = 0;
  expect_agrees_with_dense(*r, 2000, &flagged);
  const int segments = static_cast<int>(plans.size()) * 11;
  EXPECT_GT(flagged, segments / 12);  // the oracle saw real work on both sides
  EXPECT_LT(flagged, segments);
}

TEST(Continuous, ResultsDoNotDependOnTheThreadCount) {
  TempDir dir("continuous");
  write_scene(dir, {{{-0.1, 1.2, 0}, {0.1, 1.4, 2}}});
  std::vector<std::vector<std::array<double, 3>>> plans{{{0, 0, 1}, {90, 0, 1}, {100, 0.3, 1.2}, {-30, 0, 1}}};
  const auto a = run(dir, plans, 1);
  const auto b = run(dir, plans, 2);
  for (std::size_t s = 0; s < a->results[0].segments.size(); ++s) {
    const SegmentResult& x = a->results[0].segments[s];
    const SegmentResult& y = b->results[0].segments[s];
    EXPECT_EQ(x.collision, y.collision);
    EXPECT_EQ(x.clearance, y.clearance);
    EXPECT_EQ(x.lower_bound, y.lower_bound);
    EXPECT_EQ(x.min_sampled, y.min_sampled);
    EXPECT_EQ(x.steps, y.steps);
    EXPECT_EQ(x.witness_t, y.witness_t);
  }
}

// The command line, end to end, on the issue's case: one step 0 -> 200.
TEST(Continuous, CommandLineTurnsEachStepAsWritten) {
  TempDir dir("continuous");
  write_scene(dir, {post_at(100)});
  write_text(dir / "long.csv", plan_text({{0, 0, 1}, {200, 0, 1}}));
  write_text(dir / "short.csv", plan_text({{0, 0, 1}, {-160, 0, 1}}));  // the same end pose
  const std::string base = kPlancheck + " verify " + (dir / "scene.json").string() + " ";
  const std::string out = " --continuous --out " + (dir / "out").string() + " >/dev/null 2>&1";
  EXPECT_EQ(testing::run_command(base + (dir / "long.csv").string() + out), 1);
  const auto report = nlohmann::json::parse(testing::read_text(dir / "out" / "report.json"));
  EXPECT_EQ(report["plans"][0]["first_violation"]["kind"], "collision");
  EXPECT_EQ(report["plans"][0]["first_violation"]["between"], true);
  EXPECT_EQ(testing::run_command(base + (dir / "short.csv").string() + out), 0);
}

TEST(Continuous, CommandLineReportsBetweenAndSegmentColumns) {
  TempDir dir("continuous");
  write_scene(dir, {{{-0.1, 1.2, 0}, {0.1, 1.4, 2}}});
  write_text(dir / "swing.csv", plan_text({{0, 0, 1}, {10, 0, 1}, {180, 0, 1}}));
  const std::string base = kPlancheck + " verify " + (dir / "scene.json").string() + " " +
                           (dir / "swing.csv").string() + " --out " + (dir / "out").string();
  // Without --continuous the states alone are safe.
  EXPECT_EQ(testing::run_command(base + " >/dev/null 2>&1"), 0);
  EXPECT_EQ(testing::run_command(base + " --continuous >" + (dir / "stdout").string() + " 2>/dev/null"), 1);
  const auto report = nlohmann::json::parse(testing::read_text(dir / "out" / "report.json"));
  const auto& first = report["plans"][0]["first_violation"];
  EXPECT_EQ(first["state"], 1);
  EXPECT_EQ(first["kind"], "collision");
  EXPECT_EQ(first["between"], true);
  EXPECT_NE(testing::read_text(dir / "stdout").find("collision between states 1 and 2"), std::string::npos);
  const std::string csv = testing::read_text(dir / "out" / "swing.csv");
  EXPECT_NE(csv.find(",segment_min_distance,segment_min_sampled,segment_collision,segment_clearance,"), std::string::npos);
  std::istringstream lines(csv);
  std::string header, row0, row1, row2;
  std::getline(lines, header);
  std::getline(lines, row0);
  std::getline(lines, row1);
  std::getline(lines, row2);
  EXPECT_NE(row1.find(",1,1,Bar,Post0,"), std::string::npos) << row1;
  EXPECT_EQ(row2.substr(row2.size() - 8), ",,,,,,,,");  // the last state has no segment
  // Bad tolerance: one message, exit 2; the option needs --continuous.
  EXPECT_EQ(testing::run_command(base + " --continuous --continuous-tolerance 1e-12 >/dev/null 2>&1"), 2);
  EXPECT_EQ(testing::run_command(base + " --continuous --continuous-tolerance -1 >/dev/null 2>&1"), 2);
  EXPECT_EQ(testing::run_command(base + " --continuous-tolerance 1e-4 >/dev/null 2>&1"), 2);
  EXPECT_EQ(testing::run_command(base + " --continuous --continuous-tolerance 1e-4 >/dev/null 2>&1"), 1);
}

// The march's local speeds (a point's speed at each sample, grown by the
// acceleration bound between samples) against a motion whose point is at
// rest at both ends and fast in the middle: two joints on parallel axes
// (J1 about z through the origin, J2 about z through x = 1), the second
// turning back twice as fast, so that a 1 cm cube at x = 2 runs straight
// along the x axis from (2, 0) to (-2, 0), through the origin, at rest at
// either end (the two turns cancel there) and at its fastest between. A
// post across its path (or beside it, c clear) must be seen: the ends
// alone, at their speeds, would certify the whole segment 2 m clear.
TEST(Continuous, APointAtRestAtBothEndsStillMovesBetween) {
  for (const double c : {-1.0, 0.01, 0.04, 0.07, 0.2}) {
    SCOPED_TRACE("clearance " + std::to_string(c));
    TempDir dir("continuous-rest");
    // c < 0: the post across the path at the origin; else beside it, its
    // near face c beyond the cube's side (the cube turns as it runs, its
    // corners at most 2.1 mm nearer).
    const Vec3 lo = c < 0 ? Vec3(-0.02, -0.02, -0.3) : Vec3(-0.02, 0.005 + c, -0.3);
    const Vec3 hi = c < 0 ? Vec3(0.02, 0.02, 0.3) : Vec3(0.02, 0.3 + c, 0.3);
    testing::write_box_gltf(dir / "model.gltf",
                            {{.name = "world"},
                             {.name = "L1", .parent = 0},
                             {.name = "L2", .parent = 1},
                             {.name = "Tip", .parent = 2, .box = true, .lo = {1.995, -0.005, -0.005}, .hi = {2.005, 0.005, 0.005}},
                             {.name = "Post", .parent = 0, .box = true, .lo = lo, .hi = hi}});
    write_text(dir / "scene.json", R"({"format": "plancheck-scene/1", "model": "model.gltf", "length_unit": "m",
  "angle_unit": "deg", "safety_margin": 0.05, "actions": [
    {"name": "J1", "node": "L1", "type": "rotate", "pivot": [0, 0, 0], "axis": [0, 0, 1]},
    {"name": "J2", "node": "L2", "type": "rotate", "pivot": [1, 0, 0], "axis": [0, 0, 1]}]})");
    const Scene scene = load_scene(dir / "scene.json");
    const Checker checker(scene, 1);
    const SegmentChecker seg(checker, scene, ContinuousOptions{});
    for (const auto& [qa, qb] : {std::pair{std::vector<double>{0, 0}, std::vector<double>{180, -360}},
                                 std::pair{std::vector<double>{180, -360}, std::vector<double>{0, 0}},
                                 std::pair{std::vector<double>{-180, 360}, std::vector<double>{0, 0}}}) {
      SCOPED_TRACE("from " + std::to_string(qa[0]) + ", " + std::to_string(qa[1]));
      StateResult sa, sb;
      checker.check_state(qa, sa, row_request());
      checker.check_state(qb, sb, row_request());
      ASSERT_GT(sa.min_distance, 1.9);
      ASSERT_GT(sb.min_distance, 1.9);
      const SegmentResult full = seg.check(qa, qb, sa, sb);
      const SegmentResult reference = seg.check_reference(qa, qb, sa, sb);
      StateResult va, vb;
      const SegmentResult vo = seg.check_motion(qa, qb, true, va, vb, nullptr, true);
      for (const SegmentResult* r : {&reference, &full, &vo}) {
        EXPECT_FALSE(r->unresolved);
        EXPECT_EQ(r->collision || r->clearance, c < 0.05);
        if (r != &vo) {  // (verdict-only stops at the first violation)
          EXPECT_EQ(r->collision, c < 0);
        }
        if (c >= 0.05) {
          EXPECT_GE(r->lower_bound, 0.05);
          EXPECT_LE(r->lower_bound, c + 1e-9);
        }
      }
    }
  }
}

}  // namespace
}  // namespace plancheck

namespace plancheck {
namespace {

// A motion that never comes within 0.3 m of the post but needs more exact
// checks than the budget: a violation without a witness (unresolved,
// counted as clearance), naming no pair, never a contact; its lower bound
// still holds. With the budget it needs, the same motion is certified safe.
TEST(Continuous, StepBudgetRunsOutAsAnUncertifiedViolationNamingNoPair) {
  TempDir dir("continuous");
  write_scene(dir, {{{2.3, -0.1, 0}, {2.5, 0.1, 2}}});  // 0.3 m beyond the bar's reach, at azimuth 0
  const std::vector<std::vector<std::array<double, 3>>> plan{{{0, 0, 1}, {36000, 0, 1}}};  // 100 turns
  ContinuousOptions small;
  small.max_steps = 500;
  const auto r = run(dir, plan, 2, small);
  const PlanResult& p = r->results[0];
  const SegmentResult& g = p.segments[0];
  EXPECT_TRUE(g.unresolved);
  EXPECT_TRUE(g.clearance);
  EXPECT_FALSE(g.collision);
  EXPECT_EQ(g.part_a, -1);
  EXPECT_EQ(g.part_b, -1);
  EXPECT_EQ(g.witness_t, -1.0);
  EXPECT_EQ(g.steps, 500u);
  EXPECT_GE(g.lower_bound, 0.0);  // what the checks left unsettled bounds it, loosely
  EXPECT_LE(g.lower_bound, 0.3 + 1e-9);
  EXPECT_EQ(p.verdict, Verdict::kClearance);
  ASSERT_TRUE(p.first_violation.has_value());
  EXPECT_TRUE(p.first_violation->between);
  EXPECT_EQ(p.first_violation->part_a, -1);

  const auto full = run(dir, plan);
  EXPECT_FALSE(full->results[0].segments[0].unresolved);
  EXPECT_EQ(full->results[0].verdict, Verdict::kSafe);
  EXPECT_GT(full->results[0].segments[0].steps, 500u);
  EXPECT_GE(full->results[0].segments[0].lower_bound, kMargin);
}

// The command line with its own budget (200,000 checks): 55,556 turns that
// stay 0.3 m clear are "not certified", a clearance violation naming no
// pair, not a collision.
TEST(Continuous, CommandLineSaysNotCertifiedBeyondTheBudget) {
  TempDir dir("continuous");
  write_scene(dir, {{{2.3, -0.1, 0}, {2.5, 0.1, 2}}});
  write_text(dir / "far.csv", plan_text({{0, 0, 1}, {2e7, 0, 1}}));
  const std::string cmd = kPlancheck + " verify " + (dir / "scene.json").string() + " " + (dir / "far.csv").string() +
                          " --continuous --out " + (dir / "out").string() + " >" + (dir / "stdout").string() + " 2>&1";
  EXPECT_EQ(testing::run_command(cmd), 1);
  const std::string text = testing::read_text(dir / "stdout");
  EXPECT_NE(text.find("clearance between states 0 and 1 (not certified: the motion needs more than 200000 pair checks)"),
            std::string::npos)
      << text;
  // The plan line names the closest pair at a state; its violation names none.
  const std::size_t line_end = text.find("first violation:");
  ASSERT_NE(line_end, std::string::npos) << text;
  EXPECT_EQ(text.find("Post0", line_end), std::string::npos) << text;
  EXPECT_EQ(text.find("collision between"), std::string::npos) << text;
  const auto report = nlohmann::json::parse(testing::read_text(dir / "out" / "report.json"));
  const auto& first = report["plans"][0]["first_violation"];
  EXPECT_EQ(first["kind"], "clearance");
  EXPECT_EQ(first["uncertified"], true);
  EXPECT_FALSE(first.contains("parts"));
}

// check_motion (the API's segment on its own) equals verify_segments on the
// same segment, and its verdict-only mode takes the same decisions: the same
// flags, witness and pair, with a certified bound no larger.
TEST(Continuous, MotionChecksEqualVerifySegmentsInBothModes) {
  TempDir dir("continuous");
  write_scene(dir, {{{-0.1, 1.2, 0}, {0.1, 1.4, 2}},
                    {{1.9, -0.3, 0.5}, {2.1, 0.3, 0.92}},
                    {{-2.6, -0.1, 0.98}, {-2.4, 0.1, 1.2}}});
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> slew(-400, 400), boom(-0.6, 0.7), grow(0.5, 1.4);
  std::vector<std::vector<std::array<double, 3>>> plans(1);
  // 60 states under the sanitizers too: the 12 they had left no verdict-only
  // bound by chance (exact_saved 0), and 60 take half a second there.
  for (int s = 0; s < 60; ++s) plans[0].push_back({slew(rng), boom(rng), grow(rng)});
  const auto r = run(dir, plans);
  const SegmentChecker seg(*r->checker, r->scene, ContinuousOptions{});
  int flagged = 0, exact_saved = 0;
  for (std::size_t s = 0; s + 1 < r->plans[0].states.size(); ++s) {
    SCOPED_TRACE("segment " + std::to_string(s));
    const SegmentResult& g = r->results[0].segments[s];
    StateResult sa, sb;
    const auto& st = r->plans[0].states;
    const SegmentResult full = seg.check_motion(st[s], st[s + 1], false, sa, sb);
    EXPECT_EQ(full.collision, g.collision);
    EXPECT_EQ(full.clearance, g.clearance);
    EXPECT_EQ(full.witness_t, g.witness_t);
    EXPECT_EQ(full.part_a, g.part_a);
    EXPECT_EQ(full.part_b, g.part_b);
    EXPECT_EQ(full.lower_bound, g.lower_bound);
    EXPECT_EQ(full.steps, g.steps);
    const SegmentResult vo = seg.check_motion(st[s], st[s + 1], true, sa, sb);
    EXPECT_EQ(vo.collision, g.collision);
    EXPECT_EQ(vo.clearance, g.clearance);
    EXPECT_EQ(vo.unresolved, g.unresolved);
    EXPECT_EQ(vo.witness_t, g.witness_t);
    if (g.collision || g.clearance) {
      EXPECT_EQ(vo.part_a, g.part_a);
      EXPECT_EQ(vo.part_b, g.part_b);
    }
    EXPECT_LE(vo.lower_bound, g.lower_bound);
    EXPECT_GE(vo.lower_bound, g.collision ? 0.0 : (g.clearance ? 0.0 : kMargin));
    flagged += g.collision || g.clearance;
    exact_saved += sa.distance_is_bound || sb.distance_is_bound;
  }
  EXPECT_GT(flagged, 0);
  EXPECT_GT(exact_saved, 0);  // verdict-only did leave some distances as bounds
}

}  // namespace
}  // namespace plancheck
