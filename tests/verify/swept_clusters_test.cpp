// SPDX-License-Identifier: MIT
// SweptClusters (src/checks/swept_clusters.h) against the distances along
// the motion themselves: on random segments of the default arm and of the
// URDF example's arm, every pair of a moving part and a static mesh is
// asked for the most it can prove (the largest target it answers, found by
// bisection), and that bound is checked at 401 configurations along the
// motion by an exact pair search below it: it must never lie above the
// pair's distance. A 1 cm cube passing under a post between clear ends
// must be seen below the margin. MotionBound::sphere_levers and
// levers_bound give sphere_bound's value. And MotionBound::sphere_bound, the clusters' speed,
// against the paths of the mesh vertices its spheres hold.
#include "src/checks/swept_clusters.h"

#include "src/checks/continuous.h"
#include "src/scene/kinematics.h"
#include "src/scene/plan.h"
#include "src/scene/scene_loader.h"
#include "tests/support/sanitized.h"
#include "tests/verify/arm_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <vector>

namespace plancheck {
namespace {

using testing::arm_scene;
using testing::ArmSegments;
using testing::TempDir;

// The pairs of a moving part and a static mesh (the pairs the shortcut is
// for): (pair index, moving part, static part).
struct MovingStatic {
  std::size_t k;
  int moving, still;
};
std::vector<MovingStatic> moving_static(const Scene& scene, const Checker& checker) {
  std::vector<MovingStatic> out;
  const auto& pairs = checker.pairs();
  auto is_still = [&](int x) {
    return x >= 0 && static_cast<std::size_t>(x) < scene.parts.size() && !scene.parts[static_cast<std::size_t>(x)].moving();
  };
  auto is_moving = [&](int x) {
    return x >= 0 && static_cast<std::size_t>(x) < scene.parts.size() && scene.parts[static_cast<std::size_t>(x)].moving();
  };
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const auto [a, b] = pairs[k];
    if (is_moving(a) && is_still(b)) out.push_back({k, a, b});
    if (is_moving(b) && is_still(a)) out.push_back({k, b, a});
  }
  return out;
}

void never_above_the_distances(bool urdf, int segments) {
  TempDir dir("swept-clusters");
  const Scene scene = load_scene(arm_scene(dir, urdf));
  const Checker checker(scene, 1);
  const std::vector<MovingStatic> pairs = moving_static(scene, checker);
  ASSERT_FALSE(pairs.empty());
  ArmSegments random(scene, urdf ? 41 : 43);
  // loose: as the verdict-only motion check starts it (one box around all
  // the balls tried first): the same pieces pass, its bounds no higher.
  SweptClusters swept, loose;
  int box_looser = 0;
  constexpr int kSamples = 400;
  constexpr double kNone = -std::numeric_limits<double>::infinity();
  std::vector<double> qa, qb, q;
  std::vector<double> claim(pairs.size());
  PosedParts posed;
  PairAnswer answer;
  int proven = 0, at_5cm = 0, checked = 0;
  for (int i = 0; i < segments; ++i) {
    // Short and long motions: a fifth of each range, or up to all of it.
    random.next(i % 2 == 0 ? 0.2 : 1.0, qa, qb);
    checker.pose_parts(qa, posed);
    swept.start(checker, qa, qb);
    loose.start(checker, qa, qb, false);
    for (std::size_t p = 0; p < pairs.size(); ++p) {
      const auto& box = posed.box[static_cast<std::size_t>(pairs[p].still)];
      auto clear = [&](double target) {
        const double tight = swept.clear(pairs[p].moving, box.first, box.second, target);
        const double other = loose.clear(pairs[p].moving, box.first, box.second, target);
        EXPECT_EQ(other == kNone, tight == kNone) << "target " << target;
        if (tight != kNone) {
          EXPECT_LE(other, tight);
          EXPECT_GE(other, target);
          box_looser += other < tight;
        }
        return tight;
      };
      // The most it proves: the largest target it answers, by bisection
      // (from 0 to 4 m); every bound at or above what it was asked.
      claim[p] = kNone;
      double lo = 0.0, hi = 4.0;
      for (int step = 0; step < 24; ++step) {
        const double target = step == 0 ? 0.0 : 0.5 * (lo + hi);
        const double bound = clear(target);
        if (bound == kNone) {
          if (step == 0) break;
          hi = target;
          continue;
        }
        EXPECT_GE(bound, target);
        claim[p] = std::max(claim[p], bound);
        lo = target;
      }
      if (claim[p] != kNone) ++proven;
      if (clear(0.05) != kNone) ++at_5cm;
    }
    // Every claim at or below the pair's distance all along the motion.
    for (int j = 0; j <= kSamples; ++j) {
      state_between(qa, qb, static_cast<double>(j) / kSamples, q);
      checker.pose_parts(q, posed);
      for (std::size_t p = 0; p < pairs.size(); ++p) {
        if (claim[p] == kNone) continue;
        answer = PairAnswer{};
        checker.pair_distance(posed, pairs[p].k, claim[p], answer);  // exact below the claim
        ++checked;
        EXPECT_FALSE(answer.exact && answer.distance < claim[p])
            << (urdf ? "URDF arm" : "default arm") << " segment " << i << " at t = " << j << "/" << kSamples << ", "
            << checker.part_name(pairs[p].moving) << " / " << checker.part_name(pairs[p].still) << ": "
            << answer.distance << " below the proven " << claim[p];
      }
    }
  }
  std::printf("[ %s ] %d segments, %zu pairs each: %d proven (%d at 5 cm), %d samples checked\n",
              urdf ? "URDF arm" : "default arm", segments, pairs.size(), proven, at_5cm, checked);
  EXPECT_GT(proven, segments);
  EXPECT_GT(at_5cm, 0);
  EXPECT_GT(box_looser, 0);  // the box test was taken
}

TEST(SweptClusters, NeverAboveTheDistancesAlongDefaultArmMotions) { never_above_the_distances(false, 40); }

TEST(SweptClusters, NeverAboveTheDistancesAlongUrdfArmMotions) { never_above_the_distances(true, 30); }

// The motion check with the shortcut in it: a 1 cm cube 1 m out on a slew
// passes under a narrow static post at a clearance c in the middle of a
// 10-degree turn, its ends clear of the margin (6 cm and more away). The cube's
// clusters are small and slow, so the shortcut proves a lot about this
// pair (about c less 1.5 cm); it must never prove the margin when c lies
// below it. An overclaim of half the margin fails here.
TEST(SweptClusters, MotionCheckSeesAPassBelowTheMargin) {
  for (const double c : {0.005, 0.02, 0.04, 0.048, 0.052, 0.07, 0.2}) {
    TempDir dir("swept-pass");
    testing::write_obj(dir.path() / "model.obj",
                       {{"Tip", testing::box_mesh({0.995, -0.005, 0.995}, {1.005, 0.005, 1.005})},
                        {"Post", testing::box_mesh({0.9, -0.02, 1.005 + c}, {1.1, 0.02, 1.3})}});
    testing::write_text(dir.path() / "scene.json", R"({
  "format": "plancheck-scene/1", "model": "model.obj", "length_unit": "m", "angle_unit": "deg",
  "actions": [{"name": "Slew", "node": "Tip", "type": "rotate", "pivot": [0, 0, 0], "axis": [0, 0, 1]}],
  "safety_margin": 0.05
})");
    const Scene scene = load_scene(dir.path() / "scene.json");
    const Checker checker(scene, 1);
    const SegmentChecker seg(checker, scene, ContinuousOptions{});
    for (const auto& [a, b] : {std::pair{-5.0, 5.0}, std::pair{5.0, -5.0}, std::pair{-7.0, 6.0}}) {
      SCOPED_TRACE("clearance " + std::to_string(c) + ", slew " + std::to_string(a) + " -> " + std::to_string(b));
      const std::vector<double> qa{a}, qb{b};
      StateResult sa, sb;
      checker.check_state(qa, sa, row_request());
      checker.check_state(qb, sb, row_request());
      ASSERT_GT(sa.min_distance, 0.055);
      ASSERT_GT(sb.min_distance, 0.055);
      const SegmentResult full = seg.check(qa, qb, sa, sb);
      StateResult va, vb;
      const SegmentResult vo = seg.check_motion(qa, qb, true, va, vb, nullptr, true);
      for (const SegmentResult* r : {&full, &vo}) {
        EXPECT_FALSE(r->unresolved);
        EXPECT_FALSE(r->collision);
        EXPECT_EQ(r->clearance, c < 0.05);
        if (!r->clearance) {
          EXPECT_GE(r->lower_bound, 0.05);
          EXPECT_LE(r->lower_bound, c + 1e-9);
        }
      }
    }
  }
}

