// SPDX-License-Identifier: MIT
// Table 3 of Yang et al. (2021) reproduced: the default plans, per plan the
// states, plancheck's seconds on 1 and 2 threads, FCL 0.7's seconds on the
// same states (one thread: FCL has no threading of its own), the paper's
// seconds and the ratios. Every answer is checked before anything is timed:
// plancheck's collision flags must equal FCL's state by state and its
// distances agree within 1e-9 m, and the verdict-only query's verdicts equal
// the full check's, else the run stops with status 3.
//
// With --random N the states are N configurations drawn uniformly within the
// action limits instead, each checked on its own (cold: no state seeds
// another, no digging), as a sampling-based planner or the API's batch sends
// them. Both kinds go through one path: a workload is a list of groups of
// states (a plan, or the drawn set), answered and timed group by group; only
// how a group's full check runs differs (a plan through verify_plans, cold
// states one by one from nothing).
#include "bench/table3.h"

#include "bench/fcl_peer/fcl_peer.h"
#include "bench/random_states.h"
#include "bench/timing.h"
#include "src/base/error.h"
#include "src/base/parallel.h"
#include "src/scene/plan.h"
#include "src/scene/scene_loader.h"
#include "src/scene/terrain.h"
#include "src/checks/verify.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace plancheck::bench {

