// SPDX-License-Identifier: MIT
// The grid of a configuration sweep (plancheck sweep, sweep.html): one axis
// per swept driving parameter, its values as written.
#pragma once

#include "src/scene/scene.h"

#include <cstddef>
#include <string>
#include <vector>

namespace plancheck {

// Most configurations one sweep may ask for: its outputs are streamed
// (verdict.npy, distance.npy written block by block), so memory does not
// grow with the grid. Most values one axis may have.
inline constexpr std::size_t kMaxSweepConfigurations = 2'000'000'000;
inline constexpr std::size_t kMaxSweepAxisValues = 20'000'000;
// sweep.html holds every configuration's verdict in the page: at most this many.
inline constexpr std::size_t kMaxSweepPageConfigurations = 20'000'000;

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

}  // namespace plancheck
