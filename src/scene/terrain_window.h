// SPDX-License-Identifier: MIT
// Reading a scene's terrain: the raster placed by `origin` or `map_origin`,
// and only the window the moving parts can reach read from it.
#pragma once

#include "src/scene/scene.h"

namespace plancheck {

// Opens scene.terrain->dem, checks its units against the scene's, sets
// terrain->origin from map_origin when given, and reads into terrain->grid
// the window that every check can need (see the comment in the .cpp);
// the whole raster when some moving part has no reach bound. Needs the
// scene's parts, actions, pairs, scoop and probes. Throws InputError
// naming the file.
void load_terrain(Scene& scene);

}  // namespace plancheck