namespace {

using reference::FclPeer;

namespace fs = std::filesystem;

// Table 3 of the paper (shared/paper-notes.md): states and seconds per plan,
// one 2.4 GHz i7 core, 422,275 triangles.
constexpr double kPaperSeconds[10] = {1079.06, 914.57, 1028.51, 796.43, 782.63,
                                      778.73,  862.29, 1073.67, 960.73, 1114.31};
constexpr double kAgreeTolerance = 1e-9;  // m, distances plancheck vs FCL

// What is timed: groups of states (Plan::states), reported a row each.
struct Workload {
  std::vector<Plan> groups;
  // false: the groups are plans, each state seeding the next as in verify.
  // true: independent states, each checked from nothing on the undisturbed
  // terrain (Checker::check_state with no seed), as the API's batch does.
  bool cold = false;
};

// Checks `states` one by one from nothing, chunks of 4 over `threads` as
// the API's batch (src/api/plancheck.cpp, check_batch) spreads them.
void check_cold(const Checker& checker, const std::vector<std::vector<double>>& states, int threads,
                const CheckRequest& request) {
  parallel_for(states.size(), threads, 4, [&](std::size_t begin, std::size_t end, int) {
    StateResult r;
    for (std::size_t i = begin; i < end; ++i) checker.check_state(states[i], r, request);
  });
}

// Collision only, as FCL's default request asks it of each pair: every
// checked pair's flag, each stopping at its first intersecting triangle pair.
CheckRequest collide_request() {
  CheckRequest c{false, 0.0};
  c.max_triangle_pairs = 0;
  return c;
}

// The full check (collision and exact distance), or with verdict_only the
// verdict-only one (verdict_only_request), of some groups, as their user gets
// it: plans through verify_plans as `plancheck verify` runs them (regolith
// off: the same work FCL does), cold states through check_cold as the API's
// batch asks them (row_request: no listing of intersecting triangles, which
// the API does not return).
void check_groups(const Checker& checker, const Scene& scene, const std::vector<Plan>& groups, bool cold,
                  int threads, bool verdict_only = false) {
  if (!cold) {
    VerifyOptions o{threads, false, false};
    o.verdict_only = verdict_only;
    o.listed_collisions = kMaxCollisionStatesListed;  // what verify lists without --html
    verify_plans(checker, scene, groups, o);
    return;
  }
  const CheckRequest request = verdict_only ? verdict_only_request(scene.safety_margin) : row_request();
  for (const Plan& g : groups) check_cold(checker, g.states, threads, request);
}

struct Row {
  std::string name;
  std::size_t states = 0;
  int colliding = 0;
  double pc_1 = 0, pc_2 = 0;            // plancheck collision + distance, 1 and 2 threads (s)
  double pc_collide_1 = 0;              // plancheck collision only, 1 thread (s)
  double pc_verdict_1 = 0;              // plancheck verdict only (verdict_only_request), 1 thread (s)
  // Cold states only: the same states written as one plan, through
  // verify_plans as `plancheck verify` runs a plan (each state seeding the
  // next), full and verdict-only, 1 thread (s).
  double plan_1 = 0, plan_verdict_1 = 0;
  double fcl = 0, fcl_collide = 0;      // FCL, 1 thread (s)
  std::optional<double> paper;          // s
};

struct ToleranceRow {
  double rel = 0;
  double seconds = 0;        // 1 thread, all groups
  double max_abs_error = 0;  // m, against the exact distance
  double max_rel_error = 0;
};

struct Answers {
  std::vector<std::vector<StateResult>> exact;  // per group, per state: the full check
  int mismatches = 0;
  double max_diff = 0.0;  // m, largest |plancheck - FCL| distance
};

// Every state's full check, and what must agree with it: the collision-only
// query's flag, the row request's row (collision, first colliding pair,
// distance, pair, points, limits), the verdict-only query's verdict, and
// FCL's flag and distance
// (when fcl is given). States are checked from nothing here whatever the
// workload: answers never depend on coherence.
Answers check_answers(const Checker& checker, const Scene& scene, const FclPeer* fcl,
                      const std::vector<Plan>& groups, std::vector<Row>& rows) {
  Answers a;
  const CheckRequest verdict_request = verdict_only_request(scene.safety_margin);
  a.exact.resize(groups.size());
  for (std::size_t p = 0; p < groups.size(); ++p) {
    const Plan& g = groups[p];
    a.exact[p].resize(g.states.size());
    for (std::size_t s = 0; s < g.states.size(); ++s) {
      StateResult& r = a.exact[p][s];
      checker.check_state(g.states[s], r);
      rows[p].colliding += r.collision ? 1 : 0;
      StateResult c;
      checker.check_state(g.states[s], c, collide_request());
      if (c.collision != r.collision) {
        ++a.mismatches;
        std::cerr << "MISMATCH " << g.name << " state " << s << ": collision-only query differs\n";
      }
      // The row request (cold states' timing) gives the full check's row.
      StateResult w;
      checker.check_state(g.states[s], w, row_request());
      const bool first_same = !r.collision || (w.contacts.size() == 1 && w.contacts[0].part_a == r.contacts[0].part_a &&
                                               w.contacts[0].part_b == r.contacts[0].part_b);
      if (w.collision != r.collision || !first_same || w.min_distance != r.min_distance || w.part_a != r.part_a ||
          w.part_b != r.part_b || w.point_a != r.point_a || w.point_b != r.point_b ||
          w.limit_action != r.limit_action || w.distance_tolerance != r.distance_tolerance) {
        ++a.mismatches;
        std::cerr << "MISMATCH " << g.name << " state " << s << ": the row request's answer differs\n";
      }
      StateResult v;
      checker.check_state(g.states[s], v, verdict_request);
      if (state_verdict(v, scene.safety_margin) != state_verdict(r, scene.safety_margin)) {
        ++a.mismatches;
        std::cerr << "MISMATCH " << g.name << " state " << s << ": verdict-only query says "
                  << verdict_name(state_verdict(v, scene.safety_margin)) << ", the full check "
                  << verdict_name(state_verdict(r, scene.safety_margin)) << "\n";
      }
      if (!fcl) continue;
      const auto f = fcl->check(g.states[s], true);
      const auto fc = fcl->check(g.states[s], false);
      bool bad = f.collision != r.collision || fc.collision != r.collision;
      if (!r.collision && !f.collision) {
        const double d = std::abs(r.min_distance - f.distance);
        a.max_diff = std::max(a.max_diff, d);
        bad = bad || !(d <= kAgreeTolerance);
      }
      if (bad) {
        ++a.mismatches;
        std::cerr << "MISMATCH " << g.name << " state " << s << ": plancheck collision " << r.collision
                  << " distance " << r.min_distance << ", FCL collision " << f.collision << " distance "
                  << f.distance << "\n";
      }
    }
  }
  return a;
}

}  // namespace

