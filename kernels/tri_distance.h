// SPDX-License-Identifier: MIT
// Closest points between two triangles in double precision (Ericson,
// "Real-Time Collision Detection", 5.1.5 closest point on a triangle and
// 5.1.9 closest points of two segments). Disjoint triangles are closest at a
// vertex-face pair (6) or an edge-edge pair (9). Whether the triangles
// intersect is decided exactly (kernels/tri_tri_overlap.h): then the
// distance is 0 and both points are set to one approximate common point.
// Zero-area triangles are fine: their face candidates are skipped, since the
// edge pairs already cover a triangle that is a segment or a point; no
// division by zero is ever taken.
#pragma once

#include "kernels/tri_tri_overlap.h"

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross(); without it a lone includer links to an undefined template

#include <algorithm>
#include <cmath>
#include <limits>

namespace plancheck {

struct TriDistance {
  double distance = 0.0;   // Euclidean, in the coordinates given
  Eigen::Vector3d point_p = Eigen::Vector3d::Zero();  // on triangle p
  Eigen::Vector3d point_q = Eigen::Vector3d::Zero();  // on triangle q
  bool intersecting = false;
};

namespace tri_distance_detail {

using V = Eigen::Vector3d;

inline double clamp01(double x) noexcept { return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x); }

// Squared distance between segments [p1,q1] and [p2,q2] and the closest
// points c1, c2 (Ericson 5.1.9; zero-length segments tested exactly).
inline double segment_segment(const V& p1, const V& q1, const V& p2, const V& q2, V& c1,
                              V& c2) noexcept {
  const V d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0.0, t = 0.0;
  if (a == 0.0 && e == 0.0) {
    // both points
  } else if (a == 0.0) {
    t = clamp01(f / e);
  } else {
    const double c = d1.dot(r);
    if (e == 0.0) {
      s = clamp01(-c / a);
    } else {
      const double b = d1.dot(d2);
      const double denom = a * e - b * b;  // >= 0; 0 when parallel
      s = denom > 0.0 ? clamp01((b * f - c * e) / denom) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = clamp01(-c / a);
      } else if (t > 1.0) {
        t = 1.0;
        s = clamp01((b - c) / a);
      }
    }
  }
  c1 = p1 + s * d1;
  c2 = p2 + t * d2;
  return (c1 - c2).squaredNorm();
}

// Closest point on triangle (a,b,c) to p by Voronoi regions (Ericson 5.1.5).
// Returns false (no answer) for a zero-area triangle, whose closest point is
// then found among its edges by the caller.
inline bool point_triangle(const V& p, const V& a, const V& b, const V& c, V& out) noexcept {
  const V ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) { out = a; return true; }
  const V bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) { out = b; return true; }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double den = d1 - d3;
    out = den > 0.0 ? V(a + (d1 / den) * ab) : a;
    return true;
  }
  const V cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) { out = c; return true; }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double den = d2 - d6;
    out = den > 0.0 ? V(a + (d2 / den) * ac) : a;
    return true;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double den = (d4 - d3) + (d5 - d6);
    out = den > 0.0 ? V(b + ((d4 - d3) / den) * (c - b)) : b;
    return true;
  }
  const double sum = va + vb + vc;  // = |ab x ac|^2 up to rounding
  if (!(sum > 0.0)) return false;
  const double v = vb / sum, w = vc / sum;
  out = a + v * ab + w * ac;
  return true;
}

struct Best {
  double d2 = std::numeric_limits<double>::infinity();
  V p = V::Zero(), q = V::Zero();
  void offer(double d, const V& a, const V& b) noexcept {
    if (d < d2) {
      d2 = d;
      p = a;
      q = b;
    }
  }
};

// Candidate pairs that are exact for disjoint triangles: 9 edge pairs and
// the 6 vertex-face pairs.
inline void feature_pairs(const V p[3], const V q[3], Best& best) noexcept {
  V c1, c2;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const double d = segment_segment(p[i], p[(i + 1) % 3], q[j], q[(j + 1) % 3], c1, c2);
      best.offer(d, c1, c2);
    }
  for (int i = 0; i < 3; ++i) {
    if (point_triangle(p[i], q[0], q[1], q[2], c2)) best.offer((p[i] - c2).squaredNorm(), p[i], c2);
    if (point_triangle(q[i], p[0], p[1], p[2], c1)) best.offer((q[i] - c1).squaredNorm(), c1, q[i]);
  }
}

