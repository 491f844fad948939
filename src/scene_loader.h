// SPDX-License-Identifier: MIT
// Scene JSON (plancheck-scene/1) + model file -> Scene. See README "Scene file".
#pragma once

#include "src/scene.h"

#include <filesystem>
#include <string>

namespace plancheck {

// Reads the scene file, the model it names, and resolves actions, checked
// pairs and the optional blocks. Throws InputError naming the file and the
// field, node or line at fault.
Scene load_scene(const std::filesystem::path& scene_json);

// The same from the scene file's text already in memory; `scene_json` names
// it in messages, and the model and DEM paths are relative to its folder.
Scene parse_scene(const std::string& text, const std::filesystem::path& scene_json);

}  // namespace plancheck
