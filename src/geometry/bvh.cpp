// SPDX-License-Identifier: MIT
#include "src/geometry/bvh.h"

#include "src/base/error.h"
#include "kernels/leaf_bounds.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace plancheck {

static_assert(kMaxLeafSize <= kLeafLanes, "the leaf prefilters hold one leaf in 16 lanes");

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
    for (int k = 0; k < 3; ++k) {
      data.max_abs[k] = std::max(data.max_abs[k], std::abs(mesh.vertices[i][k]));
      if (static_cast<double>(static_cast<float>(mesh.vertices[i][k])) != mesh.vertices[i][k]) data.float_exact = false;
    }
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
  data.corners.resize(nt);
  constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> renumber(nv, kUnused);
  for (std::size_t s = 0; s < nt; ++s) {
    const Tri& tri = mesh.triangles[data.bvh.prim_ids[s]];
    for (int v = 0; v < 3; ++v) {
      std::uint32_t& r = renumber[tri[v]];
      if (r == kUnused) {
        r = static_cast<std::uint32_t>(data.vertices.size());
        const Vec3& x = mesh.vertices[tri[v]];
        data.vertices.push_back({x[0], x[1], x[2]});
      }
      data.corners[s][v] = r;
    }
  }
  data.vertices.shrink_to_fit();
  compute_node_obbs(data);
  compute_leaf_soa(data);
  return data;
}

void compute_leaf_soa(CollisionModelData& data) {
  const std::size_t n = data.triangle_count();
  data.soa_stride = n + kSoaPadding;
  data.soa.assign(9 * data.soa_stride, 0.0f);
  for (const BvhNode& node : data.bvh.nodes)
    if (node.is_leaf())
      store_leaf_soa(data.soa.data(), data.soa_stride, node.index, static_cast<int>(node.count),
                     node.lo, node.hi,
                     [&](std::uint32_t slot, int v) { return data.vertex(slot, v); });
}

