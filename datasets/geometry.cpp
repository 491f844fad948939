// SPDX-License-Identifier: MIT
#include "datasets/geometry.h"

#include <cmath>
#include <stdexcept>

namespace plancheck::dataset {
namespace {
constexpr double kPi = 3.14159265358979323846;
double rad(double deg) { return deg * kPi / 180.0; }
}  // namespace

void basis(const Vec3& n, Vec3& u, Vec3& v) {
  // Pick the helper axis least aligned with n so the cross product is well conditioned.
  Vec3 helper = std::abs(n.z()) < 0.9 ? Vec3::UnitZ() : Vec3::UnitX();
  u = helper.cross(n).normalized();
  v = n.cross(u);
}

std::uint32_t MeshBuilder::add(const Vec3& p) {
  mesh.vertices.push_back(p);
  return static_cast<std::uint32_t>(mesh.vertices.size() - 1);
}

void MeshBuilder::tri(std::uint32_t a, std::uint32_t b, std::uint32_t c) { mesh.triangles.push_back({a, b, c}); }

void MeshBuilder::append(const Mesh& other) {
  auto base = static_cast<std::uint32_t>(mesh.vertices.size());
  mesh.vertices.insert(mesh.vertices.end(), other.vertices.begin(), other.vertices.end());
  for (const Tri& t : other.triangles) tri(t[0] + base, t[1] + base, t[2] + base);
}

void MeshBuilder::frustum(const Vec3& a, const Vec3& b, double ra, double rb, int segments, int rings) {
  Vec3 n = (b - a).normalized(), u, v;
  basis(n, u, v);
  std::vector<std::uint32_t> ring_start;
  for (int k = 0; k <= rings; ++k) {
    double t = static_cast<double>(k) / rings;
    Vec3 c = a + t * (b - a);
    double r = ra + t * (rb - ra);
    ring_start.push_back(static_cast<std::uint32_t>(mesh.vertices.size()));
    for (int i = 0; i < segments; ++i) {
      double phi = 2.0 * kPi * i / segments;
      add(c + r * (std::cos(phi) * u + std::sin(phi) * v));
    }
  }
  auto s = static_cast<std::uint32_t>(segments);
  for (int k = 0; k < rings; ++k) {
    std::uint32_t r0 = ring_start[static_cast<std::size_t>(k)], r1 = ring_start[static_cast<std::size_t>(k) + 1];
    for (std::uint32_t i = 0; i < s; ++i) {
      std::uint32_t j = (i + 1) % s;
      tri(r0 + i, r0 + j, r1 + j);
      tri(r0 + i, r1 + j, r1 + i);
    }
  }
  if (ra > 0) {
    std::uint32_t c = add(a), r0 = ring_start.front();
    for (std::uint32_t i = 0; i < s; ++i) tri(c, r0 + (i + 1) % s, r0 + i);
  }
  if (rb > 0) {
    std::uint32_t c = add(b), r1 = ring_start.back();
    for (std::uint32_t i = 0; i < s; ++i) tri(c, r1 + i, r1 + (i + 1) % s);
  }
}

void MeshBuilder::cone(const Vec3& a, const Vec3& b, double r, int segments) {
  Vec3 n = (b - a).normalized(), u, v;
  basis(n, u, v);
  auto s = static_cast<std::uint32_t>(segments);
  std::uint32_t r0 = static_cast<std::uint32_t>(mesh.vertices.size());
  for (int i = 0; i < segments; ++i) {
    double phi = 2.0 * kPi * i / segments;
    add(a + r * (std::cos(phi) * u + std::sin(phi) * v));
  }
  std::uint32_t apex = add(b), c = add(a);
  for (std::uint32_t i = 0; i < s; ++i) {
    tri(r0 + i, r0 + (i + 1) % s, apex);
    tri(c, r0 + (i + 1) % s, r0 + i);
  }
}

void MeshBuilder::tube(const Vec3& a, const Vec3& b, double r_outer, double wall, int segments) {
  Vec3 n = (b - a).normalized(), u, v;
  basis(n, u, v);
  double ri = r_outer - wall;
  Vec3 floor = a + wall * n;
  auto ring = [&](const Vec3& c, double r) {
    std::uint32_t start = static_cast<std::uint32_t>(mesh.vertices.size());
    for (int i = 0; i < segments; ++i) {
      double phi = 2.0 * kPi * i / segments;
      add(c + r * (std::cos(phi) * u + std::sin(phi) * v));
    }
    return start;
  };
  std::uint32_t ob = ring(a, r_outer), ot = ring(b, r_outer), it = ring(b, ri), ib = ring(floor, ri);
  std::uint32_t cb = add(a), cf = add(floor);
  auto s = static_cast<std::uint32_t>(segments);
  auto band = [&](std::uint32_t r0, std::uint32_t r1) {
    for (std::uint32_t i = 0; i < s; ++i) {
      std::uint32_t j = (i + 1) % s;
      tri(r0 + i, r0 + j, r1 + j);
      tri(r0 + i, r1 + j, r1 + i);
    }
  };
  band(ob, ot);  // outer wall
  band(ot, it);  // rim
  band(it, ib);  // inner wall
  for (std::uint32_t i = 0; i < s; ++i) {
    tri(cb, ob + (i + 1) % s, ob + i);  // outside of the floor
    tri(cf, ib + i, ib + (i + 1) % s);  // inside of the floor
  }
}

void MeshBuilder::box(const Vec3& c, const Vec3& h, const Vec3& ex_in, const Vec3& ey_in, int n) {
  Vec3 ex = ex_in.normalized();
  Vec3 ey = (ey_in - ey_in.dot(ex) * ex).normalized();
  Vec3 ez = ex.cross(ey);
  const Vec3 axes[3] = {ex * h.x(), ey * h.y(), ez * h.z()};
  for (int f = 0; f < 6; ++f) {
    int k = f / 2;
    double sign = (f % 2 == 0) ? 1.0 : -1.0;
    const Vec3& normal = axes[k];
    // Two in-face axes ordered so (p, q, normal*sign) is right-handed: outward winding.
    Vec3 p = axes[(k + 1) % 3], q = axes[(k + 2) % 3] * sign;
    std::uint32_t start = static_cast<std::uint32_t>(mesh.vertices.size());
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j)
        add(c + sign * normal + (2.0 * i / n - 1.0) * p + (2.0 * j / n - 1.0) * q);
    auto idx = [&](int i, int j) { return start + static_cast<std::uint32_t>(i * (n + 1) + j); };
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        tri(idx(i, j), idx(i + 1, j), idx(i + 1, j + 1));
        tri(idx(i, j), idx(i + 1, j + 1), idx(i, j + 1));
      }
  }
}

