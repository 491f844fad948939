// SPDX-License-Identifier: MIT
// A one-axis skip test for distance searches: the separating-axis gap of two
// triangles on the direction of the closest pair found so far. Near that
// pair the direction is almost the best separating axis of the neighbouring
// triangle pairs (on locally convex patches their gap on it is at least the
// best distance), so it settles most of the pairs the general bounds leave
// around a curved contact, with one subtraction per pair once each
// triangle's span is known.
//
// Exactness: a pair is skipped only when its gap proves that the triangle
// distance kernel (kernels/tri_distance.h) would return at least `best` for
// it, so a search that skips it finds the same answers in the same order.
// For any vector n the gap g of the spans divided by |n| bounds the distance
// D from below. n is normalised here (|n| = 1 to a few ulps). Computed
// three-term dot products with |n| ~ 1 and coordinates below `size` err by
// < 1e-15 size each, a gap by twice that; the kernel's value is at least
// D - slack when slack >= 1e-13 size (its closest points lie within a few
// ulps of the triangles, as the leaf prefilters' bound uses too). Hence a
// computed gap >= best (1 + 1e-14) + 2 slack gives a kernel value >= best.
// Scalar doubles; no I/O, no allocation.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace plancheck {

struct DirectionBound {
  double n[3] = {0, 0, 0};  // unit direction from the best pair's point on a to its point on b
  // A pair whose gap (DirectionBound::gap) reaches this cannot come closer
  // than best; infinity while no direction is set.
  double cut = std::numeric_limits<double>::infinity();

  // Direction from pa to pb and cut for `best`; slack >= 1e-13 times the
  // largest coordinate magnitude of any triangle tested (see above). With
  // points too close for a well-rounded direction (|pb - pa| <= 1e-100, so
  // its squared length could be subnormal) no direction is set: false.
  bool set(const double* pa, const double* pb, double best, double slack) noexcept {
    const double d[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(len > 1e-100) || !std::isfinite(len)) {
      cut = std::numeric_limits<double>::infinity();
      return false;
    }
    for (int k = 0; k < 3; ++k) n[k] = d[k] / len;
    cut = best * (1.0 + 1e-14) + 2.0 * slack;
    return true;
  }

  // Highest projection of triangle a's vertices (9 doubles), lowest of b's:
  // the gap of a pair is low(b) - high(a).
  double high(const double* t) const noexcept {
    return std::max(std::max(dot(t), dot(t + 3)), dot(t + 6));
  }
  double low(const double* t) const noexcept {
    return std::min(std::min(dot(t), dot(t + 3)), dot(t + 6));
  }

 private:
  double dot(const double* v) const noexcept { return n[0] * v[0] + n[1] * v[1] + n[2] * v[2]; }
};

}  // namespace plancheck
