// SPDX-License-Identifier: MIT
// Model file (anything assimp reads) -> part tree and triangle meshes.
#pragma once

#include "src/scene/isolate.h"
#include "src/scene/scene.h"

#include <atomic>
#include <filesystem>
#include <functional>
#include <vector>

namespace plancheck {

// Fills scene.nodes (nodes[0] = root) and scene.parts from the model file:
// node transforms from the root down applied, vertices multiplied by
// length_scale (metres per unit). 3ds per-mesh child nodes ("Object_3") are
// folded into their object. Throws InputError on an unreadable, empty or
// malformed model and on duplicate part names (naming both paths).
// assimp runs in a child process under `limits` (src/scene/isolate.h): a crash, hang
// or memory bomb in it becomes an InputError naming the file, and what the
// child hands back is checked before it is used.
// A 3ds file within the strict native reader's subset (src/scene/tds_native.h)
// is read without assimp, in this process, to the same part tree, the same
// bits and the same warnings; `limits.native_3ds` false sends it to assimp.
// `meanwhile` runs in this process on a thread of its own while the child
// imports (run_isolated) or the native reader builds the part tree: for a
// caller with work to do ahead (and a core to do it on). Its `drawn` gives
// the model's drawn_object_meshes (below), made on the caller's thread from
// the objects the native reader has already read, else read from the file.
using DrawnMeshes = std::function<std::vector<Mesh>()>;
using WhileImporting = std::function<void(const DrawnMeshes& drawn, const std::atomic<bool>& stop)>;
void load_model(const std::filesystem::path& model, double length_scale, Scene& scene,
                const IsolationLimits& limits = {}, const WhileImporting& meanwhile = {});

// The objects of a 3ds file as drawn, each as one mesh: its points times
// `length_scale` in file order, its faces in file order (none for other
// formats; an object's faces may name points it lacks: nothing here checks).
// A part loaded from an object of one material has exactly this mesh, which
// lets work on parts start before the import is done (load_model's
// `meanwhile`); a user must compare meshes, as nothing else ties the two.
std::vector<Mesh> drawn_object_meshes(const std::filesystem::path& model, double length_scale);

// Every triangle of a model file as one mesh, node transforms applied (the
// file's own frame, its unit included, no up-axis turn: what RViz shows for a
// URDF mesh). Node names need not be unique. Same guards, isolation and
// checks as load_model; warnings are appended to `warnings`.
Mesh load_mesh(const std::filesystem::path& model, std::vector<std::string>& warnings,
               const IsolationLimits& limits = {});

}  // namespace plancheck
