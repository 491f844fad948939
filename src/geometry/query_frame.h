// SPDX-License-Identifier: MIT
// What the pair queries (collision_model.cpp, heightfield.cpp) share about
// placing two parts in one working frame: when a map preserves distances,
// the kernels' flat map type, and the relative size of the rounding margins.
#pragma once

#include "kernels/box.h"
#include "src/scene/scene.h"

#include <cmath>

namespace plancheck {

// Relative size of the rounding margin: the box and vertex mappings err by a
// few ulps of |L| |x| + |t|; 1e-12 covers that a thousand times over.
inline constexpr double kMarginRel = 1e-12;
// Orthonormality tolerance for a working frame (distances preserved to ~1e-13).
inline constexpr double kIsometryTol = 1e-13;

// True when t's linear part is orthonormal to kIsometryTol, so distances in
// t's frame equal world distances. Reflections count (a query only needs
// distances kept); kinematics' is_rigid also asks for determinant +1 and
// allows far more rounding.
inline bool is_isometry(const Affine& t) {
  const Mat3 l = t.linear();
  return ((l.transpose() * l - Mat3::Identity()).cwiseAbs().maxCoeff() <= kIsometryTol);
}

// t as the kernels' flat map.
inline AffineMap to_map(const Affine& t) {
  AffineMap m;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      m.l[3 * r + c] = t.linear()(r, c);
      m.abs_l[3 * r + c] = std::abs(t.linear()(r, c));
    }
    m.t[r] = t.translation()(r);
  }
  return m;
}

}  // namespace plancheck
