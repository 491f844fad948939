// SPDX-License-Identifier: MIT
// What verify's and sweep's setups (src/cli/distribute.h) share: the scene
// and its options as setup fields, and the scene's bytes in a fingerprint.
#pragma once

#include "src/cli/distribute.h"
#include "src/scene/scene.h"
#include "src/scene/scene_loader.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <string_view>

namespace plancheck {

// Writes "scene", "srdf" and "packages" into a setup object (in that order).
inline void put_scene_setup(nlohmann::ordered_json& s, const std::filesystem::path& scene, const SceneOptions& o) {
  nlohmann::ordered_json packages = nlohmann::ordered_json::object();
  for (const auto& [name, dir] : o.packages) packages[name] = dir.string();
  s["scene"] = scene.string();
  s["srdf"] = o.srdf.string();
  s["packages"] = packages;
}

// Reads them back; throws nlohmann::json::exception when absent or mistyped.
inline void get_scene_setup(const nlohmann::ordered_json& s, std::filesystem::path& scene, SceneOptions& o) {
  scene = s.at("scene").get<std::string>();
  o.srdf = s.at("srdf").get<std::string>();
  for (const auto& [name, dir] : s.at("packages").items()) o.packages[name] = dir.get<std::string>();
}

// The bytes a run reads from its scene: the scene file, the terrain, the
// parts' meshes as loaded.
inline void fingerprint_scene(Fingerprint& fp, const Scene& scene) {
  fp.add_file(scene.file);
  if (scene.terrain) fp.add_file(scene.terrain->dem);
  for (const Part& part : scene.parts) {
    fp.add(part.name);
    fp.add(std::string_view(reinterpret_cast<const char*>(part.mesh.vertices.data()),
                            part.mesh.vertices.size() * sizeof(Vec3)));
    fp.add(std::string_view(reinterpret_cast<const char*>(part.mesh.triangles.data()),
                            part.mesh.triangles.size() * sizeof(Tri)));
  }
}

}  // namespace plancheck
