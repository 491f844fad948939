// SPDX-License-Identifier: MIT
// The exact distance of two disjoint triangles (tri_distance_disjoint2 in
// kernels/tri_distance.h) with its 15 candidate feature pairs computed side
// by side in double lanes: the 9 edge pairs in one run of lanes, the 6
// vertex-face pairs in another. Every branch of the scalar kernel becomes a
// select between paths computed in full, each path with the very IEEE
// operations, in the same order, as the scalar code (Eigen's 3-vector dot
// product and squared norm add left to right: (x x' + y y') + z z'). With
// -ffp-contract=off (kernels/CMakeLists.txt) every lane value is therefore
// bitwise the scalar one, and the winner is taken as the scalar kernel takes
// it: the first candidate, in its order, with the strictly smallest squared
// distance. The scalar kernel branches on Voronoi regions and clamps, which
// random triangle pairs mispredict often; here nothing depends on the data
// but the final scan. Included only by kernels/leaf_bounds_<isa>.cpp files
// with their lane type D = lanes::VDouble<W, Tag>.
#pragma once

#include "kernels/lanes.h"

#include <algorithm>
#include <limits>

namespace plancheck::tri_distance_lanes {

template <class D>
struct V3 {
  D x, y, z;
};

template <class D>
inline V3<D> sub(const V3<D>& a, const V3<D>& b) noexcept {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
// a + s b, per component (Eigen's a + s * b).
template <class D>
inline V3<D> axpy(const V3<D>& a, D s, const V3<D>& b) noexcept {
  return {a.x + s * b.x, a.y + s * b.y, a.z + s * b.z};
}
template <class D>
inline D dot(const V3<D>& a, const V3<D>& b) noexcept {
  return a.x * b.x + a.y * b.y + a.z * b.z;  // left to right, as Eigen's Vector3d
}
template <class D>
inline V3<D> pick(typename D::M m, const V3<D>& a, const V3<D>& b) noexcept {
  return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z)};
}
template <class D>
inline V3<D> load3(const double (*c)[16], int at) noexcept {
  return {D::load(&c[0][at]), D::load(&c[1][at]), D::load(&c[2][at])};
}
template <class D>
inline void store3(const V3<D>& v, double (*c)[16], int at) noexcept {
  v.x.store(&c[0][at]);
  v.y.store(&c[1][at]);
  v.z.store(&c[2][at]);
}

// clamp01 of the scalar kernel: x < 0 ? 0 : (x > 1 ? 1 : x).
template <class D>
inline D clamp01(D x) noexcept {
  const D zero = D::broadcast(0.0), one = D::broadcast(1.0);
  return select(x.v < zero.v, zero, select(x.v > one.v, one, x));
}

// segment_segment for the lanes' segments [p1, q1], [p2, q2]: closest points
// c1, c2 and the squared distance.
template <class D>
inline D segments(const V3<D>& p1, const V3<D>& q1, const V3<D>& p2, const V3<D>& q2, V3<D>& c1,
                  V3<D>& c2) noexcept {
  const D zero = D::broadcast(0.0), one = D::broadcast(1.0);
  const V3<D> d1 = sub(q1, p1), d2 = sub(q2, p2), r = sub(p1, p2);
  const D a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r);
  const D c = dot(d1, r), b = dot(d1, d2);
  const auto az = a.v == zero.v, ez = e.v == zero.v;
  // a == 0 (e != 0): s = 0, t = clamp01(f / e).
  const D t_a0 = clamp01(f / e);
  // e == 0 (a != 0): s = clamp01(-c / a), t = 0.
  const D s_back = clamp01((-c) / a);
  // Both non-zero: the unclamped solution, then the clamps of t.
  const D denom = a * e - b * b;
  const D s0 = select(denom.v > zero.v, clamp01((b * f - c * e) / denom), zero);
  const D t0 = (b * s0 + f) / e;
  const auto t_low = t0.v < zero.v, t_high = t0.v > one.v;
  const D s_high = clamp01((b - c) / a);
  D s = select(t_low, s_back, select(t_high, s_high, s0));
  D t = select(t_low, zero, select(t_high, one, t0));
  // e == 0 (a != 0).
  s = select(ez, s_back, s);
  t = select(ez, zero, t);
  // a == 0: s = 0, and t = 0 too when e == 0.
  s = select(az, zero, s);
  t = select(az, select(ez, zero, t_a0), t);
  c1 = axpy(p1, s, d1);
  c2 = axpy(p2, t, d2);
  const V3<D> w = sub(c1, c2);
  return dot(w, w);
}

