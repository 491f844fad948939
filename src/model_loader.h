// SPDX-License-Identifier: MIT
// Model file (anything assimp reads) -> part tree and triangle meshes.
#pragma once

#include "src/scene.h"

#include <filesystem>

namespace plancheck {

// Fills scene.nodes (nodes[0] = root) and scene.parts from the model file:
// node transforms from the root down applied, vertices multiplied by
// length_scale (metres per unit). 3ds per-mesh child nodes ("Object_3") are
// folded into their object. Throws InputError on an unreadable, empty or
// malformed model and on duplicate part names (naming both paths).
void load_model(const std::filesystem::path& model, double length_scale, Scene& scene);

}  // namespace plancheck
