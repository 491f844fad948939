// SPDX-License-Identifier: MIT
// Box motion bounds (src/geometry/box_motion.h).
#include "src/geometry/box_motion.h"

#include "src/scene/kinematics.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace plancheck {

namespace {

// Vertices are split this many times (at the median of the longest side):
// up to 2^kSplits clusters a part.
constexpr int kSplits = 3;

double line_distance(const Vec3& x, const Vec3& p, const Vec3& u) {
  const double n = u.norm();
  return n > 0.0 ? (x - p).cross(u).norm() / n : (x - p).norm();
}

// Splits v[from, to) at the median of the longest side of its points'
// box (point(x) of each element) down to `depth` levels or fewer than
// `least` elements.
template <class T, class Point>
void split(std::vector<T>& v, std::size_t from, std::size_t to, int depth, std::size_t least, Point point,
           std::vector<std::pair<std::size_t, std::size_t>>& out) {
  if (depth == 0 || to - from < least) {
    out.push_back({from, to});
    return;
  }
  Vec3 lo = point(v[from]), hi = point(v[from]);
  for (std::size_t i = from; i < to; ++i) {
    lo = lo.cwiseMin(point(v[i]));
    hi = hi.cwiseMax(point(v[i]));
  }
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  const std::size_t mid = from + (to - from) / 2;
  std::nth_element(v.begin() + static_cast<std::ptrdiff_t>(from), v.begin() + static_cast<std::ptrdiff_t>(mid),
                   v.begin() + static_cast<std::ptrdiff_t>(to),
                   [&](const T& a, const T& b) { return point(a)[axis] < point(b)[axis]; });
  split(v, from, mid, depth - 1, least, point, out);
  split(v, mid, to, depth - 1, least, point, out);
}

}  // namespace

BoxMotion::BoxMotion(const Scene& scene, Points points) : scene_(scene), points_(points), fallback_(scene) {
  parts_.resize(scene.parts.size());
  for (std::size_t i = 0; i < scene.parts.size(); ++i) {
    const Part& part = scene.parts[i];
    PartData& d = parts_[i];
    if (!part.moving() || part.mesh.triangles.empty()) continue;
    for (int a : part.chain)
      if (scene.actions[static_cast<std::size_t>(a)].type == ActionType::kScale) d.rigid = false;
    const Action& inner = scene.actions[static_cast<std::size_t>(part.chain.back())];
    // One cluster's sphere and innermost arm over points v[from, to).
    auto cluster = [&](auto&& each) {
      Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
      each([&](const Vec3& x) {
        lo = lo.cwiseMin(x);
        hi = hi.cwiseMax(x);
      });
      Cluster c;
      c.centre = 0.5 * (lo + hi);
      each([&](const Vec3& x) {
        c.radius = std::max(c.radius, (x - c.centre).norm());
        if (inner.type == ActionType::kRotate) c.inner_arm = std::max(c.inner_arm, line_distance(x, inner.pivot, inner.axis));
      });
      // Rounding of the two loops above: a relative pad far above it.
      c.radius = c.radius * (1.0 + 1e-12) + 1e-15;
      c.inner_arm = c.inner_arm * (1.0 + 1e-12) + 1e-15;
      return c;
    };
    std::vector<std::pair<std::size_t, std::size_t>> ranges;
    if (points == Points::kCorners) {
      std::vector<Vec3> v;
      v.reserve(part.mesh.triangles.size() * 3);
      for (const Tri& t : part.mesh.triangles)
        for (std::uint32_t k : t) v.push_back(part.mesh.vertices[k]);
      split(v, 0, v.size(), kSplits, 16, [](const Vec3& x) -> const Vec3& { return x; }, ranges);
      for (const auto& range : ranges) {
        const std::size_t from = range.first, to = range.second;  // (not a binding: the lambda captures them)
        d.clusters.push_back(cluster([&](auto&& f) {
          for (std::size_t k = from; k < to; ++k) f(v[k]);
        }));
      }
    } else {
      // Whole triangles, split by their centroids: each cluster's sphere
      // holds every point of its triangles, not only their corners.
      struct Piece {
        Vec3 centroid;
        std::uint32_t tri;
      };
      std::vector<Piece> v;
      v.reserve(part.mesh.triangles.size());
      for (std::uint32_t t = 0; t < part.mesh.triangles.size(); ++t) {
        const Tri& tri = part.mesh.triangles[t];
        v.push_back({(part.mesh.vertices[tri[0]] + part.mesh.vertices[tri[1]] + part.mesh.vertices[tri[2]]) / 3.0, t});
      }
      split(v, 0, v.size(), kSplits, 2, [](const Piece& x) -> const Vec3& { return x.centroid; }, ranges);
      // Each cluster's corners once (a vertex is shared by several of its triangles).
      std::vector<std::uint32_t> stamp(part.mesh.vertices.size(), 0), corners;
      std::uint32_t n = 0;
      for (const auto& range : ranges) {
        ++n;
        corners.clear();
        for (std::size_t k = range.first; k < range.second; ++k)
          for (std::uint32_t i : part.mesh.triangles[v[k].tri])
            if (stamp[i] != n) {
              stamp[i] = n;
              corners.push_back(i);
            }
        d.clusters.push_back(cluster([&](auto&& f) {
          for (std::uint32_t i : corners) f(part.mesh.vertices[i]);
        }));
      }
    }
  }
}

