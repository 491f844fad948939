// SPDX-License-Identifier: MIT
// FCL 0.7 as an independent oracle: every part as a BVHModel<OBBRSS>, posed
// by the scene's kinematics, pairs checked one by one.
#pragma once

#include "src/scene.h"

#include <memory>
#include <utility>
#include <vector>

namespace plancheck::testing {

class FclReference {
 public:
  // parts: the meshes in checker order (parts, then terrain); pairs: checked pairs.
  FclReference(const Scene& scene, const std::vector<const Mesh*>& meshes,
               std::vector<std::pair<int, int>> pairs);
  ~FclReference();

  struct Answer {
    bool collision = false;
    double distance = 0.0;     // minimum over the pairs; 0 when colliding
    int pair = -1;             // index of the pair at the minimum
  };
  Answer check(const std::vector<double>& params) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace plancheck::testing
