// SPDX-License-Identifier: MIT
// The scoop and probe passes of verify_plans, kept out of verify.cpp: they
// change nothing the collision pass decides (the Scoop may touch the terrain
// by allowed_collisions, and the other parts are checked against the
// undisturbed terrain mesh; see README "Regolith").
#include "src/verify.h"

#include "src/parallel.h"

namespace plancheck {

void dig_and_probe(const Checker& checker, const std::vector<Plan>& plans, std::vector<PlanResult>& results,
                   const VerifyOptions& options) {
  if (const Digger* built = checker.digger()) {
    const Digger& digger = *built;
    if (options.dig_carry) {
      Dem grid = digger.undisturbed();
      for (std::size_t p = 0; p < plans.size(); ++p)
        results[p].dig = digger.dig_plan(plans[p].states, grid, results[p].dig_steps);
    } else {
      // Each plan starts from the undisturbed terrain: plans are independent.
      parallel_for(plans.size(), options.threads, 1, [&](std::size_t begin, std::size_t end, int) {
        for (std::size_t p = begin; p < end; ++p) {
          Dem grid = digger.undisturbed();
          results[p].dig = digger.dig_plan(plans[p].states, grid, results[p].dig_steps);
        }
      });
    }
  }
  if (const ProbeCaster* built = checker.probe_caster()) {
    const ProbeCaster& caster = *built;
    for (std::size_t p = 0; p < plans.size(); ++p) {
      caster.cast(plans[p].states, options.threads, results[p].probes);
      results[p].probe_targets = caster.target_names();
    }
  }
}

}  // namespace plancheck
