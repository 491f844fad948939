// SPDX-License-Identifier: MIT
// The loaded scene: part tree, meshes in the reference frame, actions, checked
// pairs and the optional terrain, scoop and probe blocks. Filled once by
// load_scene() (scene_loader.h) and read-only afterwards.
//
// Units inside the library are SI: lengths in metres (the scene's length_unit
// factor already applied to vertices, pivots, margins, limits and targets) and
// angles in radians. Reports convert back to the scene's length_unit.
#pragma once

#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace plancheck {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Affine = Eigen::Transform<double, 3, Eigen::Affine>;
using Tri = std::array<std::uint32_t, 3>;

// A triangle mesh in the reference frame, metres.
struct Mesh {
  std::vector<Vec3> vertices;
  std::vector<Tri> triangles;  // indices into vertices, file order
};

// One node of the model file's hierarchy (the part tree).
struct Node {
  std::string name;
  std::string path;            // "/root/probe/lander" style, for messages
  int parent = -1;             // index into Scene::nodes; -1 for the root
  std::vector<int> children;
  int part = -1;               // index into Scene::parts when the node owns triangles
  std::vector<int> actions;    // indices into Scene::actions carried by this node
  Vec3 origin = Vec3::Zero();  // the node's own frame origin at the reference pose (m)
  bool robot_link = false;     // a URDF link: allowed_collisions naming it means exactly this link
  // The node's frame axes at the reference pose: a robot link's (its joint
  // origins' rotations); a model node's are the reference frame's. A world
  // object's pose (objects.h) is given in the frame (origin, axes).
  Mat3 axes = Mat3::Identity();
  bool object = false;         // a world object's node (src/scene/objects.h)
};

enum class ActionType { kRotate, kTranslateAxis, kTranslateFree, kScale };

// One action of the paper's Table 1. Its geometry (pivot, axis, fixed point)
// is in SI units; its driving parameters and limits are in plan units, as
// written (contract: the motion between states is linear in the written
// values). unit_to_si and whole_turn convert a written value where it is
// used to pose (kinematics) or to bound a motion (motion_bound), never before.
struct Action {
  std::string name;            // plan column (or column prefix for x/y/z parameters)
  std::string node_name;
  int node = -1;               // index into Scene::nodes
  ActionType type = ActionType::kRotate;
  Vec3 pivot = Vec3::Zero();   // rotate: a point on the axis (m)
  Vec3 axis = Vec3::UnitZ();   // rotate / translate-with-axis: unit direction
  Vec3 fixed_point = Vec3::Zero();  // scale: the point that stays put (m)
  bool has_limits = false;
  double lower = -std::numeric_limits<double>::infinity();  // plan units, as written
  double upper = std::numeric_limits<double>::infinity();   // plan units, as written
  double unit_to_si = 1.0;     // plan unit -> rad (rotate) or m (translate); 1 for scale factors
  double whole_turn = 0.0;     // rotate in degrees: 360 (removed exactly before sin/cos); else 0
  int first_parameter = 0;     // index of its first driving parameter in a state vector
  int parameter_count = 1;     // 1 (rotate, translate with axis) or 3 (free translate, scale); 0 for a mimic
  // A URDF mimic joint has no driving parameter of its own: its value is
  // multiplier * (value of action `mimic`) + offset (SI units).
  int mimic = -1;              // index into Scene::actions of the master; -1: none
  double multiplier = 1.0;
  double offset = 0.0;
};

// A part: a node that owns at least one triangle mesh.
struct Part {
  std::string name;
  int node = -1;               // index into Scene::nodes
  Mesh mesh;                   // reference frame, metres
  std::vector<int> chain;      // actions on the node and its ancestors, root first
  int chain_id = -1;           // parts with equal chains share an id (index into Scene::chains)
  bool moving() const { return !chain.empty(); }
};

struct CheckedPair {
  int a = -1;                  // part index; a < b
  int b = -1;
};

struct Dem;  // terrain.h

enum class ObjectShape { kBox, kCylinder, kSphere, kMesh };

// A world object (scene-format.md "World objects"): its shape in its own
// frame, and where that frame stands. The part it is holds the shape posed
// in the reference frame (Part::mesh).
struct WorldObject {
  std::string name;
  ObjectShape shape = ObjectShape::kBox;
  std::shared_ptr<const Mesh> local;  // the shape in its own frame (m), shared by copies
  std::filesystem::path mesh_file;    // kMesh: the file read
  int parent = 0;                     // index into Scene::nodes (0: the root, i.e. the world)
  Affine pose = Affine::Identity();   // in the parent node's frame (m)
};