void MeshBuilder::sphere(const Vec3& c, double r, int segments, int stacks) {
  std::uint32_t top = add(c + Vec3(0, 0, r));
  std::uint32_t first = static_cast<std::uint32_t>(mesh.vertices.size());
  for (int k = 1; k < stacks; ++k) {
    double theta = kPi * k / stacks;
    for (int i = 0; i < segments; ++i) {
      double phi = 2.0 * kPi * i / segments;
      add(c + r * Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)));
    }
  }
  std::uint32_t bottom = add(c - Vec3(0, 0, r));
  auto s = static_cast<std::uint32_t>(segments);
  for (std::uint32_t i = 0; i < s; ++i) tri(top, first + i, first + (i + 1) % s);
  for (int k = 0; k + 1 < stacks - 1; ++k) {
    std::uint32_t r0 = first + static_cast<std::uint32_t>(k) * s, r1 = r0 + s;
    for (std::uint32_t i = 0; i < s; ++i) {
      std::uint32_t j = (i + 1) % s;
      tri(r0 + i, r1 + i, r1 + j);
      tri(r0 + i, r1 + j, r0 + j);
    }
  }
  std::uint32_t last = first + static_cast<std::uint32_t>(stacks - 2) * s;
  for (std::uint32_t i = 0; i < s; ++i) tri(bottom, last + (i + 1) % s, last + i);
}

