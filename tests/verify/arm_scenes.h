// SPDX-License-Identifier: MIT
// The motion tests' arms: the default dataset's scene without its scoop
// block (nothing digs), the URDF example's arm on the same lander, and
// random segments within their limits.
#pragma once

#include "src/scene/scene.h"
#include "support/fixtures.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

namespace plancheck::testing {

// Scenes of the default dataset without its scoop block (nothing digs) and
// the URDF example's arm on the same lander.
inline std::filesystem::path arm_scene(const TempDir& dir, bool urdf) {
  const std::filesystem::path data = std::filesystem::path(PLANCHECK_SOURCE_DIR) / "datasets" / "change5";
  nlohmann::ordered_json scene = nlohmann::ordered_json::parse(read_text(data / "scene.json"));
  scene.erase("scoop");
  scene["model"] = (data / scene["model"].get<std::string>()).string();
  if (scene.contains("terrain") && scene["terrain"].contains("dem"))
    scene["terrain"]["dem"] = (data / scene["terrain"]["dem"].get<std::string>()).string();
  if (!urdf) {
    write_text(dir / "arm.json", scene.dump(2));
    return dir / "arm.json";
  }
  const std::filesystem::path example = std::filesystem::path(PLANCHECK_SOURCE_DIR) / "datasets" / "urdf-example";
  nlohmann::json u = nlohmann::json::parse(read_text(example / "scene.json"));
  u["model"] = scene["model"];
  u["robot"]["urdf"] = (example / u["robot"]["urdf"].get<std::string>()).string();
  u["robot"]["srdf"] = (example / u["robot"]["srdf"].get<std::string>()).string();
  write_text(dir / "urdf.json", u.dump(2));
  return dir / "urdf.json";
}

// Random segments of an arm: qa within the limits (+-180 where there are
// none), qb up to max_step of each range from it.
struct ArmSegments {
  std::vector<double> lo, hi;
  std::mt19937_64 rng;
  std::uniform_real_distribution<double> unit{0.0, 1.0};
  ArmSegments(const Scene& scene, std::uint64_t seed) : lo(scene.parameter_names.size()), hi(lo.size()), rng(seed) {
    for (const Action& a : scene.actions)
      for (int k = 0; k < a.parameter_count; ++k) {
        lo[static_cast<std::size_t>(a.first_parameter + k)] = a.has_limits ? a.lower : -180;
        hi[static_cast<std::size_t>(a.first_parameter + k)] = a.has_limits ? a.upper : 180;
      }
  }
  void next(double max_step, std::vector<double>& qa, std::vector<double>& qb) {
    qa.resize(lo.size());
    qb.resize(lo.size());
    for (std::size_t j = 0; j < lo.size(); ++j) {
      qa[j] = lo[j] + (hi[j] - lo[j]) * unit(rng);
      qb[j] = std::clamp(qa[j] + max_step * (hi[j] - lo[j]) * (2 * unit(rng) - 1), lo[j], hi[j]);
    }
  }
};

}  // namespace plancheck::testing
