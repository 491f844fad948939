// SPDX-License-Identifier: MIT
// A robot from URDF (and SRDF) into the scene: links become parts and nodes,
// movable joints become actions (contract: scene-format.md "Robot from URDF").
#pragma once

#include "src/scene/scene.h"

#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace plancheck {

// Segments around a cylinder or sphere (a sphere has half as many latitude
// bands). The tessellations contain the true shapes (src/scene/robot_loader.cpp).
inline constexpr int kPrimitiveSegments = 64;

struct RobotSpec {
  std::filesystem::path urdf;
  std::filesystem::path srdf;                          // empty: none
  std::map<std::string, std::filesystem::path> packages;  // package:// NAME -> folder
  bool visual = false;                                 // visual instead of collision geometry
  int parent_node = -1;                                // scene node the root link hangs under; -1: a new root
  Affine origin = Affine::Identity();                  // root link frame in the reference frame (m)
  double padding = 0.0;                                // m, MoveIt's link padding
  double scale = 1.0;                                  // MoveIt's link scale
};

// Adds the robot to scene.nodes, scene.parts and scene.actions (and its
// driving parameters), fills scene.robot, and returns the SRDF's allowed
// link pairs as part index pairs. Throws InputError naming the URDF or SRDF
// and the element at fault.
std::vector<std::pair<int, int>> add_robot(const RobotSpec& spec, Scene& scene);

// A triangle mesh that contains the true shape, centred at the origin as URDF
// places them (cylinder along z); `deviation` gets the largest distance from
// the mesh to the true surface (m).
Mesh box_tessellation(const Vec3& size);
Mesh cylinder_tessellation(double radius, double length, double& deviation);
Mesh sphere_tessellation(double radius, double& deviation);

// MoveIt's scaleAndPadd for a mesh (geometric_shapes): identical vertices
// merged, each moved to centroid + scale * (v - centroid) + padding * n, with
// n its normalised sum of adjacent unit face normals.
Mesh scale_and_pad(const Mesh& mesh, double scale, double padding);

}  // namespace plancheck
