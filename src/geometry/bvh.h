// SPDX-License-Identifier: MIT
// The one BVH node type and its binned-SAH builder, plus the per-part
// collision data (BVH + triangle coordinates in the part's reference frame).
// Any wider or SoA layout for SIMD traversal must be converted from these
// nodes, never built by a second builder.
#pragma once

#include "src/geometry/collision_model.h"
#include "src/scene/scene.h"

#include <array>
#include <cstdint>
#include <vector>

namespace plancheck {

// Byte budget: 32 bytes, two nodes per 64-byte cache line.
//   24 bytes  float bounds, rounded outward so they contain the double
//             triangles (conservative: a float box never cuts a triangle off)
//    4 bytes  index: inner node -> first child (the second is index + 1);
//             leaf -> first slot in the primitive order
//    4 bytes  count: 0 for an inner node, else primitives in the leaf
// Bounds are never NaN: the builder rejects non-finite vertices.
struct BvhNode {
  float lo[3];
  float hi[3];
  std::uint32_t index;
  std::uint32_t count;
  bool is_leaf() const { return count != 0; }
};
static_assert(sizeof(BvhNode) == 32, "BvhNode byte budget");

struct Bvh {
  std::vector<BvhNode> nodes;          // nodes[0] is the root (when not empty)
  std::vector<std::uint32_t> prim_ids;  // primitive order: slot -> input primitive index
};

// Leaves of collision models hold at most this many triangles; traversal
// keeps per-leaf scratch of this size on the stack.
inline constexpr int kMaxLeafSize = 16;

struct BvhBuildOptions {
  int bins = 16;                      // SAH bins per axis
  int max_leaf_size = kMaxLeafSize;   // primitives per leaf at most
};

// Binned SAH build (Wald, "On fast construction of SAH-based bounding volume
// hierarchies", 2007) over primitive boxes [lo, hi] (double); O(n log n).
// All three axes are binned at every node; ties and degenerate centroid sets
// fall back to an index-median split, so leaves never exceed max_leaf_size.
Bvh build_bvh(const std::vector<std::array<double, 6>>& boxes,
              const BvhBuildOptions& options = {});

// Rounds outward: lo_f <= lo and hi_f >= hi as real numbers.
float round_down(double x);
float round_up(double x);

// Oriented bounds of one node, derived from the canonical tree (same
// topology, same index as bvh.nodes; not a second builder): axes from the
// principal components of the node's vertices (as in Gottschalk, Lin and
// Manocha, "OBBTree", 1996), extents from projecting every vertex of the
// node's triangles, widened to cover the rounding of those projections.
// 16 doubles, 128 bytes per node; doubles so the axes are orthonormal to
// rounding and no float re-rounding is needed. They give tight bounds on
// curved surfaces, where axis-aligned boxes of tilted patches are thick.
struct NodeObb {
  double axis[9];    // rows: orthonormal axes, part frame
  double center[3];  // part frame
  double half[3];    // half extents along the axes (m)
  double radius;     // |half|, computed as sqrt(h0 h0 + h1 h1 + h2 h2): the ball test's radius
};

// Collision structure of one part, all in the part's reference frame.
struct CollisionModelData {
  Bvh bvh;
  // Triangles in the BVH's primitive order as corner indices into
  // `vertices` (the mesh's vertices used by any triangle, renumbered in
  // order of first use so a leaf's corners sit close together). Shared
  // corners make this 12 bytes per triangle plus about 12 for vertices on a
  // closed mesh, against 72 for nine doubles per triangle; the coordinates
  // are the mesh's doubles unchanged. The mesh index of slot s is
  // bvh.prim_ids[s].
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::array<std::uint32_t, 3>> corners;
  std::size_t triangle_count() const { return corners.size(); }
  const double* vertex(std::size_t slot, int corner) const {
    return vertices[corners[slot][static_cast<std::size_t>(corner)]].data();
  }
  // max over vertices of |x|, |y|, |z| per axis: sizes rounding margins.
  std::array<double, 3> max_abs = {0, 0, 0};
  // Every vertex coordinate is a float: node boxes are then exact, and the
  // distance search's tie cull (DistanceRequest::tie_cull) can settle ties;
  // else the float boxes' outward rounding is far above a tie and the cull
  // only costs time (collision_model.cpp, box_settled).
  bool float_exact = true;
  std::vector<NodeObb> obbs;  // one per bvh node, same index
  // The triangles again as floats for the SIMD leaf prefilters
  // (kernels/leaf_bounds.h): coordinate c (= 3 v + k) of slot s at
  // soa[c * soa_stride + s], relative to the centre of the slot's leaf box;
  // soa_stride = slots + kSoaPadding. 36 bytes per triangle.
  std::vector<float> soa;
  std::size_t soa_stride = 0;
};

// Fills data.soa from data.bvh's leaves and the vertices.
void compute_leaf_soa(CollisionModelData& data);

// Fills data.obbs from data.bvh and data.triangles.
void compute_node_obbs(CollisionModelData& data);

// Builds the data for a mesh; throws InputError on an index out of range or a
// non-finite vertex.
CollisionModelData build_collision_data(const Mesh& mesh);

}  // namespace plancheck
