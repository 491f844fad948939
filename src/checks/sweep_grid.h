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

// One swept driving parameter and its values.
struct SweepAxis {
  int parameter = -1;               // index into Scene::parameter_names
  std::vector<double> values;       // as written (plan units, like a plan column), in sweep order
  std::string spec;                 // as the user wrote it, or "limits"
};

// The grid to check: its axes, how many configurations they make, and the
// values of the parameters the axes leave alone (Scene::reference_parameters).
struct SweepGrid {
  std::vector<SweepAxis> axes;
  std::size_t total = 1;
  std::vector<double> reference;

  std::vector<std::size_t> shape() const {
    std::vector<std::size_t> s;
    for (const SweepAxis& a : axes) s.push_back(a.values.size());
    return s;
  }
  // Configuration `index` in C order (the last axis fastest): the full
  // parameter vector, and (optional) each axis's value index.
  void decode(std::size_t index, std::vector<double>& params, std::vector<std::size_t>* digits) const {
    params = reference;
    for (std::size_t k = axes.size(); k-- > 0;) {
      const std::size_t n = axes[k].values.size();
      const std::size_t d = index % n;
      index /= n;
      params[static_cast<std::size_t>(axes[k].parameter)] = axes[k].values[d];
      if (digits) (*digits)[k] = d;
    }
  }
};

// The grid cut into fixed blocks: boxes of `edge` values per axis (fewer at
// the far ends), numbered in C order. The cut depends on the grid's shape
// alone, never on threads, shards or ranks, so what is certified per block
// is the same however the blocks are spread.
struct SweepBlocks {
  std::vector<std::size_t> shape, edge, count;  // per axis: values, block edge, blocks
  std::size_t blocks = 1;

  explicit SweepBlocks(const std::vector<std::size_t>& grid_shape);
  // Block b: the first value index and the number of values per axis.
  void block(std::size_t b, std::vector<std::size_t>& first, std::vector<std::size_t>& size) const;
};

// The grid from `--steps N`: N values over the limits of every driving
// parameter whose action has limits (others stay at their reference value).
std::vector<SweepAxis> sweep_axes_from_steps(const Scene& scene, long steps);

// The grid from `--grid "J1=-180:180:5,J2=0:90:10"` (plan units; parameters
// not named stay at their reference value). Throws InputError naming the item.
std::vector<SweepAxis> sweep_axes_from_grid(const Scene& scene, const std::string& grid);

}  // namespace plancheck
