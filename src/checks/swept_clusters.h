// SPDX-License-Identifier: MIT
// A moving part proven clear of a static part's box over a whole straight
// motion, without any distance search: the certified motion check's
// shortcut for the many pairs that pass far from each other
// (src/checks/continuous.cpp).
//
// The part's triangles lie in a few spheres of its reference frame
// (BoxMotion's clusters, kTriangles). On a piece [t1, t2] of the segment,
// every point of cluster i stays within radius_i + speed_i (t2 - t1) / 2
// of the cluster's centre posed at the piece's middle, speed_i being
// MotionBound::sphere_bound for that sphere (the path it bounds is at most
// that per unit of t anywhere on the motion; for a chain of rotations from
// its levers, kept per checker: levers_bound, the same value), or twice
// BoxMotion::balls' move for the cluster over the box the segment spans
// where that is less (its levers read at the middle pose, not any pose;
// the march's PoseRates takes the same balls). So when every cluster's ball
// so grown keeps `target` from the box, the part does on the whole piece.
// The segment's two halves are tried first (the whole segment's balls,
// grown by half its length, passed for 39,650 pairs of the OMPL bench's
// default-arm edges where 71,356 more passed only as halves: trying the
// whole first cost 2.8% more instructions). Pieces that fail are halved,
// down to 1/32 of the segment: the part is posed at most 33 times, once
// per time, for all the boxes it is tested against.
//
// On the default arm's planned OMPL edges, 71 of the 74 pairs per edge of
// a moving part and a static mesh that the ends do not certify are proven
// here; each cost a pair search or more before (docs/planning.md).
#pragma once

#include "src/checks/verify.h"

#include <cstdint>
#include <vector>

namespace plancheck {

class SweptClusters {
 public:
  // Pieces: 1/2^kLevels of the segment at the finest.
  static constexpr int kLevels = 5;

  // Starts a segment from qa to qb (full parameter vectors, as written);
  // nothing of an earlier segment is kept but capacity. `checker` must
  // outlive the calls up to the next start. tight: clear's bounds from
  // each ball (else a piece is proven by one box around all its balls
  // where that box keeps the target, and clear's bound is the target
  // itself: as certain, looser, no distance read).
  void start(const Checker& checker, const std::vector<double>& qa, const std::vector<double>& qb,
             bool tight = true);

  // A lower bound (m) of the distance between `part` and every point of
  // the box [lo, hi] (world frame) over the whole segment, proven at least
  // `target`; or -infinity when that is not proven (a part that is static,
  // has no triangles, has a scale action in its chain, or comes nearer).
  double clear(int part, const Vec3& lo, const Vec3& hi, double target);

  // The part's BoxMotion::balls over the box qa and qb span from its
  // middle (as the march's PoseRates reads them), when a clear() of this
  // segment computed them; else nullptr. Valid up to the next start().
  const std::vector<BoxMotion::Ball>* balls(int part) const;

 private:
  struct PartData {
    // The checker's (kept while it is the same checker): the spheres, and
    // with a chain of rotations, their levers (MotionBound::sphere_levers,
    // one row per sphere).
    bool spheres_known = false;
    std::vector<BoxMotion::Sphere> spheres;
    std::vector<double> levers;
    // The segment's.
    bool known = false;
    bool usable = false;
    // BoxMotion::balls over the segment's box (balls: their answer),
    // bounding the speeds below where they are tighter.
    bool balls_known = false, balls = false;
    std::vector<BoxMotion::Ball> ball;
    std::vector<double> speed;  // per sphere: its points' path per unit of t
    std::vector<Vec3> centre;   // per time m / 2^kLevels and sphere: the sphere's centre posed
    std::vector<double> mag;    // the same: its largest coordinate's magnitude (the tests' rounding pad)
    std::uint64_t posed = 0;    // bit m: centre at time m computed
    // Per time and piece length (kLevels + 1 of them): the box that holds
    // every sphere grown by its reach there (one test for all of them).
    struct Hull {
      Vec3 lo, hi;
      double pad = 0.0;  // covers the rounding of the box and of its test
    };
    std::vector<Hull> hull;
    std::uint64_t hull_known[kLevels + 1] = {};  // per piece length, bit m: hull at time m computed
  };
  PartData& part(int index);
  const Vec3* centres(PartData& d, int index, int m);
  // The piece [lo, hi] (in 1/2^kLevels) and its halves; false at the first
  // that fails. `least` takes the least bound of those that pass.
  bool piece(PartData& d, int index, int lo, int hi, const Vec3& blo, const Vec3& bhi, double target,
             double& least);

  // Chain c's product at time m (chain_transform, continued from its
  // prefix's at m: the arm's parts share their first joints' products).
  const Affine& chain_at(int c, int m, const std::vector<double>& q);

  const Checker* checker_ = nullptr;
  bool tight_ = true;
  std::vector<int> prefixes_;            // chain_prefixes of the checker's scene
  std::vector<Affine> chain_pose_;       // per time and chain
  std::vector<std::uint64_t> chain_known_;  // per chain: bit m, its product at time m computed
  std::uint64_t checker_id_ = 0;  // Checker::instance_id() the parts' spheres are of
  const std::vector<double>* qa_ = nullptr;
  const std::vector<double>* qb_ = nullptr;
  std::vector<PartData> parts_;
  std::vector<double> q_;
  std::vector<double> lo_, hi_, mid_;  // the box qa and qb span, its middle
};

}  // namespace plancheck
