// SPDX-License-Identifier: MIT
#include "src/scene/objects.h"

#include "src/base/error.h"
#include "src/scene/model_loader.h"
#include "src/scene/robot_loader.h"

#include <cmath>

namespace plancheck {

void ObjectPlace::error(const std::string& field, const std::string& what) const {
  const std::string message = where + (field.empty() ? "" : "." + field) + ": " + what;
  if (file.empty()) throw InputError(message);
  fail(file, message);
}

namespace {

double positive_size(double v, const ObjectPlace& at, const std::string& field) {
  if (!std::isfinite(v) || !(v > 0)) at.error(field, "must be a positive finite number");
  return v;
}

// The frame an object's pose is given in: the world, or its parent node's
// frame at the reference pose.
Affine parent_frame(const Scene& scene, int parent) {
  Affine f = Affine::Identity();
  if (parent < 0) return f;
  const Node& n = scene.nodes[static_cast<std::size_t>(parent)];
  f.translate(n.origin);
  f.rotate(n.axes);
  return f;
}

}  // namespace

Affine object_frame(const Scene& scene, const WorldObject& object) { return parent_frame(scene, object.parent) * object.pose; }

namespace {

void pose_part(Scene& scene, const WorldObject& o, Part& part, Node& node, const ObjectPlace& at) {
  const Affine place = object_frame(scene, o);
  if (!place.matrix().allFinite()) at.error("pose", "not finite");
  Mesh mesh;
  mesh.triangles = o.local->triangles;
  mesh.vertices.reserve(o.local->vertices.size());
  for (const Vec3& v : o.local->vertices) {
    mesh.vertices.push_back(place * v);
    if (!mesh.vertices.back().allFinite()) at.error("pose", "places a vertex beyond the finite numbers");
  }
  part.mesh = std::move(mesh);
  node.origin = place.translation();
  node.axes = place.linear();
}

}  // namespace

Mesh box_object(const Vec3& size, const ObjectPlace& at) {
  for (int k = 0; k < 3; ++k) positive_size(size[k], at, "box[" + std::to_string(k) + "]");
  return box_tessellation(size);
}

Mesh cylinder_object(double radius, double length, const ObjectPlace& at) {
  double deviation = 0;
  return cylinder_tessellation(positive_size(radius, at, "cylinder.radius"),
                               positive_size(length, at, "cylinder.length"), deviation);
}

Mesh sphere_object(double radius, const ObjectPlace& at) {
  double deviation = 0;
  return sphere_tessellation(positive_size(radius, at, "sphere"), deviation);
}

Mesh mesh_object(const std::filesystem::path& file, const Vec3& scale, std::vector<std::string>& warnings,
                 const ObjectPlace& at, std::map<std::filesystem::path, Mesh>* cache) {
  for (int k = 0; k < 3; ++k) positive_size(scale[k], at, "scale[" + std::to_string(k) + "]");
  Mesh m;
  const Mesh* read = nullptr;
  if (cache != nullptr)
    if (auto it = cache->find(file); it != cache->end()) read = &it->second;
  if (read != nullptr) {
    m = *read;
  } else {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) at.error("mesh", "cannot open " + file.string() + " (missing or not a file)");
    try {
      m = load_mesh(file, warnings);
    } catch (const InputError& e) {
      at.error("mesh", e.what());
    }
    if (cache != nullptr) cache->emplace(file, m);
  }
  if (m.triangles.empty()) at.error("mesh", file.string() + " holds no triangles");
  for (Vec3& v : m.vertices) v = v.cwiseProduct(scale);
  return m;
}

Affine pose_of(const Vec3& xyz, const Vec3& rpy) {
  // URDF's convention: roll about x, then pitch about y, then yaw about z (fixed axes).
  Affine t = Affine::Identity();
  t.translate(xyz);
  t.rotate(Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Vec3::UnitY()) *
           Eigen::AngleAxisd(rpy.x(), Vec3::UnitX()));
  return t;
}

int find_object(const Scene& scene, const std::string& name) {
  for (std::size_t i = 0; i < scene.objects.size(); ++i)
    if (scene.objects[i].name == name) return static_cast<int>(i);
  return -1;
}

int object_parent(const Scene& scene, const std::string& parent, const ObjectPlace& at) {
  if (parent.empty()) return -1;
  int found = -1;
  for (std::size_t i = 0; i < scene.nodes.size(); ++i) {
    if (scene.nodes[i].name != parent) continue;
    if (found >= 0)
      at.error("parent", "node name '" + parent + "' is not unique: " + scene.nodes[static_cast<std::size_t>(found)].path +
                             " and " + scene.nodes[i].path);
    found = static_cast<int>(i);
  }
  if (found < 0) at.error("parent", "no node or link named '" + parent + "'");
  if (scene.nodes[static_cast<std::size_t>(found)].object)
    at.error("parent", "'" + parent + "' is a world object; objects hang on model nodes and robot links");
  return found;
}

