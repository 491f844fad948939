// SPDX-License-Identifier: MIT
#include "src/checks/built_ahead.h"

#include "src/base/error.h"
#include "src/geometry/bvh.h"
#include "src/scene/model_loader.h"

#include <algorithm>
#include <cstring>
#include <numeric>
#include <utility>

namespace plancheck {

void BuiltAhead::build(const std::filesystem::path& model, double length_scale, const std::atomic<bool>& stop) {
  build([&] { return drawn_object_meshes(model, length_scale); }, stop);
}

void BuiltAhead::build(const std::function<std::vector<Mesh>()>& drawn, const std::atomic<bool>& stop) {
  std::vector<Mesh> meshes = drawn();
  std::vector<std::size_t> order(meshes.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return meshes[a].triangles.size() > meshes[b].triangles.size();
  });
  for (std::size_t i : order) {
    if (stop) break;
    Mesh& mesh = meshes[i];
    if (mesh.triangles.empty()) break;  // the rest are empty too
    try {
      auto data = std::make_shared<const CollisionModelData>(build_collision_data(mesh));
      built_.push_back({std::move(mesh), std::move(data)});
    } catch (const InputError&) {
      // A face out of range or a point out of range: no part has this mesh.
    }
  }
}

std::shared_ptr<const CollisionModelData> BuiltAhead::find(const Mesh& mesh) const {
  if (mesh.triangles.empty()) return nullptr;
  for (const Built& b : built_) {
    if (b.mesh.vertices.size() != mesh.vertices.size() || b.mesh.triangles.size() != mesh.triangles.size()) continue;
    if (std::memcmp(b.mesh.vertices.data(), mesh.vertices.data(), mesh.vertices.size() * sizeof(Vec3)) == 0 &&
        std::memcmp(b.mesh.triangles.data(), mesh.triangles.data(), mesh.triangles.size() * sizeof(Tri)) == 0)
      return b.data;
  }
  return nullptr;
}

}  // namespace plancheck
