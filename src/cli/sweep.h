// SPDX-License-Identifier: MIT
// `plancheck sweep`: the configuration space of a scene, checked on a grid.
// Every configuration of the grid gets the state check of `verify`
// (collision, exact minimum distance, limits) and the same verdict rules, so
// the safe set it reports is the set of states `verify` would call safe.
#pragma once

#include "src/scene/scene.h"
#include "src/scene/scene_loader.h"

#include <cstddef>
#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace plancheck {

// Most configurations one sweep may ask for (its CSV has a row for each).
inline constexpr std::size_t kMaxSweepConfigurations = 20'000'000;

// One swept driving parameter and its values.
struct SweepAxis {
  int parameter = -1;               // index into Scene::parameter_names
  std::vector<double> values;       // as written (plan units, like a plan column), in sweep order
  std::string spec;                 // as the user wrote it, or "limits"
};

// The grid from `--steps N`: N values over the limits of every driving
// parameter whose action has limits (others stay at their reference value).
std::vector<SweepAxis> sweep_axes_from_steps(const Scene& scene, long steps);

// The grid from `--grid "J1=-180:180:5,J2=0:90:10"` (plan units; parameters
// not named stay at their reference value). Throws InputError naming the item.
std::vector<SweepAxis> sweep_axes_from_grid(const Scene& scene, const std::string& grid);

struct SweepArgs {
  std::filesystem::path scene;
  SceneOptions scene_options;        // --srdf, --package
  std::optional<long> steps;         // --steps N
  bool quiet = false;                // no progress on stderr
  bool html = false;                 // also DIR/sweep.html (src/output/sweep_html.h)
  std::optional<std::string> grid;   // --grid SPEC
  std::filesystem::path out = "plancheck-sweep";
  int threads = 0;                   // 0: all hardware threads
};

// Writes DIR/sweep.csv (one row per configuration) and DIR/sweep.json (the
// summary), prints the summary; returns 0. Input errors throw InputError.
int run_sweep(const SweepArgs& args, std::ostream& out, std::ostream& err);

}  // namespace plancheck