// Every mesh vertex of a moving part travels no farther along a motion than
// sphere_bound of any cluster sphere holding it (dense samples of its path).
TEST(SweptClusters, SphereBoundHoldsTheVerticesPaths) {
  for (const bool urdf : {false, true}) {
    TempDir dir("swept-sphere");
    const Scene scene = load_scene(arm_scene(dir, urdf));
    const Checker checker(scene, 1);
    const BoxMotion& box = checker.box_motion();
    ASSERT_EQ(box.points(), BoxMotion::Points::kTriangles);
    ArmSegments random(scene, urdf ? 5 : 7);
    std::vector<BoxMotion::Sphere> spheres;
    std::vector<double> qa, qb, q;
    int checked = 0, by_levers = 0;
    const int motions = testing::case_count(20, 6);  // short and long ones in turn
    for (int i = 0; i < motions; ++i) {
      random.next(i % 2 == 0 ? 0.2 : 1.0, qa, qb);
      for (std::size_t part = 0; part < scene.parts.size(); ++part) {
        if (!scene.parts[part].moving()) continue;
        box.spheres(static_cast<int>(part), spheres);
        ASSERT_FALSE(spheres.empty());
        std::vector<double> speed, levers;
        for (const auto& s : spheres) {
          const MotionBound& bound = checker.motion_bound();
          speed.push_back(bound.sphere_bound(static_cast<int>(part), s.centre, s.radius, qa, qb));
          // A chain of rotations (the default arm's; the URDF arm's boom
          // slides): the levers give the same bound, bit for bit.
          bool rotations = true;
          for (const int a : scene.parts[part].chain)
            rotations = rotations && scene.actions[static_cast<std::size_t>(a)].type == ActionType::kRotate;
          ASSERT_EQ(bound.sphere_levers(static_cast<int>(part), s.centre, s.radius, levers), rotations);
          if (rotations) {
            EXPECT_EQ(bound.levers_bound(static_cast<int>(part), levers, qa, qb), speed.back());
            ++by_levers;
          }
        }
        const Mesh& mesh = scene.parts[part].mesh;
        // Every 7th vertex, its path over 200 steps.
        for (std::size_t v = 0; v < mesh.vertices.size(); v += 7) {
          double path = 0.0;
          Vec3 last = Vec3::Zero();
          for (int j = 0; j <= 200; ++j) {
            state_between(qa, qb, j / 200.0, q);
            const Vec3 x = part_transform(scene, static_cast<int>(part), q) * mesh.vertices[v];
            if (j > 0) path += (x - last).norm();
            last = x;
          }
          bool held = false;
          for (std::size_t c = 0; c < spheres.size(); ++c) {
            if ((mesh.vertices[v] - spheres[c].centre).norm() > spheres[c].radius) continue;
            held = true;
            EXPECT_LE(path, speed[c]) << scene.parts[part].name << " vertex " << v;
            ++checked;
          }
          EXPECT_TRUE(held) << scene.parts[part].name << " vertex " << v << " in no cluster sphere";
        }
      }
    }
    EXPECT_GT(checked, 200 * motions);
    if (!urdf) {
      EXPECT_GT(by_levers, 20 * motions);
    }
    std::printf("%s: %d motions, %d vertex paths in their spheres, %d spheres by levers\n", urdf ? "urdf" : "default",
                motions, checked, by_levers);
  }
}

}  // namespace
}  // namespace plancheck
