// SPDX-License-Identifier: MIT
// Collision structures built while the scene's model is still being imported
// (SceneOptions::while_importing): the importer's child takes one core, and
// this process would otherwise only wait. The checker takes a structure from
// here only for a part whose mesh is bitwise the mesh it was built from, so
// it is the very structure it would build itself.
#pragma once

#include "src/base/parallel.h"
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
  BuiltAhead() = default;
  ~BuiltAhead();  // stops and joins what start() began
  BuiltAhead(const BuiltAhead&) = delete;
  BuiltAhead& operator=(const BuiltAhead&) = delete;

  // Builds the structures of the model's drawn objects (`drawn`, as
  // SceneOptions::while_importing hands them over), largest first, one at a
  // time, until all are built or `stop` is true (asked before each). An
  // object that cannot be built (a face naming a point it lacks) is
  // skipped: no part has its mesh. Call once, before find().
  void build(const std::function<std::vector<Mesh>()>& drawn, const std::atomic<bool>& stop);
  // The same from the file (drawn_object_meshes: 3ds files only).
  void build(const std::filesystem::path& model, double length_scale, const std::atomic<bool>& stop);

  // The same on a thread of its own (BesideJob), returning once the meshes
  // are taken from `drawn` (so an import's objects may go): the building
  // goes on past the import, beside the caller's work and the checker's
  // (whose find() claims an object not yet started, waits for one being
  // built, takes one built), until every object is built or claimed, or
  // finish() is called. Call once, before find().
  void start(const std::function<std::vector<Mesh>()>& drawn);
  // Stops start()'s building after the object in hand, waits for it and
  // lets go of everything (find() then finds nothing).
  void finish();

  // The structure built from exactly `mesh` (same vertices bit for bit, same
  // triangles in the same order), or null. With start(): waits for such an
  // object while it is being built; one not yet started is claimed (never
  // built here) and null is returned, for the caller to build it itself.
  // Safe from many threads at once.
  std::shared_ptr<const CollisionModelData> find(const Mesh& mesh) const;

  // Objects built so far.
  std::size_t size() const;

 private:
  enum State : int { kPending, kBuilding, kBuilt, kClaimed, kSkipped };
  // Takes the meshes; objects without triangles are skipped.
  void take(std::vector<Mesh> meshes);
  // Builds pending objects, largest first, until stop_ (or none is left).
  void run(const std::atomic<bool>& stop);

  std::vector<Mesh> meshes_;                                 // the drawn objects, never changed once taken
  std::vector<std::size_t> order_;                           // largest first
  std::unique_ptr<std::atomic<int>[]> state_;                // per object: State
  std::vector<std::shared_ptr<const CollisionModelData>> data_;  // per object, once kBuilt
  std::atomic<bool> stop_{false};
  std::unique_ptr<BesideJob> job_;  // last: joined first
};

}  // namespace plancheck
