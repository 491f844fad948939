// SPDX-License-Identifier: MIT
// How far any point of a part can be from where it is at one configuration
// c, anywhere in a box of configurations around c: a tighter bound than
// MotionBound::part_bound for the sweep's boxes (src/checks/sweep_certify.h).
//
// MotionBound carries a sphere about each action's pivot outwards, so a
// rotation's lever is the farthest any pose of the inner joints could put
// the part from its axis (an arm bent back counts as stretched out). Here
// the lever is read at the pose c itself: for a point x of the part under
// rigid actions A1 (root) ... Ak, posed at p(q) = A1(...Ak(x)), the path
// from c to any q of the box is at most sum_i h_i sup dist(y_i, axis_i)
// (h_i the most action i's value moves from c within the box, in rad or m;
// y_i = A_{i+1}(...Ak(x)) the point action i turns), and
//   dist(y_i(q), axis_i) <= dist(Y_i(c) z, axis_i) + rho + sum_{j>i} h_j arm_j
// for x in a sphere (z, rho) of the part: Y_i(c) is an isometry, and the
// inner actions move y_i by at most their own path. The part's vertices
// are split into a few clusters, each in its own sphere, and the bound is
// the largest cluster's; the innermost rotation's lever is also at most the
// cluster's exact largest distance from that axis. Chains with a scale
// action (not isometries) fall back to MotionBound::part_bound over the box.
// This bound may be unified later with src/geometry/motion_bound.h.
#pragma once

#include "src/geometry/motion_bound.h"
#include "src/scene/scene.h"

#include <span>
#include <vector>

namespace plancheck {

class BoxMotion {
 public:
  // The clusters are built from every triangle's corners (kCorners, as the
  // sweep's certifier has them) or from whole triangles (kTriangles: split
  // by their centroids, each cluster's sphere holding every point of its
  // triangles, so that balls() can say where a cluster is; quicker to
  // build, the bounds a little different).
  enum class Points { kCorners, kTriangles };
  explicit BoxMotion(const Scene& scene, Points points = Points::kCorners);

  // An upper bound (m) on |p(q, x) - p(c, x)| for every point x of `part`
  // and every q with lo <= q <= hi componentwise (full parameter vectors;
  // c must lie in that box). 0 for static parts and indices past the parts
  // (the terrain); padded for rounding; +infinity when an input is not
  // finite.
  double reach(int part, std::span<const double> lo, std::span<const double> hi, std::span<const double> c) const;

  // The clusters one part's vertices are split into (statistics, tests).
  std::size_t clusters(int part) const;
  // Their spheres in the part's reference frame: empty for a static part,
  // one with no triangles, or one with a scale action in its chain (posed,
  // its spheres would not stay spheres). With kTriangles every point of
  // every triangle of the part lies in one of them.
  struct Sphere {
    Vec3 centre = Vec3::Zero();
    double radius = 0.0;
  };
  void spheres(int part, std::vector<Sphere>& out) const;
  Points points() const { return points_; }

  static constexpr std::size_t kMaxChain = 64;
  // reach's work for one box, kept to bound single points of the part
  // (the sweep's part-scale witnesses, src/geometry/solid_witness.h).
  class Lever {
   public:
    // The bound for the one point x (mesh frame, m): reach's, with the
    // point as a cluster of radius 0.
    double point(const Vec3& x) const;

   private:
    friend class BoxMotion;
    double sphere(const Vec3& centre, double radius, double inner_arm) const;
    double fixed = 0.0;  // >= 0 (or NaN): the bound whatever the point; -1: per point
    const Scene* scene = nullptr;
    const std::vector<int>* chain = nullptr;
    std::size_t outer = 0;
    double h[kMaxChain] = {};
    Affine at[kMaxChain];
  };
  Lever lever(int part, std::span<const double> lo, std::span<const double> hi, std::span<const double> c) const;
  // reach from the part's lever over the box.
  double reach(int part, const Lever& l) const;

  // Per cluster of `part`: its sphere posed at c (world frame) and how far
  // any point in it moves from there within the box (reach's bound for that
  // cluster alone: the largest move is reach). With kTriangles every point
  // of the part lies in some cluster's sphere at c, and within radius +
  // move of its centre anywhere in the box. False (out empty) where reach
  // has no clusters to go by (a static part, a chain with a scale action,
  // a non-finite box).
  struct Ball {
    Vec3 centre = Vec3::Zero();
    double radius = 0.0;
    double move = 0.0;
  };
  bool balls(int part, std::span<const double> lo, std::span<const double> hi, std::span<const double> c,
             std::vector<Ball>& out) const;

 private:
  struct Cluster {
    Vec3 centre = Vec3::Zero();  // part frame (m)
    double radius = 0.0;         // max |x - centre| over the cluster's vertices
    double inner_arm = 0.0;      // max distance of its vertices from the innermost rotation's axis
  };
  struct PartData {
    bool rigid = true;  // no scale action in the chain
    std::vector<Cluster> clusters;
  };
  const Scene& scene_;
  Points points_;
  MotionBound fallback_;
  std::vector<PartData> parts_;
};

}  // namespace plancheck
