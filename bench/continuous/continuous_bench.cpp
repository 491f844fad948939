// SPDX-License-Identifier: MIT
// Between-states checking, error against run time (issue 6): fixed
// sub-sampling at 1, 4, 16, 64 and 256 sub-steps per segment (exact check
// per sub-step) beside the certified check (src/checks/continuous.h), on the
// default plans and on grazing paths built through their colliding and
// too-close states. Answers are checked first: a fixed sampling that finds a
// collision or clearance violation the certified check did not flag means the
// certificate is wrong, and the bench exits 3.
//   plancheck_continuous_bench [DATASET_DIR] [--threads N]
#include "src/checks/continuous.h"
#include "src/base/parallel.h"
#include "src/scene/plan.h"
#include "src/scene/scene_loader.h"
#include "src/checks/verify.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>

namespace plancheck {
namespace {

struct Segment {
  std::vector<double> qa, qb;
  StateResult sa, sb;
};

struct Outcome {
  bool collision = false;
  bool violation = false;  // collision or closer than the margin
};

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

Outcome fixed_sampling(const Checker& checker, const Segment& s, int k, double margin) {
  Outcome o;
  auto note = [&](const StateResult& r) {
    o.collision |= r.collision;
    o.violation |= r.collision || (r.part_a >= 0 && r.min_distance < margin);
  };
  note(s.sa);
  note(s.sb);
  std::vector<double> q(s.qa.size());
  StateResult r;
  for (int j = 1; j < k; ++j) {
    for (std::size_t i = 0; i < q.size(); ++i) q[i] = s.qa[i] + static_cast<double>(j) / k * (s.qb[i] - s.qa[i]);
    checker.check_state(q, r);
    note(r);
  }
  return o;
}

std::vector<Segment> grazing_set(const Checker& checker, const std::vector<Plan>& plans,
                                 const std::vector<PlanResult>& results, double margin) {
  std::vector<Segment> out;
  std::mt19937_64 rng(11);
  std::normal_distribution<double> normal;
  for (std::size_t p = 0; p < plans.size(); ++p)
    for (std::size_t s = 0; s < plans[p].states.size(); ++s) {
      const StateResult& st = results[p].states[s];
      if (!st.collision && !(st.min_distance < margin)) continue;
      const auto& mid = plans[p].states[s];
      for (int k = 0; k < 7; ++k) {
        std::vector<double> u(mid.size(), 0.0);
        if (k == 0) {
          u[0] = 1.0;  // a J1 swing
        } else {
          double n = 0.0;
          for (double& x : u) {
            x = normal(rng);
            n += x * x;
          }
          for (double& x : u) x /= std::sqrt(n);
        }
        for (double a = 1.0; a <= 64.0; a *= 2.0) {
          Segment g{mid, mid, {}, {}};
          for (std::size_t j = 0; j < mid.size(); ++j) {
            g.qa[j] -= a * u[j];  // states are in plan units: degrees here
            g.qb[j] += a * u[j];
          }
          checker.check_state(g.qa, g.sa);
          checker.check_state(g.qb, g.sb);
          auto clear = [&](const StateResult& r) { return !r.collision && r.min_distance >= margin + 0.005; };
          if (clear(g.sa) && clear(g.sb)) {
            out.push_back(std::move(g));
            break;
          }
        }
      }
    }
  return out;
}

int run(int argc, char** argv) {
  std::filesystem::path dir = "datasets/change5";
  int threads = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--threads" && i + 1 < argc) threads = std::atoi(argv[++i]);
    else if (!a.empty() && a[0] != '-') dir = a;
    else {
      std::fprintf(stderr, "usage: plancheck_continuous_bench [DATASET_DIR] [--threads N]\n");
      return 2;
    }
  }
  const Scene scene = load_scene(dir / "scene.json");
  std::vector<Plan> plans;
  for (const auto& e : std::filesystem::directory_iterator(dir / "plans"))
    if (e.path().extension() == ".csv") plans.push_back(load_plan(scene, e.path()));
  std::sort(plans.begin(), plans.end(), [](const Plan& a, const Plan& b) { return a.name < b.name; });
  const Checker checker(scene, threads);
  const double margin = scene.safety_margin;
  const auto results = verify_plans(checker, scene, plans, VerifyOptions{threads, false, false});

