// SPDX-License-Identifier: MIT
#include "src/scene/reach.h"

#include <algorithm>
#include <limits>

namespace plancheck {

namespace {

// Sum of the hops between consecutive pivots; negative when an action of
// the chain is not a rotation.
double chain_hops(const Scene& scene, const std::vector<int>& chain) {
  double hops = 0.0;
  for (std::size_t i = 0; i < chain.size(); ++i) {
    const Action& a = scene.actions[static_cast<std::size_t>(chain[i])];
    if (a.type != ActionType::kRotate) return -1.0;
    if (i > 0) hops += (a.pivot - scene.actions[static_cast<std::size_t>(chain[i - 1])].pivot).norm();
  }
  return hops;
}

}  // namespace

Reach part_reach(const Scene& scene, const std::vector<int>& chain, const Mesh& mesh) {
  Reach r;
  if (chain.empty()) return r;
  const double hops = chain_hops(scene, chain);
  if (hops < 0.0) return r;
  r.centre = scene.actions[static_cast<std::size_t>(chain.front())].pivot;
  const Vec3 last = scene.actions[static_cast<std::size_t>(chain.back())].pivot;
  r.r_max = 0.0;
  r.r_min = std::numeric_limits<double>::infinity();
  for (const Tri& t : mesh.triangles)
    for (std::uint32_t v : t) {
      const double d = (mesh.vertices[v] - last).norm() + hops;
      r.r_max = std::max(r.r_max, d);
      r.r_min = std::min(r.r_min, d);
    }
  r.bounded = !mesh.triangles.empty();
  return r;
}

double point_reach(const Scene& scene, const std::vector<int>& chain, const Vec3& x) {
  if (chain.empty()) return -1.0;
  const double hops = chain_hops(scene, chain);
  if (hops < 0.0) return -1.0;
  return (x - scene.actions[static_cast<std::size_t>(chain.back())].pivot).norm() + hops;
}

}  // namespace plancheck
