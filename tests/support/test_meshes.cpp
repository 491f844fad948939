// SPDX-License-Identifier: MIT
#include "test_meshes.h"

#include <cmath>
#include <random>

namespace plancheck::testing {

Mesh make_sphere(const Vec3& centre, double radius, int rings, int segments) {
  Mesh m;
  const double pi = 3.14159265358979323846;
  m.vertices.push_back(centre + Vec3(0, 0, radius));
  for (int r = 1; r < rings; ++r) {
    const double theta = pi * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2 * pi * s / segments;
      m.vertices.push_back(centre + radius * Vec3(std::sin(theta) * std::cos(phi),
                                                  std::sin(theta) * std::sin(phi),
                                                  std::cos(theta)));
    }
  }
  m.vertices.push_back(centre - Vec3(0, 0, radius));
  const auto ring = [&](int r, int s) {
    return static_cast<std::uint32_t>(1 + (r - 1) * segments + (s % segments));
  };
  const auto bottom = static_cast<std::uint32_t>(m.vertices.size() - 1);
  for (int s = 0; s < segments; ++s) {
    m.triangles.push_back({0, ring(1, s), ring(1, s + 1)});
    m.triangles.push_back({bottom, ring(rings - 1, s + 1), ring(rings - 1, s)});
  }
  for (int r = 1; r < rings - 1; ++r)
    for (int s = 0; s < segments; ++s) {
      m.triangles.push_back({ring(r, s), ring(r + 1, s), ring(r + 1, s + 1)});
      m.triangles.push_back({ring(r, s), ring(r + 1, s + 1), ring(r, s + 1)});
    }
  return m;
}

Mesh make_torus(const Vec3& centre, double major_radius, double minor_radius, int n_major,
                int n_minor) {
  Mesh m;
  const double pi = 3.14159265358979323846;
  for (int i = 0; i < n_major; ++i) {
    const double u = 2 * pi * i / n_major;
    for (int j = 0; j < n_minor; ++j) {
      const double v = 2 * pi * j / n_minor;
      const double r = major_radius + minor_radius * std::cos(v);
      m.vertices.push_back(centre +
                           Vec3(r * std::cos(u), r * std::sin(u), minor_radius * std::sin(v)));
    }
  }
  const auto id = [&](int i, int j) {
    return static_cast<std::uint32_t>((i % n_major) * n_minor + (j % n_minor));
  };
  for (int i = 0; i < n_major; ++i)
    for (int j = 0; j < n_minor; ++j) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

Mesh make_soup(std::uint64_t seed, int n, const Vec3& centre, double half_size, double max_edge) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Mesh m;
  for (int t = 0; t < n; ++t) {
    const Vec3 c = centre + half_size * Vec3(u(rng), u(rng), u(rng));
    const auto base = static_cast<std::uint32_t>(m.vertices.size());
    for (int k = 0; k < 3; ++k)
      m.vertices.push_back(c + 0.5 * max_edge * Vec3(u(rng), u(rng), u(rng)));
    m.triangles.push_back({base, base + 1, base + 2});
  }
  return m;
}

Affine random_rigid(std::mt19937_64& rng, const Vec3& around, double spread) {
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
  q.normalize();
  Affine t = Affine::Identity();
  t.linear() = q.toRotationMatrix();
  t.translation() = around + spread * Vec3(u(rng), u(rng), u(rng));
  return t;
}

Mesh make_box(const Vec3& c, const Vec3& h) {
  Mesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.push_back(c + Vec3((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z()));
  m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return m;
}

}  // namespace plancheck::testing