// point_triangle for the lanes' points p and triangles (a, b, c): the
// closest point `out` and the squared distance |p - out|^2, or infinity
// where the scalar kernel answers nothing (a zero-area triangle whose
// regions all fail).
template <class D>
inline D point_face(const V3<D>& p, const V3<D>& a, const V3<D>& b, const V3<D>& c, V3<D>& out) noexcept {
  const D zero = D::broadcast(0.0);
  const V3<D> ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  const D d1 = dot(ab, ap), d2 = dot(ac, ap);
  const auto in_a = (d1.v <= zero.v) & (d2.v <= zero.v);
  const V3<D> bp = sub(p, b);
  const D d3 = dot(ab, bp), d4 = dot(ac, bp);
  const auto in_b = (d3.v >= zero.v) & (d4.v <= d3.v);
  const D vc = d1 * d4 - d3 * d2;
  const auto in_ab = (vc.v <= zero.v) & (d1.v >= zero.v) & (d3.v <= zero.v);
  const D den_ab = d1 - d3;
  const V3<D> on_ab = pick(den_ab.v > zero.v, axpy(a, d1 / den_ab, ab), a);
  const V3<D> cp = sub(p, c);
  const D d5 = dot(ab, cp), d6 = dot(ac, cp);
  const auto in_c = (d6.v >= zero.v) & (d5.v <= d6.v);
  const D vb = d5 * d2 - d1 * d6;
  const auto in_ac = (vb.v <= zero.v) & (d2.v >= zero.v) & (d6.v <= zero.v);
  const D den_ac = d2 - d6;
  const V3<D> on_ac = pick(den_ac.v > zero.v, axpy(a, d2 / den_ac, ac), a);
  const D va = d3 * d6 - d5 * d4;
  const D u43 = d4 - d3, u56 = d5 - d6;
  const auto in_bc = (va.v <= zero.v) & (u43.v >= zero.v) & (u56.v >= zero.v);
  const D den_bc = u43 + u56;
  const V3<D> on_bc = pick(den_bc.v > zero.v, axpy(b, u43 / den_bc, sub(c, b)), b);
  const D sum = va + vb + vc;
  const auto inside = sum.v > zero.v;
  const D v = vb / sum, w = vc / sum;
  const V3<D> face = axpy(axpy(a, v, ab), w, ac);
  // The scalar kernel's first region that holds, in its order.
  V3<D> q = face;
  q = pick(in_bc, on_bc, q);
  q = pick(in_ac, on_ac, q);
  q = pick(in_c, c, q);
  q = pick(in_ab, on_ab, q);
  q = pick(in_b, b, q);
  q = pick(in_a, a, q);
  out = q;
  const auto answered = in_a | in_b | in_ab | in_c | in_ac | in_bc | inside;
  const V3<D> g = sub(p, q);
  return select(answered, dot(g, g), D::broadcast(std::numeric_limits<double>::infinity()));
}

