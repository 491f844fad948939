// SPDX-License-Identifier: MIT
// Forward kinematics: one transform per action chain per state. Meshes are
// never rewritten; a part's posed vertex is chain_transform * reference vertex.
#pragma once

#include "src/scene/scene.h"

#include <cstdint>
#include <span>
#include <vector>

namespace plancheck {

// The transform of one action at its driving parameters as written (plan
// units), params pointing at the action's first parameter. This is the one
// place a written value becomes a pose: degrees lose whole turns exactly
// (std::remainder by 360 is exact in binary floating point, so k * 360 deg
// poses exactly like 0 and 1e300 deg turns by its true remainder), then
// convert to radians; lengths are scaled to metres; factors stay as they are.
// The value that drives a motion or meets a limit is never reduced.
Affine action_transform(const Action& action, const double* params);

// The value driving a one-parameter action in a full parameter vector, as
// written: its own parameter, or for a mimic joint (Action::mimic)
// multiplier * the master's value + offset (a robot's units are m and rad,
// so the master's written value is already what URDF's mimic multiplies).
double driving_value(const Scene& scene, const Action& action, std::span<const double> params);

// action_transform for an action of `scene` at a full parameter vector
// (a mimic joint follows its master).
Affine action_transform_at(const Scene& scene, const Action& action, std::span<const double> params);

// out[c] = A1 * A2 * ... * Ak for every chain c of scene.chains (root first),
// given a full parameter vector in scene.parameter_names order.
void chain_transforms(const Scene& scene, std::span<const double> params, std::vector<Affine>& out);

// Per chain of scene.chains: the longest earlier chain that begins it (the
// first of equal length), whose product chain_transforms continues, or -1.
// It depends on the chains alone; a caller posing many states keeps it.
std::vector<int> chain_prefixes(const Scene& scene);

// chain_transforms with chain_prefixes(scene) kept by the caller: the same
// values bit for bit.
void chain_transforms(const Scene& scene, std::span<const int> prefixes, std::span<const double> params,
                      std::vector<Affine>& out);

// One chain c's product as chain_transforms computes it (the same bits):
// continued from prefix_product, the product of chain `prefix`
// (chain_prefixes(scene)[c]) at the same params, or from the root when
// prefix is -1 (prefix_product unused). out must not be *prefix_product.
void chain_transform(const Scene& scene, int c, int prefix, const Affine* prefix_product,
                     std::span<const double> params, Affine& out);

// The transform that poses part `part` (identity for static parts).
Affine part_transform(const Scene& scene, int part, std::span<const double> params);

// part_transform's product (the same bits) and the part's velocity field
// while the parameters move at `rates` (plan units per unit of time, a
// full vector): at that instant the point of the part at world position x
// moves at w x x + u. Each rotation turns about its axis and pivot as the
// actions above it place them (the rate times the axis, through the
// pivot), a translation moves along its axis so placed. False (w and u
// unset, out still the product) when the chain has a scale action.
bool part_transform_velocity(const Scene& scene, int part, std::span<const double> params,
                             std::span<const double> rates, Affine& out, Vec3& w, Vec3& u);

// compose for one chain over many parameter vectors in a row that differ
// mostly in the chain's last actions (a grid walked with its last axis
// fastest: the sweep's target points). The product after each action is
// kept, and a call recomputes from the first action whose parameters (as
// read: its own, or a mimic's master's) differ bitwise from the last
// call's: -0 and 0 may pose differently, and a NaN equals itself only so.
// The same products in the same order as part_transform and
// chain_transforms, so the same bits. Not thread-safe: one per thread.
class ChainCache {
 public:
  ChainCache(const Scene& scene, const std::vector<int>& chain);
  // The chain's product at params (a full parameter vector); valid until
  // the next call.
  const Affine& operator()(std::span<const double> params);

 private:
  const Scene& scene_;
  std::vector<int> chain_;
  std::vector<std::vector<int>> reads_;  // per action of the chain: the parameters it reads
  std::vector<Affine> prefix_;           // prefix_[k]: the first k actions' product (prefix_[0]: identity)
  std::vector<std::uint64_t> seen_;      // per action, the bits of its parameters at the last call
  std::vector<std::size_t> first_seen_;  // where action k's bits start in seen_
  std::size_t valid_ = 0;                // actions whose products in prefix_ hold
};

// An action's parameter as the pose uses it: rad for a rotation (whole turns
// removed first when written in degrees), m for a translation, the factor for
// a scale.
double pose_value(const Action& action, double written);

// Index of the first action whose parameter lies outside its limits, or -1
// (written values against limits as written).
int first_limit_violation(const Scene& scene, std::span<const double> params);

// True when the linear part is orthonormal with determinant +1 to rounding.
bool is_rigid(const Affine& t);

}  // namespace plancheck
