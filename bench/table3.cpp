// SPDX-License-Identifier: MIT
// Table 3 of Yang et al. (2021) reproduced: the default plans, per plan the
// states, plancheck's seconds on 1 and 2 threads, FCL 0.7's seconds on the
// same states (one thread: FCL has no threading of its own), the paper's
// seconds and the ratios. Every answer is checked before anything is timed:
// plancheck's collision flags must equal FCL's state by state and its
// distances agree within 1e-9 m, else the run stops with status 3.
#include "bench/table3.h"

#include "bench/fcl_peer/fcl_peer.h"
#include "src/base/error.h"
#include "src/base/parallel.h"
#include "src/scene/plan.h"
#include "src/scene/scene_loader.h"
#include "src/scene/terrain.h"
#include "src/checks/verify.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
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
using Clock = std::chrono::steady_clock;

// Table 3 of the paper (shared/paper-notes.md): states and seconds per plan,
// one 2.4 GHz i7 core, 422,275 triangles.
constexpr int kPaperStates[10] = {381, 264, 345, 249, 276, 238, 294, 323, 286, 326};
constexpr double kPaperSeconds[10] = {1079.06, 914.57, 1028.51, 796.43, 782.63,
                                      778.73,  862.29, 1073.67, 960.73, 1114.31};
constexpr double kAgreeTolerance = 1e-9;  // m, distances plancheck vs FCL

template <class F>
double seconds_of(F&& f) {
  const auto t0 = Clock::now();
  f();
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Median of `reps` timings of f (reps >= 1).
template <class F>
double median_seconds(int reps, F&& f) {
  std::vector<double> t;
  for (int i = 0; i < reps; ++i) t.push_back(seconds_of(f));
  std::sort(t.begin(), t.end());
  const std::size_t n = t.size();
  return n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
}

struct PlanRow {
  std::string name;
  std::size_t states = 0;
  int colliding = 0;
  double pc_1 = 0, pc_2 = 0;            // plancheck collision + distance, 1 and 2 threads (s)
  double pc_collide_1 = 0;              // plancheck collision only, 1 thread (s)
  double fcl = 0, fcl_collide = 0;      // FCL, 1 thread (s)
  std::optional<double> paper;          // s
};

struct ToleranceRow {
  double rel = 0;
  double seconds = 0;        // 1 thread, all plans
  double max_abs_error = 0;  // m, against the exact distance
  double max_rel_error = 0;
};

std::string fmt(double x, const char* f = "%.3f") {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, x);
  return buf;
}

std::string lscpu_model() {
  std::ifstream f("/proc/cpuinfo");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("model name", 0) == 0) {
      const auto p = line.find(':');
      return p == std::string::npos ? line : line.substr(p + 2);
    }
  return "unknown";
}

}  // namespace

