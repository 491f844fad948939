// SPDX-License-Identifier: MIT
// Box tests for BVH traversal: a node box mapped by an affine transform into
// the working frame is enclosed by the axis-aligned box with centre M c and
// half extents |M| h (Arvo's transformed-box bound, "Transforming
// Axis-Aligned Bounding Boxes", Graphics Gems 1990), which holds for any
// affine M, rigid or not. Callers widen boxes by a margin that covers the
// rounding of these computations and of the mapped vertices, so a culled pair
// provably holds no touching triangles.
#pragma once

#include <algorithm>
#include <cmath>

namespace plancheck {

// An affine map x -> L x + t, L row-major; abs_l = |L| element-wise.
struct AffineMap {
  double l[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  double t[3] = {0, 0, 0};
  double abs_l[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};

  void apply(const double* x, double* out) const noexcept {
    for (int r = 0; r < 3; ++r)
      out[r] = l[3 * r] * x[0] + l[3 * r + 1] * x[1] + l[3 * r + 2] * x[2] + t[r];
  }
};

// Working-frame box of a float node box [lo, hi] under m, widened by margin.
inline void map_box(const AffineMap& m, const float* lo, const float* hi, const double* margin,
                    double* out_lo, double* out_hi) noexcept {
  double c[3], h[3];
  for (int k = 0; k < 3; ++k) {
    c[k] = 0.5 * (static_cast<double>(lo[k]) + static_cast<double>(hi[k]));
    h[k] = 0.5 * (static_cast<double>(hi[k]) - static_cast<double>(lo[k]));
  }
  for (int r = 0; r < 3; ++r) {
    const double cr = m.l[3 * r] * c[0] + m.l[3 * r + 1] * c[1] + m.l[3 * r + 2] * c[2] + m.t[r];
    const double hr =
        m.abs_l[3 * r] * h[0] + m.abs_l[3 * r + 1] * h[1] + m.abs_l[3 * r + 2] * h[2] + margin[r];
    out_lo[r] = cr - hr;
    out_hi[r] = cr + hr;
  }
}

// The float box as doubles, widened by margin (for the identity map).
inline void widen_box(const float* lo, const float* hi, const double* margin, double* out_lo,
                      double* out_hi) noexcept {
  for (int k = 0; k < 3; ++k) {
    out_lo[k] = static_cast<double>(lo[k]) - margin[k];
    out_hi[k] = static_cast<double>(hi[k]) + margin[k];
  }
}

// Closed overlap (touching boxes overlap).
inline bool boxes_overlap(const double* alo, const double* ahi, const double* blo,
                          const double* bhi) noexcept {
  return alo[0] <= bhi[0] && blo[0] <= ahi[0] && alo[1] <= bhi[1] && blo[1] <= ahi[1] &&
         alo[2] <= bhi[2] && blo[2] <= ahi[2];
}

// Squared Euclidean distance between two boxes (0 when they overlap).
inline double box_distance_squared(const double* alo, const double* ahi, const double* blo,
                                   const double* bhi) noexcept {
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    // Plain comparisons, not std::fmax: boxes are never NaN here, and fmax
    // is an out-of-line libm call in the hottest loop of distance queries.
    const double g1 = alo[k] - bhi[k], g2 = blo[k] - ahi[k];
    const double g = g1 > g2 ? g1 : g2;
    const double gap = g > 0.0 ? g : 0.0;
    d2 += gap * gap;
  }
  return d2;
}

// Axis-aligned box of a triangle (9 doubles): box[0..2] lo, box[3..5] hi.
// Exact (min and max only), so disjoint boxes prove disjoint triangles.
inline void triangle_box(const double* t, double* box) noexcept {
  for (int k = 0; k < 3; ++k) {
    box[k] = std::min({t[k], t[3 + k], t[6 + k]});
    box[3 + k] = std::max({t[k], t[3 + k], t[6 + k]});
  }
}

}  // namespace plancheck
