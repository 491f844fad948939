// SPDX-License-Identifier: MIT
// Plan CSV against the fuzz scene (every action kind, so every column unit).
// A plan that loads has exactly the rows the contract counts, each a full
// parameter vector.
#include "src/base/error.h"
#include "src/scene/plan.h"
#include "src/scene/scene_loader.h"
#include "tests/fuzz/support.h"

#include <cmath>
#include <string_view>

using namespace plancheck;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const Scene scene = load_scene(fuzz::write_scene());
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const Plan plan = parse_plan(scene, text, "fuzz.csv");
    const std::size_t rows = fuzz::plan_rows(text);
    fuzz::require(rows > 0, "a loaded plan has rows");
    fuzz::require(plan.states.size() == rows, "one state per data row");
    fuzz::require(plan.lines.size() == rows, "one line number per state");
    fuzz::require(plan.times.empty() || plan.times.size() == rows, "a time per state or none");
    for (const auto& state : plan.states) {
      fuzz::require(state.size() == scene.parameter_names.size(), "full parameter vector");
      for (double v : state) fuzz::require(std::isfinite(v), "finite parameters");
    }
    if (plan.target) fuzz::require(plan.target->allFinite() && plan.tolerance >= 0.0, "finite target and tolerance");
  } catch (const InputError&) {
  }
  return 0;
}
