// SPDX-License-Identifier: MIT
// verify --continuous against dense exact sampling on thousands of random
// segments read from plan CSVs as written: steps of up to three turns either
// way, starts anywhere (past +-180 and several turns out), two rotations,
// translations and a scale moving at once, in m/deg and in mm/rad. The
// sampling step is fine enough, by the motion bound, that sampling cannot
// miss a contact: the certified check must never call "safe" a segment where
// a sample touches or comes closer than the margin. Controls whose written
// motion goes the long way round and misses the obstacle (where the short
// way would hit) must not be flagged: no shortest-path "fix".
#include "src/checks/continuous.h"
#include "src/scene/plan.h"
#include "src/scene/scene_loader.h"
#include "src/checks/verify.h"
#include "support/fixtures.h"
#include "tests/verify/dense_sampling.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <sstream>

namespace plancheck {
namespace {

using testing::Dense;
using testing::TempDir;

constexpr double kPi = 3.14159265358979323846;
constexpr double kMargin = 0.05;  // m
// Dense sampling step: the motion bound between neighbouring samples stays
// below the margin, so samples all at least the margin away prove the true
// minimum above margin / 2 > 0: no contact lies between them.
constexpr double kSampleStep = 0.04;  // m

struct Units {
  const char* length;  // length_unit
  const char* angle;   // angle_unit
  double per_metre;    // length units per metre
  double per_degree;   // angle units per degree
};
constexpr Units kMetreDegree{"m", "deg", 1.0, 1.0};
constexpr Units kMillimetreRadian{"mm", "rad", 1000.0, kPi / 180};

// Parameters of one state, in degrees and metres (written out in the
// scene's units): Slew (deg), Boom (m), Grow.x, Spin (deg), Lift (m).
using Row = std::array<double, 5>;

// Bar [0.2, 2] x [-0.05, 0.05] x [0.95, 1.05] on Slew (rotate about +z
// through the origin), Boom (translate along +x), Grow (scale about
// (0, 0, 1)); Blade [-2.1, -0.9] x [1.45, 1.55] x [0.98, 1.02] on Lift
// (translate along +z) and Spin (rotate about +z through (-1.5, 1.5, 0));
// static posts. Every pair of parts is checked.
void write_scene(const TempDir& dir, const Units& u, const std::vector<std::pair<Vec3, Vec3>>& posts) {
  const double k = u.per_metre;
  std::vector<std::pair<std::string, Mesh>> parts{
      {"Bar", testing::box_mesh(Vec3(0.2, -0.05, 0.95) * k, Vec3(2, 0.05, 1.05) * k)},
      {"Blade", testing::box_mesh(Vec3(-2.1, 1.45, 0.98) * k, Vec3(-0.9, 1.55, 1.02) * k)}};
  for (std::size_t i = 0; i < posts.size(); ++i)
    parts.emplace_back("Post" + std::to_string(i), testing::box_mesh(posts[i].first * k, posts[i].second * k));
  testing::write_obj(dir / "model.obj", parts);
  std::ostringstream s;
  s.precision(17);
  s << R"({"format": "plancheck-scene/1", "model": "model.obj", "length_unit": ")" << u.length
    << R"(", "angle_unit": ")" << u.angle << R"(", "actions": [
    {"name": "Slew", "node": "Bar", "type": "rotate", "pivot": [0, 0, 0], "axis": [0, 0, 1]},
    {"name": "Boom", "node": "Bar", "type": "translate", "axis": [1, 0, 0]},
    {"name": "Grow", "node": "Bar", "type": "scale", "fixed_point": [0, 0, )"
    << k << R"(]},
    {"name": "Lift", "node": "Blade", "type": "translate", "axis": [0, 0, 1]},
    {"name": "Spin", "node": "Blade", "type": "rotate", "pivot": [)"
    << -1.5 * k << ", " << 1.5 * k << R"(, 0], "axis": [0, 0, 1]}],
  "safety_margin": )" << kMargin * k
    << "}";
  testing::write_text(dir / "scene.json", s.str());
}

// A plan CSV in the scene's units, every value printed exactly.
std::string plan_text(const Units& u, const std::vector<Row>& rows) {
  std::ostringstream s;
  s.precision(17);
  s << "Slew,Boom,Grow.x,Spin,Lift\n";
  for (const Row& r : rows)
    s << r[0] * u.per_degree << "," << r[1] * u.per_metre << "," << r[2] << "," << r[3] * u.per_degree << ","
      << r[4] * u.per_metre << "\n";
  return s.str();
}

// The state a row writes, built here rather than read back, so the
// reference follows the contract and not the parser: each value as written
// in the scene's units, in parameter order Slew, Boom, Grow.x/y/z, Lift, Spin.
std::vector<double> written_state(const Units& u, const Row& r) {
  return {r[0] * u.per_degree, r[1] * u.per_metre, r[2], 1, 1, r[4] * u.per_metre, r[3] * u.per_degree};
}

struct Tally {
  long segments = 0, samples = 0;
  long sampled_contact = 0, sampled_below_margin = 0, flagged = 0, proven_clear = 0;
};

// Verifies the plans with --continuous's code path and holds every segment
// against dense sampling.
void check_against_dense(const TempDir& dir, const Units& u, const std::vector<std::vector<Row>>& plans,
                         Tally& tally, bool controls = false) {
  const Scene scene = load_scene(dir / "scene.json");
  ASSERT_EQ(scene.parameter_names, (std::vector<std::string>{"Slew", "Boom", "Grow.x", "Grow.y", "Grow.z", "Lift", "Spin"}));
  std::vector<Plan> loaded;
  for (std::size_t i = 0; i < plans.size(); ++i) {
    const auto file = dir / ("p" + std::to_string(i) + ".csv");
    testing::write_text(file, plan_text(u, plans[i]));
    loaded.push_back(load_plan(scene, file));
  }
  const Checker checker(scene, 2);
  std::vector<PlanResult> results = verify_plans(checker, scene, loaded, VerifyOptions{2, false, false});
  ContinuousOptions options;
  options.threads = 2;
  verify_segments(checker, scene, loaded, results, options);
  const SegmentChecker seg(checker, scene, options);
  const double margin = scene.safety_margin;
  for (std::size_t p = 0; p < loaded.size(); ++p)
    for (std::size_t s = 0; s + 1 < loaded[p].states.size(); ++s) {
      const std::vector<double> qa = written_state(u, plans[p][s]);
      const std::vector<double> qb = written_state(u, plans[p][s + 1]);
      ASSERT_EQ(loaded[p].states[s], qa);  // the parser keeps what was written
      const SegmentResult& g = results[p].segments[s];
      const long n = std::max(1L, static_cast<long>(std::ceil(seg.pair_bound(qa, qb) / kSampleStep)));
      const Dense d = testing::dense(checker, seg, qa, qb, n);
      const bool flagged = g.collision || g.clearance;
      ++tally.segments;
      tally.samples += n + 1;
      tally.sampled_contact += d.collision;
      tally.sampled_below_margin += d.min_sampled < margin;
      tally.flagged += flagged;
      tally.proven_clear += d.lower >= margin + options.tolerance;
      const auto where = [&] {
        std::ostringstream w;
        w.precision(17);
        w << "plan " << p << " segment " << s << ": Slew " << qa[0] << " -> " << qb[0] << ", Spin " << qa[6]
          << " -> " << qb[6] << " (" << n << " samples)";
        return w.str();
      };
      ASSERT_TRUE(g.checked) << where();
      ASSERT_LT(d.max_step_bound, margin) << where();  // the reference itself is dense enough
      if (d.collision) {
        EXPECT_TRUE(g.collision) << where();
      }
      if (d.min_sampled < margin) {
        EXPECT_TRUE(flagged) << where() << ": sampled " << d.min_sampled;
      }
      if (d.lower >= margin + options.tolerance) {
        EXPECT_FALSE(flagged) << where() << ": proven " << d.lower;
      }
      if (!d.collision && d.lower > options.contact_tolerance) {
        EXPECT_FALSE(g.collision) << where();
      }
      EXPECT_LE(g.lower_bound, d.min_sampled) << where();
      if (controls) {
        EXPECT_GE(d.lower, margin + options.tolerance) << where() << ": not a control";
      }
    }
}

// Random walks: each step moves a random subset of the actions, rotations by
// up to three turns either way, from starts anywhere (often just either side
// of +-180 degrees, often several turns out).
std::vector<std::vector<Row>> random_plans(std::uint64_t seed, int plans, int states) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto pick = [&](double lo, double hi) { return lo + (hi - lo) * unit(rng); };
  auto angle_start = [&] {
    const double r = unit(rng);
    if (r < 0.3) return (unit(rng) < 0.5 ? 180.0 : -180.0) + pick(-15, 15);  // either side of +-180
    if (r < 0.5) return pick(-1080, 1080);                                   // turns out
    return pick(-180, 180);
  };
  auto angle_step = [&] {
    const double r = unit(rng);
    if (r < 0.4) return pick(-1080, 1080);  // up to three turns
    if (r < 0.7) return pick(-400, 400);
    return pick(-40, 40);  // small, often across +-180 from the starts above
  };
  std::vector<std::vector<Row>> out(static_cast<std::size_t>(plans));
  for (auto& plan : out) {
    Row q{angle_start(), pick(-0.6, 0.6), pick(0.6, 1.3), angle_start(), pick(-0.3, 0.3)};
    plan.push_back(q);
    for (int s = 1; s < states; ++s) {
      if (unit(rng) < 0.15) q[0] = angle_start(), q[3] = angle_start();  // a jump: the next start anywhere
      if (unit(rng) < 0.7) q[0] += angle_step();
      if (unit(rng) < 0.5) q[1] = pick(-0.6, 0.6);
      if (unit(rng) < 0.4) q[2] = pick(0.6, 1.3);
      if (unit(rng) < 0.6) q[3] += angle_step();
      if (unit(rng) < 0.4) q[4] = pick(-0.3, 0.3);
      plan.push_back(q);
    }
  }
  return out;
}

const std::vector<std::pair<Vec3, Vec3>> kPosts{
    {{-0.1, 1.2, 0}, {0.1, 1.4, 2}},        // azimuth 90 at radius 1.3: the bar sweeps through it
    {{1.6, -1.8, 0.5}, {1.8, -1.6, 1.5}},   // azimuth -45 at radius 2.4: only when boomed out or grown
    {{-2.6, -0.3, 0}, {-2.4, -0.1, 0.9}}};  // below the bar's path at azimuth ~185: near misses

#ifdef PLANCHECK_SANITIZED
constexpr int kPlans = 10;  // the same code paths at sanitizer speed; Release checks 1,000 segments
#else
constexpr int kPlans = 50;
#endif

void random_segments(const Units& u, std::uint64_t seed) {
  TempDir dir("continuous-property");
  write_scene(dir, u, kPosts);
  Tally t;
  check_against_dense(dir, u, random_plans(seed, kPlans, 21), t);
  std::printf("[ %s/%s ] %ld segments, %ld dense samples: %ld sampled a contact, %ld below the margin, "
              "%ld flagged, %ld proven clear\n",
              u.length, u.angle, t.segments, t.samples, t.sampled_contact, t.sampled_below_margin, t.flagged,
              t.proven_clear);
  EXPECT_EQ(t.segments, kPlans * 20);
  // Real work on both sides: many contacts found between states, many segments proven clear.
  EXPECT_GT(t.sampled_contact, kPlans * 2);
  EXPECT_GT(t.proven_clear, kPlans * 2);
}

TEST(ContinuousProperty, RandomSegmentsInMetresAndDegreesAgreeWithDenseSampling) {
  random_segments(kMetreDegree, 13);
}

TEST(ContinuousProperty, RandomSegmentsInMillimetresAndRadiansAgreeWithDenseSampling) {
  random_segments(kMillimetreRadian, 29);
}

// The post at azimuth 90: each control starts u degrees past it (plus whole
// turns) and turns the long way (more than 180 degrees) to stop before it
// again; the short way to the same end pose would pass through it.
TEST(ContinuousProperty, TheLongWayRoundThatMissesIsNotFlagged) {
  for (const Units& u : {kMetreDegree, kMillimetreRadian}) {
    TempDir dir("continuous-property");
    write_scene(dir, u, {kPosts[0]});
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<std::vector<Row>> plans;
    for (int c = 0; c < 90; ++c) {
      const double gap = 25.0;                          // degrees kept clear of the post either side
      const double past = gap + (125 - gap) * unit(rng);  // start, degrees past the post
      // More than half a turn, and at least `gap` short of the post again.
      const double turn = 181 + (360 - 2 * gap - past - 181) * unit(rng);
      const double whole = 360.0 * std::floor(unit(rng) * 5 - 2);  // -2 .. 2 turns out
      const bool ccw = c % 2 == 0;  // turn away from the post: the long way round
      const double start = ccw ? 90 + past + whole : 90 - past + whole;
      const double end = ccw ? start + turn : start - turn;
      // The Blade is lifted out of the way; the bar at reach 2 m.
      plans.push_back({Row{start, 0, 1, 0, 0.5}, Row{end, 0, 1, 0, 0.5}});
    }
    Tally t;
    check_against_dense(dir, u, plans, t, /*controls=*/true);
    EXPECT_EQ(t.segments, 90);
    EXPECT_EQ(t.flagged, 0);
    EXPECT_EQ(t.sampled_below_margin, 0);
  }
}

}  // namespace
}  // namespace plancheck
