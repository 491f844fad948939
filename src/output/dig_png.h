// SPDX-License-Identifier: MIT
// The PNG of `plancheck dig`, drawn with cairo: three panels side by side,
// north up, each titled: the terrain before, after (one shared height colour
// ramp), and after - before (blue lowered, white unchanged, red raised,
// symmetric scale); under them a colour bar for each scale with its unit, in
// the first panel a scale bar, and in every panel the plan's target (a
// ringed cross; a note under the panels when it lies off the map) and the
// deepest scoop point (a ring).
#pragma once

#include "src/scene/scene.h"
#include "src/scene/terrain.h"

#include <filesystem>
#include <optional>
#include <string>

namespace plancheck {

struct DigMapRequest {
  const Dem* before = nullptr;             // grids in metres
  const Dem* after = nullptr;
  Vec3 origin = Vec3::Zero();              // the terrain's placement (TerrainConfig::origin, m)
  std::optional<Vec3> target;              // the plan's target (m, reference frame): a ringed cross
  std::optional<Vec3> deepest;             // where the scoop went deepest (m): a ring
  std::string plan_name;                   // for the "after" title
  std::string length_unit = "m";           // labels are in this unit
  double length_scale = 1.0;               // metres per length_unit
  int panel_pixels = 360;                  // the longer side of a panel (px)
};

struct DigMapResult {
  double z_min = 0.0, z_max = 0.0;  // height ramp (m)
  double diff_max = 0.0;            // |after - before| at full colour (m)
  int width = 0, height = 0;        // the image (px)
  // Panel k's top-left corner and size (px), for tests.
  int panel_x[3] = {0, 0, 0};
  int panel_y = 0, panel_w = 0, panel_h = 0;
};

DigMapResult write_dig_png(const std::filesystem::path& file, const DigMapRequest& request);

// A "nice" length of 1, 2 or 5 times a power of ten, at most `limit`.
double nice_length(double limit);

}  // namespace plancheck
