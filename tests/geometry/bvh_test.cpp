// SPDX-License-Identifier: MIT
#include "src/geometry/bvh.h"

#include "support/test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

namespace plancheck {
namespace {

bool contains(const BvhNode& outer, const BvhNode& inner) {
  for (int k = 0; k < 3; ++k)
    if (inner.lo[k] < outer.lo[k] || inner.hi[k] > outer.hi[k]) return false;
  return true;
}

// Walks the tree: every slot in exactly one leaf, leaves small, children
// inside parents, triangles (as doubles) inside their leaf boxes.
void check_invariants(const Mesh& mesh, const CollisionModelData& d) {
  const Bvh& bvh = d.bvh;
  const std::size_t n = mesh.triangles.size();
  ASSERT_EQ(bvh.prim_ids.size(), n);
  ASSERT_EQ(d.triangle_count(), n);
  std::vector<int> slot_seen(n, 0), prim_seen(n, 0);
  std::vector<std::uint32_t> stack{0};
  std::size_t visited = 0;
  while (!stack.empty()) {
    const std::uint32_t i = stack.back();
    stack.pop_back();
    ++visited;
    ASSERT_LT(i, bvh.nodes.size());
    const BvhNode& node = bvh.nodes[i];
    for (int k = 0; k < 3; ++k) ASSERT_LE(node.lo[k], node.hi[k]);
    if (node.is_leaf()) {
      ASSERT_LE(node.count, static_cast<std::uint32_t>(kMaxLeafSize));
      for (std::uint32_t s = node.index; s < node.index + node.count; ++s) {
        ASSERT_LT(s, n);
        ++slot_seen[s];
        ++prim_seen[bvh.prim_ids[s]];
        const Tri& t = mesh.triangles[bvh.prim_ids[s]];
        for (int v = 0; v < 3; ++v)
          for (int k = 0; k < 3; ++k) {
            const double x = mesh.vertices[t[v]][k];
            ASSERT_EQ(d.vertex(s, v)[k], x);
            ASSERT_LE(static_cast<double>(node.lo[k]), x);
            ASSERT_GE(static_cast<double>(node.hi[k]), x);
          }
      }
    } else {
      ASSERT_LT(node.index + 1, bvh.nodes.size());
      ASSERT_TRUE(contains(node, bvh.nodes[node.index]));
      ASSERT_TRUE(contains(node, bvh.nodes[node.index + 1]));
      stack.push_back(node.index);
      stack.push_back(node.index + 1);
    }
  }
  EXPECT_EQ(visited, bvh.nodes.size());  // no unreachable nodes
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_EQ(slot_seen[i], 1) << "slot " << i;
    ASSERT_EQ(prim_seen[i], 1) << "triangle " << i;
  }
}

TEST(Bvh, InvariantsHoldOnVariousMeshes) {
  const std::vector<Mesh> meshes = {
      testing::make_sphere(Vec3(1.7374e6, -2, 3), 1.3, 24, 32),
      testing::make_torus(Vec3::Zero(), 2.0, 0.5, 40, 20),
      testing::make_soup(3, 3000, Vec3(0.1, 0.2, 0.3), 1.0, 0.2),
  };
  for (const Mesh& m : meshes) {
    const CollisionModelData d = build_collision_data(m);
    check_invariants(m, d);
  }
}

// Every vertex of a node's triangles projects inside the node's oriented
// box, whose axes are orthonormal.
void check_obbs(const CollisionModelData& d) {
  ASSERT_EQ(d.obbs.size(), d.bvh.nodes.size());
  std::vector<std::pair<std::uint32_t, std::uint32_t>> range(d.bvh.nodes.size());
  for (std::size_t i = d.bvh.nodes.size(); i-- > 0;) {
    const BvhNode& n = d.bvh.nodes[i];
    range[i] = n.is_leaf() ? std::make_pair(n.index, n.index + n.count)
                           : std::make_pair(range[n.index].first, range[n.index + 1].second);
  }
  for (std::size_t i = 0; i < d.obbs.size(); ++i) {
    const NodeObb& o = d.obbs[i];
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> axes(o.axis);
    ASSERT_LE((axes * axes.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-14);
    const Vec3 c(o.center[0], o.center[1], o.center[2]);
    for (std::uint32_t s = range[i].first; s < range[i].second; ++s)
      for (int v = 0; v < 3; ++v) {
        const Vec3 x(d.vertex(s, v)[0], d.vertex(s, v)[1], d.vertex(s, v)[2]);
        const Vec3 local = axes * (x - c);
        for (int k = 0; k < 3; ++k) ASSERT_LE(std::abs(local[k]), o.half[k]) << "node " << i;
      }
  }
}

TEST(Bvh, OrientedBoxesContainTheirTriangles) {
  for (const Mesh& m : {testing::make_sphere(Vec3(1.7374e6, -2, 3), 1.3, 24, 32),
                        testing::make_soup(4, 2000, Vec3(0.1, 0.2, 0.3), 1.0, 0.2)})
    check_obbs(build_collision_data(m));
  // Flat and degenerate content: coplanar squares and repeated triangles.
  Mesh same;
  same.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  for (int i = 0; i < 9; ++i) same.triangles.push_back({0, 1, 2});
  check_obbs(build_collision_data(same));
}

// compute_node_obbs projects each vertex once per node when the vertices are
// numbered in order of first use (build_collision_data's numbering), every
// corner otherwise: the same vertex values, so the boxes must be the same
// bits either way. Reversing the numbering sends a copy down the other path.
TEST(Bvh, OrientedBoxesDoNotDependOnVertexNumbering) {
  Mesh flat;  // zero coordinates (signed zeros among the projections) and a flat patch
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j) flat.vertices.push_back(Vec3(0.05 * i - 0.5, 0.05 * j - 0.5, 0.0));
  for (std::uint32_t i = 0; i < 20; ++i)
    for (std::uint32_t j = 0; j < 20; ++j) {
      const std::uint32_t a = i * 21 + j;
      flat.triangles.push_back({a, a + 1, a + 21});
      flat.triangles.push_back({a + 1, a + 22, a + 21});
    }
  for (const Mesh& m : {testing::make_sphere(Vec3(1.7374e6, -2, 3), 1.3, 24, 32),
                        testing::make_soup(4, 2000, Vec3(0.1, 0.2, 0.3), 1.0, 0.2),
                        testing::make_torus(Vec3(0.3, 0, -0.2), 0.5, 0.12, 60, 40), flat}) {
    const CollisionModelData built = build_collision_data(m);
    CollisionModelData reversed = built;
    const auto nv = static_cast<std::uint32_t>(built.vertices.size());
    for (std::uint32_t v = 0; v < nv; ++v) reversed.vertices[nv - 1 - v] = built.vertices[v];
    for (auto& c : reversed.corners)
      for (std::uint32_t& v : c) v = nv - 1 - v;
    reversed.obbs.clear();
    compute_node_obbs(reversed);
    ASSERT_EQ(reversed.obbs.size(), built.obbs.size());
    EXPECT_EQ(std::memcmp(reversed.obbs.data(), built.obbs.data(), built.obbs.size() * sizeof(NodeObb)), 0);
    check_obbs(reversed);
  }
}

TEST(Bvh, DegenerateInputs) {
  // All triangles at one place (equal centroids): still small leaves.
  Mesh same;
  same.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  for (int i = 0; i < 37; ++i) same.triangles.push_back({0, 1, 2});
  check_invariants(same, build_collision_data(same));
  // A single triangle, a zero-area triangle, and an empty mesh.
  Mesh one;
  one.vertices = {Vec3(0.1, 0.2, 0.3), Vec3(0.1, 0.2, 0.3), Vec3(0.1, 0.2, 0.3)};
  one.triangles = {{0, 1, 2}};
  check_invariants(one, build_collision_data(one));
  const CollisionModelData empty = build_collision_data(Mesh{});
  EXPECT_TRUE(empty.bvh.nodes.empty());
}

TEST(Bvh, FloatBoundsAreRoundedOutward) {
  for (double x : {0.1, -0.1, 1.7374e6 + 0.3, -1e-40, 3.0, 1e38 * 3.3}) {
    EXPECT_LE(static_cast<double>(round_down(x)), x);
    EXPECT_GE(static_cast<double>(round_up(x)), x);
  }
}

TEST(Bvh, RejectsBadInput) {
  Mesh bad;
  bad.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0)};
  bad.triangles = {{0, 1, 2}};
  EXPECT_THROW(build_collision_data(bad), std::exception);
  bad.vertices.push_back(Vec3(std::numeric_limits<double>::quiet_NaN(), 0, 0));
  EXPECT_THROW(build_collision_data(bad), std::exception);
}

}  // namespace
}  // namespace plancheck
