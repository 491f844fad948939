// SPDX-License-Identifier: MIT
// A plain, independent clearance check for the generator: posed arm triangles
// against static triangles (lander, ascender, terrain) and against other arm
// links, exact triangle-triangle distance in double, pruned by a uniform grid
// and boxes only. It decides which states of the designed plans violate, so
// the real verifier can later be compared with it (expected.json).
#pragma once

#include "datasets/change5.h"

#include <set>
#include <string>
#include <utility>
#include <vector>

namespace plancheck::dataset {

struct Triangle {
  Vec3 p[3];
};

// Distance between two triangles (0 when they touch or intersect).
double triangle_distance(const Triangle& a, const Triangle& b);

struct StateCheck {
  double min_distance = 0.0;   // m, capped at the checker's cutoff
  bool collision = false;
  std::string part_a, part_b;  // the pair at min_distance (empty when above cutoff)
  std::set<std::pair<std::string, std::string>> colliding;  // part pairs that intersect
};

class Checker {
 public:
  // Parts named in `allowed` pairs are not checked against each other
  // ("terrain" is the DEM). Distances above `cutoff` are reported as cutoff.
  Checker(const Model& model, const std::vector<double>& dem, const std::vector<std::pair<std::string, std::string>>& allowed,
          double cutoff);
  StateCheck check(const Joints& q) const;

 private:
  // A uniform grid over one static part's triangles (CSR layout).
  struct Grid {
    Vec3 min = Vec3::Zero();
    int nx = 0, ny = 0, nz = 0;
    std::vector<std::uint32_t> start, items;  // items: indices into static_tris_
  };
  struct StaticPart {
    std::string name;
    Eigen::AlignedBox3d box;
    std::size_t first = 0, count = 0;  // range in static_tris_
    Grid grid;
  };
  struct MovingPart {
    std::string name;
    int chain;  // 0..3: J1..J4
    std::vector<Triangle> tris;  // reference frame
    Eigen::AlignedBox3d box;     // reference frame
    std::vector<Eigen::AlignedBox3d> cluster_boxes;  // reference frame, kCluster triangles each
  };
  static constexpr std::size_t kCluster = 32;
  bool allowed(const std::string& a, const std::string& b) const;
  template <class Fn>
  void for_cells(const Grid& g, const Eigen::AlignedBox3d& b, Fn&& fn) const;

  std::vector<StaticPart> static_parts_;
  std::vector<Triangle> static_tris_;
  std::vector<int> static_owner_;
  std::vector<Eigen::AlignedBox3d> static_boxes_;
  std::vector<MovingPart> moving_;
  std::set<std::pair<std::string, std::string>> allowed_;
  double cutoff_;
  double cell_ = 0.1;
};

}  // namespace plancheck::dataset
