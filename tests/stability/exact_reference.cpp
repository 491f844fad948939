// SPDX-License-Identifier: MIT
#include "stability/exact_reference.h"

#include <CGAL/Exact_rational.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/intersections.h>
#include <CGAL/squared_distance_3.h>

#include <cmath>
#include <vector>

namespace plancheck::stability {

namespace {

using FT = CGAL::Exact_rational;
using K = CGAL::Simple_cartesian<FT>;
using Point = K::Point_3;
using Segment = K::Segment_3;
using Triangle = K::Triangle_3;

// A triangle as the simplex it exactly is.
struct Simplex {
  int dim = 2;
  Point v[3];
};

Simplex classify(const Point& a, const Point& b, const Point& c) {
  Simplex s;
  if (!CGAL::collinear(a, b, c)) {
    s.dim = 2;
    s.v[0] = a;
    s.v[1] = b;
    s.v[2] = c;
    return s;
  }
  if (a == b && b == c) {
    s.dim = 0;
    s.v[0] = a;
    return s;
  }
  // Collinear: the two extreme points (lexicographic order orders a line).
  Point lo = a, hi = a;
  for (const Point& p : {b, c}) {
    if (CGAL::compare_xyz(p, lo) == CGAL::SMALLER) lo = p;
    if (CGAL::compare_xyz(p, hi) == CGAL::LARGER) hi = p;
  }
  s.dim = 1;
  s.v[0] = lo;
  s.v[1] = hi;
  return s;
}

bool intersects(const Simplex& a, const Simplex& b) {
  if (a.dim < b.dim) return intersects(b, a);
  const Triangle ta(a.v[0], a.v[1], a.v[2]);
  const Segment sa(a.v[0], a.v[1]);
  switch (a.dim * 3 + b.dim) {
    case 8: return CGAL::do_intersect(ta, Triangle(b.v[0], b.v[1], b.v[2]));
    case 7: return CGAL::do_intersect(ta, Segment(b.v[0], b.v[1]));
    case 6: return ta.has_on(b.v[0]);
    case 4: return CGAL::do_intersect(sa, Segment(b.v[0], b.v[1]));
    case 3: return sa.has_on(b.v[0]);
    default: return a.v[0] == b.v[0];
  }
}

// Squared distance point - simplex.
FT point_sq(const Point& p, const Simplex& s) {
  switch (s.dim) {
    case 2: return CGAL::squared_distance(p, Triangle(s.v[0], s.v[1], s.v[2]));
    case 1: return CGAL::squared_distance(p, Segment(s.v[0], s.v[1]));
    default: return CGAL::squared_distance(p, s.v[0]);
  }
}

// Edges of a simplex (a segment is its own single edge; a point has none).
std::vector<Segment> edges(const Simplex& s) {
  if (s.dim == 2)
    return {Segment(s.v[0], s.v[1]), Segment(s.v[1], s.v[2]), Segment(s.v[2], s.v[0])};
  if (s.dim == 1) return {Segment(s.v[0], s.v[1])};
  return {};
}

// Exact squared distance of two disjoint simplices: the minimum is attained
// at a vertex of one against the other, or between two edges.
FT disjoint_sq(const Simplex& a, const Simplex& b) {
  FT best = CGAL::squared_distance(a.v[0], b.v[0]);
  for (int i = 0; i <= a.dim; ++i) best = CGAL::min(best, point_sq(a.v[i], b));
  for (int i = 0; i <= b.dim; ++i) best = CGAL::min(best, point_sq(b.v[i], a));
  for (const Segment& ea : edges(a))
    for (const Segment& eb : edges(b)) best = CGAL::min(best, CGAL::squared_distance(ea, eb));
  return best;
}

ExactAnswer answer_of(bool overlap, const FT& sq) {
  ExactAnswer r;
  r.overlap = overlap;
  r.distance_is_zero = CGAL::is_zero(sq);
  r.distance = std::sqrt(CGAL::to_double(sq));
  return r;
}

Point point_of(const Vec3& v) { return Point(v.x(), v.y(), v.z()); }

}  // namespace

ExactAnswer exact_tri_tri(const double* p, const double* q) {
  const Simplex a = classify(Point(p[0], p[1], p[2]), Point(p[3], p[4], p[5]), Point(p[6], p[7], p[8]));
  const Simplex b = classify(Point(q[0], q[1], q[2]), Point(q[3], q[4], q[5]), Point(q[6], q[7], q[8]));
  if (intersects(a, b)) return answer_of(true, FT(0));
  return answer_of(false, disjoint_sq(a, b));
}

ExactAnswer exact_mesh_mesh(const Mesh& a, const Affine& ta, const Mesh& b, const Affine& tb) {
  auto posed = [](const Mesh& m, const Affine& t) {
    std::vector<Point> out;
    out.reserve(m.vertices.size());
    for (const Vec3& v : m.vertices) out.push_back(point_of(t * v));
    return out;
  };
  const std::vector<Point> va = posed(a, ta), vb = posed(b, tb);
  bool overlap = false;
  FT best = -1;
  for (const Tri& x : a.triangles) {
    const Simplex sa = classify(va[x[0]], va[x[1]], va[x[2]]);
    for (const Tri& y : b.triangles) {
      const Simplex sb = classify(vb[y[0]], vb[y[1]], vb[y[2]]);
      if (intersects(sa, sb)) {
        overlap = true;
        best = 0;
        continue;
      }
      if (overlap) continue;
      const FT d = disjoint_sq(sa, sb);
      if (best < 0 || d < best) best = d;
    }
  }
  return answer_of(overlap, best);
}

}  // namespace plancheck::stability
