// SPDX-License-Identifier: MIT
// Case generators for the stability suite: pairs of triangles per category,
// deterministic (fixed seeds). A generator only intends a configuration
// (touching, a gap of g, coplanar, ...); the exact reference decides what
// each case really is, so a rounding in a generator never makes a wrong
// expectation. Where a category needs exactness (touching, coplanarity) the
// coordinates are dyadic with few enough bits that every sum is exact.
#pragma once

#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace plancheck::stability {

using T9 = std::array<double, 9>;
using V3 = Eigen::Vector3d;

struct Case {
  std::string category;
  T9 p{}, q{};
};

inline T9 tri(const V3& a, const V3& b, const V3& c) {
  return {a.x(), a.y(), a.z(), b.x(), b.y(), b.z(), c.x(), c.y(), c.z()};
}
inline V3 vtx(const T9& t, int i) { return V3(t[3 * i], t[3 * i + 1], t[3 * i + 2]); }
inline T9 shifted(const T9& t, const V3& d) {
  return tri(vtx(t, 0) + d, vtx(t, 1) + d, vtx(t, 2) + d);
}

class Gen {
 public:
  explicit Gen(std::uint64_t seed) : rng_(seed) {}
  // k * 2^-bits * range, |k| <= 2^bits: exact, bits + log2(range) significant bits.
  double dyadic(int bits, double range) {
    const std::int64_t n = std::int64_t{1} << bits;
    std::uniform_int_distribution<std::int64_t> d(-n, n);
    return std::ldexp(static_cast<double>(d(rng_)), -bits) * range;
  }
  V3 dyadic3(int bits, double range) { return V3(dyadic(bits, range), dyadic(bits, range), dyadic(bits, range)); }
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  V3 unit() {
    for (;;) {
      V3 v(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
      if (v.norm() > 0.2 && v.norm() <= 1.0) return v.normalized();
    }
  }
  // A proper triangle with dyadic vertices (20 fractional bits, |x| <= 1).
  T9 dyadic_triangle() {
    for (;;) {
      const V3 a = dyadic3(20, 1), b = dyadic3(20, 1), c = dyadic3(20, 1);
      const V3 n = (b - a).cross(c - a);
      if (n.norm() > 0.05 && (b - a).norm() > 0.2 && (c - a).norm() > 0.2 && (c - b).norm() > 0.2)
        return tri(a, b, c);
    }
  }
  // Dyadic barycentric weights (multiples of 1/16): all > 0, or on_edge: w2 = 0.
  std::array<double, 3> weights(bool on_edge) {
    if (on_edge) {
      const int w0 = integer(1, 15);
      return {w0 / 16.0, (16 - w0) / 16.0, 0.0};
    }
    const int w0 = integer(1, 14), w1 = integer(1, 15 - w0);
    return {w0 / 16.0, w1 / 16.0, (16 - w0 - w1) / 16.0};
  }

 private:
  std::mt19937_64 rng_;
};

inline V3 normal_of(const T9& t) {
  return (vtx(t, 1) - vtx(t, 0)).cross(vtx(t, 2) - vtx(t, 0)).normalized();
}
inline V3 point_at(const T9& t, const std::array<double, 3>& w) {
  return w[0] * vtx(t, 0) + w[1] * vtx(t, 1) + w[2] * vtx(t, 2);  // exact for dyadic inputs
}

// The gaps the task names: 1e-3 m down to 1e-12 m, one per decade.
inline std::vector<double> decade_gaps() {
  std::vector<double> g;
  for (int e = 3; e <= 12; ++e) g.push_back(std::pow(10.0, -e));
  return g;
}

// All categories, in table order. Each returns its cases.
std::vector<Case> touching_cases();        // vertex/edge/face contacts, distance 0
std::vector<Case> gap_cases();             // the touching configurations moved apart by 1e-3 .. 1e-12
std::vector<Case> coplanar_cases();        // coplanar overlapping and disjoint (gaps to 2^-40)
std::vector<Case> edge_edge_cases();       // crossing edges and edge-edge gaps
std::vector<Case> grazing_cases();         // edges entering a face at angles 1e-3 .. 1e-12 rad
std::vector<Case> near_parallel_cases();   // faces tilted 1e-3 .. 1e-12 rad against each other
std::vector<Case> degenerate_cases();      // collinear, repeated-vertex, point triangles
std::vector<Case> sliver_cases();          // heights 1e-6 .. 1e-15 over the long edge
std::vector<Case> mm_beside_m_cases();     // 1 mm triangles at 1e-6 .. 1e-12 from 2 m triangles
std::vector<Case> random_cases();          // general position controls

}  // namespace plancheck::stability
