// SPDX-License-Identifier: MIT
// Upper bounds on how far any point of a part can travel while the driving
// parameters move linearly from one vector to another (the contract's motion
// between states). Conservative advancement (Schwarzer, Saha and Latombe
// 2005) certifies a segment by comparing such a bound with a distance.
#pragma once

#include "src/scene/scene.h"

#include <cstdint>
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

  // part_bound for the points of `part` within the sphere (centre, radius)
  // of its reference frame (a cluster of its triangles, BoxMotion::spheres):
  // the same bound with that sphere in place of the part's extent, so at
  // most part_bound's for a sphere holding the part. Per unit of t it
  // bounds those points' speed anywhere on the segment (the parameters
  // move linearly; every lever is read for any pose).
  double sphere_bound(int part, const Vec3& centre, double radius, std::span<const double> qa,
                      std::span<const double> qb) const;

  // sphere_bound in two steps, for many spheres of a part over many
  // motions: the lever each action of the part's chain (root first) turns
  // the sphere's points about, which for rotations does not depend on the
  // pose (false, levers empty, when the chain has any other action), then
  // a motion's bound from them: sphere_bound's value, bit for bit.
  bool sphere_levers(int part, const Vec3& centre, double radius, std::vector<double>& levers) const;
  double levers_bound(int part, std::span<const double> levers, std::span<const double> qa,
                      std::span<const double> qb) const;

  // An upper bound (m) on how much the distance between parts a and b can
  // change over the same motion: the sum of their part_bound, except that
  // the actions both chains begin with, when all rigid (rotations and
  // translations), move both parts alike and leave their distance as it is:
  // then only each chain's own actions after them count (a link and its
  // neighbour on one arm move relative to each other by the joints between
  // them only). Indices past the parts are static, as in part_bound.
  double pair_bound(int a, int b, std::span<const double> qa, std::span<const double> qb) const;

  // pair_bound of every pair at once (out[k] for pairs[k]), the same values:
  // each part's bound from a given shared prefix is computed once (a part in
  // many pairs, most of them with static parts, is bounded once).
  void pair_bounds(const std::vector<std::pair<int, int>>& pairs, std::span<const double> qa,
                   std::span<const double> qb, std::vector<double>& out) const;

  // The same for a pair list planned once (pair_plan): what each pair's
  // two bounds start from is found once, not on every motion.
  struct PairPlan {
    std::vector<std::pair<int, std::size_t>> keys;           // (part, shared prefix), each once
    std::vector<std::pair<std::uint32_t, std::uint32_t>> of;  // per pair: its two parts' keys
  };
  PairPlan pair_plan(const std::vector<std::pair<int, int>>& pairs) const;
  void pair_bounds(const PairPlan& plan, std::span<const double> qa, std::span<const double> qb,
                   std::vector<double>& out) const;

 private:
  struct PartExtent {
    Vec3 centre = Vec3::Zero();  // bounding-sphere centre of the vertices (m)
    double radius = 0.0;         // max |x - centre| (m)
    // About the innermost action of the chain (its pivot or fixed point):
    double inner_radius = 0.0;   // max |x - c| (m)
    double inner_arm = 0.0;      // rotate: max distance of a vertex from its axis (m)
  };
  // part_bound over the chain's actions from index `first` inward (the
  // motion in the frame the first `first` actions map into the world).
  double bound_from(int part, std::size_t first, std::span<const double> qa, std::span<const double> qb) const;
  // The same for points within extent e of the part.
  double bound_from(int part, const PartExtent& e, std::size_t first, std::span<const double> qa,
                    std::span<const double> qb) const;
  // The common prefix of a's and b's chains that moves both alike.
  std::size_t shared_actions(int a, int b) const;

  const Scene& scene_;
  std::vector<PartExtent> extents_;
};

}  // namespace plancheck