int run_table3(int argc, char** argv) {
  CLI::App app{"plancheck_bench table3: the paper's Table 3 beside FCL"};
  std::string scene_file, json_file;
  std::vector<std::string> plan_files;
  bool with_fcl = false;
  int reps = 5, fcl_reps = 1;
  std::vector<double> tolerances = {0.0, 1e-3, 1e-2, 5e-2, 0.1, 0.2};
  app.add_option("SCENE", scene_file, "scene file")->required();
  app.add_option("PLAN", plan_files, "plan files (default: the scene folder's plans/*.csv)");
  app.add_option("--json", json_file, "also write the tables as JSON here");
  app.add_flag("--fcl", with_fcl, "time FCL 0.7 on the same states (and check answers against it)");
  app.add_option("--repetitions", reps, "timed repetitions of plancheck (median)")->check(CLI::PositiveNumber);
  app.add_option("--fcl-repetitions", fcl_reps, "timed repetitions of FCL (median)")->check(CLI::PositiveNumber);
  app.add_option("--tolerances", tolerances, "relative distance tolerances for the error table");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  try {
    const Scene scene = load_scene(scene_file);
    if (plan_files.empty()) {
      const fs::path dir = fs::path(scene_file).parent_path() / "plans";
      if (fs::is_directory(dir))
        for (const auto& e : fs::directory_iterator(dir))
          if (e.path().extension() == ".csv") plan_files.push_back(e.path().string());
      std::sort(plan_files.begin(), plan_files.end());
    }
    if (plan_files.empty()) throw InputError("no plans given and none in the scene folder's plans/");
    std::vector<Plan> plans;
    for (const auto& p : plan_files) plans.push_back(load_plan(scene, p));
    std::size_t total_states = 0;
    for (const Plan& p : plans) total_states += p.states.size();

    std::cerr << "table3: building plancheck structures\n";
    std::unique_ptr<Checker> checker;
    const double pc_build = seconds_of([&] { checker = std::make_unique<Checker>(scene, 2); });
    std::unique_ptr<FclPeer> fcl;
    Mesh terrain;
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

    // 1. Answers first: exact plancheck against FCL, state by state.
    std::cerr << "table3: checking answers on " << total_states << " states\n";
    std::vector<std::vector<StateResult>> exact(plans.size());
    std::vector<PlanRow> rows(plans.size());
    int mismatches = 0;
    double max_diff = 0.0;
    for (std::size_t p = 0; p < plans.size(); ++p) {
      rows[p].name = plans[p].name;
      rows[p].states = plans[p].states.size();
      if (plans.size() == 10 && plans[p].states.size() > 0) rows[p].paper = kPaperSeconds[p];
      exact[p].resize(plans[p].states.size());
      for (std::size_t s = 0; s < plans[p].states.size(); ++s) {
        StateResult& r = exact[p][s];
        checker->check_state(plans[p].states[s], r);
        rows[p].colliding += r.collision ? 1 : 0;
        StateResult c;
        checker->check_state(plans[p].states[s], c, CheckRequest{false, 0.0});
        if (c.collision != r.collision) {
          ++mismatches;
          std::cerr << "MISMATCH " << plans[p].name << " state " << s << ": collision-only query differs\n";
        }
        if (!fcl) continue;
        const auto f = fcl->check(plans[p].states[s], true);
        const auto fc = fcl->check(plans[p].states[s], false);
        bool bad = f.collision != r.collision || fc.collision != r.collision;
        if (!r.collision && !f.collision) {
          const double d = std::abs(r.min_distance - f.distance);
          max_diff = std::max(max_diff, d);
          bad = bad || !(d <= kAgreeTolerance);
        }
        if (bad) {
          ++mismatches;
          std::cerr << "MISMATCH " << plans[p].name << " state " << s << ": plancheck collision "
                    << r.collision << " distance " << r.min_distance << ", FCL collision " << f.collision
                    << " distance " << f.distance << "\n";
        }
      }
    }
    if (mismatches > 0) {
      std::cerr << "table3: " << mismatches << " states disagree; nothing timed\n";
      return 3;
    }
    std::cerr << "table3: answers agree" << (fcl ? " with FCL (max distance difference " + fmt(max_diff, "%.3g") + " m)" : "")
              << "\n";

    // 2. Timing: plancheck per plan on 1 and 2 threads, and collision only.
    std::cerr << "table3: timing plancheck (" << reps << " repetitions, median)\n";
    for (std::size_t p = 0; p < plans.size(); ++p) {
      const std::vector<Plan> one{plans[p]};
      // Collision and distance only (regolith off): the same work FCL does.
      rows[p].pc_1 = median_seconds(reps, [&] { verify_plans(*checker, scene, one, VerifyOptions{1, false, false}); });
      rows[p].pc_2 = median_seconds(reps, [&] { verify_plans(*checker, scene, one, VerifyOptions{2, false, false}); });
      rows[p].pc_collide_1 = median_seconds(reps, [&] {
        StateResult r;
        for (const auto& st : plans[p].states) checker->check_state(st, r, CheckRequest{false, 0.0});
      });
    }
    // The whole workload in one call, as `plancheck verify` runs it.
    const double all_1 = median_seconds(reps, [&] { verify_plans(*checker, scene, plans, VerifyOptions{1, false, false}); });
    const double all_2 = median_seconds(reps, [&] { verify_plans(*checker, scene, plans, VerifyOptions{2, false, false}); });

    if (fcl) {
      std::cerr << "table3: timing FCL (" << fcl_reps << " repetitions, median)\n";
      for (std::size_t p = 0; p < plans.size(); ++p) {
        rows[p].fcl = median_seconds(fcl_reps, [&] {
          for (const auto& st : plans[p].states) fcl->check(st, true);
        });
        rows[p].fcl_collide = median_seconds(fcl_reps, [&] {
          for (const auto& st : plans[p].states) fcl->check(st, false);
        });
      }
    }

    // 3. Error against run time for the relative distance tolerance.
    std::cerr << "table3: tolerance table\n";
    std::vector<ToleranceRow> tol_rows;
    for (double rel : tolerances) {
      ToleranceRow t;
      t.rel = rel;
      std::vector<std::vector<double>> got(plans.size());
      t.seconds = median_seconds(reps, [&] {
        for (std::size_t p = 0; p < plans.size(); ++p) {
          got[p].assign(plans[p].states.size(), 0.0);
          StateResult r;
          StateSeed seed;  // coherence as in verify_plans
          for (std::size_t s = 0; s < plans[p].states.size(); ++s) {
            checker->check_state(plans[p].states[s], r, CheckRequest{true, rel}, &seed);
            got[p][s] = r.min_distance;
          }
        }
      });
      for (std::size_t p = 0; p < plans.size(); ++p)
        for (std::size_t s = 0; s < plans[p].states.size(); ++s) {
          const double e = exact[p][s].min_distance;
          if (!std::isfinite(e)) continue;
          const double err = got[p][s] - e;
          if (err < 0 || err > rel * e * (1 + 1e-12) + 1e-15) {
            std::cerr << "table3: tolerance " << rel << " broke its bound at " << plans[p].name << " state " << s
                      << "\n";
            return 3;
          }
          t.max_abs_error = std::max(t.max_abs_error, err);
          if (e > 0) t.max_rel_error = std::max(t.max_rel_error, err / e);
        }
      tol_rows.push_back(t);
    }

    // 4. Output.
    PlanRow total;
    total.name = "total";
    double paper_total = 0;
    bool have_paper = true;
    for (const PlanRow& r : rows) {
      total.states += r.states;
      total.colliding += r.colliding;
      total.pc_1 += r.pc_1;
      total.pc_2 += r.pc_2;
      total.pc_collide_1 += r.pc_collide_1;
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

    std::ostream& out = std::cout;
    out << "Table 3 (Yang et al. 2021) on " << scene_file << ": " << total.states << " states, "
        << checker->triangle_count() << " triangles in collision structures\n";
    out << "machine: " << lscpu_model() << ", " << hardware_threads() << " hardware threads\n";
    out << "plancheck: exact collision + exact minimum distance per state; median of " << reps << " runs\n";
    if (fcl) out << "FCL 0.7 OBBRSS, 1 thread, collide then distance with a shared DistanceResult; median of " << fcl_reps << " runs\n";
    out << "\n| plan | states | colliding | plancheck 1T s | plancheck 2T s | 2T/1T speed-up | FCL s | FCL/plancheck 1T | plancheck collide 1T s | FCL collide s | FCL/plancheck collide | paper s | paper/plancheck 2T |\n";
    out << "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    auto line = [&](const PlanRow& r) {
      out << "| " << r.name << " | " << r.states << " | " << r.colliding << " | " << fmt(r.pc_1, "%.4f") << " | "
          << fmt(r.pc_2, "%.4f") << " | " << fmt(r.pc_1 / r.pc_2, "%.2f") << " | "
          << (fcl ? fmt(r.fcl, "%.3f") : "-") << " | " << (fcl ? fmt(r.fcl / r.pc_1, "%.1f") : "-") << " | "
          << fmt(r.pc_collide_1, "%.4f") << " | " << (fcl ? fmt(r.fcl_collide, "%.4f") : "-") << " | "
          << (fcl ? fmt(r.fcl_collide / r.pc_collide_1, "%.1f") : "-") << " | "
          << (r.paper ? fmt(*r.paper, "%.2f") : "-") << " | " << (r.paper ? fmt(*r.paper / r.pc_2, "%.0f") : "-")
          << " |\n";
    };
    for (const PlanRow& r : rows) line(r);
    line(total);
    out << "\nwhole workload in one verify_plans call: " << fmt(all_1) << " s on 1 thread, " << fmt(all_2)
        << " s on 2 threads (speed-up " << fmt(all_1 / all_2, "%.2f") << "x, "
        << fmt(static_cast<double>(total.states) / all_2, "%.0f") << " states/s)\n";
    if (total.paper)
      out << "paper / plancheck (2 threads, one call): " << fmt(*total.paper / all_2, "%.0f") << "x\n";
    out << "build: plancheck " << fmt(pc_build) << " s (2 threads)";
    if (fcl) out << ", FCL " << fmt(fcl_build) << " s";
    out << "\nmemory: plancheck " << fmt(memory / 1e6, "%.1f") << " MB = " << fmt(memory / scene_tris, "%.1f")
        << " bytes per scene triangle (" << fmt(memory / std::max(1.0, tris), "%.1f") << " per kept triangle)";
    if (fcl)
      out << ", FCL " << fmt(fcl->memory_bytes() / 1e6, "%.1f") << " MB = "
          << fmt(fcl->memory_bytes() / static_cast<double>(scene_tris), "%.1f") << " bytes per triangle";
    out << "\n\nrelative distance tolerance -> time (1 thread, all plans, collision + distance) -> max observed error\n";
    out << "| rel tolerance | seconds | max abs error (m) | max rel error |\n|---|---|---|---|\n";
    for (const ToleranceRow& t : tol_rows)
      out << "| " << fmt(t.rel, "%g") << " | " << fmt(t.seconds, "%.4f") << " | " << fmt(t.max_abs_error, "%.3g")
          << " | " << fmt(t.max_rel_error, "%.3g") << " |\n";

    if (!json_file.empty()) {
      nlohmann::json j;
      j["format"] = "plancheck-bench-table3/1";
      j["scene"] = scene_file;
      j["machine"] = lscpu_model();
      j["hardware_threads"] = hardware_threads();
      j["repetitions"] = reps;
      j["fcl_repetitions"] = fcl ? fcl_reps : 0;
      j["triangles"] = {{"scene", scene_tris}, {"kept", checker->triangle_count()}};
      j["memory_bytes"] = {{"plancheck", checker->memory_bytes()}, {"fcl", fcl ? fcl->memory_bytes() : 0}};
      j["build_seconds"] = {{"plancheck", pc_build}, {"fcl", fcl_build}};
      j["answers_checked_against_fcl"] = static_cast<bool>(fcl);
      j["max_distance_difference_vs_fcl"] = max_diff;
      auto row_json = [&](const PlanRow& r) {
        nlohmann::json x = {{"plan", r.name},
                            {"states", r.states},
                            {"colliding_states", r.colliding},
                            {"plancheck_seconds_1_thread", r.pc_1},
                            {"plancheck_seconds_2_threads", r.pc_2},
                            {"plancheck_collide_seconds_1_thread", r.pc_collide_1}};
        if (fcl) {
          x["fcl_seconds"] = r.fcl;
          x["fcl_collide_seconds"] = r.fcl_collide;
          x["fcl_over_plancheck_1_thread"] = r.fcl / r.pc_1;
          x["fcl_over_plancheck_collide"] = r.fcl_collide / r.pc_collide_1;
        }
        if (r.paper) {
          x["paper_seconds"] = *r.paper;
          x["paper_over_plancheck_2_threads"] = *r.paper / r.pc_2;
        }
        return x;
      };
      for (const PlanRow& r : rows) j["plans"].push_back(row_json(r));
      j["total"] = row_json(total);
      j["whole_workload"] = {{"seconds_1_thread", all_1}, {"seconds_2_threads", all_2}, {"speedup", all_1 / all_2}};
      for (const ToleranceRow& t : tol_rows)
        j["tolerance"].push_back({{"rel_tolerance", t.rel},
                                  {"seconds_1_thread", t.seconds},
                                  {"max_abs_error", t.max_abs_error},
                                  {"max_rel_error", t.max_rel_error}});
      std::ofstream f(json_file);
      f << j.dump(2) << "\n";
      if (!f) throw InputError("cannot write " + json_file);
    }
    (void)kPaperStates;
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "plancheck bench: " << e.what() << "\n";
    return 2;
  }
}

}  // namespace plancheck::bench
