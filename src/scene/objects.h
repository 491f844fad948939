// SPDX-License-Identifier: MIT
// World objects (contract: scene-format.md "World objects"): boxes,
// cylinders, spheres and mesh files placed in the world or on a node or
// robot link, each a part of the scene. The scene file's `objects` and the
// API's run-time add, move and remove all go through here, so an object
// added at run time is the very part the scene file would have made.
#pragma once

#include "src/scene/scene.h"

#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace plancheck {

// Where messages point: "FILE: objects[2].box: ..." for a scene file,
// "objects['Rock'].box: ..." at run time (file empty).
struct ObjectPlace {
  std::filesystem::path file;  // the scene file; empty at run time
  std::string where;           // "objects[2]", "objects['Rock']"
  [[noreturn]] void error(const std::string& field, const std::string& what) const;
};

// An object's shape in its own frame (m): a box of full edge lengths `size`
// centred at the origin (exact, 12 triangles), a cylinder along z centred
// (radius, length) or a sphere (radius) as the URDF loader meshes them
// (containing the true shape), or every triangle of `file` (anything the
// model loader reads) times `scale`. Sizes must be positive and finite.
Mesh box_object(const Vec3& size, const ObjectPlace& at);
Mesh cylinder_object(double radius, double length, const ObjectPlace& at);
Mesh sphere_object(double radius, const ObjectPlace& at);
// `cache` (optional): files read so far, so objects sharing a file read it once.
Mesh mesh_object(const std::filesystem::path& file, const Vec3& scale, std::vector<std::string>& warnings,
                 const ObjectPlace& at, std::map<std::filesystem::path, Mesh>* cache = nullptr);

// The pose of a URDF origin: translation xyz, then roll, pitch, yaw about
// the fixed x, y, z axes (SI units).
Affine pose_of(const Vec3& xyz, const Vec3& rpy);

// Where `object` stands in the reference frame at the reference pose: its
// parent's frame times its pose.
Affine object_frame(const Scene& scene, const WorldObject& object);

// The node an object named `parent` hangs on: a model node or a robot link
// ("" : the world, -1). Not another object.
int object_parent(const Scene& scene, const std::string& parent, const ObjectPlace& at);

// Most world objects a scene holds: a scene file of a few megabytes must not
// ask for gigabytes (a sphere is some 4,000 triangles from 20 bytes of JSON).
inline constexpr std::size_t kMaxObjects = 4096;

// Adds `object` (name, shape, local mesh, parent, pose set) as a node and a
// part of `scene`; its name must be unique among parts, nodes and links, and
// the scene may hold at most kMaxObjects.
// The checked pairs are not derived again: call derive_pairs (scene_loader.h).
void add_object(Scene& scene, WorldObject object, const ObjectPlace& at);

// The object named `name` to a new pose in its parent's frame (its part's
// mesh posed again); the pairs do not change.
void move_object(Scene& scene, const std::string& name, const Affine& pose, const ObjectPlace& at);

// Removes the object named `name` (its node and part; indices after it move
// down). Refused while a probe or the scoop is on it. Call derive_pairs after.
void remove_object(Scene& scene, const std::string& name, const ObjectPlace& at);

// The index into Scene::objects of the object named `name`, or -1.
int find_object(const Scene& scene, const std::string& name);

}  // namespace plancheck