void add_object(Scene& scene, WorldObject object, const ObjectPlace& at) {
  if (scene.objects.size() >= kMaxObjects) at.error("", "more than " + std::to_string(kMaxObjects) + " objects");
  if (object.name.empty()) at.error("name", "empty name");
  for (const Node& n : scene.nodes)
    if (n.name == object.name)
      at.error("name", "'" + object.name + "' is already the name of " +
                           (n.object ? std::string("an object") : n.part >= 0 ? "the part " + n.path : "the node " + n.path));
  if (scene.find_part(object.name) >= 0) at.error("name", "'" + object.name + "' is already a part's name");
  if (scene.terrain && scene.terrain->collide && object.name == "terrain")
    at.error("name", "'terrain' is the terrain's name");
  if (scene.nodes.empty()) {  // a scene with neither model nor robot has no root yet
    scene.nodes.emplace_back();
  }
  const int tree_parent = object.parent < 0 ? 0 : object.parent;
  Node node;
  node.name = object.name;
  node.parent = tree_parent;
  node.path = scene.nodes[static_cast<std::size_t>(tree_parent)].path + "/" + object.name;
  node.object = true;
  Part part;
  part.name = object.name;
  pose_part(scene, object, part, node, at);
  const int index = static_cast<int>(scene.nodes.size());
  part.node = index;
  node.part = static_cast<int>(scene.parts.size());
  scene.nodes[static_cast<std::size_t>(tree_parent)].children.push_back(index);
  scene.nodes.push_back(std::move(node));
  scene.parts.push_back(std::move(part));
  scene.objects.push_back(std::move(object));
}

void move_object(Scene& scene, const std::string& name, const Affine& pose, const ObjectPlace& at) {
  const int i = find_object(scene, name);
  if (i < 0) at.error("", "no object named '" + name + "'");
  WorldObject o = scene.objects[static_cast<std::size_t>(i)];
  o.pose = pose;
  const int p = scene.find_part(name);
  Part& part = scene.parts[static_cast<std::size_t>(p)];
  Node& node = scene.nodes[static_cast<std::size_t>(part.node)];
  pose_part(scene, o, part, node, at);
  scene.objects[static_cast<std::size_t>(i)] = std::move(o);
}

void remove_object(Scene& scene, const std::string& name, const ObjectPlace& at) {
  const int i = find_object(scene, name);
  if (i < 0) at.error("", "no object named '" + name + "'");
  const int part = scene.find_part(name);
  for (const ProbeConfig& p : scene.probes)
    if (p.part_index == part) at.error("", "probe '" + p.name + "' is fixed to it");
  if (scene.scoop && scene.scoop->part_index == part) at.error("", "it is the scoop");
  const int node = scene.parts[static_cast<std::size_t>(part)].node;
  // Objects hang on no object, so nothing hangs on this node.
  auto node_after = [&](int n) { return n > node ? n - 1 : n; };
  auto part_after = [&](int p) { return p > part ? p - 1 : p; };
  scene.nodes.erase(scene.nodes.begin() + node);
  for (Node& n : scene.nodes) {
    n.parent = n.parent < 0 ? n.parent : node_after(n.parent);
    std::erase(n.children, node);
    for (int& c : n.children) c = node_after(c);
    if (n.part >= 0) n.part = part_after(n.part);
  }
  scene.parts.erase(scene.parts.begin() + part);
  for (Part& p : scene.parts) p.node = node_after(p.node);
  for (Action& a : scene.actions) a.node = node_after(a.node);
  scene.objects.erase(scene.objects.begin() + i);
  for (WorldObject& o : scene.objects) o.parent = o.parent < 0 ? -1 : node_after(o.parent);
  std::erase_if(scene.allowed.nodes, [&](const auto& r) { return r.first == node || r.second == node; });
  for (auto& [a, b] : scene.allowed.nodes) {
    a = a < 0 ? a : node_after(a);
    b = b < 0 ? b : node_after(b);
  }
  std::erase_if(scene.allowed.parts, [&](const auto& r) { return r.first == part || r.second == part; });
  for (auto& [a, b] : scene.allowed.parts) {
    a = part_after(a);
    b = part_after(b);
  }
  for (ProbeConfig& p : scene.probes) p.part_index = part_after(p.part_index);
  if (scene.scoop) scene.scoop->part_index = part_after(scene.scoop->part_index);
}

}  // namespace plancheck
