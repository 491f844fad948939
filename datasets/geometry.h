// SPDX-License-Identifier: MIT
// Closed triangle-mesh primitives for the synthetic lander (metres, z up).
// Every primitive's triangle count is a closed formula (given beside it) so
// the model can be tuned to the paper's Table 2 counts exactly.
#pragma once

#include "src/scene/scene.h"

#include <cstdint>
#include <vector>

namespace plancheck::dataset {

class MeshBuilder {
 public:
  Mesh mesh;

  std::size_t triangle_count() const { return mesh.triangles.size(); }

  // Frustum between centres a and b with radii ra, rb; `segments` around,
  // `rings` along; caps are fans (a cap of radius 0 is skipped).
  // Triangles: 2*segments*rings + segments per non-zero cap.
  void frustum(const Vec3& a, const Vec3& b, double ra, double rb, int segments, int rings = 1);
  // Cone from base centre a (radius r) to apex b. Triangles: 2*segments.
  void cone(const Vec3& a, const Vec3& b, double r, int segments);
  void cylinder(const Vec3& a, const Vec3& b, double r, int segments, int rings = 1) {
    frustum(a, b, r, r, segments, rings);
  }
  // Tube (hollow cylinder, open at b, closed by a floor at a): inner and outer
  // walls, rim annulus at b, floor disc at a with thickness `wall`.
  // Triangles: 8*segments.
  void tube(const Vec3& a, const Vec3& b, double r_outer, double wall, int segments);
  static std::size_t count_tube(int segments) { return static_cast<std::size_t>(8 * segments); }
  // Box with half extents h, centred at c, axes ex, ey (ez = ex x ey); each face
  // split n x n. Triangles: 12*n*n.
  void box(const Vec3& c, const Vec3& h, const Vec3& ex = Vec3::UnitX(), const Vec3& ey = Vec3::UnitY(), int n = 1);
  // UV sphere: segments around, stacks from pole to pole.
  // Triangles: 2*segments*(stacks-1).
  void sphere(const Vec3& c, double r, int segments, int stacks);
  // Torus around axis through c: major radius R, minor r. Partial arcs
  // (sweep < 360 deg) get fan caps. Triangles: 2*u*v (+ 2*v for a partial arc).
  void torus(const Vec3& c, const Vec3& axis, double major, double minor, int u, int v,
             double start_deg = 0.0, double sweep_deg = 360.0, const Vec3& ref = Vec3::Zero());
  // Parabolic dish opening along `axis`, rim radius r, depth d, shell thickness
  // t. Triangles: 4*segments*rings (two faces) + 2*segments (rim).
  void dish(const Vec3& c, const Vec3& axis, double r, double depth, double t, int segments, int rings);
  // Prism over a regular polygon (n sides, circumradius r) from a to b, rotated
  // by phase_deg. Triangles: 2*n sides + 2*(n-2) caps.
  void prism(const Vec3& a, const Vec3& b, double r, int n, double phase_deg = 0.0);
  // An open fan of `n` triangles (a thin single-sided label); the only
  // non-closed piece, used to reach odd triangle totals.
  void label(const Vec3& c, const Vec3& normal, double r, int n);

  void append(const Mesh& other);

  // Adds closed pieces (cylinder / cone studs along the segment a-b) so that
  // triangle_count() becomes exactly `target` (an open label fills an odd
  // remainder). Returns false when target is already exceeded.
  bool fill_to(std::size_t target, const Vec3& a, const Vec3& b, double r);

 private:
  std::uint32_t add(const Vec3& p);
  void tri(std::uint32_t a, std::uint32_t b, std::uint32_t c);
};

// An orthonormal pair (u, v) perpendicular to unit axis n, chosen deterministically.
void basis(const Vec3& n, Vec3& u, Vec3& v);

}  // namespace plancheck::dataset
