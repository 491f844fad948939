// SPDX-License-Identifier: MIT
// Scene-level stability (issue 6, part 2), rotation axes: given unnormalised,
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

// --- rotation axes ---------------------------------------------------------

TEST(SceneStability, UnnormalisedAxesPoseExactlyLikeTheUnitAxis) {
  BarScene unit;
  const Checker reference(unit.scene);
  const auto states = unit.states({"0", "-0.001", "-10", "-35", "0.5", "90", "-123.456"});
  // Powers of two times the unit axis normalise to the very same doubles;
  // the others to within an ulp. Nearly zero (1e-300, even subnormal) and
  // huge (1e300) components are directions like any other.
  for (const std::string axis : {"[0, 2, 0]", "[0, 0.0009765625, 0]", "[0, 1e-300, 0]", "[0, 5e-324, 0]",
                                 "[0, 1e-160, 0]", "[0, 3, 0]", "[0, 1e200, 0]", "[0, 1e300, 0]"}) {
    BarScene other(axis);
    ASSERT_EQ(other.scene.actions[0].axis, Vec3(0, 1, 0)) << axis;
    const Checker checker(other.scene);
    for (const auto& s : states) {
      const StateResult a = check(reference, s), b = check(checker, s);
      EXPECT_EQ(a.collision, b.collision) << axis << " at " << s[0];
      EXPECT_EQ(a.min_distance, b.min_distance) << axis << " at " << s[0];
    }
  }
}

TEST(SceneStability, TiltedAxesGivenAtAnyScaleAgree) {
  // (1, 2, 2) / 3 at scales from subnormal to huge: the same unit axis to an ulp.
  for (double s : {5e-324 * 1024, 1e-300, 1e-160, 1e-3, 1.0, 7.0, 1e160, 1e300}) {
    std::ostringstream axis;
    axis.precision(17);
    axis << "[" << s << ", " << 2 * s << ", " << 2 * s << "]";
    BarScene tilted(axis.str());
    const Vec3 u = tilted.scene.actions[0].axis;
    EXPECT_NEAR(u.norm(), 1.0, 4e-16) << axis.str();
    EXPECT_LE((u - Vec3(1, 2, 2) / 3).cwiseAbs().maxCoeff(), 4e-16) << axis.str();
    EXPECT_TRUE(is_rigid(action_transform(tilted.scene.actions[0], std::vector<double>{1.0}.data())))
        << axis.str();
  }
}

TEST(SceneStability, ZeroAxisIsRefusedNamingTheField) {
  for (const std::string axis : {"[0, 0, 0]", "[-0.0, 0, 0.0]"}) {
    TempDir dir("stability-zero-axis");
    testing::write_obj(dir / "model.obj", {{"Slab", testing::box_mesh({-3, -1, -1}, {3, 1, 0})},
                                           {"Bar", testing::box_mesh({0, -0.125, 0}, {2, 0.125, 0.25})}});
    testing::write_text(dir / "scene.json", R"({"format": "plancheck-scene/1", "model": "model.obj",
      "actions": [{"name": "J1", "node": "Bar", "type": "rotate", "pivot": [0, 0, 0], "axis": )" + axis + "}]}");
    try {
      load_scene(dir / "scene.json");
      ADD_FAILURE() << axis << ": accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("actions[0].axis: zero-length axis"), std::string::npos) << e.what();
    }
    const std::string cmd = std::string(PLANCHECK_BINARY_DIR) + "/plancheck scene " + (dir / "scene.json").string() +
                            " > /dev/null 2> " + (dir / "err.txt").string();
    EXPECT_EQ(testing::run_command(cmd), 2) << axis;
    EXPECT_NE(testing::read_text(dir / "err.txt").find("actions[0].axis"), std::string::npos);
  }
}

}  // namespace
}  // namespace plancheck
