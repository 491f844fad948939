// SPDX-License-Identifier: MIT
// Plan orchestration and verdicts: verify_plans shards the plans' states
// over threads (each state checked by the Checker, verify.cpp), runs the
// dig and probe passes (regolith.cpp), then judges each state and plan.
// Reports are assembled from these results in src/output/.
#include "src/checks/verify.h"

#include "src/base/parallel.h"
#include "src/base/progress.h"
#include "src/checks/regolith.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <utility>

namespace plancheck {

Verdict state_verdict(const StateResult& st, double margin) {
  if (st.collision) return Verdict::kCollision;
  // Below the margin, or too close to it to settle in double: a violation.
  if (margin > 0.0 && st.part_a >= 0 && st.min_distance < margin + st.distance_tolerance) return Verdict::kClearance;
  if (st.limit_action >= 0) return Verdict::kLimits;
  return Verdict::kSafe;
}

CheckRequest row_request() {
  CheckRequest r;
  r.max_triangle_pairs = 0;
  r.all_contacts = false;
  return r;
}

CheckRequest verdict_only_request(double safety_margin) {
  CheckRequest r = row_request();
  // A margin of 0 (or less) judges contacts only: every distance may be a bound.
  r.exact_below = std::max(safety_margin, 0.0);
  return r;
}

const char* verdict_name(Verdict v) {
  switch (v) {
    case Verdict::kSafe: return "safe";
    case Verdict::kCollision: return "collision";
    case Verdict::kClearance: return "clearance";
    case Verdict::kLimits: return "limits";
    case Verdict::kTarget: return "target";
  }
  return "?";
}

std::vector<PlanResult> verify_plans(const Checker& checker, const Scene& scene,
                                     const std::vector<Plan>& plans, const VerifyOptions& options) {
  std::vector<PlanResult> results(plans.size());
  std::vector<std::vector<double>> state_seconds(plans.size());
  // States are independent: shard them; each writes only its own slot.
  // Within a run of up to kRun states of one plan, the states go in order,
  // each seeding the next (coherence). Runs are fixed blocks of each plan's
  // states, so which state seeds which, and hence which of several equally
  // close pairs is reported, depends neither on the thread count nor on the
  // other plans of the call (verify --shard and MPI check plans in groups).
  constexpr std::size_t kRun = 16;
  struct Run {
    std::size_t plan, begin, end;
  };
  std::vector<Run> runs;
  for (std::size_t p = 0; p < plans.size(); ++p) {
    const std::size_t n = plans[p].states.size();
    results[p].plan = &plans[p];
    results[p].states.resize(n);
    state_seconds[p].resize(n);
    for (std::size_t s = 0; s < n; s += kRun) runs.push_back(Run{p, s, std::min(n, s + kRun)});
  }

  // A digging scene's terrain pairs wait for the dig pass (regolith.cpp),
  // which checks each state against the terrain as dug through that state.
  const bool terrain_later = options.regolith && checker.terrain_is_dug();
  CheckRequest request = options.verdict_only ? verdict_only_request(scene.safety_margin) : CheckRequest{};
  // The full listing only for the colliding states it is asked for (below).
  const bool list_later = request.max_triangle_pairs > 0 && options.listed_collisions != std::numeric_limits<std::size_t>::max();
  if (list_later) {
    request.max_triangle_pairs = 0;
    request.all_contacts = false;
    request.bounds_after_contact = true;
  }
  parallel_for(runs.size(), options.threads, 1, [&](std::size_t run_begin, std::size_t run_end, int) {
    std::size_t done = 0;
    StateSeed seed;  // each run starts from a fresh one (reset), in storage kept across the runs
    for (std::size_t k = run_begin; k < run_end; ++k) {
      const Run& run = runs[k];
      const std::size_t p = run.plan;
      seed.reset();
      for (std::size_t s = run.begin; s < run.end; ++s) {
        const auto t0 = std::chrono::steady_clock::now();
        if (terrain_later)
          checker.check_state_without_terrain(plans[p].states[s], results[p].states[s], request, &seed);
        else
          checker.check_state(plans[p].states[s], results[p].states[s], request, &seed);
        state_seconds[p][s] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      }
      done += run.end - run.begin;
    }
    if (options.progress) options.progress->add(done);
  });

  // Digging (with the terrain pairs of digging scenes) and probes, before
  // the verdicts: the dug terrain's contacts and distances are part of them.
  if (options.regolith) dig_and_probe(checker, plans, results, options, state_seconds);

  if (list_later) {
    // The listed colliding states checked again with every contact and the
    // full listing. A colliding state's contacts do not depend on its seed
    // (a pair skipped by its carried separation is apart), and the collision
    // test walks the same way whatever the listing's length, so the first
    // contact and its first triangle pair are the full check's, and
    // everything else in the state (its contact point, what it carried to
    // the next: bounds_after_contact) is unchanged. The dug terrain's pairs
    // (terrain_later) were listed in full by the dig pass, after the
    // others: they are kept after the others' full list.
    std::vector<std::pair<std::size_t, std::size_t>> listed;
    for (std::size_t p = 0; p < plans.size(); ++p) {
      std::size_t count = 0;
      for (std::size_t s = 0; s < results[p].states.size() && count < options.listed_collisions; ++s)
        if (results[p].states[s].collision) {
          listed.emplace_back(p, s);
          ++count;
        }
    }
    parallel_for(listed.size(), options.threads, 1, [&](std::size_t begin, std::size_t end, int) {
      StateResult full;
      for (std::size_t i = begin; i < end; ++i) {
        const auto [p, s] = listed[i];
        const auto t0 = std::chrono::steady_clock::now();
        if (terrain_later)
          checker.check_state_without_terrain(plans[p].states[s], full, CheckRequest{});
        else
          checker.check_state(plans[p].states[s], full, CheckRequest{});
        std::vector<PairContact>& contacts = results[p].states[s].contacts;
        const bool first_same = full.contacts.empty() ||
                                (!contacts.empty() && contacts[0].part_a == full.contacts[0].part_a &&
                                 contacts[0].part_b == full.contacts[0].part_b && !contacts[0].triangles.empty() &&
                                 !full.contacts[0].triangles.empty() &&
                                 contacts[0].triangles[0] == full.contacts[0].triangles[0]);
        if (!first_same) throw std::logic_error("verify_plans: the listing found another first contact");
        if (terrain_later)
          for (PairContact& c : contacts)
            if (c.part_b == checker.terrain_index()) full.contacts.push_back(std::move(c));
        contacts.swap(full.contacts);
        state_seconds[p][s] += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      }
    });
  }

  const double margin = scene.safety_margin;
  for (std::size_t p = 0; p < plans.size(); ++p) {
    PlanResult& r = results[p];
    r.seconds = std::accumulate(state_seconds[p].begin(), state_seconds[p].end(), 0.0);
    for (std::size_t s = 0; s < r.states.size(); ++s) {
      const StateResult& st = r.states[s];
      // A verdict-only state's lower bound counts too: the plan's minimum is
      // then a bound as well (min_part_a -1).
      if ((st.part_a >= 0 || st.distance_is_bound) && st.min_distance < r.min_distance) {
        r.min_distance = st.min_distance;
        r.min_distance_state = s;
        r.min_part_a = st.part_a;
        r.min_part_b = st.part_b;
        r.min_point_a = st.point_a;
        r.min_point_b = st.point_b;
      }
      if (r.first_violation) continue;
      Violation v;
      v.state = s;
      v.kind = state_verdict(st, margin);
      if (v.kind == Verdict::kSafe) continue;
      if (v.kind == Verdict::kCollision) {
        v.part_a = st.contacts[0].part_a;
        v.part_b = st.contacts[0].part_b;
      } else if (v.kind == Verdict::kClearance) {
        v.part_a = st.part_a;
        v.part_b = st.part_b;
      } else {
        v.action = st.limit_action;
      }
      r.first_violation = v;
    }
    const Plan& plan = plans[p];
    if (plan.target && !plan.states.empty()) {
      const Vec3 reached = checker.target_point(plan.states.back());
      r.target_error = (reached - *plan.target).norm();
      if (!r.first_violation && *r.target_error > plan.tolerance) {
        Violation v;
        v.state = plan.states.size() - 1;
        v.kind = Verdict::kTarget;
        r.first_violation = v;
      }
    }
    r.verdict = r.first_violation ? r.first_violation->kind : Verdict::kSafe;
  }
  return results;
}

}  // namespace plancheck
