// SPDX-License-Identifier: MIT
// The synthetic Chang'e-5-like scene: model tree, arm kinematics, terrain and
// plans. Shared by the generator's translation units only.
#pragma once

#include "src/scene/scene.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace plancheck::dataset {

// ---- Fixed layout (metres, z up, ground z = 0, lander centre at x = y = 0) ----
inline constexpr double kDeckTop = 1.35;               // top of the lander deck plate
inline const Vec3 kShoulderPivot{0.90, 0.0, 1.66};     // J2 axis point; J1 axis is x=0.9, y=0
inline const Vec3 kElbowPivot{2.50, 0.0, 1.66};        // J3 axis point at the reference pose
inline const Vec3 kWristPivot{4.10, 0.0, 1.66};        // J4 axis point at the reference pose
inline const Vec3 kScoopBottom{4.40, 0.0, 1.36};       // M at the reference pose
inline constexpr double kUpperArm = 1.60;
inline constexpr double kForearm = 1.60;
inline const Vec3 kCanCentre{0.40, 0.85, kDeckTop};    // sample storage can, base centre
inline constexpr double kCanRadius = 0.10;
inline constexpr double kCanHeight = 0.25;
inline constexpr double kHandleSpan = 0.09;            // bail half-width
inline constexpr double kHandleLift = 0.09;            // bail posts above the rim
inline const Vec3 kReceptacleCentre{-0.05, 0.15, 2.15}; // ascender receptacle, base centre
inline constexpr double kReceptacleHeight = 0.27;      // tube plus funnel
// Terrain: 150 x 150 cells of 2 cm, lower-left corner at (1.80, -1.50).
inline constexpr int kDemSize = 150;
inline constexpr double kDemCell = 0.02;
inline const Vec3 kDemOrigin{1.80, -1.50, 0.0};

// Pitch joints turn about -y so that a positive angle raises the link.
inline const Vec3 kPitchAxis{0.0, -1.0, 0.0};

struct ModelNode {
  std::string name;
  int parent = -1;
  Mesh mesh;
};

struct Model {
  std::vector<ModelNode> nodes;
  int find(const std::string& name) const {
    for (std::size_t i = 0; i < nodes.size(); ++i)
      if (nodes[i].name == name) return static_cast<int>(i);
    return -1;
  }
  bool in_subtree(int node, int root) const {
    for (int n = node; n >= 0; n = nodes[static_cast<std::size_t>(n)].parent)
      if (n == root) return true;
    return false;
  }
};

// Table 2 of the paper.
inline constexpr std::size_t kLanderTriangles = 268730;
inline constexpr std::size_t kAscenderTriangles = 120676;
inline constexpr std::array<std::size_t, 4> kJointTriangles{5970, 8723, 8952, 7060};
inline constexpr std::size_t kScoopTriangles = 2164;

Model build_model();

// Heights of the DEM, row 0 = top (largest y), heights in metres relative to
// terrain.origin's z (0).
std::vector<double> build_terrain();
double terrain_height(const std::vector<double>& dem, double x, double y);  // bilinear, world x, y

// Rotation of the arm joints (degrees) -> pose of each joint's frame.
using Joints = std::array<double, 4>;
struct JointLimits {
  double lower, upper;
};
inline constexpr std::array<JointLimits, 4> kLimits{{{-180, 180}, {-20, 135}, {-165, 5}, {-80, 150}}};

// Rigid transforms of the moving chains J1, J1J2, J1J2J3, J1J2J3J4 per the
// scene contract's composition rule A1(A2(...Ak(x))).
std::array<Affine, 4> chain_poses(const Joints& q);
Vec3 scoop_bottom(const Joints& q);

}  // namespace plancheck::dataset