// What allowed_collisions and an SRDF declared, kept so the checked pairs can
// be derived again when world objects change (resolve_pairs in
// scene_loader.h): node pairs as allowed_collisions names them (-1: the
// terrain), part pairs as the SRDF names links.
struct AllowedRules {
  std::vector<std::pair<int, int>> nodes;
  std::vector<std::pair<int, int>> parts;
};

struct TerrainConfig {
  std::filesystem::path dem;   // resolved against the scene file's folder
  Vec3 origin = Vec3::Zero();  // where the grid's (xll, yll, 0) sits (m); from map_origin when given
  bool collide = true;
  // The grid read from `dem` once, by the scene loader (length_scale
  // applied): the window of the raster the moving parts can reach
  // (scene/terrain_window.h); everything that needs the terrain starts
  // from it. Shared and immutable, so copies of a Scene share one grid.
  std::shared_ptr<const Dem> grid;
  int band = 1;                // the raster band holding heights (1 = first)
  // The map point [E, N, H] (map units, as written) at the reference-frame
  // origin; the loader turns it into `origin` once the raster's georeference is read.
  std::optional<Vec3> map_origin;
};

struct ScoopTemplate {
  double pit = -1.0;
  double rim = 0.25;
  double rim_start = 0.7;
};

struct ScoopConfig {
  std::string part;
  int part_index = -1;
  Vec3 bottom_point = Vec3::Zero();  // M at the reference pose (m)
  double width = 0.1;                // W (m)
  ScoopTemplate templ;
  std::string model = "template";    // "template" (paper) or "swept"
  double capacity = 0.0;             // m^3
  double bulk_density = 1240.0;      // kg/m^3
  double repose_angle = 40.0 * 3.14159265358979323846 / 180.0;  // rad
};

struct ProbeConfig {
  std::string name;
  std::string part;
  int part_index = -1;
  Vec3 origin = Vec3::Zero();        // at the reference pose (m)
  Vec3 direction = -Vec3::UnitZ();   // unit
  int fan_count = 1;                 // 1: a single ray
  double fan_half_angle = 0.0;       // rad
  double max_range = 0.0;            // m
};

// What a scene's robot (a URDF, src/scene/robot_loader.h) added, for messages and
// `plancheck scene`.
struct RobotInfo {
  std::filesystem::path urdf;
  std::filesystem::path srdf;        // empty: none
  std::string name;                  // the URDF's robot name
  bool visual = false;               // visual geometry instead of collision
  double padding = 0.0;              // m, MoveIt's link padding
  double scale = 1.0;                // MoveIt's link scale
  int links = 0, joints = 0;         // as read from the URDF
  std::vector<std::pair<std::string, std::string>> adjacent;  // (parent link, child link) of every joint
  std::vector<std::pair<std::string, std::string>> disabled;  // the SRDF's disable_collisions pairs
  int boxes = 0, cylinders = 0, spheres = 0;  // primitive geometries tessellated
  double largest_deviation = 0.0;    // m, over every primitive of the robot
};

struct Scene {
  std::filesystem::path file;        // the scene JSON
  std::filesystem::path model_file;  // resolved model path
  std::string length_unit = "m";     // as written in the scene
  std::string angle_unit = "deg";
  double length_scale = 1.0;         // metres per length_unit
  double angle_scale = 3.14159265358979323846 / 180.0;  // radians per angle_unit

  std::vector<Node> nodes;           // nodes[0] is the root
  std::vector<Part> parts;
  std::vector<Action> actions;
  std::vector<std::vector<int>> chains;  // distinct action chains; chains[part.chain_id]

  // Driving parameters in plan-column order: "J1", "Boom", "Mast.x", ...
  std::vector<std::string> parameter_names;
  std::vector<double> reference_parameters;  // 0 for rotate/translate, 1 for scale (plan units)

  std::vector<CheckedPair> checked_pairs;
  double safety_margin = 0.0;        // m
  // Parts that allowed_collisions lets touch the terrain pseudo-part (sorted).
  // The terrain is static: with terrain->collide, every moving part not listed
  // here is checked against it (static parts never are).
  std::vector<int> terrain_allowed_parts;

  std::optional<TerrainConfig> terrain;
  std::optional<ScoopConfig> scoop;
  std::vector<ProbeConfig> probes;
  std::optional<RobotInfo> robot;    // the scene's robot (URDF), if any
  std::vector<WorldObject> objects;  // scene file's `objects`, then those added at run time
  AllowedRules allowed;              // what checked_pairs was derived from

  std::vector<std::string> warnings;  // non-fatal load remarks (ignored primitives, ...)

  int find_part(const std::string& name) const {
    for (std::size_t i = 0; i < parts.size(); ++i)
      if (parts[i].name == name) return static_cast<int>(i);
    return -1;
  }
};

}  // namespace plancheck