// tri_distance_disjoint2(p, q, p_out, q_out), bitwise: returns the squared
// distance, p_out and q_out get the closest points (3 doubles each).
template <class D>
double disjoint2(const double* p, const double* q, double* p_out, double* q_out) noexcept {
  constexpr int W = D::kWidth;
  // Registers of W lanes; lanes left over fill one more register (padded
  // with copies of lane 0) when they are at least half of it, else go one at
  // a time: wide divisions cost more than narrow ones, so a nearly empty wide
  // register is slower than its few lanes alone.
  constexpr auto lanes_for = [](int n) { return n % W * 2 >= W ? (n + W - 1) / W * W : n / W * W; };
  constexpr int kSeg = lanes_for(9), kPt = lanes_for(6);
  using D1 = typename D::One;
  // Lane inputs (SoA, component-major).
  alignas(64) double s_p1[3][16], s_q1[3][16], s_p2[3][16], s_q2[3][16];
  alignas(64) double f_p[3][16], f_a[3][16], f_b[3][16], f_c[3][16];
  for (int l = 0; l < std::max(9, kSeg); ++l) {
    const int k = l < 9 ? l : 0, i = k / 3, j = k % 3;
    for (int x = 0; x < 3; ++x) {
      s_p1[x][l] = p[3 * i + x];
      s_q1[x][l] = p[3 * ((i + 1) % 3) + x];
      s_p2[x][l] = q[3 * j + x];
      s_q2[x][l] = q[3 * ((j + 1) % 3) + x];
    }
  }
  // Vertex-face lanes in the scalar kernel's order: p_i on q, then q_i on p.
  for (int l = 0; l < std::max(6, kPt); ++l) {
    const int k = l < 6 ? l : 0, i = k / 2;
    const double* point = (k % 2 == 0 ? p : q) + 3 * i;
    const double* tri = k % 2 == 0 ? q : p;
    for (int x = 0; x < 3; ++x) {
      f_p[x][l] = point[x];
      f_a[x][l] = tri[x];
      f_b[x][l] = tri[3 + x];
      f_c[x][l] = tri[6 + x];
    }
  }
  alignas(64) double s_d[16], s_c1[3][16], s_c2[3][16], f_d[16], f_o[3][16];
  for (int l = 0; l < kSeg; l += W) {
    V3<D> c1, c2;
    segments<D>(load3<D>(s_p1, l), load3<D>(s_q1, l), load3<D>(s_p2, l), load3<D>(s_q2, l), c1, c2)
        .store(&s_d[l]);
    store3(c1, s_c1, l);
    store3(c2, s_c2, l);
  }
  for (int l = kSeg; l < 9; ++l) {
    V3<D1> c1, c2;
    segments<D1>(load3<D1>(s_p1, l), load3<D1>(s_q1, l), load3<D1>(s_p2, l), load3<D1>(s_q2, l), c1, c2)
        .store(&s_d[l]);
    store3(c1, s_c1, l);
    store3(c2, s_c2, l);
  }
  for (int l = 0; l < kPt; l += W) {
    V3<D> o;
    point_face<D>(load3<D>(f_p, l), load3<D>(f_a, l), load3<D>(f_b, l), load3<D>(f_c, l), o).store(&f_d[l]);
    store3(o, f_o, l);
  }
  for (int l = kPt; l < 6; ++l) {
    V3<D1> o;
    point_face<D1>(load3<D1>(f_p, l), load3<D1>(f_a, l), load3<D1>(f_b, l), load3<D1>(f_c, l), o).store(&f_d[l]);
    store3(o, f_o, l);
  }
  // The scalar kernel's Best::offer: the first strictly smallest.
  double best = std::numeric_limits<double>::infinity();
  int at = -1;
  for (int k = 0; k < 9; ++k)
    if (s_d[k] < best) best = s_d[k], at = k;
  for (int k = 0; k < 6; ++k)
    if (f_d[k] < best) best = f_d[k], at = 9 + k;
  if (at < 0) {  // nothing offered: the scalar kernel's zero points
    for (int x = 0; x < 3; ++x) p_out[x] = q_out[x] = 0.0;
    return best;
  }
  for (int x = 0; x < 3; ++x) {
    if (at < 9) {
      p_out[x] = s_c1[x][at];
      q_out[x] = s_c2[x][at];
    } else if ((at - 9) % 2 == 0) {  // p's vertex on q
      p_out[x] = f_p[x][at - 9];
      q_out[x] = f_o[x][at - 9];
    } else {  // q's vertex on p
      p_out[x] = f_o[x][at - 9];
      q_out[x] = f_p[x][at - 9];
    }
  }
  return best;
}

}  // namespace plancheck::tri_distance_lanes
