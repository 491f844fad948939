// SPDX-License-Identifier: MIT
// Small synthetic meshes for geometry tests and measurements.
#pragma once

#include "src/scene/scene.h"

#include <cstdint>
#include <random>

namespace plancheck::testing {

// UV sphere: 2 * rings * (segments - 1) triangles roughly.
Mesh make_sphere(const Vec3& centre, double radius, int rings, int segments);

// Torus around the z axis: 2 * n_major * n_minor triangles.
Mesh make_torus(const Vec3& centre, double major_radius, double minor_radius, int n_major,
                int n_minor);

// n independent random triangles in the box centre +- half_size, edge length
// up to max_edge.
Mesh make_soup(std::uint64_t seed, int n, const Vec3& centre, double half_size, double max_edge);

// A closed box of 12 triangles (one leaf), half extents h, centred at c.
Mesh make_box(const Vec3& c, const Vec3& h);

// A uniformly random rotation (a normalised Gaussian quaternion) and a
// translation uniform in around +- spread per axis.
Affine random_rigid(std::mt19937_64& rng, const Vec3& around, double spread);

}  // namespace plancheck::testing
