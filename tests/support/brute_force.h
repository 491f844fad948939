// SPDX-License-Identifier: MIT
// Obviously-correct slow references for the geometry queries, usable by any
// test suite: an exact-rational triangle-triangle intersection test written
// independently of kernels/tri_tri_overlap.h, an independent long-double
// triangle distance, and all-pairs collision and distance between posed
// meshes.
#pragma once

#include "src/scene/scene.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace plancheck::testing {

// Exact closed intersection of two triangles (degenerate ones included), in
// GMP rationals, by construction: two closed triangles meet iff an edge of one
// meets the other; edge-vs-triangle meets are computed as actual rational
// points (plane crossing, barycentric signs), never via the kernel's
// orientation-predicate logic.
bool exact_tri_tri_reference(const Vec3 p[3], const Vec3 q[3]);

// Triangle-triangle distance by a plain method in long double: for disjoint
// triangles, the minimum over the 6 point-triangle distances (projection to
// the plane if inside, else nearest edge) and the 9 segment-segment
// distances (interior critical point of the line pair, else endpoint to
// segment). Only meaningful when the triangles do not intersect.
long double reference_tri_distance(const Vec3 p[3], const Vec3 q[3]);

// Mesh vertices mapped by t (world frame).
std::vector<Vec3> posed_vertices(const Mesh& mesh, const Affine& t);

// All intersecting triangle pairs (index in a, index in b) of two posed
// vertex sets, by the kernel on every pair with a bounding-box prefilter.
std::vector<std::pair<std::uint32_t, std::uint32_t>> brute_force_collide(
    const Mesh& a, const std::vector<Vec3>& va, const Mesh& b, const std::vector<Vec3>& vb,
    bool stop_at_first = false);

struct BruteDistance {
  double distance = 0.0;
  std::uint32_t triangle_a = 0, triangle_b = 0;
};

// Minimum over all triangle pairs of kernels/tri_distance.h.
BruteDistance brute_force_distance(const Mesh& a, const std::vector<Vec3>& va, const Mesh& b,
                                   const std::vector<Vec3>& vb);

}  // namespace plancheck::testing
