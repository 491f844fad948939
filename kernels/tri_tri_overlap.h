// SPDX-License-Identifier: MIT
// Exact closed triangle-triangle intersection test on double coordinates.
// Touching (a shared point, edge or face part) counts as intersecting. Every
// decision is the sign of an orientation determinant of input points
// (kernels/predicates.h: filtered, exact fallback), so the answer is exact for
// the given doubles and invariant under vertex permutations and swapping.
//
// Proper, non-coplanar triangles follow Guigue and Devillers ("Fast and
// robust triangle-triangle overlap test using orientation predicates", JGT
// 2003): each triangle is rotated so its first vertex is alone on one closed
// side of the other's plane and the other triangle's orientation is flipped so
// that side is positive; then the two intersection intervals on the planes'
// common line overlap iff orient3d(p0,p1,q0,q1) <= 0 and
// orient3d(p0,p2,q0,q2) >= 0 (with our sign convention, det[b-a,c-a,d-a]).
// Coplanar triangles are tested in the coordinate plane where their
// projection is exactly non-degenerate. Zero-area triangles are treated as the
// segment or point they are (collinear vertices: the segment between the two
// extreme ones).
#pragma once

#include "kernels/predicates.h"

#include <algorithm>
#include <utility>

namespace plancheck {

namespace tri_overlap_detail {

using P = const double*;

inline bool same_point(P a, P b) noexcept { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }

// Exact test that a, b, c are collinear (all three projected 2D determinants
// are zero, i.e. (b-a) x (c-a) == 0). Also returns the projected signs: s[k]
// is the sign of the normal's k component (projection dropping axis k).
inline bool collinear(P a, P b, P c, int s[3]) noexcept {
  s[0] = orient2d_projected(a, b, c, 1, 2);
  s[1] = orient2d_projected(a, b, c, 2, 0);
  s[2] = orient2d_projected(a, b, c, 0, 1);
  return s[0] == 0 && s[1] == 0 && s[2] == 0;
}

inline bool collinear(P a, P b, P c) noexcept {
  int s[3];
  return collinear(a, b, c, s);
}

// A triangle as the simplex it really is.
struct Simplex {
  int dim = 2;        // 0 point, 1 segment, 2 triangle
  P v[3] = {};        // dim+1 meaningful vertices
  int drop = 2;       // dim 2: axis whose removal keeps the triangle non-degenerate
};

inline Simplex classify(P a, P b, P c) noexcept {
  Simplex s;
  // Fast path: the largest normal component certified non-zero by the
  // orient2d filter proves a proper triangle and is the axis the exact path
  // below would drop, so the answer is the same. Without it an axis-aligned
  // triangle (two components exactly zero, common in CAD models) costs two
  // exact evaluations per call.
  {
    using namespace predicate_detail;
    const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
    const double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
    const double l[3] = {uy * vz, uz * vx, ux * vy};
    const double r[3] = {uz * vy, ux * vz, uy * vx};
    int k = 0;
    double best = -1.0;
    for (int i = 0; i < 3; ++i)
      if (std::abs(l[i] - r[i]) > best) {
        best = std::abs(l[i] - r[i]);
        k = i;
      }
    const double mag = std::abs(l[k]) + std::abs(r[k]);
    if (mag > kUnderflowGuard && best > kOrient2dBound * mag) {
      s.dim = 2;
      s.v[0] = a;
      s.v[1] = b;
      s.v[2] = c;
      s.drop = k;
      return s;
    }
  }
  int sg[3];
  if (!collinear(a, b, c, sg)) {
    s.dim = 2;
    s.v[0] = a;
    s.v[1] = b;
    s.v[2] = c;
    // Prefer the axis with the largest normal component (best conditioned);
    // any axis with an exactly non-zero component would be correct.
    const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
    const double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
    const double n[3] = {std::abs(uy * vz - uz * vy), std::abs(uz * vx - ux * vz),
                         std::abs(ux * vy - uy * vx)};
    int best = -1;
    for (int k = 0; k < 3; ++k)
      if (sg[k] != 0 && (best < 0 || n[k] > n[best])) best = k;
    s.drop = best;
    return s;
  }
  if (same_point(a, b) && same_point(a, c)) {
    s.dim = 0;
    s.v[0] = a;
    return s;
  }
  // Collinear, not all equal: the extreme points along an axis on which they
  // are not all equal (that axis orders the points of the line).
  int axis = 0;
  while (a[axis] == b[axis] && a[axis] == c[axis]) ++axis;
  P lo = a, hi = a;
  for (P p : {b, c}) {
    if (p[axis] < lo[axis]) lo = p;
    if (p[axis] > hi[axis]) hi = p;
  }
  s.dim = 1;
  s.v[0] = lo;
  s.v[1] = hi;
  return s;
}

inline void other_axes(int drop, int& i, int& j) noexcept {
  i = (drop + 1) % 3;
  j = (drop + 2) % 3;
}

// Closed 1D interval overlap of [a,b] and [c,d] (unordered ends).
inline bool intervals_overlap(double a, double b, double c, double d) noexcept {
  if (a > b) std::swap(a, b);
  if (c > d) std::swap(c, d);
  return std::max(a, c) <= std::min(b, d);
}

// Closed segment-segment test in the (i, j) projection; segments may be points.
inline bool seg_seg_2d(P a, P b, P c, P d, int i, int j) noexcept {
  const int d1 = orient2d_projected(a, b, c, i, j);
  const int d2 = orient2d_projected(a, b, d, i, j);
  if (d1 * d2 > 0) return false;
  const int d3 = orient2d_projected(c, d, a, i, j);
  const int d4 = orient2d_projected(c, d, b, i, j);
  if (d3 * d4 > 0) return false;
  if (d1 == 0 && d2 == 0 && d3 == 0 && d4 == 0) {
    // All on one line (or points): compare along an axis that orders it.
    const int k = (a[i] == b[i] && a[i] == c[i] && a[i] == d[i]) ? j : i;
    return intervals_overlap(a[k], b[k], c[k], d[k]);
  }
  return true;
}

// Closed point-in-triangle in the (i, j) projection; the projected triangle
// must be non-degenerate.
inline bool point_in_tri_2d(P r, P t0, P t1, P t2, int i, int j) noexcept {
  const int s0 = orient2d_projected(t0, t1, r, i, j);
  const int s1 = orient2d_projected(t1, t2, r, i, j);
  const int s2 = orient2d_projected(t2, t0, r, i, j);
  return (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
}

inline bool seg_tri_2d(P a, P b, P t0, P t1, P t2, int i, int j) noexcept {
  return point_in_tri_2d(a, t0, t1, t2, i, j) || point_in_tri_2d(b, t0, t1, t2, i, j) ||
         seg_seg_2d(a, b, t0, t1, i, j) || seg_seg_2d(a, b, t1, t2, i, j) ||
         seg_seg_2d(a, b, t2, t0, i, j);
}

inline bool tri_tri_2d(const P p[3], const P q[3], int i, int j) noexcept {
  for (int e = 0; e < 3; ++e)
    for (int f = 0; f < 3; ++f)
      if (seg_seg_2d(p[e], p[(e + 1) % 3], q[f], q[(f + 1) % 3], i, j)) return true;
  return point_in_tri_2d(p[0], q[0], q[1], q[2], i, j) ||
         point_in_tri_2d(q[0], p[0], p[1], p[2], i, j);
}

// Point r on the closed segment [a, b] (a may equal b).
inline bool point_on_segment(P r, P a, P b) noexcept {
  if (!collinear(a, b, r)) return false;
  for (int k = 0; k < 3; ++k)
    if (r[k] < std::min(a[k], b[k]) || r[k] > std::max(a[k], b[k])) return false;
  return true;
}

inline bool seg_seg_3d(P a, P b, P c, P d) noexcept {
  if (same_point(a, b)) return point_on_segment(a, c, d);
  if (same_point(c, d)) return point_on_segment(c, a, b);
  if (orient3d(a, b, c, d) != 0) return false;
  int sc[3], sd[3];
  const bool c_on = collinear(a, b, c, sc);
  const bool d_on = collinear(a, b, d, sd);
  if (c_on && d_on) {
    int k = 0;
    while (a[k] == b[k]) ++k;
    return intervals_overlap(a[k], b[k], c[k], d[k]);
  }
  // Coplanar, one plane: drop an axis on which the plane's normal is non-zero.
  const int* s = c_on ? sd : sc;
  int drop = 0;
  while (s[drop] == 0) ++drop;
  int i, j;
  other_axes(drop, i, j);
  return seg_seg_2d(a, b, c, d, i, j);
}

inline bool point_tri_3d(P r, const Simplex& t) noexcept {
  if (orient3d(t.v[0], t.v[1], t.v[2], r) != 0) return false;
  int i, j;
  other_axes(t.drop, i, j);
  return point_in_tri_2d(r, t.v[0], t.v[1], t.v[2], i, j);
}

inline bool seg_tri_3d(P a, P b, const Simplex& t) noexcept {
  const int sa = orient3d(t.v[0], t.v[1], t.v[2], a);
  const int sb = orient3d(t.v[0], t.v[1], t.v[2], b);
  if (sa * sb > 0) return false;
  if (sa == 0 && sb == 0) {
    int i, j;
    other_axes(t.drop, i, j);
    return seg_tri_2d(a, b, t.v[0], t.v[1], t.v[2], i, j);
  }
  // The segment meets the plane in one point; it is inside the closed
  // triangle iff the line ab sees the three edges with one orientation
  // (Pluecker-style sign test).
  const int s0 = orient3d(a, b, t.v[0], t.v[1]);
  const int s1 = orient3d(a, b, t.v[1], t.v[2]);
  const int s2 = orient3d(a, b, t.v[2], t.v[0]);
  return (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
}

// Index of the vertex alone on one closed side, and that side's sign (see
// the file comment). Requires signs not all zero and not all equal non-zero.
inline void lone_vertex(const int s[3], int& index, int& side) noexcept {
  for (int k = 0; k < 3; ++k) {
    const int o1 = s[(k + 1) % 3], o2 = s[(k + 2) % 3];
    if (s[k] != 0 && o1 * s[k] <= 0 && o2 * s[k] <= 0) {
      index = k;
      side = s[k];
      return;
    }
  }
  // Pattern (0, +, +) up to rotation and sign: the zero vertex is alone on
  // the closed side opposite to the other two.
  for (int k = 0; k < 3; ++k)
    if (s[k] == 0) {
      index = k;
      side = -s[(k + 1) % 3];
      return;
    }
  index = 0;
  side = 1;
}

inline bool tri_tri_3d(const Simplex& ps, const Simplex& qs) noexcept {
  P p[3] = {ps.v[0], ps.v[1], ps.v[2]};
  P q[3] = {qs.v[0], qs.v[1], qs.v[2]};
  int sp[3], sq[3];
  for (int k = 0; k < 3; ++k) sp[k] = orient3d(q[0], q[1], q[2], p[k]);
  if (sp[0] == sp[1] && sp[1] == sp[2] && sp[0] != 0) return false;
  for (int k = 0; k < 3; ++k) sq[k] = orient3d(p[0], p[1], p[2], q[k]);
  if (sq[0] == sq[1] && sq[1] == sq[2] && sq[0] != 0) return false;
  if ((sq[0] == 0 && sq[1] == 0 && sq[2] == 0) || (sp[0] == 0 && sp[1] == 0 && sp[2] == 0)) {
    int i, j;
    other_axes(ps.drop, i, j);
    return tri_tri_2d(p, q, i, j);
  }
  int k, side;
  lone_vertex(sp, k, side);
  P pr[3] = {p[k], p[(k + 1) % 3], p[(k + 2) % 3]};
  if (side < 0) {  // reverse q so p's lone vertex is on its positive side
    std::swap(q[1], q[2]);
    std::swap(sq[1], sq[2]);
  }
  lone_vertex(sq, k, side);
  P qr[3] = {q[k], q[(k + 1) % 3], q[(k + 2) % 3]};
  if (side < 0) std::swap(pr[1], pr[2]);
  return orient3d(pr[0], pr[1], qr[0], qr[1]) <= 0 && orient3d(pr[0], pr[2], qr[0], qr[2]) >= 0;
}

}  // namespace tri_overlap_detail

// Exact closed intersection test of triangles (p0, p1, p2) and (q0, q1, q2),
// each vertex a pointer to 3 doubles.
inline bool tri_tri_overlap(const double* p0, const double* p1, const double* p2,
                            const double* q0, const double* q1, const double* q2) noexcept {
  using namespace tri_overlap_detail;
  // Early out, valid for any degeneracy: a zero-area triangle gives orient3d
  // == 0 for every point, so three equal non-zero signs mean a proper plane
  // with the whole other simplex strictly on one side.
  const int s0 = orient3d(p0, p1, p2, q0);
  if (s0 != 0 && s0 == orient3d(p0, p1, p2, q1) && s0 == orient3d(p0, p1, p2, q2)) return false;
  const int t0 = orient3d(q0, q1, q2, p0);
  if (t0 != 0 && t0 == orient3d(q0, q1, q2, p1) && t0 == orient3d(q0, q1, q2, p2)) return false;
  const Simplex a = classify(p0, p1, p2);
  const Simplex b = classify(q0, q1, q2);
  const Simplex& hi = a.dim >= b.dim ? a : b;
  const Simplex& lo = a.dim >= b.dim ? b : a;
  switch (hi.dim * 3 + lo.dim) {
    case 8: return tri_tri_3d(hi, lo);
    case 7: return seg_tri_3d(lo.v[0], lo.v[1], hi);
    case 6: return point_tri_3d(lo.v[0], hi);
    case 4: return seg_seg_3d(hi.v[0], hi.v[1], lo.v[0], lo.v[1]);
    case 3: return point_on_segment(lo.v[0], hi.v[0], hi.v[1]);
    default: return same_point(hi.v[0], lo.v[0]);
  }
}

}  // namespace plancheck