std::size_t BoxMotion::clusters(int part) const {
  if (part < 0 || static_cast<std::size_t>(part) >= parts_.size()) return 0;
  return parts_[static_cast<std::size_t>(part)].clusters.size();
}

void BoxMotion::spheres(int part, std::vector<Sphere>& out) const {
  out.clear();
  if (part < 0 || static_cast<std::size_t>(part) >= parts_.size()) return;
  const PartData& d = parts_[static_cast<std::size_t>(part)];
  if (!d.rigid) return;
  for (const Cluster& c : d.clusters) out.push_back({c.centre, c.radius});
}

BoxMotion::Lever BoxMotion::lever(int part, std::span<const double> lo, std::span<const double> hi,
                                  std::span<const double> c) const {
  Lever l;
  if (part < 0 || static_cast<std::size_t>(part) >= parts_.size()) return l;
  const PartData& d = parts_[static_cast<std::size_t>(part)];
  const Part& p = scene_.parts[static_cast<std::size_t>(part)];
  if (d.clusters.empty()) return l;
  if (!d.rigid) {
    l.fixed = fallback_.part_bound(part, lo, hi);
    return l;
  }
  const std::size_t k = p.chain.size();
  if (k > kMaxChain) {
    l.fixed = std::numeric_limits<double>::infinity();
    return l;
  }
  // Per action: how far its value moves from c within the box (rad or m
  // along the path), and its transform at c.
  for (std::size_t n = 0; n < k; ++n) {
    const Action& a = scene_.actions[static_cast<std::size_t>(p.chain[n])];
    if (a.type == ActionType::kTranslateFree) {
      const std::size_t f = static_cast<std::size_t>(a.first_parameter);
      double s = 0.0;
      for (std::size_t j = 0; j < 3; ++j) {
        const double e = std::max(std::abs(hi[f + j] - c[f + j]), std::abs(lo[f + j] - c[f + j]));
        s += e * e;
      }
      l.h[n] = std::sqrt(s) * a.unit_to_si;
    } else {
      // Driving values are affine in one parameter: extremes at lo and hi.
      const double vc = driving_value(scene_, a, c);
      const double e = std::max(std::abs(driving_value(scene_, a, hi) - vc), std::abs(driving_value(scene_, a, lo) - vc));
      l.h[n] = e * a.unit_to_si * (a.type == ActionType::kTranslateAxis ? a.axis.norm() : 1.0);
    }
    if (!std::isfinite(l.h[n])) {
      l.fixed = std::numeric_limits<double>::infinity();
      return l;
    }
  }
  std::size_t outer = k;  // the outermost action that moves: nothing outside it matters
  for (std::size_t n = 0; n < k && outer == k; ++n)
    if (l.h[n] > 0.0) outer = n;
  if (outer == k) return l;
  for (std::size_t n = outer + 1; n < k; ++n)
    l.at[n] = action_transform_at(scene_, scene_.actions[static_cast<std::size_t>(p.chain[n])], c);
  l.scene = &scene_;
  l.chain = &p.chain;
  l.outer = outer;
  l.fixed = -1.0;
  return l;
}

double BoxMotion::Lever::sphere(const Vec3& centre, double radius, double inner_arm) const {
  if (fixed >= 0.0 || std::isnan(fixed)) return fixed;
  const std::size_t k = chain->size();
  Vec3 y = centre;
  double path = 0.0;  // sum over the actions inside n of h_j arm_j
  for (std::size_t n = k; n-- > outer;) {
    const Action& a = scene->actions[static_cast<std::size_t>((*chain)[n])];
    if (a.type == ActionType::kRotate) {
      if (h[n] != 0.0) {
        double arm = line_distance(y, a.pivot, a.axis) + radius + path;
        if (n + 1 == k) arm = std::min(arm, inner_arm);
        path += h[n] * arm;
      }
    } else {
      path += h[n];
    }
    if (n > outer) y = at[n] * y;
  }
  if (!std::isfinite(path)) return std::numeric_limits<double>::infinity();
  return path * (1.0 + 1e-9) + 1e-12;
}

double BoxMotion::Lever::point(const Vec3& x) const {
  return sphere(x, 0.0, std::numeric_limits<double>::infinity());
}

double BoxMotion::reach(int part, std::span<const double> lo, std::span<const double> hi,
                        std::span<const double> c) const {
  return reach(part, lever(part, lo, hi, c));
}

bool BoxMotion::balls(int part, std::span<const double> lo, std::span<const double> hi, std::span<const double> c,
                      std::vector<Ball>& out) const {
  out.clear();
  const Lever l = lever(part, lo, hi, c);
  if (part < 0 || static_cast<std::size_t>(part) >= parts_.size()) return false;
  const PartData& d = parts_[static_cast<std::size_t>(part)];
  if (d.clusters.empty() || !d.rigid || !(l.fixed == -1.0 || l.fixed == 0.0)) return false;
  const Affine t = part_transform(scene_, part, c);
  for (const Cluster& cl : d.clusters)
    out.push_back({t * cl.centre, cl.radius, l.fixed == 0.0 ? 0.0 : l.sphere(cl.centre, cl.radius, cl.inner_arm)});
  return true;
}

double BoxMotion::reach(int part, const Lever& l) const {
  if (l.fixed >= 0.0 || std::isnan(l.fixed)) return l.fixed;
  double best = 0.0;
  for (const Cluster& cl : parts_[static_cast<std::size_t>(part)].clusters)
    best = std::max(best, l.sphere(cl.centre, cl.radius, cl.inner_arm));
  return best;
}

}  // namespace plancheck
