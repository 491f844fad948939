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
  struct StaticPart {
    std::string name;
    Eigen::AlignedBox3d box;
  };
  struct MovingPart {
    std::string name;
    int chain;  // 0..3: J1..J4
    std::vector<Triangle> tris;  // reference frame
  };
  bool allowed(const std::string& a, const std::string& b) const;

  std::vector<StaticPart> static_parts_;
  std::vector<Triangle> static_tris_;
  std::vector<int> static_owner_;
  std::vector<Eigen::AlignedBox3d> static_boxes_;
  std::vector<MovingPart> moving_;
  std::set<std::pair<std::string, std::string>> allowed_;
  double cutoff_;
  // Uniform grid over the static triangles (CSR layout).
  Vec3 grid_min_;
  double cell_ = 0.1;
  int nx_ = 0, ny_ = 0, nz_ = 0;
  std::vector<std::uint32_t> cell_start_, cell_items_;
};

}  // namespace plancheck::dataset
