// SPDX-License-Identifier: MIT
// The PNG of `plancheck dig`: three panels side by side, north up: the
// terrain before, after (one shared height colour ramp), and after - before
// (blue lowered, white unchanged, red raised, symmetric scale).
#pragma once

#include "src/terrain.h"

#include <filesystem>

namespace plancheck {

struct MapScale {
  double z_min = 0.0, z_max = 0.0;  // height ramp (m)
  double diff_max = 0.0;            // |after - before| at full colour (m)
};

// Writes the map; each grid sample becomes a square of `pixels` pixels.
MapScale write_dig_png(const std::filesystem::path& file, const Dem& before, const Dem& after, int pixels);

}  // namespace plancheck
