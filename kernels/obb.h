// SPDX-License-Identifier: MIT
// Oriented-box tests for the pair traversal: the separating-axis test over
// the 15 axes of two boxes (Gottschalk, Lin and Manocha, "OBBTree", 1996;
// Ericson, Real-Time Collision Detection, 4.4.1), and distance lower bounds
// from the gaps on some of those axes. Every test takes a tolerance `tol`
// that the caller sizes to cover the rounding of its inputs, so "disjoint"
// is a proof and a lower bound never exceeds the true distance.
// Scalar doubles; no I/O, no allocation.
#pragma once

#include "kernels/box.h"

#include <algorithm>
#include <cmath>

namespace plancheck {

// Box b relative to box a (Gottschalk's R and T): r[3i+j] = a_i . b_j,
// abs_r = |r| + 1e-12 (the epsilon keeps near-parallel edge-cross axes from
// a false separation), t[i] = a_i . (c_b - c_a), in a's axes.
struct ObbRelative {
  double r[9], abs_r[9], t[3];
};

// Two oriented boxes with half extents ha (a's axes) and hb (b's axes):
// true when an axis separates them by more than tol.
inline bool obb_disjoint(const ObbRelative& p, const double* ha, const double* hb, double tol) noexcept {
  const double* R = p.r;
  const double* A = p.abs_r;
  const double* T = p.t;
  for (int i = 0; i < 3; ++i) {
    const double rb = hb[0] * A[3 * i] + hb[1] * A[3 * i + 1] + hb[2] * A[3 * i + 2];
    if (std::abs(T[i]) > ha[i] + rb + tol) return true;
  }
  for (int j = 0; j < 3; ++j) {
    const double ra = ha[0] * A[j] + ha[1] * A[3 + j] + ha[2] * A[6 + j];
    const double tj = T[0] * R[j] + T[1] * R[3 + j] + T[2] * R[6 + j];
    if (std::abs(tj) > ra + hb[j] + tol) return true;
  }
  for (int i = 0; i < 3; ++i) {
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      // Axis a_i x b_j.
      const double ra = ha[i1] * A[3 * i2 + j] + ha[i2] * A[3 * i1 + j];
      const double rb = hb[j1] * A[3 * i + j2] + hb[j2] * A[3 * i + j1];
      const double tl = T[i2] * R[3 * i1 + j] - T[i1] * R[3 * i2 + j];
      if (std::abs(tl) > ra + rb + tol) return true;
    }
  }
  return false;
}

// Distance lower bound of two oriented boxes from their six face axes and
// the centre-to-centre axis (each separating-axis gap bounds the distance
// from below); dist_centres = |t|. 0 when no axis separates.
inline double obb_lower(const ObbRelative& p, double dist_centres, const double* ha, const double* hb,
                        double tol) noexcept {
  const double* R = p.r;
  const double* A = p.abs_r;
  const double* T = p.t;
  double gap = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double rb = hb[0] * A[3 * i] + hb[1] * A[3 * i + 1] + hb[2] * A[3 * i + 2];
    gap = std::max(gap, std::abs(T[i]) - ha[i] - rb);
  }
  double tb[3];
  for (int j = 0; j < 3; ++j) {
    const double ra = ha[0] * A[j] + ha[1] * A[3 + j] + ha[2] * A[6 + j];
    tb[j] = T[0] * R[j] + T[1] * R[3 + j] + T[2] * R[6 + j];
    gap = std::max(gap, std::abs(tb[j]) - ra - hb[j]);
  }
  if (dist_centres > 0.0) {
    const double ra = ha[0] * std::abs(T[0]) + ha[1] * std::abs(T[1]) + ha[2] * std::abs(T[2]);
    const double rb = hb[0] * std::abs(tb[0]) + hb[1] * std::abs(tb[1]) + hb[2] * std::abs(tb[2]);
    gap = std::max(gap, dist_centres - (ra + rb) / dist_centres);
  }
  return std::max(0.0, gap - tol);
}

// Distance lower bound of the balls around two nodes (centres ca, cb, radii
// ra, rb), d2 = |cb - ca|^2 as the caller computed it: |cb - ca| - ra - rb
// less a tolerance, `extra` (the rounding of the caller's inputs) plus a
// few ulps of every term.
inline double ball_gap(double d2, const double* ca, const double* cb, double ra, double rb,
                       double extra) noexcept {
  const double centres = std::sqrt(d2);
  const double tol = extra + 1e-12 * (centres + ra + rb + std::abs(cb[0]) + std::abs(cb[1]) +
                                      std::abs(cb[2]) + std::abs(ca[0]) + std::abs(ca[1]) +
                                      std::abs(ca[2]));
  return centres - ra - rb - tol;
}