  std::vector<Segment> plan_segments;
  for (std::size_t p = 0; p < plans.size(); ++p)
    for (std::size_t s = 0; s + 1 < plans[p].states.size(); ++s)
      plan_segments.push_back({plans[p].states[s], plans[p].states[s + 1], results[p].states[s], results[p].states[s + 1]});
  std::vector<Segment> grazes = grazing_set(checker, plans, results, margin);

  const SegmentChecker certified(checker, scene, ContinuousOptions{});
  int status = 0;
  std::printf("between-states check, %s, margin %.3g m, %d thread(s); time excludes the states' own checks\n",
              dir.string().c_str(), margin, threads);
  std::printf("%-16s %-12s %9s %10s %10s %10s %10s %12s\n", "set", "method", "segments", "collisions", "missed",
              "violations", "missed", "seconds");
  for (const auto& [name, set] : {std::pair{"default plans", &plan_segments}, std::pair{"grazing paths", &grazes}}) {
    // Certified first: the reference every fixed sampling is checked against.
    std::vector<SegmentResult> ref(set->size());
    double t0 = now();
    parallel_for(set->size(), threads, 1, [&](std::size_t b, std::size_t e, int) {
      for (std::size_t i = b; i < e; ++i) ref[i] = certified.check((*set)[i].qa, (*set)[i].qb, (*set)[i].sa, (*set)[i].sb);
    });
    const double certified_seconds = now() - t0;
    std::size_t ref_collisions = 0, ref_violations = 0, steps = 0;
    for (const auto& r : ref) {
      ref_collisions += r.collision;
      ref_violations += r.collision || r.clearance;
      steps += r.steps;
    }
    for (int k : {1, 4, 16, 64, 256}) {
      std::vector<Outcome> out(set->size());
      t0 = now();
      parallel_for(set->size(), threads, 1, [&](std::size_t b, std::size_t e, int) {
        for (std::size_t i = b; i < e; ++i) out[i] = fixed_sampling(checker, (*set)[i], k, margin);
      });
      const double seconds = now() - t0;
      std::size_t found_c = 0, found_v = 0;
      for (std::size_t i = 0; i < out.size(); ++i) {
        found_c += out[i].collision;
        found_v += out[i].violation;
        if ((out[i].collision && !ref[i].collision) || (out[i].violation && !(ref[i].collision || ref[i].clearance))) {
          std::fprintf(stderr, "FAIL: %s segment %zu: %d sub-steps find what the certified check missed\n", name, i, k);
          status = 3;
        }
      }
      char method[32];
      std::snprintf(method, sizeof method, "fixed %d", k);
      std::printf("%-16s %-12s %9zu %10zu %10zu %10zu %10zu %12.4f\n", name, method, set->size(), found_c,
                  ref_collisions - std::min(ref_collisions, found_c), found_v,
                  ref_violations - std::min(ref_violations, found_v), seconds);
    }
    std::printf("%-16s %-12s %9zu %10zu %10s %10zu %10s %12.4f  (%zu pair checks)\n", name, "certified", set->size(),
                ref_collisions, "0", ref_violations, "0", certified_seconds, steps);
  }
  std::printf("missed: segments the certified check flags that the sampling passes (it never misses: "
              "any sampled violation it lacked would exit 3)\n");
  return status;
}

}  // namespace
}  // namespace plancheck

int main(int argc, char** argv) {
  try {
    return plancheck::run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "plancheck_continuous_bench: %s\n", e.what());
    return 2;
  }
}
