// SPDX-License-Identifier: MIT
// Scene-level stability (issue 6, part 2): rotation axes given unnormalised,
// nearly zero or huge; rotations by whole turns and by huge angles; a scene
// translated by the lunar radius. The scenes are small boxes whose
// coordinates are exact in float (assimp) and in double.
//
// Contract decisions checked here (documented in scene_loader.cpp/plan.cpp):
//  - any finite non-zero axis is a direction, however small or large its
//    components (1e-300 and 1e300 included); only an all-zero axis is
//    refused, naming the action's field (exit 2 on the command line);
//  - angles in degrees lose their whole turns exactly (remainder by 360)
//    before the conversion to radians whenever the limit check cannot tell:
//    k * 360 deg poses exactly like 0 deg, 1e300 deg like its remainder;
//    angles in radians are used as given (whole turns are not exact there).
#include "src/base/error.h"
#include "src/scene/kinematics.h"
#include "src/scene/plan.h"
#include "src/scene/scene_loader.h"
#include "src/checks/verify.h"
#include "support/fixtures.h"
#include "stability/stability_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

namespace plancheck {
namespace {

using namespace stability;

// --- whole turns and huge angles ------------------------------------------

TEST(SceneStability, WholeTurnsInDegreesPoseExactlyLikeZero) {
  BarScene s;
  const Checker checker(s.scene);
  const StateResult zero = check(checker, s.states({"0"})[0]);
  ASSERT_TRUE(zero.collision);  // lying on the slab: touching
  ASSERT_EQ(zero.min_distance, 0.0);
  // 360 deg in double radians is fl(2 pi), whose sine is -2.4e-16: without
  // the exact reduction the bar would lift off by ~1e-15 m and a touching
  // contact would be reported free (a false safe with no margin).
  for (const std::string turns : {"360", "-360", "720", "1080", "-3600", "360000", "395824185999360", "3.6e20"}) {
    const auto st = s.states({turns});
    const StateResult r = check(checker, st[0]);
    EXPECT_TRUE(r.collision) << turns << " deg";
    EXPECT_EQ(r.min_distance, 0.0) << turns << " deg";
  }
}

TEST(SceneStability, HugeDegreeAnglesTurnByTheirExactRemainder) {
  BarScene s;
  const Checker checker(s.scene);
  // remainder(v, 360) is exact; 10^k = -80 mod 360 for k >= 3 (10^22 is
  // an exact double, 1e300 is not: its remainder is computed).
  for (const char* small : {"1000000", "1e15", "1e22"}) EXPECT_EQ(std::remainder(std::stod(small), 360.0), -80.0);
  for (const std::string big : {"1000000", "-1000000", "1e15", "1e22", "1e300", "-1e300", "1.7976931348623157e308"}) {
    char small[64];
    std::snprintf(small, sizeof small, "%.17g", std::remainder(std::stod(big), 360.0));
    const auto st = s.states({big, small});
    const StateResult a = check(checker, st[0]), b = check(checker, st[1]);
    EXPECT_EQ(a.collision, b.collision) << big << " vs " << small;
    EXPECT_EQ(a.min_distance, b.min_distance) << big << " vs " << small;
  }
}

TEST(SceneStability, LimitsStillSeeTheAngleAsWritten) {
  // Reduction never changes a limit verdict: 360 is outside [-180, 180] and
  // stays a violation; inside [-720, 720] it poses like 0.
  BarScene narrow("[0, 1, 0]", R"(, "limits": [-180, 180])");
  for (const auto& st : narrow.states({"360", "-540", "1e300"}))
    EXPECT_EQ(first_limit_violation(narrow.scene, st), 0) << st[0];
  EXPECT_EQ(first_limit_violation(narrow.scene, narrow.states({"180"})[0]), -1);
  BarScene wide("[0, 1, 0]", R"(, "limits": [-720, 720])");
  const Checker checker(wide.scene);
  for (const auto& st : wide.states({"360", "-720", "720"})) {
    EXPECT_EQ(first_limit_violation(wide.scene, st), -1);
    EXPECT_TRUE(check(checker, st).collision);
  }
  // Limits [300, 400]: 360 is inside, its remainder 0 is not, so it is kept as
  // written (and the pose is within an ulp of the reference pose).
  BarScene offset("[0, 1, 0]", R"(, "limits": [300, 400])");
  const auto st = offset.states({"360"})[0];
  EXPECT_EQ(first_limit_violation(offset.scene, st), -1);
}

// --- the scene far from the origin ---------------------------------------

TEST(SceneStability, LunarRadiusTranslationKeepsFlagsAndDistances) {
  BarScene s;
  const auto states = s.states({"0", "360", "-0.001", "-0.0001", "-1", "-30", "0.001", "5", "-90", "45", "-1e-9"});
  const Checker near(s.scene);
  for (const Vec3& dir : {Vec3(Vec3::UnitX()), Vec3(0.48, -0.6, 0.64)}) {
    const Vec3 t = kLunarRadius * dir;
    // Along x the translation is exact for every coordinate here (dyadic,
    // small), so even the touching states must keep their flags.
    const bool exact = dir == Vec3::UnitX();
    const Scene far_scene = translated(s.scene, t);
    const Checker far(far_scene);
    for (const auto& st : states) {
      const StateResult a = check(near, st), b = check(far, st);
      EXPECT_NEAR(a.min_distance, b.min_distance, 1e-6) << st[0] << " rad, dir " << dir.transpose();
      if (exact || a.min_distance > 1e-6 || (a.collision && std::abs(st[0]) > 1e-6)) {
        EXPECT_EQ(a.collision, b.collision) << st[0] << " rad, dir " << dir.transpose();
      }
    }
  }
}

// The margin guard widens with the coordinates: at the lunar radius the
// double distance may be off by more than the 1e-9 m guard (16 eps times
// 1.7e6 m is 6e-9 m), so a distance 3e-9 m above the margin is settled as
// safe near the origin and counted as a violation out there.
TEST(SceneStability, MarginGuardGrowsWithCoordinates) {
  BarScene s;
  const auto states = s.states({"-1"});
  const Checker near(s.scene);
  const StateResult a = check(near, states[0]);
  ASSERT_FALSE(a.collision);
  EXPECT_EQ(a.distance_tolerance, kDistanceTolerance);
  const double margin = a.min_distance - 3e-9;
  EXPECT_EQ(state_verdict(a, margin), Verdict::kSafe);
  EXPECT_EQ(state_verdict(a, a.min_distance - 0.5e-9), Verdict::kClearance);

  const Scene far_scene = translated(s.scene, kLunarRadius * Vec3(0.48, -0.6, 0.64));
  const Checker far(far_scene);
  const StateResult b = check(far, states[0]);
  ASSERT_FALSE(b.collision);
  EXPECT_GE(b.distance_tolerance, 16.0 * std::numeric_limits<double>::epsilon() * kLunarRadius);
  EXPECT_LT(b.distance_tolerance, 1e-7);
  EXPECT_EQ(state_verdict(b, margin), Verdict::kClearance);
  EXPECT_EQ(state_verdict(b, a.min_distance - 1e-6), Verdict::kSafe);
}

}  // namespace
}  // namespace plancheck