// True when ball_gap(d2, ...) < cut (1 - 1e-15) for any centres and any
// extra >= 0, without its square root: so a test "ball_gap >= cut" (or its
// square, times a factor <= 1, against fl(cut^2)) fails. Proof, u = 2^-53:
// the computed sqrt is <= sqrt(d2) (1 + u); ball_gap <= fl(fl(centres - ra)
// - rb) (tol >= 0, rounding is monotonic) <= centres - ra - rb + 3u
// (centres + ra + rb); and d2 < fl(reach^2) with reach = fl((ra + rb + cut)
// (1 - 1e-12)) gives sqrt(d2) < (ra + rb + cut)(1 - 1e-12)(1 + 4u). Together
// ball_gap < cut - 1e-12 (ra + rb + cut) + 8u (centres + ra + rb + cut),
// and centres < 1.01 (ra + rb + cut) here, so the last two terms sum to
// less than -1e-15 cut. NaN or infinite d2: false (nothing proven).
inline bool balls_within(double d2, double ra, double rb, double cut) noexcept {
  const double reach = (ra + rb + cut) * (1.0 - 1e-12);
  return d2 < reach * reach;
}

// An oriented box in the frame of an axis-aligned one: axis rows are unit
// vectors in that frame, half points at its three half extents.
struct PosedObb {
  double axis[9];
  double center[3];
  const double* half;
};

// The same 15-axis test with box b axis-aligned, [blo, bhi]: true when
// proven disjoint.
inline bool obb_box_disjoint(const PosedObb& o, const double* blo, const double* bhi, double tol) noexcept {
  double e[3], T[3], R[9], A[9];
  for (int k = 0; k < 3; ++k) {
    e[k] = 0.5 * (bhi[k] - blo[k]);
    T[k] = o.center[k] - 0.5 * (blo[k] + bhi[k]);
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      R[3 * i + j] = o.axis[3 * j + i];
      A[3 * i + j] = std::abs(R[3 * i + j]) + 1e-12;
    }
  const double* h = o.half;
  for (int i = 0; i < 3; ++i)
    if (std::abs(T[i]) > e[i] + h[0] * A[3 * i] + h[1] * A[3 * i + 1] + h[2] * A[3 * i + 2] + tol) return true;
  for (int j = 0; j < 3; ++j) {
    const double tj = T[0] * R[j] + T[1] * R[3 + j] + T[2] * R[6 + j];
    if (std::abs(tj) > e[0] * A[j] + e[1] * A[3 + j] + e[2] * A[6 + j] + h[j] + tol) return true;
  }
  for (int i = 0; i < 3; ++i) {
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const double ra = e[i1] * A[3 * i2 + j] + e[i2] * A[3 * i1 + j];
      const double rb = h[j1] * A[3 * i + j2] + h[j2] * A[3 * i + j1];
      const double tl = T[i2] * R[3 * i1 + j] - T[i1] * R[3 * i2 + j];
      if (std::abs(tl) > ra + rb + tol) return true;
    }
  }
  return false;
}

// Distance lower bound of an oriented box and an axis-aligned box: the
// oriented box's enclosing box against the box (Euclidean), and the gaps on
// the oriented box's own face axes.
inline double obb_box_lower(const PosedObb& o, const double* blo, const double* bhi, double tol) noexcept {
  double olo[3], ohi[3], e[3], T[3];
  for (int k = 0; k < 3; ++k) {
    const double r = o.half[0] * std::abs(o.axis[k]) + o.half[1] * std::abs(o.axis[3 + k]) +
                     o.half[2] * std::abs(o.axis[6 + k]);
    olo[k] = o.center[k] - r, ohi[k] = o.center[k] + r;
    e[k] = 0.5 * (bhi[k] - blo[k]);
    T[k] = o.center[k] - 0.5 * (blo[k] + bhi[k]);
  }
  double gap = std::sqrt(box_distance_squared(olo, ohi, blo, bhi));
  for (int j = 0; j < 3; ++j) {
    const double* a = &o.axis[3 * j];
    const double tj = T[0] * a[0] + T[1] * a[1] + T[2] * a[2];
    const double rb = e[0] * std::abs(a[0]) + e[1] * std::abs(a[1]) + e[2] * std::abs(a[2]);
    gap = std::max(gap, std::abs(tj) - o.half[j] - rb);
  }
  return std::max(0.0, gap - tol);
}

}  // namespace plancheck
