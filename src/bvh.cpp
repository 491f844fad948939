// SPDX-License-Identifier: MIT
#include "src/bvh.h"

#include "src/error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace plancheck {

float round_down(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}

float round_up(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

namespace {

struct Bounds {
  double lo[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                  std::numeric_limits<double>::infinity()};
  double hi[3] = {-std::numeric_limits<double>::infinity(),
                  -std::numeric_limits<double>::infinity(),
                  -std::numeric_limits<double>::infinity()};
  void grow(const double* l, const double* h) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], l[k]);
      hi[k] = std::max(hi[k], h[k]);
    }
  }
  void grow(const Bounds& b) { grow(b.lo, b.hi); }
  double half_area() const {
    if (lo[0] > hi[0]) return 0.0;
    const double dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    return dx * dy + dy * dz + dz * dx;
  }
};

struct Task {
  std::uint32_t node, begin, end;
};

}  // namespace

Bvh build_bvh(const std::vector<std::array<double, 6>>& boxes, const BvhBuildOptions& options) {
  Bvh bvh;
  const std::uint32_t n = static_cast<std::uint32_t>(boxes.size());
  bvh.prim_ids.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) bvh.prim_ids[i] = i;
  if (n == 0) return bvh;
  const int bins = std::max(2, options.bins);
  const std::uint32_t max_leaf = static_cast<std::uint32_t>(std::max(1, options.max_leaf_size));

  std::vector<std::array<double, 3>> centroid(n);
  for (std::uint32_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) centroid[i][k] = 0.5 * (boxes[i][k] + boxes[i][3 + k]);

  bvh.nodes.reserve(2 * (n / max_leaf + 1));
  bvh.nodes.push_back(BvhNode{});
  std::vector<Task> stack{{0, 0, n}};
  std::vector<Bounds> bin_bounds(bins), right_bounds(bins);
  std::vector<std::uint32_t> bin_count(bins);
  std::uint32_t* ids = bvh.prim_ids.data();

  while (!stack.empty()) {
    const Task task = stack.back();
    stack.pop_back();
    Bounds bounds, cbounds;
    for (std::uint32_t i = task.begin; i < task.end; ++i) {
      const auto& b = boxes[ids[i]];
      bounds.grow(b.data(), b.data() + 3);
      cbounds.grow(centroid[ids[i]].data(), centroid[ids[i]].data());
    }
    BvhNode& node = bvh.nodes[task.node];
    for (int k = 0; k < 3; ++k) {
      node.lo[k] = round_down(bounds.lo[k]);
      node.hi[k] = round_up(bounds.hi[k]);
    }
    const std::uint32_t count = task.end - task.begin;
    if (count <= max_leaf) {
      node.index = task.begin;
      node.count = count;
      continue;
    }

    // Best SAH split over all axes and bin boundaries.
    double best_cost = std::numeric_limits<double>::infinity();
    int best_axis = -1, best_split = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const double extent = cbounds.hi[axis] - cbounds.lo[axis];
      if (!(extent > 0.0)) continue;
      const double scale = bins / extent;
      std::fill(bin_bounds.begin(), bin_bounds.end(), Bounds{});
      std::fill(bin_count.begin(), bin_count.end(), 0u);
      for (std::uint32_t i = task.begin; i < task.end; ++i) {
        const int b = std::min(
            bins - 1, static_cast<int>((centroid[ids[i]][axis] - cbounds.lo[axis]) * scale));
        bin_bounds[b].grow(boxes[ids[i]].data(), boxes[ids[i]].data() + 3);
        ++bin_count[b];
      }
      Bounds acc;
      for (int b = bins - 1; b > 0; --b) {
        acc.grow(bin_bounds[b]);
        right_bounds[b] = acc;
      }
      acc = Bounds{};
      std::uint32_t left_count = 0;
      for (int b = 0; b < bins - 1; ++b) {
        acc.grow(bin_bounds[b]);
        left_count += bin_count[b];
        const std::uint32_t right_count = count - left_count;
        if (left_count == 0 || right_count == 0) continue;
        const double cost =
            acc.half_area() * left_count + right_bounds[b + 1].half_area() * right_count;
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = axis;
          best_split = b;
        }
      }
    }

    std::uint32_t mid;
    if (best_axis >= 0) {
      const int axis = best_axis;
      const double lo = cbounds.lo[axis];
      const double scale = bins / (cbounds.hi[axis] - lo);
      auto* it = std::partition(ids + task.begin, ids + task.end, [&](std::uint32_t id) {
        return std::min(bins - 1, static_cast<int>((centroid[id][axis] - lo) * scale)) <=
               best_split;
      });
      mid = static_cast<std::uint32_t>(it - ids);
    } else {
      // All centroids equal: any split is as good; halve by index.
      mid = task.begin + count / 2;
    }
    const std::uint32_t left = static_cast<std::uint32_t>(bvh.nodes.size());
    node.index = left;
    node.count = 0;
    bvh.nodes.push_back(BvhNode{});
    bvh.nodes.push_back(BvhNode{});
    // Right first so the left subtree is built (and laid out) first.
    stack.push_back({left + 1, mid, task.end});
    stack.push_back({left, task.begin, mid});
  }
  return bvh;
}

CollisionModelData build_collision_data(const Mesh& mesh) {
  CollisionModelData data;
  const std::size_t nv = mesh.vertices.size();
  for (std::size_t i = 0; i < nv; ++i) {
    if (!mesh.vertices[i].allFinite())
      throw InputError("collision model: vertex " + std::to_string(i) + " is not finite");
    // Node bounds are floats; keep every coordinate far inside float range.
    if (mesh.vertices[i].cwiseAbs().maxCoeff() > 1e30)
      throw InputError("collision model: vertex " + std::to_string(i) + " is beyond 1e30 m");
    for (int k = 0; k < 3; ++k)
      data.max_abs[k] = std::max(data.max_abs[k], std::abs(mesh.vertices[i][k]));
  }
  const std::size_t nt = mesh.triangles.size();
  if (nt > std::numeric_limits<std::uint32_t>::max() / 2)
    throw InputError("collision model: too many triangles (" + std::to_string(nt) + ")");
  std::vector<std::array<double, 6>> boxes(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    const Tri& tri = mesh.triangles[t];
    for (int c = 0; c < 3; ++c)
      if (tri[c] >= nv)
        throw InputError("collision model: triangle " + std::to_string(t) + " uses vertex " +
                         std::to_string(tri[c]) + " of " + std::to_string(nv));
    for (int k = 0; k < 3; ++k) {
      const double a = mesh.vertices[tri[0]][k], b = mesh.vertices[tri[1]][k],
                   c = mesh.vertices[tri[2]][k];
      boxes[t][k] = std::min({a, b, c});
      boxes[t][3 + k] = std::max({a, b, c});
    }
  }
  data.bvh = build_bvh(boxes);
  data.triangles.resize(nt);
  for (std::size_t s = 0; s < nt; ++s) {
    const Tri& tri = mesh.triangles[data.bvh.prim_ids[s]];
    for (int v = 0; v < 3; ++v)
      for (int k = 0; k < 3; ++k) data.triangles[s][3 * v + k] = mesh.vertices[tri[v]][k];
  }
  return data;
}

}  // namespace plancheck
