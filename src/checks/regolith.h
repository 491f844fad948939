// SPDX-License-Identifier: MIT
// The scoop and probe passes of verify_plans (src/checks/plan_check.cpp), and
// the digging walk they share with verify --continuous (src/checks/continuous.cpp).
#pragma once

#include "src/checks/dig.h"
#include "src/checks/verify.h"
#include "src/geometry/heightfield.h"
#include "src/scene/plan.h"

#include <cstddef>
#include <functional>
#include <vector>

namespace plancheck {

// The scoop and probe passes of verify_plans: digging runs sequentially
// along each plan (plans in parallel unless options.dig_carry), so results do
// not depend on the thread count. In a digging scene, state s of a plan sees
// the terrain as dug by states 0..s of that plan (its own dig included; with
// dig_carry, after the earlier plans' digs too): its terrain pairs are
// checked there (Checker::check_terrain, adding the time to
// state_seconds[p][s]) and its probes cast there. Without digging, probes see
// the undisturbed terrain.
void dig_and_probe(const Checker& checker, const std::vector<Plan>& plans, std::vector<PlanResult>& results,
                   const VerifyOptions& options, std::vector<std::vector<double>>& state_seconds);

// What dig_along_plans reports, per plan p (each callback optional). A plan's
// calls come in state order on one thread; different plans' calls may run
// concurrently (not with dig_carry).
struct DigWalk {
  // State s dug `changed` into the grid; the field (when there is one) still
  // shows the terrain through state s - 1 (the plan's start for s = 0).
  std::function<void(std::size_t p, std::size_t s, const SampleRect& changed)> before_refit;
  // The field now shows the terrain dug through state s (nullptr: no field).
  std::function<void(std::size_t p, std::size_t s, Heightfield* field)> after_state;
  std::function<void(std::size_t p, DigSummary summary, std::vector<DigStep>& steps)> after_plan;
  // false: a walk that wants only the terrains (Digger::dig_plan's volumes).
  bool volumes = true;
};

// The dig walk of dig_and_probe: each plan dug state by state from the
// undisturbed grid (with dig_carry, from where the previous plan left it,
// plans in order; else plans in parallel), a copy of `base` (nullptr: none)
// refit over each state's changed samples. Deterministic, so two walks show
// the same terrains at the same states.
void dig_along_plans(const Digger& digger, const Heightfield* base, const std::vector<Plan>& plans,
                     bool dig_carry, int threads, const DigWalk& walk);

}  // namespace plancheck
