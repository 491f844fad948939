// SPDX-License-Identifier: MIT
// Exact reference answers for the stability suite, computed with CGAL over
// exact rationals (Simple_cartesian<Exact_rational>, GMP): every operation
// is exact, so the flag and the squared distance are the true ones for the
// given doubles. Kept out of the production code: tests link CGAL, the
// library does not.
#pragma once

#include "src/scene/scene.h"

#include <string>

namespace plancheck::stability {

struct ExactAnswer {
  bool overlap = false;      // closed triangles (or the segment/point they are) share a point
  double distance = 0.0;     // sqrt of the exact squared distance, rounded to double (<= 1 ulp)
  bool distance_is_zero = false;  // the exact squared distance is exactly 0
};

// Triangles as 9 doubles (x0 y0 z0 x1 ... z2). Zero-area triangles are
// handled as the segment or point they are.
ExactAnswer exact_tri_tri(const double* p, const double* q);

// Exact answer for two triangle sets given as posed (world-frame) meshes:
// overlap = some pair shares a point; distance = minimum over pairs.
ExactAnswer exact_mesh_mesh(const Mesh& a, const Affine& ta, const Mesh& b, const Affine& tb);

}  // namespace plancheck::stability