void MeshBuilder::torus(const Vec3& c, const Vec3& axis, double major, double minor, int u_count, int v_count,
                        double start_deg, double sweep_deg, const Vec3& ref) {
  Vec3 n = axis.normalized(), e1, e2;
  basis(n, e1, e2);
  if (ref.norm() > 0) {
    e1 = (ref - ref.dot(n) * n).normalized();
    e2 = n.cross(e1);
  }
  bool full = sweep_deg >= 360.0;
  int rings = full ? u_count : u_count + 1;
  auto vv = static_cast<std::uint32_t>(v_count);
  std::uint32_t start = static_cast<std::uint32_t>(mesh.vertices.size());
  std::vector<Vec3> centres;
  for (int i = 0; i < rings; ++i) {
    double a = rad(start_deg + sweep_deg * i / u_count);
    Vec3 radial = std::cos(a) * e1 + std::sin(a) * e2;
    centres.push_back(c + major * radial);
    for (int j = 0; j < v_count; ++j) {
      double b = 2.0 * kPi * j / v_count;
      add(c + (major + minor * std::cos(b)) * radial + minor * std::sin(b) * n);
    }
  }
  for (int i = 0; i < u_count; ++i) {
    std::uint32_t r0 = start + static_cast<std::uint32_t>(i) * vv;
    std::uint32_t r1 = start + static_cast<std::uint32_t>((i + 1) % rings) * vv;
    for (std::uint32_t j = 0; j < vv; ++j) {
      std::uint32_t k = (j + 1) % vv;
      tri(r0 + j, r1 + j, r1 + k);
      tri(r0 + j, r1 + k, r0 + k);
    }
  }
  if (!full) {
    std::uint32_t c0 = add(centres.front()), c1 = add(centres.back());
    std::uint32_t last = start + static_cast<std::uint32_t>(rings - 1) * vv;
    for (std::uint32_t j = 0; j < vv; ++j) {
      tri(c0, start + (j + 1) % vv, start + j);
      tri(c1, last + j, last + (j + 1) % vv);
    }
  }
}

void MeshBuilder::dish(const Vec3& c, const Vec3& axis, double r, double depth, double t, int segments, int rings) {
  Vec3 n = axis.normalized(), u, v;
  basis(n, u, v);
  auto s = static_cast<std::uint32_t>(segments);
  auto surface = [&](double offset, bool front) {
    std::uint32_t centre = add(c + offset * n);
    std::uint32_t first = static_cast<std::uint32_t>(mesh.vertices.size());
    for (int k = 1; k <= rings; ++k) {
      double rho = r * k / rings;
      double z = depth * (rho / r) * (rho / r) + offset;
      for (int i = 0; i < segments; ++i) {
        double phi = 2.0 * kPi * i / segments;
        add(c + rho * (std::cos(phi) * u + std::sin(phi) * v) + z * n);
      }
    }
    for (std::uint32_t i = 0; i < s; ++i) {
      if (front) tri(centre, first + i, first + (i + 1) % s);
      else tri(centre, first + (i + 1) % s, first + i);
    }
    for (int k = 0; k + 1 < rings; ++k) {
      std::uint32_t r0 = first + static_cast<std::uint32_t>(k) * s, r1 = r0 + s;
      for (std::uint32_t i = 0; i < s; ++i) {
        std::uint32_t j = (i + 1) % s;
        if (front) {
          tri(r0 + i, r1 + i, r1 + j);
          tri(r0 + i, r1 + j, r0 + j);
        } else {
          tri(r0 + i, r1 + j, r1 + i);
          tri(r0 + i, r0 + j, r1 + j);
        }
      }
    }
    return first + static_cast<std::uint32_t>(rings - 1) * s;  // outermost ring
  };
  std::uint32_t outer_front = surface(0.0, true);
  std::uint32_t outer_back = surface(-t, false);
  for (std::uint32_t i = 0; i < s; ++i) {
    std::uint32_t j = (i + 1) % s;
    tri(outer_front + i, outer_back + i, outer_back + j);
    tri(outer_front + i, outer_back + j, outer_front + j);
  }
}

