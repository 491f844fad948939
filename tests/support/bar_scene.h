// SPDX-License-Identifier: MIT
// A scene whose distance has a closed form: a 2 m bar pitching about a
// horizontal axis 1 m above a wide slab (one rotate action "J1", limits
// -90..30 deg, safety margin 0.05 m).
#pragma once

#include "support/fixtures.h"

namespace plancheck::testing {

// Slab top at z = 0 over x in [-3, 3]; bar [0, 2] x [-0.1, 0.1] x [0.9, 1.1]
// turning about +y through (0, 0, 1). A positive angle a tilts the bar's free
// end down; its lowest corner then sits at z = 1 - 2 sin a - h cos a, over
// the slab's top face, so that is the distance (vertex to face). assimp reads
// OBJ coordinates in single precision, so the bar's underside is float(0.9),
// h = 1 - float(0.9); 2, 1 and 0 are exact in float. <= 0: in contact.
double bar_distance(double degrees);

// Writes DIR/model.obj and DIR/scene.json.
void write_bar_scene(const TempDir& dir);

}  // namespace plancheck::testing
