// SPDX-License-Identifier: MIT
// Filtered orientation predicates on double coordinates. Each determinant is
// first evaluated in double with Shewchuk's static forward error bound
// ("Adaptive Precision Floating-Point Arithmetic and Fast Robust Geometric
// Predicates", 1997, errboundA, here rounded up to 8 eps for orient3d and
// 4 eps for orient2d); when |det| does not clear the bound, the sign is
// settled exactly by src/geometry/exact.cpp. The result is always the exact sign for
// the given doubles. Non-finite or underflowing evaluations also take the
// exact path (the bound assumes no underflow).
#pragma once

#include "src/geometry/exact.h"

#include <cmath>

namespace plancheck {

namespace predicate_detail {
inline constexpr double kEps = 0x1p-53;                 // unit roundoff of double
inline constexpr double kOrient3dBound = 8.0 * kEps;   // >= (7 + 56 eps) eps
inline constexpr double kOrient2dBound = 4.0 * kEps;   // >= (3 + 16 eps) eps
inline constexpr double kUnderflowGuard = 1e-250;       // below this the bound is not trusted
}  // namespace predicate_detail

// Sign of det[b-a, c-a, d-a]: +1 when d is on the side of plane (a, b, c)
// that (b-a) x (c-a) points to.
inline int orient3d(const double* a, const double* b, const double* c, const double* d) noexcept {
  using namespace predicate_detail;
  const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
  const double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
  const double wx = d[0] - a[0], wy = d[1] - a[1], wz = d[2] - a[2];
  const double vywz = vy * wz, vzwy = vz * wy;
  const double vzwx = vz * wx, vxwz = vx * wz;
  const double vxwy = vx * wy, vywx = vy * wx;
  const double det = ux * (vywz - vzwy) + uy * (vzwx - vxwz) + uz * (vxwy - vywx);
  const double permanent = std::abs(ux) * (std::abs(vywz) + std::abs(vzwy)) +
                           std::abs(uy) * (std::abs(vzwx) + std::abs(vxwz)) +
                           std::abs(uz) * (std::abs(vxwy) + std::abs(vywx));
  const double bound = kOrient3dBound * permanent;
  if (permanent > kUnderflowGuard) {
    if (det > bound) return 1;
    if (det < -bound) return -1;
  }
  return exact_orient3d(a, b, c, d);
}

// Sign of det[b-a, c-a] for 2D points (x, y).
inline int orient2d(const double* a, const double* b, const double* c) noexcept {
  using namespace predicate_detail;
  const double l = (b[0] - a[0]) * (c[1] - a[1]);
  const double r = (b[1] - a[1]) * (c[0] - a[0]);
  const double det = l - r;
  const double bound = kOrient2dBound * (std::abs(l) + std::abs(r));
  if (std::abs(l) + std::abs(r) > kUnderflowGuard) {
    if (det > bound) return 1;
    if (det < -bound) return -1;
  }
  return exact_orient2d(a, b, c);
}

// orient2d of the projections of 3D points on coordinates (i, j).
inline int orient2d_projected(const double* a, const double* b, const double* c, int i,
                              int j) noexcept {
  const double pa[2] = {a[i], a[j]}, pb[2] = {b[i], b[j]}, pc[2] = {c[i], c[j]};
  return orient2d(pa, pb, pc);
}

}  // namespace plancheck
