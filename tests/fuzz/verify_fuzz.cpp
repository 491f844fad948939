// SPDX-License-Identifier: MIT
// The verify invariant: a plan either fails to load with InputError, or every
// one of its rows is checked (one result per row the contract counts, each
// with a collision test and a distance), and a "safe" verdict agrees with
// every state's result and with the limits computed here from the scene.
#include "src/base/error.h"
#include "src/scene/plan.h"
#include "src/scene/scene_loader.h"
#include "src/checks/verify.h"
#include "tests/fuzz/support.h"

#include <cmath>
#include <memory>
#include <string_view>
#include <vector>

using namespace plancheck;

namespace {

// The first action whose limits the state leaves (-1: none), NaN outside.
int outside_limits(const Scene& scene, const std::vector<double>& state) {
  for (std::size_t a = 0; a < scene.actions.size(); ++a) {
    const Action& action = scene.actions[a];
    if (!action.has_limits) continue;
    for (int k = 0; k < action.parameter_count; ++k) {
      const double v = state[static_cast<std::size_t>(action.first_parameter + k)];
      if (std::isnan(v) || v < action.lower || v > action.upper) return static_cast<int>(a);
    }
  }
  return -1;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const Scene scene = load_scene(fuzz::write_scene());
  static const auto checker = std::make_unique<const Checker>(scene, 1);
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  std::vector<Plan> plans;
  try {
    plans.push_back(parse_plan(scene, text, "fuzz.csv"));
  } catch (const InputError&) {
    return 0;
  }
  const std::size_t rows = fuzz::plan_rows(text);
  fuzz::require(plans[0].states.size() == rows, "the plan holds every data row");
  VerifyOptions options;
  options.threads = 1;
  const std::vector<PlanResult> results = verify_plans(*checker, scene, plans, options);
  fuzz::require(results.size() == 1, "one result per plan");
  const PlanResult& r = results[0];
  fuzz::require(r.states.size() == rows, "one state result per data row");
  bool any_violation = false;
  for (std::size_t s = 0; s < rows; ++s) {
    const StateResult& st = r.states[s];
    // A state that was never checked keeps StateResult's defaults: no pair, infinite distance.
    fuzz::require(st.part_a >= 0 && st.part_b >= 0 && std::isfinite(st.min_distance), "every state checked");
    fuzz::require(st.collision == !st.contacts.empty(), "collision flag matches the contacts");
    fuzz::require(st.limit_action == outside_limits(scene, plans[0].states[s]), "limits checked");
    any_violation = any_violation || st.collision || st.limit_action >= 0 || st.min_distance < scene.safety_margin;
  }
  if (r.verdict == Verdict::kSafe) {
    fuzz::require(!any_violation && !r.first_violation, "a safe verdict only without a violating state");
    fuzz::require(!plans[0].target || (r.target_error && *r.target_error <= plans[0].tolerance),
                  "a safe verdict reaches the target");
  } else {
    fuzz::require(r.first_violation.has_value(), "an unsafe verdict names its violation");
  }
  return 0;
}
