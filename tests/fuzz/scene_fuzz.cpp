// SPDX-License-Identifier: MIT
// Scene JSON: the input is the scene file's text, read next to the fuzz
// scene's model.obj and dem.asc (support.h), so actions, pairs, terrain,
// scoop and probe blocks resolve against a real model.
#include "src/base/error.h"
#include "src/scene/scene_loader.h"
#include "tests/fuzz/support.h"

#include <set>
#include <string>

using namespace plancheck;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path scene_json = fuzz::write_scene();
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const Scene scene = parse_scene(text, scene_json);
    // What the checker relies on from a loaded scene.
    fuzz::require(scene.parameter_names.size() == scene.reference_parameters.size(), "one reference per parameter");
    fuzz::require(std::set<std::string>(scene.parameter_names.begin(), scene.parameter_names.end()).size() ==
                      scene.parameter_names.size(), "parameter names unique");
    fuzz::require(!scene.parts.empty(), "a loaded scene has parts");
    for (const auto& [a, b] : scene.checked_pairs)
      fuzz::require(a >= 0 && b >= 0 && a < b && b < static_cast<int>(scene.parts.size()), "checked pair in range");
    for (const Action& action : scene.actions) {
      fuzz::require(action.node >= 0 && action.node < static_cast<int>(scene.nodes.size()), "action node in range");
      fuzz::require(action.first_parameter + action.parameter_count <= static_cast<int>(scene.parameter_names.size()),
                    "action parameters in range");
      fuzz::require(!action.has_limits || action.lower <= action.upper, "limits ordered");
    }
  } catch (const InputError&) {
  }
  return 0;
}