int run_table3(int argc, char** argv) {
  CLI::App app{"plancheck_bench table3: the paper's Table 3 (or random cold states) beside FCL"};
  std::string scene_file, json_file;
  std::vector<std::string> plan_files;
  bool with_fcl = false;
  int reps = 5, fcl_reps = 1;
  std::size_t random_count = 0;
  std::uint64_t random_seed = 1;
  std::vector<double> tolerances = {0.0, 1e-3, 1e-2, 5e-2, 0.1, 0.2};
  app.add_option("SCENE", scene_file, "scene file")->required();
  app.add_option("PLAN", plan_files, "plan files (default: the scene folder's plans/*.csv)");
  app.add_option("--json", json_file, "also write the tables as JSON here");
  app.add_flag("--fcl", with_fcl, "time FCL 0.7 on the same states (and check answers against it)");
  app.add_option("--repetitions", reps, "timed repetitions of plancheck (median)")->check(CLI::PositiveNumber);
  app.add_option("--fcl-repetitions", fcl_reps, "timed repetitions of FCL (median)")->check(CLI::PositiveNumber);
  app.add_option("--tolerances", tolerances, "relative distance tolerances for the error table");
  app.add_option("--random", random_count,
                 "instead of plans, N configurations drawn uniformly within the action limits, each checked "
                 "cold (no coherence between states, no digging)")
      ->check(CLI::PositiveNumber);
  app.add_option("--seed", random_seed, "seed of --random (std::mt19937_64)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  try {
    const Scene scene = load_scene(scene_file);
    Workload work;
    if (random_count > 0) {
      if (!plan_files.empty()) throw InputError("--random draws its own states: give no plan files with it");
      work.cold = true;
      Plan g;
      g.name = "random";
      g.states = random_states(scene, random_count, random_seed);
      work.groups.push_back(std::move(g));
    } else {
      if (plan_files.empty()) {
        const fs::path dir = fs::path(scene_file).parent_path() / "plans";
        if (fs::is_directory(dir))
          for (const auto& e : fs::directory_iterator(dir))
            if (e.path().extension() == ".csv") plan_files.push_back(e.path().string());
        std::sort(plan_files.begin(), plan_files.end());
      }
      if (plan_files.empty()) throw InputError("no plans given and none in the scene folder's plans/");
      for (const auto& p : plan_files) work.groups.push_back(load_plan(scene, p));
    }
    const std::vector<Plan>& groups = work.groups;
    std::size_t total_states = 0;
    for (const Plan& p : groups) total_states += p.states.size();

    std::cerr << "table3: building plancheck structures\n";
    std::unique_ptr<Checker> checker;
    const double pc_build = seconds_of([&] { checker = std::make_unique<Checker>(scene, 2); });
    std::unique_ptr<FclPeer> fcl;
    Mesh terrain;  // FCL's terrain: the undisturbed grid, as check_state sees it
    double fcl_build = 0;
    if (scene.terrain && scene.terrain->collide)
      terrain = dem_mesh(*scene.terrain->grid, scene.terrain->origin);
    if (with_fcl) {
      std::cerr << "table3: building FCL models (OBBRSS)\n";
      std::vector<const Mesh*> meshes;
      for (const Part& p : scene.parts) meshes.push_back(&p.mesh);
      if (scene.terrain && scene.terrain->collide) meshes.push_back(&terrain);
      fcl_build = seconds_of([&] { fcl = std::make_unique<FclPeer>(scene, meshes, checker->pairs()); });
    }

    std::vector<Row> rows(groups.size());
    for (std::size_t p = 0; p < groups.size(); ++p) {
      rows[p].name = groups[p].name;
      rows[p].states = groups[p].states.size();
      if (!work.cold && groups.size() == 10 && !groups[p].states.empty()) rows[p].paper = kPaperSeconds[p];
    }

    // 1. Answers first: exact plancheck against FCL, state by state.
    std::cerr << "table3: checking answers on " << total_states << " states\n";
    const Answers answers = check_answers(*checker, scene, fcl.get(), groups, rows);
    if (answers.mismatches > 0) {
      std::cerr << "table3: " << answers.mismatches << " states disagree; nothing timed\n";
      return 3;
    }
    std::cerr << "table3: answers agree"
              << (fcl ? " with FCL (max distance difference " + fmt(answers.max_diff, "%.3g") + " m)" : "") << "\n";

    // 2. Timing: plancheck per group on 1 and 2 threads, and collision only.
    std::cerr << "table3: timing plancheck (" << reps << " repetitions, median)\n";
    for (std::size_t p = 0; p < groups.size(); ++p) {
      const std::vector<Plan> one{groups[p]};
      rows[p].pc_1 = median_seconds(reps, [&] { check_groups(*checker, scene, one, work.cold, 1); });
      rows[p].pc_2 = median_seconds(reps, [&] { check_groups(*checker, scene, one, work.cold, 2); });
      rows[p].pc_collide_1 =
          median_seconds(reps, [&] { check_cold(*checker, groups[p].states, 1, collide_request()); });
      rows[p].pc_verdict_1 = median_seconds(reps, [&] { check_groups(*checker, scene, one, work.cold, 1, true); });
      if (work.cold) {
        rows[p].plan_1 = median_seconds(reps, [&] { check_groups(*checker, scene, one, false, 1); });
        rows[p].plan_verdict_1 = median_seconds(reps, [&] { check_groups(*checker, scene, one, false, 1, true); });
      }
    }
    // The whole workload in one call, as `plancheck verify` runs it (plans
    // only: cold states have no plan boundaries, their one group is all).
    double all_1 = rows[0].pc_1, all_2 = rows[0].pc_2;
    if (!work.cold || groups.size() > 1) {
      all_1 = median_seconds(reps, [&] { check_groups(*checker, scene, groups, work.cold, 1); });
      all_2 = median_seconds(reps, [&] { check_groups(*checker, scene, groups, work.cold, 2); });
    }

    if (fcl) {
      std::cerr << "table3: timing FCL (" << fcl_reps << " repetitions, median)\n";
      for (std::size_t p = 0; p < groups.size(); ++p) {
        rows[p].fcl = median_seconds(fcl_reps, [&] {
          for (const auto& st : groups[p].states) fcl->check(st, true);
        });
        rows[p].fcl_collide = median_seconds(fcl_reps, [&] {
          for (const auto& st : groups[p].states) fcl->check(st, false);
        });
      }
    }

    // 3. Error against run time for the relative distance tolerance.
    std::cerr << "table3: tolerance table\n";
    std::vector<ToleranceRow> tol_rows;
    for (double rel : tolerances) {
      ToleranceRow t;
      t.rel = rel;
      std::vector<std::vector<double>> got(groups.size());
      t.seconds = median_seconds(reps, [&] {
        for (std::size_t p = 0; p < groups.size(); ++p) {
          got[p].assign(groups[p].states.size(), 0.0);
          StateResult r;
          StateSeed seed;  // plans: coherence as in verify_plans; cold states: none
          for (std::size_t s = 0; s < groups[p].states.size(); ++s) {
            checker->check_state(groups[p].states[s], r, CheckRequest{true, rel}, work.cold ? nullptr : &seed);
            got[p][s] = r.min_distance;
          }
        }
      });
      for (std::size_t p = 0; p < groups.size(); ++p)
        for (std::size_t s = 0; s < groups[p].states.size(); ++s) {
          const double e = answers.exact[p][s].min_distance;
          if (!std::isfinite(e)) continue;
          const double err = got[p][s] - e;
          if (err < 0 || err > rel * e * (1 + 1e-12) + 1e-15) {
            std::cerr << "table3: tolerance " << rel << " broke its bound at " << groups[p].name << " state " << s
                      << "\n";
            return 3;
          }
          t.max_abs_error = std::max(t.max_abs_error, err);
          if (e > 0) t.max_rel_error = std::max(t.max_rel_error, err / e);
        }
      tol_rows.push_back(t);
    }

    // 4. Output.
    Row total;
    total.name = "total";
    double paper_total = 0;
    bool have_paper = true;
    for (const Row& r : rows) {
      total.states += r.states;
      total.colliding += r.colliding;
      total.pc_1 += r.pc_1;
      total.pc_2 += r.pc_2;
      total.pc_collide_1 += r.pc_collide_1;
      total.pc_verdict_1 += r.pc_verdict_1;
      total.plan_1 += r.plan_1;
      total.plan_verdict_1 += r.plan_verdict_1;
      total.fcl += r.fcl;
      total.fcl_collide += r.fcl_collide;
      if (r.paper) paper_total += *r.paper; else have_paper = false;
    }
    if (have_paper) total.paper = paper_total;
    const double memory = static_cast<double>(checker->memory_bytes());
    const double tris = static_cast<double>(checker->triangle_count());
    std::size_t scene_tris = 0;
    for (const Part& p : scene.parts) scene_tris += p.mesh.triangles.size();
    if (!terrain.triangles.empty()) scene_tris += terrain.triangles.size();
    const std::vector<std::string> drawn = work.cold ? drawn_parameters(scene) : std::vector<std::string>{};

    std::ostream& out = std::cout;
    if (work.cold) {
      out << "Cold states on " << scene_file << ": " << total.states
          << " configurations drawn uniformly within the action limits (seed " << random_seed << "; drawn:";
      for (const auto& n : drawn) out << " " << n;
      out << "), each checked on its own: no state seeds another, no digging (the undisturbed terrain); "
          << checker->triangle_count() << " triangles in collision structures\n";
    } else {
      out << "Table 3 (Yang et al. 2021) on " << scene_file << ": " << total.states << " states, "
          << checker->triangle_count() << " triangles in collision structures\n";
    }
    out << "machine: " << cpu_model() << ", " << hardware_threads() << " hardware threads\n";
    out << "plancheck: exact collision + exact minimum distance per state"
        << (work.cold ? " (as the API's batch: the first colliding pair, no triangle listing)" : "")
        << "; collide: every checked pair's flag, first contact each (as FCL's default request); median of "
        << reps << " runs\n";
    if (fcl) out << "FCL 0.7 OBBRSS, 1 thread, collide then distance with a shared DistanceResult; median of " << fcl_reps << " runs\n";
    out << "\n| " << (work.cold ? "states" : "plan")
        << " | states | colliding | plancheck 1T s | plancheck 2T s | 2T/1T speed-up | FCL s | FCL/plancheck 1T | plancheck collide 1T s | FCL collide s | FCL/plancheck collide | plancheck verdict-only 1T s | FCL collide/plancheck verdict-only | paper s | paper/plancheck 2T |\n";
    out << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    auto line = [&](const Row& r) {
      out << "| " << r.name << " | " << r.states << " | " << r.colliding << " | " << fmt(r.pc_1, "%.4f") << " | "
          << fmt(r.pc_2, "%.4f") << " | " << fmt(r.pc_1 / r.pc_2, "%.2f") << " | "
          << (fcl ? fmt(r.fcl, "%.3f") : "-") << " | " << (fcl ? fmt(r.fcl / r.pc_1, "%.1f") : "-") << " | "
          << fmt(r.pc_collide_1, "%.4f") << " | " << (fcl ? fmt(r.fcl_collide, "%.4f") : "-") << " | "
          << (fcl ? fmt(r.fcl_collide / r.pc_collide_1, "%.1f") : "-") << " | " << fmt(r.pc_verdict_1, "%.4f")
          << " | " << (fcl ? fmt(r.fcl_collide / r.pc_verdict_1, "%.1f") : "-") << " | "
          << (r.paper ? fmt(*r.paper, "%.2f") : "-") << " | " << (r.paper ? fmt(*r.paper / r.pc_2, "%.0f") : "-")
          << " |\n";
    };
    for (const Row& r : rows) line(r);
    line(total);
    if (!work.cold) {
      out << "\nwhole workload in one verify_plans call: " << fmt(all_1) << " s on 1 thread, " << fmt(all_2)
          << " s on 2 threads (speed-up " << fmt(all_1 / all_2, "%.2f") << "x, "
          << fmt(static_cast<double>(total.states) / all_2, "%.0f") << " states/s)\n";
      if (total.paper)
        out << "paper / plancheck (2 threads, one call): " << fmt(*total.paper / all_2, "%.0f") << "x\n";
    } else {
      out << "\n" << fmt(1e6 * total.pc_1 / static_cast<double>(total.states), "%.1f") << " us per state on 1 thread, "
          << fmt(static_cast<double>(total.states) / total.pc_2, "%.0f") << " states/s on 2 threads\n";
      out << "the same states as one plan through verify_plans (as `plancheck verify` runs a plan), 1 thread: "
          << fmt(total.plan_1, "%.4f") << " s (" << fmt(total.plan_1 / total.pc_1, "%.2f") << "x the batch"
          << (fcl ? ", " + fmt(total.fcl / total.plan_1, "%.1f") + "x FCL" : "") << "), verdict-only "
          << fmt(total.plan_verdict_1, "%.4f") << " s (" << fmt(total.plan_verdict_1 / total.pc_verdict_1, "%.2f")
          << "x the batch" << (fcl ? ", " + fmt(total.fcl_collide / total.plan_verdict_1, "%.1f") + "x FCL's collide" : "")
          << ")\n";
    }
    out << "build: plancheck " << fmt(pc_build) << " s (2 threads)";
    if (fcl) out << ", FCL " << fmt(fcl_build) << " s";
    out << "\nmemory: plancheck " << fmt(memory / 1e6, "%.1f") << " MB = " << fmt(memory / scene_tris, "%.1f")
        << " bytes per scene triangle (" << fmt(memory / std::max(1.0, tris), "%.1f") << " per kept triangle)";
    if (fcl)
      out << ", FCL " << fmt(fcl->memory_bytes() / 1e6, "%.1f") << " MB = "
          << fmt(fcl->memory_bytes() / static_cast<double>(scene_tris), "%.1f") << " bytes per triangle";
    out << "\n\nrelative distance tolerance -> time (1 thread, all " << (work.cold ? "states" : "plans")
        << ", collision + distance) -> max observed error\n";
    out << "| rel tolerance | seconds | max abs error (m) | max rel error |\n|---|---|---|---|\n";
    for (const ToleranceRow& t : tol_rows)
      out << "| " << fmt(t.rel, "%g") << " | " << fmt(t.seconds, "%.4f") << " | " << fmt(t.max_abs_error, "%.3g")
          << " | " << fmt(t.max_rel_error, "%.3g") << " |\n";

    if (!json_file.empty()) {
      nlohmann::json j;
      j["format"] = "plancheck-bench-table3/1";
      j["scene"] = scene_file;
      j["mode"] = work.cold ? "random" : "plans";
      if (work.cold) {
        j["seed"] = random_seed;
        j["drawn_parameters"] = drawn;
      }
      j["machine"] = cpu_model();
      j["hardware_threads"] = hardware_threads();
      j["repetitions"] = reps;
      j["fcl_repetitions"] = fcl ? fcl_reps : 0;
      j["triangles"] = {{"scene", scene_tris}, {"kept", checker->triangle_count()}};
      j["memory_bytes"] = {{"plancheck", checker->memory_bytes()}, {"fcl", fcl ? fcl->memory_bytes() : 0}};
      j["build_seconds"] = {{"plancheck", pc_build}, {"fcl", fcl_build}};
      j["answers_checked_against_fcl"] = static_cast<bool>(fcl);
      j["max_distance_difference_vs_fcl"] = answers.max_diff;
      auto row_json = [&](const Row& r) {
        nlohmann::json x = {{"plan", r.name},
                            {"states", r.states},
                            {"colliding_states", r.colliding},
                            {"plancheck_seconds_1_thread", r.pc_1},
                            {"plancheck_seconds_2_threads", r.pc_2},
                            {"plancheck_collide_seconds_1_thread", r.pc_collide_1},
                            {"plancheck_verdict_only_seconds_1_thread", r.pc_verdict_1}};
        if (work.cold) {
          x["plancheck_as_one_plan_seconds_1_thread"] = r.plan_1;
          x["plancheck_as_one_plan_verdict_only_seconds_1_thread"] = r.plan_verdict_1;
        }
        if (fcl) {
          x["fcl_seconds"] = r.fcl;
          x["fcl_collide_seconds"] = r.fcl_collide;
          x["fcl_over_plancheck_1_thread"] = r.fcl / r.pc_1;
          x["fcl_over_plancheck_collide"] = r.fcl_collide / r.pc_collide_1;
          x["fcl_collide_over_plancheck_verdict_only"] = r.fcl_collide / r.pc_verdict_1;
        }
        if (r.paper) {
          x["paper_seconds"] = *r.paper;
          x["paper_over_plancheck_2_threads"] = *r.paper / r.pc_2;
        }
        return x;
      };
      for (const Row& r : rows) j["plans"].push_back(row_json(r));
      j["total"] = row_json(total);
      j["whole_workload"] = {{"seconds_1_thread", all_1}, {"seconds_2_threads", all_2}, {"speedup", all_1 / all_2}};
      for (const ToleranceRow& t : tol_rows)
        j["tolerance"].push_back({{"rel_tolerance", t.rel},
                                  {"seconds_1_thread", t.seconds},
                                  {"max_abs_error", t.max_abs_error},
                                  {"max_rel_error", t.max_rel_error}});
      write_json_text(json_file, j.dump(2));
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "plancheck bench: " << e.what() << "\n";
    return 2;
  }
}

}  // namespace plancheck::bench
