// SPDX-License-Identifier: MIT
#include "src/checks/probes.h"

#include "src/scene/kinematics.h"
#include "src/base/parallel.h"
#include "src/scene/terrain.h"

#include <cmath>

namespace plancheck {

ProbeCaster::ProbeCaster(const Scene& scene) : scene_(scene) {
  for (const Part& p : scene.parts) {
    if (p.moving()) continue;
    rays_.add_mesh(p.mesh);
    names_.push_back(p.name);
  }
  if (scene.terrain && scene.terrain->collide) {
    terrain_ = std::make_unique<const Heightfield>(*scene.terrain->grid, scene.terrain->origin);
    // Embree's bounds of the terrain are fixed at commit: widen them in z
    // far beyond any dig (a pit or rim kilometres deep is not soil any
    // scoop moves); only rays that miss the grid's footprint are culled.
    rays_.add_heightfield(*terrain_, 1e4);
    names_.push_back("terrain");
  }
  rays_.commit();
  for (const ProbeConfig& p : scene.probes) {
    directions_.push_back(fan_directions(p));
    rays_per_state_ += directions_.back().size();
  }
}

std::vector<Vec3> ProbeCaster::fan_directions(const ProbeConfig& probe) {
  const Vec3 d = probe.direction.normalized();
  if (probe.fan_count <= 1) return {d};
  Vec3 axis = d.cross(Vec3::UnitZ());
  if (std::abs(d.z()) > 1.0 - 1e-9) axis = d.cross(Vec3::UnitX());
  axis.normalize();
  std::vector<Vec3> out;
  const int n = probe.fan_count;
  const double a = probe.fan_half_angle;
  for (int k = 0; k < n; ++k) {
    const double theta = -a + 2.0 * a * k / (n - 1);
    out.push_back((Eigen::AngleAxisd(theta, axis) * d).normalized());
  }
  return out;
}

void ProbeCaster::cast(const std::vector<std::vector<double>>& states, int threads,
                       std::vector<std::vector<ProbeReading>>& out, const Heightfield* terrain) const {
  const std::size_t np = scene_.probes.size();
  out.assign(states.size(), std::vector<ProbeReading>(np));
  if (np == 0 || states.empty()) return;
  // Chunks of states make one ray stream each, so Embree sees many rays at once.
  const std::size_t grain = std::max<std::size_t>(1, 4096 / std::max<std::size_t>(rays_per_state_, 1));
  parallel_for(states.size(), threads, grain, [&](std::size_t begin, std::size_t end, int) {
    cast_range(states, begin, end, out, terrain);
  });
}

void ProbeCaster::cast_state(const std::vector<double>& params, std::vector<ProbeReading>& out,
                             const Heightfield* terrain) const {
  std::vector<std::vector<ProbeReading>> one(1, std::vector<ProbeReading>(scene_.probes.size()));
  const std::vector<std::vector<double>> states{params};
  cast_range(states, 0, 1, one, terrain);
  out = std::move(one[0]);
}

void ProbeCaster::cast_range(const std::vector<std::vector<double>>& states, std::size_t begin, std::size_t end,
                             std::vector<std::vector<ProbeReading>>& out, const Heightfield* terrain) const {
  const std::size_t np = scene_.probes.size();
  {
    std::vector<Ray> rays;
    rays.reserve((end - begin) * rays_per_state_);
    for (std::size_t s = begin; s < end; ++s)
      for (std::size_t p = 0; p < np; ++p) {
        const ProbeConfig& probe = scene_.probes[p];
        const Affine t = part_transform(scene_, probe.part_index, states[s]);
        const Vec3 o = t * probe.origin;
        for (const Vec3& d : directions_[p]) rays.push_back({o, (t.linear() * d).normalized(), probe.max_range});
      }
    std::vector<RayHit> hits;
    rays_.intersect(rays, hits, terrain);
    std::size_t k = 0;
    for (std::size_t s = begin; s < end; ++s)
      for (std::size_t p = 0; p < np; ++p) {
        ProbeReading best{scene_.probes[p].max_range, -1};
        for (std::size_t j = 0; j < directions_[p].size(); ++j, ++k)
          if (hits[k].hit && hits[k].distance < best.distance) best = {hits[k].distance, hits[k].mesh};
        out[s][p] = best;
      }
  }
}

}  // namespace plancheck
