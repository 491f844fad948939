// SPDX-License-Identifier: MIT
#include "brute_force.h"

#include "kernels/tri_distance.h"
#include "kernels/tri_tri_overlap.h"

#include <gmpxx.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace plancheck::testing {
namespace {

using Q3 = std::array<mpq_class, 3>;

Q3 to_q(const Vec3& v) { return {mpq_class(v.x()), mpq_class(v.y()), mpq_class(v.z())}; }
Q3 sub(const Q3& a, const Q3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Q3 add(const Q3& a, const Q3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Q3 scale(const mpq_class& s, const Q3& a) { return {s * a[0], s * a[1], s * a[2]}; }
mpq_class dot(const Q3& a, const Q3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Q3 cross(const Q3& a, const Q3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
bool is_zero(const Q3& a) { return sgn(a[0]) == 0 && sgn(a[1]) == 0 && sgn(a[2]) == 0; }

// Closed segments [p, p+u] and [q, q+v] in rationals, by solving for the
// meeting parameters.
bool segments_meet(const Q3& p, const Q3& p2, const Q3& q, const Q3& q2) {
  const Q3 u = sub(p2, p), v = sub(q2, q), r = sub(q, p);
  const bool u0 = is_zero(u), v0 = is_zero(v);
  if (u0 && v0) return is_zero(r);
  if (u0 || v0) {
    // point x on segment [s, s+d]
    const Q3& d = u0 ? v : u;
    const Q3 x = u0 ? sub(p, q) : r;  // x - s
    if (!is_zero(cross(x, d))) return false;
    const mpq_class t = dot(x, d);
    return sgn(t) >= 0 && t <= dot(d, d);
  }
  const Q3 w = cross(u, v);
  if (is_zero(w)) {
    if (!is_zero(cross(r, u))) return false;  // parallel lines, not the same
    const mpq_class uu = dot(u, u);
    mpq_class a = dot(r, u), b = dot(add(r, v), u);
    if (a > b) std::swap(a, b);
    return std::max(a, mpq_class(0)) <= std::min(b, uu);
  }
  if (sgn(dot(r, w)) != 0) return false;  // skew lines
  const mpq_class ww = dot(w, w);
  const mpq_class s = dot(cross(r, v), w) / ww;
  const mpq_class t = dot(cross(r, u), w) / ww;
  return sgn(s) >= 0 && s <= 1 && sgn(t) >= 0 && t <= 1;
}

// x (on the plane of proper triangle a,b,c with normal n) inside the closed triangle.
bool inside(const Q3& x, const Q3& a, const Q3& b, const Q3& c, const Q3& n) {
  const int s0 = sgn(dot(cross(sub(b, a), sub(x, a)), n));
  const int s1 = sgn(dot(cross(sub(c, b), sub(x, b)), n));
  const int s2 = sgn(dot(cross(sub(a, c), sub(x, c)), n));
  return s0 >= 0 && s1 >= 0 && s2 >= 0;  // n orients the triangle counter-clockwise
}

// Closed segment [s, t] against the closed triangle t3 (maybe degenerate).
bool segment_meets_triangle(const Q3& s, const Q3& t, const std::array<Q3, 3>& tri) {
  const Q3 n = cross(sub(tri[1], tri[0]), sub(tri[2], tri[0]));
  if (is_zero(n)) {
    for (int i = 0; i < 3; ++i)
      if (segments_meet(s, t, tri[i], tri[(i + 1) % 3])) return true;
    return false;
  }
  const mpq_class fs = dot(n, sub(s, tri[0])), ft = dot(n, sub(t, tri[0]));
  if ((sgn(fs) > 0 && sgn(ft) > 0) || (sgn(fs) < 0 && sgn(ft) < 0)) return false;
  if (sgn(fs) == 0 && sgn(ft) == 0) {
    if (inside(s, tri[0], tri[1], tri[2], n) || inside(t, tri[0], tri[1], tri[2], n)) return true;
    for (int i = 0; i < 3; ++i)
      if (segments_meet(s, t, tri[i], tri[(i + 1) % 3])) return true;
    return false;
  }
  const mpq_class lambda = fs / (fs - ft);
  const Q3 x = add(s, scale(lambda, sub(t, s)));
  return inside(x, tri[0], tri[1], tri[2], n);
}

using L3 = std::array<long double, 3>;
L3 L(const Vec3& v) { return {v.x(), v.y(), v.z()}; }
L3 lsub(const L3& a, const L3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
long double ldot(const L3& a, const L3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
L3 lcross(const L3& a, const L3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
L3 lmad(const L3& a, long double s, const L3& d) {
  return {a[0] + s * d[0], a[1] + s * d[1], a[2] + s * d[2]};
}
long double lnorm(const L3& a) { return std::sqrt(ldot(a, a)); }

long double point_segment(const L3& x, const L3& a, const L3& b) {
  const L3 d = lsub(b, a);
  const long double dd = ldot(d, d);
  long double t = dd > 0 ? ldot(lsub(x, a), d) / dd : 0;
  t = std::clamp(t, 0.0L, 1.0L);
  return lnorm(lsub(x, lmad(a, t, d)));
}

long double segment_segment(const L3& a, const L3& b, const L3& c, const L3& d) {
  long double best = std::min({point_segment(a, c, d), point_segment(b, c, d),
                               point_segment(c, a, b), point_segment(d, a, b)});
  const L3 u = lsub(b, a), v = lsub(d, c), r = lsub(c, a);
  const long double uu = ldot(u, u), vv = ldot(v, v), uv = ldot(u, v);
  const long double det = uu * vv - uv * uv;
  if (det > 1e-30L * uu * vv) {
    // Stationary point of |a + s u - c - t v|^2.
    const long double ru = ldot(r, u), rv = ldot(r, v);
    const long double s = (ru * vv - rv * uv) / det;
    const long double t = (ru * uv - rv * uu) / det;
    if (s >= 0 && s <= 1 && t >= 0 && t <= 1)
      best = std::min(best, lnorm(lsub(lmad(a, s, u), lmad(c, t, v))));
  }
  return best;
}

long double point_triangle(const L3& x, const L3& a, const L3& b, const L3& c) {
  long double best = std::min({point_segment(x, a, b), point_segment(x, b, c),
                               point_segment(x, c, a)});
  const L3 n = lcross(lsub(b, a), lsub(c, a));
  const long double nn = ldot(n, n);
  if (nn > 0) {
    const long double h = ldot(lsub(x, a), n) / nn;
    const L3 y = lmad(x, -h, n);  // projection on the plane
    const long double s0 = ldot(lcross(lsub(b, a), lsub(y, a)), n);
    const long double s1 = ldot(lcross(lsub(c, b), lsub(y, b)), n);
    const long double s2 = ldot(lcross(lsub(a, c), lsub(y, c)), n);
    if (s0 >= 0 && s1 >= 0 && s2 >= 0) best = std::min(best, std::abs(h) * std::sqrt(nn));
  }
  return best;
}

}  // namespace

bool exact_tri_tri_reference(const Vec3 p[3], const Vec3 q[3]) {
  const std::array<Q3, 3> pq = {to_q(p[0]), to_q(p[1]), to_q(p[2])};
  const std::array<Q3, 3> qq = {to_q(q[0]), to_q(q[1]), to_q(q[2])};
  for (int i = 0; i < 3; ++i) {
    if (segment_meets_triangle(pq[i], pq[(i + 1) % 3], qq)) return true;
    if (segment_meets_triangle(qq[i], qq[(i + 1) % 3], pq)) return true;
  }
  return false;
}

long double reference_tri_distance(const Vec3 p[3], const Vec3 q[3]) {
  const L3 a[3] = {L(p[0]), L(p[1]), L(p[2])}, b[3] = {L(q[0]), L(q[1]), L(q[2])};
  long double best = std::numeric_limits<long double>::infinity();
  for (int i = 0; i < 3; ++i) {
    best = std::min(best, point_triangle(a[i], b[0], b[1], b[2]));
    best = std::min(best, point_triangle(b[i], a[0], a[1], a[2]));
    for (int j = 0; j < 3; ++j)
      best = std::min(best, segment_segment(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3]));
  }
  return best;
}

std::vector<Vec3> posed_vertices(const Mesh& mesh, const Affine& t) {
  std::vector<Vec3> out;
  out.reserve(mesh.vertices.size());
  for (const Vec3& v : mesh.vertices) out.push_back(t * v);
  return out;
}

namespace {
struct Box {
  Vec3 lo, hi;
};
std::vector<Box> triangle_boxes(const Mesh& m, const std::vector<Vec3>& v) {
  std::vector<Box> boxes;
  boxes.reserve(m.triangles.size());
  for (const Tri& t : m.triangles) {
    Box b{v[t[0]], v[t[0]]};
    for (int k = 1; k < 3; ++k) {
      b.lo = b.lo.cwiseMin(v[t[k]]);
      b.hi = b.hi.cwiseMax(v[t[k]]);
    }
    boxes.push_back(b);
  }
  return boxes;
}
}  // namespace

std::vector<std::pair<std::uint32_t, std::uint32_t>> brute_force_collide(
    const Mesh& a, const std::vector<Vec3>& va, const Mesh& b, const std::vector<Vec3>& vb,
    bool stop_at_first) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  const auto ba = triangle_boxes(a, va), bb = triangle_boxes(b, vb);
  for (std::uint32_t i = 0; i < a.triangles.size(); ++i)
    for (std::uint32_t j = 0; j < b.triangles.size(); ++j) {
      // Exact box prefilter: disjoint boxes cannot hold touching triangles.
      if ((ba[i].hi.array() < bb[j].lo.array()).any() ||
          (bb[j].hi.array() < ba[i].lo.array()).any())
        continue;
      const Tri& s = a.triangles[i];
      const Tri& t = b.triangles[j];
      if (tri_tri_overlap(va[s[0]].data(), va[s[1]].data(), va[s[2]].data(), vb[t[0]].data(),
                          vb[t[1]].data(), vb[t[2]].data())) {
        pairs.emplace_back(i, j);
        if (stop_at_first) return pairs;
      }
    }
  return pairs;
}

BruteDistance brute_force_distance(const Mesh& a, const std::vector<Vec3>& va, const Mesh& b,
                                   const std::vector<Vec3>& vb) {
  BruteDistance best;
  best.distance = std::numeric_limits<double>::infinity();
  for (std::uint32_t i = 0; i < a.triangles.size(); ++i) {
    double p[9];
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) p[3 * k + c] = va[a.triangles[i][k]][c];
    for (std::uint32_t j = 0; j < b.triangles.size(); ++j) {
      double q[9];
      for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c) q[3 * k + c] = vb[b.triangles[j][k]][c];
      const TriDistance d = tri_distance(p, q);
      if (d.distance < best.distance) {
        best.distance = d.distance;
        best.triangle_a = i;
        best.triangle_b = j;
      }
    }
  }
  return best;
}

}  // namespace plancheck::testing
