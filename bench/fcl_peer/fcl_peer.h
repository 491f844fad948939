// SPDX-License-Identifier: MIT
// FCL 0.7, the library robotics users would otherwise pick, set up the way
// its documentation and broadphase callbacks use it: every part one
// BVHModel<OBBRSS> built once, posed per state by the scene's kinematics;
// per state every checked pair is collided, then (unless a pair collides)
// distanced with one DistanceResult shared across the pairs, so the best
// distance so far prunes the next pair's traversal. The one FCL adapter:
// the Table 3 bench times it and the tests use it as an independent oracle.
// FclMeshPair is the same for two bare meshes (the two-mesh bench). FCL
// never enters plancheck_core.
#pragma once

#include "src/scene/scene.h"

#include <memory>
#include <utility>
#include <vector>

namespace plancheck::reference {

struct FclAnswer {
  bool collision = false;
  double distance = 0.0;  // m, minimum over the pairs; 0 when colliding, inf when not asked
};

class FclPeer {
 public:
  // meshes: in the checker's part order (parts, then terrain); pairs: the
  // checker's checked pairs, indices into meshes.
  FclPeer(const Scene& scene, const std::vector<const Mesh*>& meshes,
          std::vector<std::pair<int, int>> pairs);
  ~FclPeer();

  using Answer = FclAnswer;
  // with_distance false: collision only (every pair collided, no distance).
  // rel_err: FCL's DistanceRequest::rel_err. Not thread-safe: the parts'
  // FCL objects are re-posed in place (one FclPeer per thread).
  Answer check(const std::vector<double>& params, bool with_distance = true, double rel_err = 0.0) const;

  std::size_t memory_bytes() const;  // BVH nodes, vertices and triangles of every model

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Two meshes, each one BVHModel<OBBRSS> built once, queried at given poses
// the way FCL's own mesh-mesh tests do (fcl::collide, then fcl::distance
// unless they collide; no broadphase, one pair). Thread-safe: a query keeps
// no state.
class FclMeshPair {
 public:
  FclMeshPair(const Mesh& a, const Mesh& b);
  ~FclMeshPair();
  // with_distance false: collision only (distance inf unless colliding).
  FclAnswer check(const Affine& ta, const Affine& tb, bool with_distance = true) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace plancheck::reference