// For intersecting triangles: where an edge of one crosses the other's plane
// (approximately a common point when it falls inside).
inline void piercing_pairs(const V s[3], const V t[3], bool s_is_p, Best& best) noexcept {
  const V n = (t[1] - t[0]).cross(t[2] - t[0]);
  V c;
  for (int i = 0; i < 3; ++i) {
    const V& a = s[i];
    const V& b = s[(i + 1) % 3];
    const double da = n.dot(a - t[0]), db = n.dot(b - t[0]);
    if (!((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0))) continue;
    const V x = a + (da / (da - db)) * (b - a);
    if (!point_triangle(x, t[0], t[1], t[2], c)) continue;
    if (s_is_p)
      best.offer((x - c).squaredNorm(), x, c);
    else
      best.offer((x - c).squaredNorm(), c, x);
  }
}

}  // namespace tri_distance_detail

// True when an axis across an edge of p and an edge of q (the nine
// edge-edge axes of the separating axis test) proves the triangles (9
// doubles each) at least `reach` apart; slack >= 1e-14 times their largest
// coordinate magnitude (big). The axes are left
// unnormalised (gap^2 against reach^2 |n|^2). A dot product with n errs by
// < 3u |n|_1 big <= 5.2u |n| big, a gap by twice that: `slack` >= 1e-14 big
// per unit of |n| covers it, and the 1e-12 factors the squares' rounding.
// Disjoint pairs that the normals do not separate are mostly edge-edge
// configurations, where one of these axes carries the whole distance.
inline bool edge_axes_reach(const double* p, const double* q, double reach, double slack) noexcept {
  const double need = reach + slack;
  const double need2 = need * need * (1.0 + 1e-12);
  for (int i = 0; i < 3; ++i) {
    const double* a0 = p + 3 * i;
    const double* a1 = p + 3 * ((i + 1) % 3);
    const double e[3] = {a1[0] - a0[0], a1[1] - a0[1], a1[2] - a0[2]};
    for (int j = 0; j < 3; ++j) {
      const double* b0 = q + 3 * j;
      const double* b1 = q + 3 * ((j + 1) % 3);
      const double f[3] = {b1[0] - b0[0], b1[1] - b0[1], b1[2] - b0[2]};
      const double n[3] = {e[1] * f[2] - e[2] * f[1], e[2] * f[0] - e[0] * f[2], e[0] * f[1] - e[1] * f[0]};
      const double l2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
      if (!(l2 > 0.0)) continue;  // parallel edges: no axis
      double plo = std::numeric_limits<double>::infinity(), phi = -plo, qlo = plo, qhi = -plo;
      for (int v = 0; v < 3; ++v) {
        const double x = n[0] * p[3 * v] + n[1] * p[3 * v + 1] + n[2] * p[3 * v + 2];
        const double y = n[0] * q[3 * v] + n[1] * q[3 * v + 1] + n[2] * q[3 * v + 2];
        plo = std::min(plo, x);
        phi = std::max(phi, x);
        qlo = std::min(qlo, y);
        qhi = std::max(qhi, y);
      }
      const double gap = std::max(qlo - phi, plo - qhi) * (1.0 - 1e-12);
      if (gap > 0.0 && gap * gap >= need2 * l2) return true;
    }
  }
  return false;
}

// For triangles already known to be disjoint (e.g. after an exact
// collision query over their sets found no intersecting pair): the same
// feature-pair minimum tri_distance returns for them, without the exact
// overlap test. Returns the squared distance; p_out, q_out get the points.
inline double tri_distance_disjoint2(const double* p, const double* q, Eigen::Vector3d& p_out,
                                     Eigen::Vector3d& q_out) noexcept {
  using namespace tri_distance_detail;
  const V pv[3] = {V(p[0], p[1], p[2]), V(p[3], p[4], p[5]), V(p[6], p[7], p[8])};
  const V qv[3] = {V(q[0], q[1], q[2]), V(q[3], q[4], q[5]), V(q[6], q[7], q[8])};
  Best best;
  feature_pairs(pv, qv, best);
  p_out = best.p;
  q_out = best.q;
  return best.d2;
}

// Triangles given as 9 doubles each (x0 y0 z0 x1 ... z2).
inline TriDistance tri_distance(const double* p, const double* q) noexcept {
  using namespace tri_distance_detail;
  const V pv[3] = {V(p[0], p[1], p[2]), V(p[3], p[4], p[5]), V(p[6], p[7], p[8])};
  const V qv[3] = {V(q[0], q[1], q[2]), V(q[3], q[4], q[5]), V(q[6], q[7], q[8])};
  TriDistance r;
  Best best;
  feature_pairs(pv, qv, best);
  if (tri_tri_overlap(p, p + 3, p + 6, q, q + 3, q + 6)) {
    piercing_pairs(pv, qv, true, best);
    piercing_pairs(qv, pv, false, best);
    r.intersecting = true;
    r.distance = 0.0;
    r.point_p = r.point_q = 0.5 * (best.p + best.q);
    return r;
  }
  r.distance = std::sqrt(best.d2);
  r.point_p = best.p;
  r.point_q = best.q;
  return r;
}

}  // namespace plancheck
