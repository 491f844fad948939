// SPDX-License-Identifier: MIT
// Probes: rays (or fans of rays) fixed to a part, cast at every state against
// the static parts and the terrain with Embree. Built only when the scene has
// probes. The terrain here is the undisturbed grid: digging changes a few
// centimetres under the scoop, and a ray scene rebuilt per state would cost
// more than the whole check; a probe pointed into a fresh pit reads the
// surface as it was.
//
// Fan pattern: with count n > 1 and half angle a, ray k (k = 0..n-1) is the
// probe direction d rotated by -a + 2a k / (n - 1) about the axis
// e = normalize(d x z), or normalize(d x x) when d is within 1e-9 of +-z; all
// at the reference pose, then moved with the part. The fan is planar: it
// spans the plane of d and e x d. The probe reports the shortest of its rays.
#pragma once

#include "src/raycast.h"
#include "src/scene.h"

#include <string>
#include <vector>

namespace plancheck {

struct ProbeReading {
  double distance = 0.0;  // m; max_range when nothing is hit
  int hit = -1;           // index into ProbeCaster::target_name, -1: nothing
};

class ProbeCaster {
 public:
  explicit ProbeCaster(const Scene& scene);

  // Directions of one probe's rays at the reference pose (unit), fan order.
  static std::vector<Vec3> fan_directions(const ProbeConfig& probe);

  const std::string& target_name(int index) const { return names_[static_cast<std::size_t>(index)]; }
  const std::vector<std::string>& target_names() const { return names_; }
  std::size_t rays_per_state() const { return rays_per_state_; }

  // out[s][p]: probe p (scene.probes order) at state s. Rays of many states
  // are cast as one stream; results do not depend on `threads`.
  void cast(const std::vector<std::vector<double>>& states, int threads,
            std::vector<std::vector<ProbeReading>>& out) const;

 private:
  const Scene& scene_;
  RayScene rays_;
  std::vector<std::string> names_;            // per ray-scene mesh: part name or "terrain"
  std::vector<std::vector<Vec3>> directions_;  // per probe
  std::size_t rays_per_state_ = 0;
};

}  // namespace plancheck
