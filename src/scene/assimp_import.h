// SPDX-License-Identifier: MIT
// A model file through assimp, in a child process: private to src/scene
// (model_loader.cpp builds the part tree from what assimp reads).
#pragma once

#include "src/scene/isolate.h"
#include "src/scene/scene.h"

#include <filesystem>
#include <functional>

struct aiScene;

namespace plancheck {

// Fills scene.nodes, scene.parts and scene.warnings from assimp's scene of
// the model file. Runs in the child process; throws InputError.
using PartTreeBuilder = std::function<void(const aiScene& ai, Scene& scene)>;

// The checks ahead of assimp (a non-empty regular file; OFF counts, PLY
// header and 3ds keyframer tracks its readers would choke on), then assimp's
// import and `build` in a child process under `limits` (src/scene/isolate.h),
// then what the child hands back checked and moved into `scene` (its nodes
// and parts replaced, its warnings appended). Every failure, a crash or hang
// of the importer included, is an InputError naming `model`.
// `meanwhile` runs in this process while the child imports (run_isolated).
void import_isolated(const std::filesystem::path& model, const IsolationLimits& limits,
                     const PartTreeBuilder& build, Scene& scene,
                     const std::function<void(const std::atomic<bool>& stop)>& meanwhile = {});

}  // namespace plancheck