void compute_node_obbs(CollisionModelData& data) {
  const auto& nodes = data.bvh.nodes;
  const std::size_t n = nodes.size();
  data.obbs.assign(n, NodeObb{});
  if (n == 0) return;
  // Vertex moments and slot ranges, bottom-up: children always have larger
  // indices than their parent, so a reverse sweep sees children first.
  struct Moments {
    double count = 0, sum[3] = {0, 0, 0}, outer[6] = {0, 0, 0, 0, 0, 0};
    std::uint32_t begin = 0, end = 0;
  };
  std::vector<Moments> m(n);
  // Moments about the root box's centre, so parts modelled far from their
  // origin do not lose the covariance to cancellation.
  double origin[3];
  for (int k = 0; k < 3; ++k)
    origin[k] = 0.5 * (static_cast<double>(nodes[0].lo[k]) + static_cast<double>(nodes[0].hi[k]));
  for (std::size_t i = n; i-- > 0;) {
    const BvhNode& node = nodes[i];
    Moments& mi = m[i];
    if (node.is_leaf()) {
      mi.begin = node.index;
      mi.end = node.index + node.count;
      for (std::uint32_t s = mi.begin; s < mi.end; ++s)
        for (int v = 0; v < 3; ++v) {
          const double* xv = data.vertex(s, v);
          const double x[3] = {xv[0] - origin[0], xv[1] - origin[1], xv[2] - origin[2]};
          mi.count += 1;
          for (int k = 0; k < 3; ++k) mi.sum[k] += x[k];
          mi.outer[0] += x[0] * x[0];
          mi.outer[1] += x[0] * x[1];
          mi.outer[2] += x[0] * x[2];
          mi.outer[3] += x[1] * x[1];
          mi.outer[4] += x[1] * x[2];
          mi.outer[5] += x[2] * x[2];
        }
    } else {
      const Moments& l = m[node.index];
      const Moments& r = m[node.index + 1];
      mi.count = l.count + r.count;
      for (int k = 0; k < 3; ++k) mi.sum[k] = l.sum[k] + r.sum[k];
      for (int k = 0; k < 6; ++k) mi.outer[k] = l.outer[k] + r.outer[k];
      mi.begin = std::min(l.begin, r.begin);
      mi.end = std::max(l.end, r.end);
    }
  }
  // Each node projects its vertices onto its axes, at every level of the
  // tree. Its slots name each vertex ~6 times on a closed mesh (three
  // corners, each vertex shared by ~6 triangles); projecting each vertex
  // once gives the same minimum and maximum (the same values, visited in
  // another order; only the sign of a zero could differ, and it is lost
  // below: the centre adds 0.5 (lo + hi) to a sum that starts at +0, the
  // half extents add a positive margin). That needs build_collision_data's
  // numbering (vertices in order of first use by the slots, every vertex
  // used): the vertices first used within the slots [b, e) are then the
  // index range [first_new[b], first_new[e]), and any other corner there
  // has an index below first_new[b]. Other numberings project every corner.
  std::vector<std::uint32_t> first_new(data.triangle_count() + 1, 0);
  bool first_use = true;
  {
    std::uint32_t seen = 0;
    for (std::size_t s = 0; s < data.triangle_count() && first_use; ++s) {
      first_new[s] = seen;
      for (int v = 0; v < 3; ++v) {
        const std::uint32_t c = data.corners[s][static_cast<std::size_t>(v)];
        if (c == seen)
          ++seen;
        else if (c > seen)
          first_use = false;
      }
    }
    first_new[data.triangle_count()] = seen;
    first_use = first_use && seen == data.vertices.size();
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Moments& mi = m[i];
    const Eigen::Vector3d mean(mi.sum[0] / mi.count, mi.sum[1] / mi.count, mi.sum[2] / mi.count);
    Eigen::Matrix3d cov;
    cov << mi.outer[0], mi.outer[1], mi.outer[2], mi.outer[1], mi.outer[3], mi.outer[4],
        mi.outer[2], mi.outer[4], mi.outer[5];
    cov = cov / mi.count - mean * mean.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    eig.computeDirect(cov);
    // Re-orthonormalise (Gram-Schmidt, then a cross product) so the axes are
    // orthonormal to rounding even for repeated eigenvalues; fall back to
    // the coordinate axes if the solver returned anything non-finite.
    Eigen::Vector3d e0 = eig.eigenvectors().col(2), e1 = eig.eigenvectors().col(1);
    bool ok = e0.allFinite() && e1.allFinite() && e0.norm() > 0.5;
    if (ok) {
      e0.normalize();
      e1 -= e1.dot(e0) * e0;
      ok = e1.norm() > 0.5;
      e1.normalize();
    }
    if (!ok) {
      e0 = Eigen::Vector3d::UnitX();
      e1 = Eigen::Vector3d::UnitY();
    }
    const Eigen::Vector3d e2 = e0.cross(e1);
    const Eigen::Vector3d axes[3] = {e0, e1, e2};
    double lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::numeric_limits<double>::infinity();
      hi[k] = -std::numeric_limits<double>::infinity();
    }
    const auto project = [&](const double* x) {
      for (int k = 0; k < 3; ++k) {
        const double p = axes[k][0] * x[0] + axes[k][1] * x[1] + axes[k][2] * x[2];
        lo[k] = std::min(lo[k], p);
        hi[k] = std::max(hi[k], p);
      }
    };
    if (first_use) {
      const std::uint32_t new_begin = first_new[mi.begin], new_end = first_new[mi.end];
      for (std::uint32_t c = new_begin; c < new_end; ++c) project(data.vertices[c].data());
      for (std::uint32_t s = mi.begin; s < mi.end; ++s)
        for (int v = 0; v < 3; ++v) {
          const std::uint32_t c = data.corners[s][static_cast<std::size_t>(v)];
          if (c < new_begin) project(data.vertices[c].data());
        }
    } else {
      for (std::uint32_t s = mi.begin; s < mi.end; ++s)
        for (int v = 0; v < 3; ++v) project(data.vertex(s, v));
    }
    NodeObb& o = data.obbs[i];
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    double extent = 0.0;
    for (int k = 0; k < 3; ++k) {
      for (int j = 0; j < 3; ++j) o.axis[3 * k + j] = axes[k][j];
      c += 0.5 * (lo[k] + hi[k]) * axes[k];
      o.half[k] = 0.5 * (hi[k] - lo[k]);
      extent += o.half[k];
    }
    // Projections, the centre's reconstruction and the axes' deviation from
    // orthonormality each err by a few ulps of |x| <= |c| + extent.
    const double margin = 1e-12 * (c.cwiseAbs().sum() + extent) + 1e-300;
    for (int k = 0; k < 3; ++k) {
      o.center[k] = c[k];
      o.half[k] += margin;
    }
    o.radius = std::sqrt(o.half[0] * o.half[0] + o.half[1] * o.half[1] + o.half[2] * o.half[2]);
  }
}

}  // namespace plancheck
