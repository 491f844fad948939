// SPDX-License-Identifier: MIT
// The scoop and probe passes of verify_plans, kept out of verify.cpp. In a
// digging scene each plan's states go in order: state s digs, a per-plan copy
// of the terrain heightfield is refit over the samples that dig changed, and
// then s's terrain pairs are checked and its probes cast against that copy.
// So state s sees the terrain as dug through its own dig (the Scoop itself is
// allowed to touch the terrain; every other part meets the pit and rim).
// dig_along_plans is that walk on its own: verify --continuous takes it again
// to check the motion after state s against the same copy.
#include "src/checks/regolith.h"

#include "src/base/parallel.h"

#include <chrono>
#include <optional>
#include <stdexcept>

namespace plancheck {

void dig_along_plans(const Digger& digger, const Heightfield* base, const std::vector<Plan>& plans,
                     bool dig_carry, int threads, const DigWalk& walk) {
  const SampleRect whole{0, 0, digger.undisturbed().ncols - 1, digger.undisturbed().nrows - 1};
  auto run_plan = [&](std::size_t p, Dem& grid, Heightfield* field) {
    auto after_state = [&](std::size_t s, const Dem& now, const SampleRect& changed) {
      if (field) {
        if (walk.before_refit) walk.before_refit(p, s, changed);
        field->refit(now, changed);
      }
      if (walk.after_state) walk.after_state(p, s, field);
    };
    std::vector<DigStep> steps;
    DigSummary summary = digger.dig_plan(plans[p].states, grid, steps, after_state, walk.volumes);
    if (walk.after_plan) walk.after_plan(p, std::move(summary), steps);
  };
  if (dig_carry) {
    Dem grid = digger.undisturbed();
    std::optional<Heightfield> field;
    if (base) field.emplace(*base);
    for (std::size_t p = 0; p < plans.size(); ++p) {
      // The previous plan's final relaxation belongs to no state: sync all.
      if (field) field->refit(grid, whole);
      run_plan(p, grid, field ? &*field : nullptr);
    }
  } else {
    // Each plan starts from the undisturbed terrain: plans are independent.
    parallel_for(plans.size(), threads, 1, [&](std::size_t begin, std::size_t end, int) {
      for (std::size_t p = begin; p < end; ++p) {
        Dem grid = digger.undisturbed();
        std::optional<Heightfield> field;
        if (base) field.emplace(*base);
        run_plan(p, grid, field ? &*field : nullptr);
      }
    });
  }
}

void dig_and_probe(const Checker& checker, const std::vector<Plan>& plans, std::vector<PlanResult>& results,
                   const VerifyOptions& options, std::vector<std::vector<double>>& state_seconds) {
  const ProbeCaster* caster = checker.probe_caster();
  if (caster) {
    for (std::size_t p = 0; p < plans.size(); ++p) {
      results[p].probes.assign(plans[p].states.size(), std::vector<ProbeReading>());
      results[p].probe_targets = caster->target_names();
    }
  }
  const Digger* built = checker.digger();
  // The terrain to dig as a heightfield: the checker's, or the probes' when
  // the terrain is not a collision part (both come from the same DEM).
  const Heightfield* base = checker.terrain() ? checker.terrain() : (caster ? caster->terrain() : nullptr);
  const bool follow = built && base;  // states see the dug terrain
  if (built) {
    const bool check = checker.terrain_is_dug();
    double zmin = 0.0, zmax = 0.0;
    if (base) {
      double lo[3], hi[3];
      if (base->block_box(static_cast<int>(base->levels().size()) - 1, 0, 0, lo, hi)) zmin = lo[2], zmax = hi[2];
    }
    // Coherence along each plan's terrain pairs (plans run on one thread each).
    std::vector<StateSeed> seeds(plans.size());
    const CheckRequest request = options.verdict_only ? verdict_only_request(checker.safety_margin()) : CheckRequest{};
    DigWalk walk;
    walk.after_state = [&](std::size_t p, std::size_t s, Heightfield* field) {
      if (!field) return;
      if (caster) {
        // The probe scene's Embree bounds were fixed at commit with 1e4 m of z slack.
        double lo[3], hi[3];
        if (field->block_box(static_cast<int>(field->levels().size()) - 1, 0, 0, lo, hi) &&
            (lo[2] < zmin - 1e4 || hi[2] > zmax + 1e4))
          throw std::runtime_error("dug terrain beyond the probe scene's bounds");
        caster->cast_state(plans[p].states[s], results[p].probes[s], field);
      }
      if (!check) return;
      const auto t0 = std::chrono::steady_clock::now();
      checker.check_terrain(plans[p].states[s], *field, results[p].states[s], &seeds[p], request);
      state_seconds[p][s] += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    };
    walk.after_plan = [&](std::size_t p, DigSummary summary, std::vector<DigStep>& steps) {
      results[p].dig = std::move(summary);
      results[p].dig_steps.swap(steps);
    };
    dig_along_plans(*built, follow ? base : nullptr, plans, options.dig_carry, options.threads, walk);
  }
  if (caster && !follow) {
    for (std::size_t p = 0; p < plans.size(); ++p) caster->cast(plans[p].states, options.threads, results[p].probes);
  }
}

}  // namespace plancheck
