// SPDX-License-Identifier: MIT
// Upper bounds on how far any point of a part can travel while the driving
// parameters move linearly from one vector to another (the contract's motion
// between states). Conservative advancement (Schwarzer, Saha and Latombe
// 2005) certifies a segment by comparing such a bound with a distance.
#pragma once

#include "src/scene/scene.h"

#include <span>
#include <vector>

namespace plancheck {

class MotionBound {
 public:
  // Extents are taken from the triangle vertices of every scene part; parts
  // index Scene::parts (indices past the end, such as the terrain pseudo-part
  // of a Checker, are static).
  explicit MotionBound(const Scene& scene);

  // An upper bound (m) on the length of the path of every point of `part`
  // while the parameters go linearly from qa to qb (full vectors, as written). 0 for
  // static parts. Padded for rounding; +infinity when an input is not finite.
  double part_bound(int part, std::span<const double> qa, std::span<const double> qb) const;

 private:
  struct PartExtent {
    Vec3 centre = Vec3::Zero();  // bounding-sphere centre of the vertices (m)
    double radius = 0.0;         // max |x - centre| (m)
    // About the innermost action of the chain (its pivot or fixed point):
    double inner_radius = 0.0;   // max |x - c| (m)
    double inner_arm = 0.0;      // rotate: max distance of a vertex from its axis (m)
  };
  const Scene& scene_;
  std::vector<PartExtent> extents_;
};

}  // namespace plancheck
