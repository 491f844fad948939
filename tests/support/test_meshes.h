// SPDX-License-Identifier: MIT
// Small synthetic meshes for geometry tests and measurements.
#pragma once

#include "src/scene/scene.h"

#include <cstdint>

namespace plancheck::testing {

// UV sphere: 2 * rings * (segments - 1) triangles roughly.
Mesh make_sphere(const Vec3& centre, double radius, int rings, int segments);

// Torus around the z axis: 2 * n_major * n_minor triangles.
Mesh make_torus(const Vec3& centre, double major_radius, double minor_radius, int n_major,
                int n_minor);

// n independent random triangles in the box centre +- half_size, edge length
// up to max_edge.
Mesh make_soup(std::uint64_t seed, int n, const Vec3& centre, double half_size, double max_edge);

}  // namespace plancheck::testing
