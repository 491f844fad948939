// SPDX-License-Identifier: MIT
// Plan CSV -> states (contract: docs/formats.md "Plan file").
#pragma once

#include "src/scene/scene.h"

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace plancheck {

// Target tolerance when a plan gives "# target:" without "# tolerance:", in
// the scene's length_unit (1 cm in a scene in metres).
inline constexpr double kDefaultTargetTolerance = 0.01;

// A plan's name names its CSV report and its lines: at most this many bytes
// of UTF-8 text without control characters.
inline constexpr std::size_t kMaxPlanNameBytes = 200;

struct Plan {
  std::string name;                        // "# name:" or the file stem
  std::filesystem::path file;
  std::optional<Vec3> target;              // "# target:" (m, reference frame)
  double tolerance = 0.0;                  // "# tolerance:" (m); default kDefaultTargetTolerance
  std::vector<double> times;               // the optional time column (s); empty without it
  // Full parameter vectors in scene.parameter_names order, each value as
  // written in the plan (plan units: 200 deg is 200, 720 is two turns).
  std::vector<std::vector<double>> states;
  std::vector<long> lines;                 // file line of each state, for messages
};

// The contract's motion between two states: each driving parameter moves
// linearly from its value as written in qa to its value as written in qb;
// out is the state at t in [0, 1]. The ends are the states, bit for bit.
// (Only the pose reduces an angle: kinematics.h, pose_value.)
void state_between(const std::vector<double>& qa, const std::vector<double>& qb, double t, std::vector<double>& out);

// Throws InputError naming the file, line and column at fault.
Plan load_plan(const Scene& scene, const std::filesystem::path& csv);

// The same from the file's text already in memory; `csv` names it in
// messages and gives the default plan name (the fuzz targets use this).
Plan parse_plan(const Scene& scene, std::string_view text, const std::filesystem::path& csv);

}  // namespace plancheck
