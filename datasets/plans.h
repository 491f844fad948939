// SPDX-License-Identifier: MIT
// The ten plans of the paper's Table 3: smooth joint paths between waypoints
// found by the generator's own inverse kinematics.
#pragma once

#include "datasets/change5.h"
#include "datasets/checker.h"

#include <string>
#include <vector>

namespace plancheck::dataset {

inline constexpr std::array<int, 10> kPlanStates{381, 264, 345, 249, 276, 238, 294, 323, 286, 326};

struct PlanOut {
  std::string name;                // plan01 ...
  std::string task;                // one line for the file comment and expected.json
  std::string designed;            // "safe", "collision", "clearance" or "limits"
  std::vector<Joints> states;      // degrees, already rounded to what the CSV holds
};

// Joint angles (deg) putting the scoop bottom M at `m` with the scoop pitched
// `pitch` degrees (0 = level, positive = nose up), elbow up. Throws when out of reach.
Joints inverse_kinematics(const Vec3& m, double pitch);

std::vector<PlanOut> build_plans(const std::vector<double>& dem, const Checker& checker);

}  // namespace plancheck::dataset
