// SPDX-License-Identifier: MIT
#include "stability/cases.h"

#include <cmath>

namespace plancheck::stability {

namespace {

// q: a triangle with vertex x, on the side of p's plane that n points to
// (apex directions dyadic, so q is exact; the reference says what it is).
T9 apex_above(Gen& g, const V3& x, const V3& n) {
  for (;;) {
    const V3 u = g.dyadic3(10, 1), v = g.dyadic3(10, 1);
    if (u.dot(n) > 0.1 && v.dot(n) > 0.1 && u.cross(v).norm() > 0.05) return tri(x, x + u, x + v);
  }
}

// The touching configurations (distance exactly 0 by construction).
std::vector<Case> touching_kinds(Gen& g, int per_kind, bool name_kinds) {
  std::vector<Case> out;
  auto add = [&](const char* kind, const T9& p, const T9& q) {
    out.push_back({name_kinds ? std::string("touch ") + kind : std::string(kind), p, q});
  };
  for (int i = 0; i < per_kind; ++i) {
    const T9 p = g.dyadic_triangle();
    const V3 n = normal_of(p);
    // vertex on the face interior
    add("vertex-face", p, apex_above(g, point_at(p, g.weights(false)), n));
    // vertex on an edge, and on a vertex
    add("vertex-edge", p, apex_above(g, point_at(p, g.weights(true)), n));
    add("vertex-vertex", p, apex_above(g, vtx(p, 0), n));
    // an edge lying on the face, and q sharing p's edge
    {
      const V3 a = point_at(p, g.weights(false)), b = point_at(p, g.weights(false));
      add("edge-face", p, tri(a, b, vtx(apex_above(g, a, n), 1)));
      add("edge-edge shared", p, tri(vtx(p, 0), vtx(p, 1), vtx(p, 0) + g.dyadic3(10, 1)));
    }
  }
  return out;
}

}  // namespace

std::vector<Case> touching_cases() {
  Gen g(1);
  return touching_kinds(g, 40, true);
}

std::vector<Case> gap_cases() {
  Gen g(2);
  std::vector<Case> out;
  for (const Case& c : touching_kinds(g, 6, false)) {
    const V3 n = normal_of(c.p);
    for (double gap : decade_gaps()) {
      char name[64];
      std::snprintf(name, sizeof name, "gap %.0e", gap);
      out.push_back({name, c.p, shifted(c.q, gap * n)});
      out.push_back({name, c.p, shifted(c.q, -gap * n)});  // the same depth of penetration
    }
  }
  return out;
}

std::vector<Case> coplanar_cases() {
  Gen g(3);
  std::vector<Case> out;
  for (int i = 0; i < 24; ++i) {
    // Plane o + a u + b v; small-integer u, v (scaled 2^-4), a, b with 40
    // fractional bits: every vertex is exact, so coplanarity is exact.
    V3 o = g.dyadic3(4, 8), u = g.dyadic3(4, 1), v = g.dyadic3(4, 1);
    if (i % 3 == 0) {  // axis-aligned planes too
      o.z() = 0.5;
      u.z() = 0;
      v.z() = 0;
    }
    if (u.cross(v).norm() < 0.1) continue;
    auto at = [&](double a, double b) { return V3(o + a * u + b * v); };
    auto rp = [&]() { return std::array<double, 2>{g.dyadic(40, 1), g.dyadic(40, 1)}; };
    // random pairs (overlap or not, as it comes)
    {
      auto a = rp(), b = rp(), c = rp(), d = rp(), e = rp(), f = rp();
      out.push_back({"coplanar random", tri(at(a[0], a[1]), at(b[0], b[1]), at(c[0], c[1])),
                     tri(at(d[0], d[1]), at(e[0], e[1]), at(f[0], f[1]))});
    }
    // edge against edge across a gap of 2^-k in parameter space (k = 10 .. 40),
    // and the same with the edges overlapping by 2^-k (parameter triangle
    // (0,0) (1,0) (0,1); q mirrored across its long edge).
    for (int k = 10; k <= 40; k += 6) {
      const double d = std::ldexp(1.0, -k);
      const T9 p = tri(at(0, 0), at(0.5, 0), at(0, 0.5));
      out.push_back({"coplanar disjoint", p, tri(at(0.5 + d, d), at(d, 0.5 + d), at(0.5, 0.5))});
      out.push_back({"coplanar overlap", p, tri(at(0.5 - d, -d), at(-d, 0.5 - d), at(0.5, 0.5))});
      out.push_back({"coplanar touching", p, tri(at(0.5, 0), at(0, 0.5), at(0.5 + d, 0.5 + d))});
      // vertex to edge
      out.push_back({"coplanar disjoint", p, tri(at(0.25 + d, 0.25 + d), at(1, 0.5), at(0.5, 1))});
      // one inside the other (containment, no edge crossing)
      out.push_back({"coplanar overlap", p, tri(at(d, d), at(2 * d, d), at(d, 2 * d))});
    }
  }
  return out;
}

std::vector<Case> edge_edge_cases() {
  Gen g(4);
  std::vector<Case> out;
  for (int i = 0; i < 40; ++i) {
    const T9 p = g.dyadic_triangle();
    const V3 x = point_at(p, g.weights(true));  // on edge p0 p1
    const V3 e = vtx(p, 1) - vtx(p, 0);
    // q's edge crosses p's edge at x, from below p's plane to above it,
    // q's third vertex further out beyond p's edge (so only the edges meet).
    const V3 n = normal_of(p);
    const V3 out_dir = e.cross(n);  // in p's plane, away from p2 or toward it
    const V3 away = out_dir.dot(vtx(p, 2) - vtx(p, 0)) > 0 ? V3(-out_dir) : out_dir;
    auto dyadic8 = [](const V3& v) {
      return V3(std::ldexp(std::round(std::ldexp(v.x(), 8)), -8), std::ldexp(std::round(std::ldexp(v.y(), 8)), -8),
                std::ldexp(std::round(std::ldexp(v.z(), 8)), -8));
    };
    const V3 up = dyadic8(n), side = dyadic8(away.normalized());  // exact steps from x
    // q0 q1 passes exactly through x (x +- up are exact); q2 is beyond p's edge.
    const T9 qx = tri(x + up, x - up, x + side + 0.25 * up);
    out.push_back({"edge-edge cross", p, qx});
    // The crossing moved apart along the common perpendicular of the edges.
    const V3 m = e.cross(up).normalized();
    for (double gap : decade_gaps()) {
      char name[64];
      std::snprintf(name, sizeof name, "edge-edge gap %.0e", gap);
      out.push_back({name, p, shifted(qx, (m.dot(side) > 0 ? 1.0 : -1.0) * gap * m)});
    }
  }
  return out;
}

std::vector<Case> grazing_cases() {
  Gen g(5);
  std::vector<Case> out;
  for (int i = 0; i < 8; ++i) {
    // p: a large triangle in z = 0; q's edge comes down onto it at angle t.
    const T9 p = tri(V3(-2, -2, 0), V3(2, -2, 0), V3(0, 2, 0));
    const double phi = g.uniform(0, 6.283);
    const V3 dir(std::cos(phi), std::sin(phi), 0.0);
    const V3 side(-dir.y(), dir.x(), 0.0);
    for (double t : {1e-3, 1e-6, 1e-9, 1e-12}) {
      const double len = 1.0, drop = len * std::sin(t);
      const V3 a = V3(0, 0, 0) - 0.5 * dir;
      for (double h : {0.5 * drop, drop, 2 * drop, 0.0, -0.5 * drop}) {
        const V3 start = a + V3(0, 0, h);
        const V3 end = start + len * (std::cos(t) * dir - std::sin(t) * V3::UnitZ());
        char name[64];
        std::snprintf(name, sizeof name, "grazing %.0e rad", t);
        out.push_back({name, p, tri(start, end, start + 0.3 * side + V3(0, 0, 0.1))});
        // the same edge, ending just short of the face
        out.push_back({name, p, tri(start, start + (1 - 1e-3) * (end - start), start + 0.3 * side + V3(0, 0, 0.1))});
      }
    }
  }
  return out;
}

std::vector<Case> near_parallel_cases() {
  Gen g(6);
  std::vector<Case> out;
  for (int i = 0; i < 8; ++i) {
    const T9 p = g.dyadic_triangle();
    const V3 n = normal_of(p), c = (vtx(p, 0) + vtx(p, 1) + vtx(p, 2)) / 3;
    const V3 axis = (vtx(p, 1) - vtx(p, 0)).normalized();
    for (double t : {1e-3, 1e-6, 1e-9, 1e-12}) {
      const Eigen::AngleAxisd r(t, axis);
      for (double h : {1e-3, 1e-6, 1e-9, 1e-12, 0.0, -1e-9}) {
        // q: p shrunk about its centroid, tilted by t and lifted by h
        T9 q;
        for (int k = 0; k < 3; ++k) {
          const V3 v = c + r * (0.8 * (vtx(p, k) - c)) + h * n;
          q[3 * k] = v.x();
          q[3 * k + 1] = v.y();
          q[3 * k + 2] = v.z();
        }
        char name[64];
        std::snprintf(name, sizeof name, "near-parallel %.0e rad", t);
        out.push_back({name, p, q});
      }
    }
  }
  return out;
}

std::vector<Case> degenerate_cases() {
  Gen g(7);
  std::vector<Case> out;
  for (int i = 0; i < 30; ++i) {
    const T9 p = g.dyadic_triangle();
    const V3 n = normal_of(p);
    const V3 x = point_at(p, g.weights(false)), d = g.dyadic3(10, 1);
    const V3 up = V3(std::ldexp(std::round(std::ldexp(n.x(), 8)), -8), std::ldexp(std::round(std::ldexp(n.y(), 8)), -8),
                     std::ldexp(std::round(std::ldexp(n.z(), 8)), -8));
    // collinear q through a face point (piercing), on the face, and above it
    out.push_back({"collinear", p, tri(x - up, x + 0.5 * up, x + up)});
    out.push_back({"collinear", p, tri(x, x + 0.25 * up, x + up)});           // touching at its end
    out.push_back({"collinear", p, tri(x + 1e-9 * n, x + 0.25 * up, x + up)});  // just above
    out.push_back({"collinear", p, tri(x, x + 0.5 * (vtx(p, 0) - x), vtx(p, 0))});  // lying in the face
    // repeated vertex: a segment written as (a, a, b) in every position
    out.push_back({"repeated vertex", p, tri(x - up, x - up, x + up)});
    out.push_back({"repeated vertex", p, tri(x + 1e-6 * n, x + up, x + 1e-6 * n)});
    out.push_back({"repeated vertex", tri(vtx(p, 0), vtx(p, 0), vtx(p, 1)), tri(x - up, x + d, x + up)});
    // point triangles: on the face, above it, and two points
    out.push_back({"point", p, tri(x, x, x)});
    out.push_back({"point", p, tri(x + 1e-12 * n, x + 1e-12 * n, x + 1e-12 * n)});
    out.push_back({"point", tri(x, x, x), tri(x, x, x)});
    out.push_back({"point", tri(x, x, x), tri(x + d, x + d, x + d)});
    // two collinear triangles (segments) crossing and apart
    out.push_back({"collinear", tri(x - d, x, x + d), tri(x - up, x + up, x)});
    out.push_back({"collinear", tri(x - d, x, x + d), tri(x - up + 1e-10 * d.cross(up).normalized(), x + up, x)});
  }
  return out;
}

std::vector<Case> sliver_cases() {
  Gen g(8);
  std::vector<Case> out;
  for (int i = 0; i < 12; ++i) {
    const T9 p = g.dyadic_triangle();
    const V3 n = normal_of(p);
    const V3 a = vtx(p, 0), b = vtx(p, 1);
    const V3 x = point_at(p, g.weights(false));
    for (double h : {1e-6, 1e-9, 1e-12, 1e-15}) {
      // a sliver standing on p's face (touching along... no: its long edge
      // hovering h above the face, its apex h further), and one crossing p.
      const V3 e = g.dyadic3(10, 1);
      const V3 m = 0.5 * ((x - e) + (x + e));
      const V3 off = h * (e.cross(n)).normalized();
      out.push_back({"sliver", p, tri(x - e, x + e, m + off)});                       // lying in/near the face
      out.push_back({"sliver", p, tri(x - e + h * n, x + e + h * n, m + off + h * n)});  // just above
      out.push_back({"sliver", tri(a, b, 0.5 * (a + b) + h * n), tri(x - n, x + n, x + n + off)});
      out.push_back({"sliver", tri(a, b, 0.5 * (a + b) + h * n), tri(0.5 * (a + b) + n, 0.5 * (a + b) - n, 0.5 * (a + b) + n + off)});
    }
  }
  return out;
}

std::vector<Case> mm_beside_m_cases() {
  Gen g(9);
  std::vector<Case> out;
  for (int i = 0; i < 20; ++i) {
    // a 2 m triangle near (3, 3, 1) m and a 1 mm triangle at its face
    const T9 big = shifted(g.dyadic_triangle(), V3(3, 3, 1));
    const T9 p = tri(vtx(big, 0), 2 * vtx(big, 1) - vtx(big, 0), 2 * vtx(big, 2) - vtx(big, 0));
    const V3 n = normal_of(p);
    const V3 x = point_at(p, g.weights(false));
    for (double h : {0.0, 1e-6, 1e-9, 1e-12, -1e-9}) {
      const V3 u = g.dyadic3(10, 1e-3), v = g.dyadic3(10, 1e-3);
      const V3 apex = x + h * n;
      out.push_back({"mm beside m", p, tri(apex, apex + u + 1e-3 * n, apex + v + 1e-3 * n)});
      out.push_back({"mm beside m", p, tri(apex + u, apex - u, apex + v + 1e-3 * n)});
    }
  }
  return out;
}

std::vector<Case> random_cases() {
  Gen g(10);
  std::vector<Case> out;
  for (int i = 0; i < 200; ++i) {
    const V3 c = V3(g.uniform(-1, 1), g.uniform(-1, 1), g.uniform(-1, 1)) * 0.3;
    T9 p, q;
    for (int k = 0; k < 9; ++k) p[k] = g.uniform(-0.5, 0.5);
    for (int k = 0; k < 9; ++k) q[k] = g.uniform(-0.5, 0.5) + c[k % 3];
    out.push_back({"random", p, q});
  }
  return out;
}

}  // namespace plancheck::stability