void MeshBuilder::prism(const Vec3& a, const Vec3& b, double r, int n_sides, double phase_deg) {
  Vec3 n = (b - a).normalized(), u, v;
  basis(n, u, v);
  if (std::abs(n.z()) > 0.9) {
    u = Vec3::UnitX();
    v = n.cross(u);
  }
  auto s = static_cast<std::uint32_t>(n_sides);
  std::uint32_t r0 = static_cast<std::uint32_t>(mesh.vertices.size());
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < n_sides; ++i) {
      double phi = rad(phase_deg) + 2.0 * kPi * i / n_sides;
      add((k == 0 ? a : b) + r * (std::cos(phi) * u + std::sin(phi) * v));
    }
  std::uint32_t r1 = r0 + s;
  for (std::uint32_t i = 0; i < s; ++i) {
    std::uint32_t j = (i + 1) % s;
    tri(r0 + i, r0 + j, r1 + j);
    tri(r0 + i, r1 + j, r1 + i);
  }
  for (std::uint32_t i = 1; i + 1 < s; ++i) {
    tri(r0, r0 + i + 1, r0 + i);
    tri(r1, r1 + i, r1 + i + 1);
  }
}

void MeshBuilder::label(const Vec3& c, const Vec3& normal, double r, int n) {
  Vec3 nn = normal.normalized(), u, v;
  basis(nn, u, v);
  std::uint32_t centre = add(c);
  std::uint32_t first = static_cast<std::uint32_t>(mesh.vertices.size());
  for (int i = 0; i <= n; ++i) {
    double phi = 2.0 * kPi * i / (n + 1);
    add(c + r * (std::cos(phi) * u + std::sin(phi) * v));
  }
  for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(n); ++i) tri(centre, first + i, first + i + 1);
}

bool MeshBuilder::fill_to(std::size_t target, const Vec3& a, const Vec3& b, double r) {
  if (triangle_count() > target) return false;
  std::size_t rem = target - triangle_count();
  if (rem == 0) return true;
  if (rem < 6) {
    // Too few for a closed stud: an open label (1-5 triangles).
    label(a + (b - a) * 0.5 + Vec3(0, 0, r * 1.05), Vec3::UnitZ(), r * 0.5, static_cast<int>(rem));
    return true;
  }
  Vec3 dir = (b - a);
  Vec3 n = dir.normalized(), u, w;
  basis(n, u, w);
  if (rem % 2 == 1) {
    label(a + 0.5 * dir + u * (r * 1.02), u, r * 0.4, 3);
    rem -= 3;
  }
  // A long pipe (cable harness) with rings takes the bulk, 96 triangles a ring.
  constexpr int kSeg = 48;
  if (rem >= 6 + 2 * 2 * kSeg) {
    std::size_t rings = rem / (2 * kSeg) - 1;  // 2*seg*(rings+1) <= rem
    cylinder(a, b, r, kSeg, static_cast<int>(rings));
    rem -= 2 * kSeg * (rings + 1);
  }
  // Studs (bolt heads) along the pipe for the rest: 4*s for a short cylinder,
  // 2*s for a cone, s >= 3.
  int stud = 0;
  auto spot = [&](int k) { return a + dir * (0.05 + 0.9 * ((k * 7) % 19) / 19.0); };
  if (rem % 4 == 2) {
    Vec3 p = spot(stud++);
    cone(p + u * r, p + u * (r + 0.02), 0.01, 3);
    rem -= 6;
  }
  while (rem > 0 && rem < 12) {
    // A small tetrahedron (4 triangles) where a stud would be too thin.
    Vec3 p = spot(stud++) + w * r;
    std::uint32_t i0 = add(p), i1 = add(p + 0.01 * u), i2 = add(p + 0.01 * n), i3 = add(p + 0.01 * w);
    tri(i0, i2, i1);
    tri(i0, i1, i3);
    tri(i0, i3, i2);
    tri(i1, i2, i3);
    rem -= 4;
  }
  while (rem > 0) {
    std::size_t s = std::min<std::size_t>(rem / 4, 24);
    if (rem - 4 * s != 0 && rem - 4 * s < 12) s = (rem - 12) / 4;  // leave room for a last stud
    Vec3 p = spot(stud++);
    cylinder(p + w * r, p + w * (r + 0.015), 0.012, static_cast<int>(s));
    rem -= 4 * s;
  }
  return true;
}

}  // namespace plancheck::dataset
