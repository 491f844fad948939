// SPDX-License-Identifier: MIT
// Forward kinematics: one transform per action chain per state. Meshes are
// never rewritten; a part's posed vertex is chain_transform * reference vertex.
#pragma once

#include "src/scene/scene.h"

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

// The transform that poses part `part` (identity for static parts).
Affine part_transform(const Scene& scene, int part, std::span<const double> params);

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
