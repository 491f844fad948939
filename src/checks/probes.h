// SPDX-License-Identifier: MIT
// Probes: rays (or fans of rays) fixed to a part, cast at every state against
// the static parts and the terrain with Embree (rtcIntersect1M on one scene).
// Built only when the scene has probes. The static parts are Embree
// triangle meshes; the terrain is an Embree user geometry whose callback
// walks a Heightfield in double (raycast.h), so the one committed scene sees
// whatever dug copy of the terrain a cast names: verify casts each state of
// a digging scene against the terrain as dug through that state (see
// regolith.cpp), and a probe pointed into a fresh pit reads its depth.
//
// Fan pattern: with count n > 1 and half angle a, ray k (k = 0..n-1) is the
// probe direction d rotated by -a + 2a k / (n - 1) about the axis
// e = normalize(d x z), or normalize(d x x) when d is within 1e-9 of +-z; all
// at the reference pose, then moved with the part. The fan is planar: it
// spans the plane of d and e x d. The probe reports the shortest of its rays.
#pragma once

#include "src/geometry/heightfield.h"
#include "src/geometry/raycast.h"
#include "src/scene/scene.h"

#include <memory>
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
  // terrain: a dug copy of terrain() to see (nullptr: the undisturbed one).
  void cast(const std::vector<std::vector<double>>& states, int threads,
            std::vector<std::vector<ProbeReading>>& out, const Heightfield* terrain = nullptr) const;

  // One state's readings (out[p]) against `terrain` (nullptr: undisturbed).
  void cast_state(const std::vector<double>& params, std::vector<ProbeReading>& out,
                  const Heightfield* terrain = nullptr) const;

  // The undisturbed terrain the ray scene walks (nullptr: the scene has none).
  const Heightfield* terrain() const { return terrain_.get(); }

 private:
  // Rays of states [begin, end) into out.
  void cast_range(const std::vector<std::vector<double>>& states, std::size_t begin, std::size_t end,
                  std::vector<std::vector<ProbeReading>>& out, const Heightfield* terrain) const;

  const Scene& scene_;
  std::unique_ptr<const Heightfield> terrain_;  // before rays_, which points into it
  RayScene rays_;
  std::vector<std::string> names_;            // per ray-scene mesh: part name or "terrain"
  std::vector<std::vector<Vec3>> directions_;  // per probe
  std::size_t rays_per_state_ = 0;
};

}  // namespace plancheck
