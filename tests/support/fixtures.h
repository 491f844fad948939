// SPDX-License-Identifier: MIT
// Small scenes written to a temporary folder for end-to-end tests.
#pragma once

#include "src/scene/scene.h"

#include <filesystem>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace plancheck::testing {

// A fresh empty folder under the system temp dir, removed by the destructor.
class TempDir {
 public:
  explicit TempDir(const std::string& tag = "test");
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
  // Writes `text` to the file `name` in the folder (write_text) and gives its path.
  std::filesystem::path write(const std::string& name, const std::string& text) const;

 private:
  std::filesystem::path path_;
};

void write_text(const std::filesystem::path& file, const std::string& text);
std::string read_text(const std::filesystem::path& file);

// An axis-aligned box [lo, hi] as 12 triangles, outward facing.
Mesh box_mesh(const Vec3& lo, const Vec3& hi);

// Wavefront OBJ with one `o NAME` object per part (assimp makes each a node
// under the root). Coordinates printed with 17 significant digits.
void write_obj(const std::filesystem::path& file, const std::vector<std::pair<std::string, Mesh>>& parts);

// A cold state of the scene: every action's parameters uniform within its
// limits (-180 to 180 without), widened by `widen` of that range on each
// side (0: within the limits), one draw of rng per parameter.
std::vector<double> random_state(const Scene& scene, std::mt19937_64& rng, double widen);

// Runs a shell command; returns its exit status (not the raw wait status).
int run_command(const std::string& command);

}  // namespace plancheck::testing
