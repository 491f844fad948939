// SPDX-License-Identifier: MIT
// Scene JSON (plancheck-scene/1) + model file -> Scene. See docs/formats.md "Scene file".
#pragma once

#include "src/scene/scene.h"

#include <atomic>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace plancheck {

// What the command line adds to a scene: `--srdf FILE` (a bare .urdf only)
// and `--package NAME=DIR` (paths as given; they win over a scene's own
// robot.packages).
struct SceneOptions {
  std::filesystem::path srdf;
  std::map<std::string, std::filesystem::path> packages;
  // Not part of the scene: work a caller (a layer above) wants done while
  // the scene's model file is imported (in its child process, or by the
  // native 3ds reader), when this process would only wait or has a core to
  // spare. Called on a thread of its own; `drawn()` gives the model's drawn
  // objects as meshes (drawn_object_meshes in model_loader.h: from the
  // objects the import has read, else from the file; none for other
  // formats); `stop` turns true once the import has answered, and the load
  // waits for it to return. What it throws is dropped. It takes a core: set
  // it only with a thread budget of 2 or more.
  std::function<void(const std::function<std::vector<Mesh>()>& drawn, const std::atomic<bool>& stop)>
      while_importing;
};

// Reads the scene file, the model it names, and resolves actions, checked
// pairs and the optional blocks. A file ending in .urdf is a robot alone
// (lengths m, angles rad). Throws InputError naming the file and the field,
// node or line at fault.
Scene load_scene(const std::filesystem::path& scene_json, const SceneOptions& options = {});

// The same from the scene file's text already in memory; `scene_json` names
// it in messages, and the model and DEM paths are relative to its folder.
Scene parse_scene(const std::string& text, const std::filesystem::path& scene_json,
                  const SceneOptions& options = {});

// Chains and checked pairs derived from the scene's parts, actions and
// allowed rules (Scene::allowed): what loading does once the parts are
// known, and again after world objects change (src/scene/objects.h).
void derive_pairs(Scene& scene);

}  // namespace plancheck
