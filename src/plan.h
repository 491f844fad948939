// SPDX-License-Identifier: MIT
// Plan CSV -> states (contract: README "Plan file").
#pragma once

#include "src/scene.h"

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace plancheck {

// Target tolerance when a plan gives "# target:" without "# tolerance:", in
// the scene's length_unit (1 cm in a scene in metres).
inline constexpr double kDefaultTargetTolerance = 0.01;

struct Plan {
  std::string name;                        // "# name:" or the file stem
  std::filesystem::path file;
  std::optional<Vec3> target;              // "# target:" (m, reference frame)
  double tolerance = 0.0;                  // "# tolerance:" (m); default kDefaultTargetTolerance
  std::vector<double> times;               // the optional time column (s); empty without it
  std::vector<std::vector<double>> states; // full parameter vectors (SI), scene.parameter_names order
  std::vector<long> lines;                 // file line of each state, for messages
};

// A value written for driving parameter `parameter` (plan units), in SI, as
// a plan column reads it: degrees lose whole turns exactly (see plan.cpp),
// lengths are scaled by length_unit, factors stay as they are.
double parameter_to_si(const Scene& scene, int parameter, double value);

// Throws InputError naming the file, line and column at fault.
Plan load_plan(const Scene& scene, const std::filesystem::path& csv);

// The same from the file's text already in memory; `csv` names it in
// messages and gives the default plan name (the fuzz targets use this).
Plan parse_plan(const Scene& scene, std::string_view text, const std::filesystem::path& csv);

}  // namespace plancheck
