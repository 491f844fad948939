// SPDX-License-Identifier: MIT
// Scene JSON (plancheck-scene/1) + model file -> Scene. See README "Scene file".
#pragma once

#include "src/scene/scene.h"

#include <filesystem>
#include <map>
#include <string>

namespace plancheck {

// What the command line adds to a scene: `--srdf FILE` (a bare .urdf only)
// and `--package NAME=DIR` (paths as given; they win over a scene's own
// robot.packages).
struct SceneOptions {
  std::filesystem::path srdf;
  std::map<std::string, std::filesystem::path> packages;
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

}  // namespace plancheck
