// SPDX-License-Identifier: MIT
// Collision structures built while the scene's model is still being imported
// (SceneOptions::while_importing): the importer's child takes one core, and
// this process would otherwise only wait. The checker takes a structure from
// here only for a part whose mesh is bitwise the mesh it was built from, so
// it is the very structure it would build itself.
#pragma once

#include "src/scene/scene.h"

#include <atomic>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <vector>

namespace plancheck {

struct CollisionModelData;  // src/geometry/bvh.h

class BuiltAhead {
 public:
  // Builds the structures of the model's drawn objects (`drawn`, as
  // SceneOptions::while_importing hands them over), largest first, one at a
  // time, until all are built or `stop` is true (asked before each). An
  // object that cannot be built (a face naming a point it lacks) is
  // skipped: no part has its mesh.
  void build(const std::function<std::vector<Mesh>()>& drawn, const std::atomic<bool>& stop);
  // The same from the file (drawn_object_meshes: 3ds files only).
  void build(const std::filesystem::path& model, double length_scale, const std::atomic<bool>& stop);

  // The structure built from exactly `mesh` (same vertices bit for bit, same
  // triangles in the same order), or null.
  std::shared_ptr<const CollisionModelData> find(const Mesh& mesh) const;

  std::size_t size() const { return built_.size(); }

 private:
  struct Built {
    Mesh mesh;
    std::shared_ptr<const CollisionModelData> data;
  };
  std::vector<Built> built_;
};

}  // namespace plancheck
