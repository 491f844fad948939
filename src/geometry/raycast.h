// SPDX-License-Identifier: MIT
// A thin owner of an Embree device and scene of triangle meshes. Embree is
// single precision: hit distances carry about 1e-7 relative error, which is
// why collision and distance never go through here (they are exact, in
// collision_model); probes and the swept scoop's lower surface do.
#pragma once

#include "src/scene/scene.h"

#include <memory>
#include <vector>

namespace plancheck {

class Heightfield;

struct Ray {
  Vec3 origin = Vec3::Zero();
  Vec3 direction = -Vec3::UnitZ();  // unit
  double max_range = 0.0;           // hits farther than this are ignored
};

struct RayHit {
  bool hit = false;
  double distance = 0.0;  // along the unit direction; max_range when no hit
  int mesh = -1;          // index of the mesh hit (add_mesh order)
  unsigned triangle = 0;
};

class RayScene {
 public:
  RayScene();
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  // Adds a mesh (reference frame, metres) posed by `pose`; returns its index.
  int add_mesh(const Mesh& mesh, const Affine& pose = Affine::Identity());
  // Adds a terrain as an Embree user geometry whose intersect callback walks
  // a Heightfield in double (Heightfield::intersect_ray); returns its index.
  // `base` is walked unless intersect() names another field: a dug copy of
  // base, passed through the intersect context, so one committed scene
  // serves every state of every plan. Its Embree bounds are base's box
  // widened by `z_slack` (m) below and above, which must cover any dug copy.
  // A hit's triangle is the dem_mesh index.
  int add_heightfield(const Heightfield& base, double z_slack);
  // Builds the hierarchy; call once after the last add_mesh.
  void commit();

  // Casts rays[i] into hits[i]. Rays go to Embree as one stream
  // (rtcIntersect1M) so it can reorder them; safe to call from many threads.
  // terrain: the field a heightfield geometry walks (nullptr: its base).
  void intersect(const std::vector<Ray>& rays, std::vector<RayHit>& hits,
                 const Heightfield* terrain = nullptr) const;

  std::size_t mesh_count() const { return mesh_count_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::size_t mesh_count_ = 0;
};

}  // namespace plancheck
