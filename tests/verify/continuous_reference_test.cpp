// SPDX-License-Identifier: MIT
// The per-pair motion check (SegmentChecker::check, check_motion) against
// the previous algorithm kept as its slow reference (check_reference,
// check_motion_reference: one bound for all pairs, a whole configuration
// checked at every bisection midpoint), segment by segment, full and
// verdict-only: the same verdict (safe, clearance, collision), a lower bound
// no larger than any distance the reference sampled, a certificate above the
// margin on every safe segment, and a witness that an exact check at its
// configuration confirms. Segments: random ones of a slewing bar past posts
// (up to three turns, whole turns, the long way round), contacts grazed at
// 1e-9 m either side of touching and of the margin, random motions of the
// default arm and of the URDF example's arm (one chain of links: the pair
// bound that leaves out their shared joints), and motions of both arms that
// dip 1e-9 m below the margin between clear ends.
#include "src/checks/continuous.h"
#include "src/scene/plan.h"
#include "src/scene/scene_loader.h"
#include "src/checks/verify.h"
#include "support/fixtures.h"
#include "support/sanitized.h"
#include "tests/verify/arm_scenes.h"
#include "tests/verify/bar_scene.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>
#include <sstream>
#include <thread>

namespace plancheck {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;
using testing::write_text;
using testing::arm_scene;
using testing::ArmSegments;

constexpr double kMargin = 0.05;

int kind(const SegmentResult& g) { return g.collision ? 2 : (g.clearance ? 1 : 0); }

struct Tally {
  int segments = 0, flagged = 0, collisions = 0, partly_certified = 0;
};

// One segment both ways, both modes. band: the segment's minimum may lie
// within the tolerance of the margin (or of touching), where either verdict
// is allowed: then only the guarantees are checked, not equality.
void compare(const Checker& checker, const SegmentChecker& seg, double margin, const std::vector<double>& qa,
             const std::vector<double>& qb, Tally& tally, bool band = false) {
  const ContinuousOptions o = seg.options();
  StateResult sa, sb;
  checker.check_state(qa, sa, row_request());
  checker.check_state(qb, sb, row_request());
  const SegmentResult fast = seg.check(qa, qb, sa, sb);
  const SegmentResult ref = seg.check_reference(qa, qb, sa, sb);
  StateResult va, vb;
  double until = -1.0;
  const SegmentResult fast_vo = seg.check_motion(qa, qb, true, va, vb, &until);
  const SegmentResult ref_vo = seg.check_motion_reference(qa, qb, true, va, vb);
  ASSERT_FALSE(fast.unresolved);
  ASSERT_FALSE(ref.unresolved);
  if (!band) {
    EXPECT_EQ(kind(fast), kind(ref)) << "fast lower " << fast.lower_bound << ", reference sampled " << ref.min_sampled;
  }
  EXPECT_EQ(kind(ref_vo), kind(ref));
  // Verdict-only takes the same steps: the same verdict, witness and pair.
  EXPECT_EQ(kind(fast_vo), kind(fast));
  EXPECT_EQ(fast_vo.witness_t, fast.witness_t);
  EXPECT_EQ(fast_vo.steps, fast.steps);
  // Its bound may be looser (a far pair proven by one box around all its
  // balls, SweptClusters), never tighter, and a certificate all the same.
  EXPECT_LE(fast_vo.lower_bound, fast.lower_bound);
  if (kind(fast) == 0) {
    EXPECT_GE(fast_vo.lower_bound, margin);
  }
  if (kind(fast) != 0) {
    EXPECT_EQ(fast_vo.part_a, fast.part_a);
    EXPECT_EQ(fast_vo.part_b, fast.part_b);
  }
  // first_violation (a motion validator's question): safe exactly where
  // verdict-only is, certified as far; safe, the same answer; found below
  // the margin, verdict-only's first pass (its witness and pair when no
  // contact followed) and no bound (NaN); never more steps.
  {
    StateResult fa, fb;
    double first_until = -1.0;
    const SegmentResult first = seg.check_motion(qa, qb, true, fa, fb, &first_until, true);
    EXPECT_EQ(kind(first) == 0, kind(fast_vo) == 0);
    EXPECT_EQ(first_until, until);
    EXPECT_LE(first.steps, fast_vo.steps);
    if (kind(fast_vo) == 0 || margin == 0.0) {
      EXPECT_EQ(kind(first), kind(fast_vo));
      EXPECT_EQ(first.witness_t, fast_vo.witness_t);
      EXPECT_EQ(first.lower_bound, fast_vo.lower_bound);
      EXPECT_EQ(first.steps, fast_vo.steps);
    } else {
      EXPECT_EQ(kind(first), 1);
      EXPECT_TRUE(std::isnan(first.lower_bound));
      if (kind(fast_vo) == 1) {
        EXPECT_EQ(first.witness_t, fast_vo.witness_t);
        EXPECT_EQ(first.part_a, fast_vo.part_a);
        EXPECT_EQ(first.part_b, fast_vo.part_b);
      }
      if (first.witness_t >= 0.0) {
        // Real: an exact check at its configuration comes below the margin.
        std::vector<double> q;
        state_between(qa, qb, first.witness_t, q);
        StateResult w;
        checker.check_state(first.witness_t == 0.0 ? qa : (first.witness_t == 1.0 ? qb : q), w, row_request());
        EXPECT_LT(w.collision ? 0.0 : w.min_distance, margin + o.tolerance) << "at t = " << first.witness_t;
      }
    }
  }
  // Never above what the reference saw at any configuration.
  EXPECT_LE(fast.lower_bound, ref.min_sampled);
  EXPECT_LE(fast_vo.lower_bound, ref.min_sampled);
  if (kind(fast) == 0) {
    EXPECT_GE(fast.lower_bound, margin);
    EXPECT_GE(fast.min_sampled, fast.lower_bound);
  } else if (fast.witness_t >= 0.0) {
    // The witness is real: an exact check at its configuration.
    std::vector<double> q;
    state_between(qa, qb, fast.witness_t, q);
    const std::vector<double>& at = fast.witness_t == 0.0 ? qa : (fast.witness_t == 1.0 ? qb : q);
    StateResult w;
    checker.check_state(at, w, row_request());
    const double d = w.collision ? 0.0 : w.min_distance;
    if (fast.collision) {
      EXPECT_LT(d, o.contact_tolerance) << "at t = " << fast.witness_t;
    } else {
      EXPECT_LT(d, margin + o.tolerance) << "at t = " << fast.witness_t;
    }
  }
  // Certified up to certified_until: no configuration before it is below
  // the margin (sampled at 17 points), and none beyond 1.
  EXPECT_GE(until, 0.0);
  EXPECT_LE(until, 1.0);
  if (kind(fast) == 0) {
    EXPECT_EQ(until, 1.0);
  } else if (until > 0.0) {
    ++tally.partly_certified;
    std::vector<double> q;
    StateResult r;
    for (int j = 0; j <= 16; ++j) {
      state_between(qa, qb, until * j / 16.0, q);
      checker.check_state(q, r, row_request());
      EXPECT_FALSE(r.collision) << "certified until " << until;
      EXPECT_GE(r.min_distance, margin) << "certified until " << until;
    }
  }
  ++tally.segments;
  tally.flagged += kind(fast) != 0;
  tally.collisions += fast.collision;
}

// The slewing bar past posts (bar_scene.h).
struct BarScene {
  TempDir dir{"continuous-reference"};
  Scene scene;
  std::unique_ptr<Checker> checker;
  std::unique_ptr<SegmentChecker> seg;
  explicit BarScene(const std::vector<std::pair<Vec3, Vec3>>& posts) {
    testing::write_bar_scene(dir, posts);
    scene = load_scene(dir / "scene.json");
    checker = std::make_unique<Checker>(scene, 1);
    seg = std::make_unique<SegmentChecker>(*checker, scene, ContinuousOptions{});
  }
  // Slew (deg), Boom (m), Grow.x, as the state vector Slew, Boom, Grow.x/y/z.
  static std::vector<double> state(double slew, double boom, double grow) { return {slew, boom, grow, 1, 1}; }
};

TEST(ContinuousReference, RandomBarSegmentsWholeTurnsAndTheLongWayRound) {
  BarScene s({{{-0.1, 1.2, 0}, {0.1, 1.4, 2}}, {{1.9, -0.3, 0.5}, {2.1, 0.3, 0.92}}, {{-2.6, -0.1, 0.98}, {-2.4, 0.1, 1.2}}});
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto pick = [&](double lo, double hi) { return lo + (hi - lo) * unit(rng); };
  Tally t;
  const int n = testing::kSanitized ? 30 : 200;
  for (int i = 0; i < n; ++i) {
    SCOPED_TRACE("random segment " + std::to_string(i));
    const double slew = pick(-1080, 1080);
    const double step = unit(rng) < 0.3 ? pick(-1080, 1080) : pick(-90, 90);
    compare(*s.checker, *s.seg, kMargin, BarScene::state(slew, pick(-0.6, 0.7), pick(0.5, 1.4)),
            BarScene::state(slew + step, pick(-0.6, 0.7), pick(0.5, 1.4)), t);
  }
  // Whole turns and the long way round past the post at azimuth 90.
  for (const auto& [from, to] : {std::pair{0.0, 720.0}, std::pair{720.0, 0.0}, std::pair{-30.0, 330.0},
                                 std::pair{120.0, 420.0}, std::pair{130.0, 410.0}, std::pair{1e4 + 60, 1e4 + 120}}) {
    SCOPED_TRACE("slew " + std::to_string(from) + " -> " + std::to_string(to));
    compare(*s.checker, *s.seg, kMargin, BarScene::state(from, -0.4, 1), BarScene::state(to, -0.4, 1), t);
  }
  EXPECT_GT(t.flagged, t.segments / 10);  // real work on both sides
  EXPECT_LT(t.flagged, t.segments);
  EXPECT_GT(t.collisions, 0);
  EXPECT_GT(t.partly_certified, 0);  // the certificate reaches into flagged segments
}

// Post face at y = face, the bar's far corners sweep radius rho: on a slew
// through 90 degrees the minimum is face - rho (corner to face).
TEST(ContinuousReference, GrazingAt1e9EitherSideOfTouchingAndOfTheMargin) {
  const double rho = std::hypot(2.0, static_cast<double>(0.05f));
  const double tol = ContinuousOptions{}.tolerance;
  struct Case {
    double gap;
    int kind;  // expected: 0 safe, 1 clearance, 2 collision; -1 either (within a tolerance band)
  };
  for (const Case c : {Case{-1e-9, 2}, Case{1e-9, -1}, Case{kMargin - 1e-9, -1}, Case{kMargin - 2e-5, 1},
                       Case{kMargin + 1e-9, -1}, Case{kMargin + 3 * tol, 0}, Case{0.5 * kMargin, 1}}) {
    SCOPED_TRACE("gap " + std::to_string(c.gap));
    const double face = static_cast<double>(static_cast<float>(rho + c.gap));
    BarScene s({{{-0.1, face, 0}, {0.1, face + 0.2, 2}}});
    Tally t;
    // (89 -> 91 passes the corners' closest points by: its minimum is the
    // end face's, 0.000625 m farther.)
    for (const auto& [from, to] : {std::pair{60.0, 120.0}, std::pair{0.0, 180.0}, std::pair{89.0, 91.0}}) {
      const auto qa = BarScene::state(from, 0, 1), qb = BarScene::state(to, 0, 1);
      compare(*s.checker, *s.seg, kMargin, qa, qb, t, c.kind < 0);
      if (c.kind >= 0 && from != 89.0) {
        StateResult sa, sb;
        EXPECT_EQ(kind(s.seg->check_motion(qa, qb, true, sa, sb)), c.kind);
      }
    }
  }
}

// check_motion keeps the end states its thread checked last and takes them
// for a later motion with an end of the same bits, the same checker and the
// same request (a planner's chained motions). A motion checked so equals
// the same motion checked cold (on a new thread, nothing kept): the segment,
// its certified_until and both end states, field by field. Chains forward,
// backward, with the mode alternating (a verdict-only end is a bound, a full
// one exact), and alternating between two checkers whose posts differ (a
// state kept for one is no answer for the other), with every motion also
// held against the reference (compare).
struct Checked {
  SegmentResult g;
  StateResult sa, sb;
  double until = -1.0;
};
Checked check_motion_on(const SegmentChecker& seg, const std::vector<double>& qa, const std::vector<double>& qb,
                        bool verdict_only) {
  Checked c;
  c.g = seg.check_motion(qa, qb, verdict_only, c.sa, c.sb, &c.until);
  return c;
}
void expect_same_state(const StateResult& x, const StateResult& y, const char* which) {
  SCOPED_TRACE(which);
  EXPECT_EQ(x.collision, y.collision);
  EXPECT_EQ(x.contacts.size(), y.contacts.size());
  EXPECT_EQ(x.min_distance, y.min_distance);
  EXPECT_EQ(x.distance_is_bound, y.distance_is_bound);
  EXPECT_EQ(x.distance_tolerance, y.distance_tolerance);
  EXPECT_EQ(x.part_a, y.part_a);
  EXPECT_EQ(x.part_b, y.part_b);
  EXPECT_EQ(x.point_a, y.point_a);
  EXPECT_EQ(x.point_b, y.point_b);
}
// Every field of two motion checks, the bound bit for bit (NaN included).
void expect_same_checked(const Checked& x, const Checked& y) {
  EXPECT_EQ(kind(x.g), kind(y.g));
  EXPECT_EQ(std::memcmp(&x.g.lower_bound, &y.g.lower_bound, sizeof(double)), 0)
      << x.g.lower_bound << " " << y.g.lower_bound;
  EXPECT_EQ(x.g.min_sampled, y.g.min_sampled);
  EXPECT_EQ(x.g.witness_t, y.g.witness_t);
  EXPECT_EQ(x.g.part_a, y.g.part_a);
  EXPECT_EQ(x.g.part_b, y.g.part_b);
  EXPECT_EQ(x.g.steps, y.g.steps);
  EXPECT_EQ(x.g.unresolved, y.g.unresolved);
  EXPECT_EQ(x.until, y.until);
  expect_same_state(x.sa, y.sa, "from");
  expect_same_state(x.sb, y.sb, "to");
}
void expect_same_as_cold(const SegmentChecker& seg, const std::vector<double>& qa, const std::vector<double>& qb,
                         bool verdict_only) {
  const Checked warm = check_motion_on(seg, qa, qb, verdict_only);
  Checked cold;
  std::thread([&] { cold = check_motion_on(seg, qa, qb, verdict_only); }).join();
  expect_same_checked(warm, cold);
}

TEST(ContinuousReference, MotionsSharingEndsEqualColdOnes) {
  const std::vector<std::pair<Vec3, Vec3>> posts{{{-0.1, 1.2, 0}, {0.1, 1.4, 2}}, {{1.9, -0.3, 0.5}, {2.1, 0.3, 0.92}}};
  BarScene s(posts), moved({{{-0.1, 1.12, 0}, {0.1, 1.32, 2}}, {{1.95, -0.3, 0.5}, {2.15, 0.3, 0.93}}});
  std::mt19937_64 rng(43);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<std::vector<double>> walk{BarScene::state(0, 0, 1)};
  const int n = testing::kSanitized ? 12 : 40;
  for (int i = 0; i < n; ++i) {
    const auto& q = walk.back();
    // Every fourth step holds the slew: states equal in their first value.
    walk.push_back(BarScene::state(q[0] + (i % 4 == 3 ? 0.0 : 60 * (2 * unit(rng) - 1)), std::clamp(q[1] + 0.2 * (2 * unit(rng) - 1), -0.6, 0.7),
                                   std::clamp(q[2] + 0.2 * (2 * unit(rng) - 1), 0.5, 1.4)));
  }
  walk.push_back(walk.back());  // a motion that stays put: both ends one state
  Tally t;
  int bounds = 0;  // verdict-only ends that are bounds (what a full end must not take)
  for (int order = 0; order < 4; ++order) {
    for (std::size_t i = 0; i + 1 < walk.size(); ++i) {
      SCOPED_TRACE("order " + std::to_string(order) + ", motion " + std::to_string(i));
      const auto& qa = order == 1 ? walk[walk.size() - 1 - i] : walk[i];
      const auto& qb = order == 1 ? walk[walk.size() - 2 - i] : walk[i + 1];
      const bool verdict_only = order == 2 ? i % 2 == 0 : order != 3 || i % 4 < 2;
      const SegmentChecker& seg = order == 3 && i % 2 == 1 ? *moved.seg : *s.seg;
      expect_same_as_cold(seg, qa, qb, verdict_only);
      StateResult sa, sb;
      seg.check_motion(qa, qb, true, sa, sb);
      bounds += sa.distance_is_bound;
      compare(order == 3 && i % 2 == 1 ? *moved.checker : *s.checker, seg, kMargin, qa, qb, t);
    }
  }
  EXPECT_GT(bounds, 0);
  EXPECT_GT(t.flagged, 0);
  EXPECT_LT(t.flagged, t.segments);
}

void random_arm_segments(bool urdf, int count, double max_step) {
  TempDir dir("continuous-reference");
  const Scene scene = load_scene(arm_scene(dir, urdf));
  const Checker checker(scene, 1);
  const SegmentChecker seg(checker, scene, ContinuousOptions{});
  ArmSegments random(scene, urdf ? 7 : 3);
  Tally t;
  for (int i = 0; i < count; ++i) {
    SCOPED_TRACE((urdf ? "URDF arm segment " : "default arm segment ") + std::to_string(i));
    std::vector<double> qa, qb;
    random.next(max_step, qa, qb);
    compare(checker, seg, scene.safety_margin, qa, qb, t);
  }
  std::printf("[ %s ] %d segments, %d flagged, %d collisions\n", urdf ? "URDF arm" : "default arm", t.segments,
              t.flagged, t.collisions);
  EXPECT_GT(t.flagged, 0);
  EXPECT_LT(t.flagged, t.segments);
}

TEST(ContinuousReference, RandomMotionsOfTheDefaultArm) {
  random_arm_segments(false, testing::kSanitized ? 4 : 30, 0.15);
}

TEST(ContinuousReference, RandomMotionsOfTheUrdfArmAlongOneChain) {
  random_arm_segments(true, testing::kSanitized ? 20 : 80, 0.2);  // 20: the first that hold a safe segment (18 flagged)
}

// check_motion with its pairs marching on 2 and 4 threads: the same answer,
// bit for bit, as on one, on random motions of both arms (some unsafe: the
// parallel pass then gives way to the serial one), in all four modes, and
// with a budget small enough that some motions run out of it.
void threads_equal_one(bool urdf, int count, std::size_t max_steps) {
  TempDir dir("continuous-threads");
  const Scene scene = load_scene(arm_scene(dir, urdf));
  const Checker checker(scene, 1);
  ContinuousOptions o;
  o.max_steps = max_steps;
  o.parallel_pairs = 2;  // on threads wherever two pairs need samples
  const SegmentChecker seg(checker, scene, o);
  ArmSegments random(scene, urdf ? 29 : 31);
  int kinds[3] = {0, 0, 0}, unresolved = 0;
  for (int i = 0; i < count; ++i) {
    std::vector<double> qa, qb;
    random.next(urdf ? 0.2 : 0.15, qa, qb);
    for (int mode = 0; mode < 4; ++mode) {
      const bool verdict_only = mode != 0, first = mode == 3;
      SCOPED_TRACE((urdf ? "URDF arm motion " : "default arm motion ") + std::to_string(i) + ", mode " +
                   std::to_string(mode) + ", budget " + std::to_string(max_steps));
      // Each on a thread of its own: no end state kept from another call.
      auto on_thread = [&](int threads) {
        Checked c;
        std::thread([&] { c.g = seg.check_motion(qa, qb, verdict_only, c.sa, c.sb, &c.until, first, threads); }).join();
        return c;
      };
      const Checked one = on_thread(1);
      if (mode == 0) ++kinds[kind(one.g)], unresolved += one.g.unresolved;
      for (int threads : {2, 4}) expect_same_checked(on_thread(threads), one);
    }
  }
  std::printf("[ %s ] %d motions: %d safe, %d clearance, %d collision, %d unresolved (budget %zu)\n",
              urdf ? "URDF arm" : "default arm", count, kinds[0], kinds[1], kinds[2], unresolved, max_steps);
  EXPECT_GT(kinds[0], 0);
  EXPECT_GT(kinds[1] + kinds[2], 0);
}

TEST(ContinuousReference, MotionsOnThreadsEqualOneThread) {
  threads_equal_one(false, testing::kSanitized ? 6 : 40, ContinuousOptions{}.max_steps);
  threads_equal_one(true, testing::kSanitized ? 10 : 60, ContinuousOptions{}.max_steps);
  threads_equal_one(false, testing::kSanitized ? 6 : 30, 40);  // some run out of the budget
}

// Arm motions that dip 1e-9 m below the margin between clear ends. For
// random segments whose least distance lies inside (both ends at least 5 mm
// farther), located by 65 exact samples and a golden-section search around
// the least, the margin is set 1e-9 m above the least distance found: a
// configuration on the segment is then below it, so every algorithm, full
// and verdict-only, must flag a clearance violation (compare() checks its
// witness exactly). A motion bound too small on any pair (the pair bound
// scaled by 0.3) certifies some of these dips as safe.
void grazing_arm_segments(bool urdf, int want) {
  TempDir dir("continuous-reference");
  const Scene scene = load_scene(arm_scene(dir, urdf));
  const Checker checker(scene, 1);
  ArmSegments random(scene, urdf ? 17 : 13);
  std::vector<double> qa, qb, q;
  StateResult r;
  Tally t;
  int found = 0, tries = 0;
  while (found < want && tries < 300) {
    ++tries;
    random.next(0.5, qa, qb);
    auto dist = [&](double u) {
      state_between(qa, qb, u, q);
      checker.check_state(q, r, row_request());
      return r.collision ? 0.0 : r.min_distance;
    };
    constexpr int kSamples = 64;
    std::vector<double> d(kSamples + 1);
    d.front() = dist(0.0);
    d.back() = dist(1.0);
    if (!(d.front() > 0.0 && d.back() > 0.0)) continue;  // an end in contact: no dip between clear ends
    for (int i = 1; i < kSamples; ++i) d[static_cast<std::size_t>(i)] = dist(static_cast<double>(i) / kSamples);
    const auto least = static_cast<int>(std::min_element(d.begin(), d.end()) - d.begin());
    const double dmin = d[static_cast<std::size_t>(least)];
    if (least == 0 || least == kSamples || !(dmin > 0.0) || d.front() < dmin + 0.005 || d.back() < dmin + 0.005) continue;
    // Golden section between the least sample's neighbours; the least
    // distance seen stays a distance some configuration has.
    double a = static_cast<double>(least - 1) / kSamples, b = static_cast<double>(least + 1) / kSamples;
    double best = dmin;
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    double x1 = b - g * (b - a), x2 = a + g * (b - a), f1 = dist(x1), f2 = dist(x2);
    for (int i = 0; i < 40; ++i) {
      best = std::min({best, f1, f2});
      if (f1 < f2) {
        b = x2, x2 = x1, f2 = f1, x1 = b - g * (b - a), f1 = dist(x1);
      } else {
        a = x1, x1 = x2, f1 = f2, x2 = a + g * (b - a), f2 = dist(x2);
      }
    }
    best = std::min({best, f1, f2});
    Scene grazed = scene;
    grazed.safety_margin = best + 1e-9;
    const SegmentChecker seg(checker, grazed, ContinuousOptions{});
    SCOPED_TRACE((urdf ? "URDF arm, grazing segment " : "default arm, grazing segment ") + std::to_string(found) +
                 ", margin " + std::to_string(grazed.safety_margin));
    Tally one;
    compare(checker, seg, grazed.safety_margin, qa, qb, one);
    EXPECT_EQ(one.flagged, 1) << "a configuration lies 1e-9 m below the margin";
    StateResult sa, sb;
    EXPECT_EQ(kind(seg.check_motion(qa, qb, true, sa, sb)), 1);
    EXPECT_EQ(kind(seg.check_motion_reference(qa, qb, true, sa, sb)), 1);
    ++found;
  }
  std::printf("[ %s ] %d grazing segments of %d tried\n", urdf ? "URDF arm" : "default arm", found, tries);
  EXPECT_EQ(found, want);
}

TEST(ContinuousReference, DefaultArmMotionsGrazingTheMarginAt1e9) {
  grazing_arm_segments(false, testing::kSanitized ? 2 : 4);
}

TEST(ContinuousReference, UrdfArmMotionsGrazingTheMarginAt1e9) {
  grazing_arm_segments(true, testing::kSanitized ? 2 : 8);
}

}  // namespace
}  // namespace plancheck
