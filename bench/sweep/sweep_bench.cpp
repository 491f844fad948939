// SPDX-License-Identifier: MIT
// The sweep's certified regions against checking every configuration
// (issue 17), as a plain table:
//   plancheck_sweep_bench datasets/change5/scene.json [--steps 10,5,2.5] [--threads 2] [--json FILE]
// For each step (degrees, or the scene's angle unit), the grid over the full
// limits of every limited driving parameter (as `plancheck sweep --grid
// NAME=LO:HI:STEP,...`), checked in certified blocks (SweepCertifier, what
// `sweep` runs): configurations, configurations with an exact distance,
// single-pair answers, seconds, configurations a minute. Beside it the
// per-configuration check (`sweep --exact-distance`: each configuration's
// full state check, seeded in runs of 32 along the grid) timed on 16 spans
// of 4,096 consecutive configurations at random places, extrapolated to the
// grid, and the speed-up over it.
// Before anything is timed, 2,000 configurations (100 in each of 20 random
// blocks) are compared with Checker::check_state, verify's state check:
// the same verdicts, and certified distances never above its. A wrong
// answer stops the bench with status 3.
#include "src/base/parallel.h"
#include "src/checks/sweep_certify.h"
#include "src/checks/sweep_grid.h"
#include "src/checks/verify.h"
#include "src/scene/scene_loader.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace plancheck;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

void require(bool ok, const std::string& what) {
  if (ok) return;
  std::fprintf(stderr, "plancheck_sweep_bench: wrong answer: %s\n", what.c_str());
  std::exit(3);
}

// "NAME=LO:HI:STEP,..." over every driving parameter with limits.
std::string full_limits_grid(const Scene& scene, double step) {
  std::ostringstream g;
  g.precision(17);
  bool first = true;
  for (const Action& a : scene.actions) {
    if (!a.has_limits || a.parameter_count != 1 || a.mimic >= 0) continue;
    if (!first) g << ",";
    first = false;
    g << scene.parameter_names[static_cast<std::size_t>(a.first_parameter)] << "=" << a.lower << ":" << a.upper
      << ":" << step;
  }
  return g.str();
}

struct Row {
  double step = 0.0;
  std::size_t configurations = 0, blocks = 0, exact = 0, contact = 0, pair_checks = 0, witnessed = 0, contact_boxes = 0;
  std::size_t point_tests = 0;  // exact answers at the pair groups' points (SweepBlockResult::point_tests)
  double seconds = 0.0;
  double per_configuration_seconds = 0.0;  // extrapolated
};

Row run_step(const Checker& checker, const Scene& scene, double step, int threads) {
  Row row;
  row.step = step;
  SweepGrid grid;
  grid.axes = sweep_axes_from_grid(scene, full_limits_grid(scene, step));
  grid.reference = scene.reference_parameters;
  for (const SweepAxis& a : grid.axes) grid.total *= a.values.size();
  row.configurations = grid.total;
  const SweepCertifier certifier(checker, scene, grid);
  const SweepBlocks& blocks = certifier.blocks();
  row.blocks = blocks.blocks;
  const double margin = scene.safety_margin;

  // 1. The answer: 20 random blocks, 100 random configurations in each.
  std::mt19937_64 rng(20261126);
  std::vector<double> params;
  for (int b = 0; b < 20; ++b) {
    const std::size_t block = std::uniform_int_distribution<std::size_t>(0, blocks.blocks - 1)(rng);
    SweepBlockResult r;
    certifier.check_block(block, r);
    std::vector<std::size_t> first, size;
    blocks.block(block, first, size);
    for (int n = 0; n < 100; ++n) {
      const std::size_t i = std::uniform_int_distribution<std::size_t>(0, r.verdict.size() - 1)(rng);
      std::size_t rest = i, index = 0;
      std::vector<std::size_t> digit(size.size());
      for (std::size_t k = size.size(); k-- > 0;) {
        digit[k] = rest % size[k];
        rest /= size[k];
      }
      for (std::size_t k = 0; k < size.size(); ++k) index = index * blocks.shape[k] + first[k] + digit[k];
      grid.decode(index, params, nullptr);
      StateResult st;
      checker.check_state(params, st);
      const Verdict v = state_verdict(st, margin);
      require(v == r.verdict[i], "verdict at configuration " + std::to_string(index) + " of the " +
                                     std::to_string(step) + " grid");
      require(st.collision ? r.distance[i] == 0.0 : r.distance[i] <= st.min_distance + kDistanceTieTolerance,
              "distance above the state check's at configuration " + std::to_string(index));
    }
  }

  // 2. The certified sweep of the whole grid.
  std::atomic<std::size_t> exact{0}, contact{0}, pair_checks{0}, witnessed{0}, contact_boxes{0}, point_tests{0};
  const auto t0 = Clock::now();
  parallel_for(blocks.blocks, threads, 1, [&](std::size_t b0, std::size_t b1, int) {
    SweepBlockResult r;
    for (std::size_t b = b0; b < b1; ++b) {
      certifier.check_block(b, r);
      std::size_t e = 0, c = 0;
      for (std::uint8_t x : r.exact) e += x;
      for (Verdict v : r.verdict) c += v == Verdict::kCollision;
      exact += e;
      contact += c;
      pair_checks += r.pair_checks;
      witnessed += r.witnessed;
      contact_boxes += r.contact_boxes;
      point_tests += r.point_tests;
    }
  });
  row.seconds = since(t0);
  row.exact = exact;
  row.contact = contact;
  row.pair_checks = pair_checks;
  row.witnessed = witnessed;
  row.contact_boxes = contact_boxes;
  row.point_tests = point_tests;

  // 3. Per configuration, on 16 spans of 4,096 consecutive configurations
  // (sweep --exact-distance's work: full state checks seeded in runs of 32).
  constexpr std::size_t kSpan = 4096, kSpans = 16, kRun = 32;
  const std::size_t span = std::min(kSpan, grid.total);
  std::vector<std::size_t> starts;
  for (std::size_t s = 0; s < kSpans; ++s)
    starts.push_back(std::uniform_int_distribution<std::size_t>(0, grid.total - span)(rng) / kRun * kRun);
  CheckRequest request;
  request.max_triangle_pairs = 0;
  request.all_contacts = false;
  const auto t1 = Clock::now();
  parallel_for(starts.size() * span / kRun, threads, 1, [&](std::size_t r0, std::size_t r1, int) {
    std::vector<double> p;
    StateResult st;
    for (std::size_t r = r0; r < r1; ++r) {
      const std::size_t s = starts[r / (span / kRun)] + (r % (span / kRun)) * kRun;
      StateSeed seed;
      for (std::size_t i = s; i < std::min(grid.total, s + kRun); ++i) {
        grid.decode(i, p, nullptr);
        checker.check_state(p, st, request, &seed);
      }
    }
  });
  const double sampled = since(t1);
  row.per_configuration_seconds = sampled * static_cast<double>(grid.total) / static_cast<double>(starts.size() * span);
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  std::string scene_path, json_path;
  std::vector<double> steps = {10, 5, 2.5};
  int threads = 2;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--steps" && i + 1 < argc) {
      steps.clear();
      std::stringstream s(argv[++i]);
      for (std::string x; std::getline(s, x, ',');) steps.push_back(std::stod(x));
    } else if (a == "--threads" && i + 1 < argc) {
      threads = std::atoi(argv[++i]);
    } else if (a == "--json" && i + 1 < argc) {
      json_path = argv[++i];
    } else if (scene_path.empty() && a.rfind("--", 0) != 0) {
      scene_path = a;
    } else {
      std::fprintf(stderr, "usage: plancheck_sweep_bench SCENE.json [--steps 10,5,2.5] [--threads N] [--json FILE]\n");
      return 2;
    }
  }
  if (scene_path.empty()) {
    std::fprintf(stderr, "usage: plancheck_sweep_bench SCENE.json [--steps 10,5,2.5] [--threads N] [--json FILE]\n");
    return 2;
  }
  const Scene scene = load_scene(scene_path);
  const Checker checker(scene, threads);
  std::printf("certified sweep of the full limits, %d threads (%s)\n", threads, scene_path.c_str());
  std::printf("%6s %12s %7s %12s %12s %12s %13s %12s %8s %12s %8s %13s %9s %11s %14s %8s\n", "step", "configs",
              "blocks", "in contact", "exact free", "witnessed", "contact boxes", "exact tests", "growth", "point tests",
              "growth", "pair answers", "seconds", "configs/min", "per-config s*", "speed-up");
  std::vector<Row> rows;
  for (double step : steps) {
    const Row r = run_step(checker, scene, step, threads);
    rows.push_back(r);
    // Exact tests: configurations with an exact answer of their own (not a witness's).
    const std::size_t tests = r.exact - r.witnessed;
    char growth[32] = "", point_growth[32] = "";
    if (rows.size() > 1) {
      const Row& prev = rows[rows.size() - 2];
      if (prev.exact > prev.witnessed)
        std::snprintf(growth, sizeof growth, "%.1fx", static_cast<double>(tests) / static_cast<double>(prev.exact - prev.witnessed));
      if (prev.point_tests > 0)
        std::snprintf(point_growth, sizeof point_growth, "%.1fx",
                      static_cast<double>(r.point_tests) / static_cast<double>(prev.point_tests));
    }
    std::printf("%6g %12zu %7zu %12zu %12zu %12zu %13zu %12zu %8s %12zu %8s %13zu %9.2f %11.3g %14.1f %7.1fx\n", r.step,
                r.configurations, r.blocks, r.contact, r.exact - r.contact, r.witnessed, r.contact_boxes, tests, growth,
                r.point_tests, point_growth, r.pair_checks, r.seconds, 60.0 * static_cast<double>(r.configurations) / r.seconds,
                r.per_configuration_seconds, r.per_configuration_seconds / r.seconds);
    std::fflush(stdout);
  }
  std::printf("in contact: configurations in collision; exact free: without contact, with an exact distance (some "
              "pair within the margin's cutoff, not certified in clearance); witnessed: in contact by a box's "
              "witness (a triangle crossing or the parts' pieces) with no test of their own; exact tests: in contact "
              "+ exact free - witnessed; growth: exact tests over the previous step's; point tests: the exact "
              "answers computed, at the points of each pair group's projection of a block (a group that sees J1 and "
              "J2 answers a point once for the block's J3 and J4 values), not a witness's\n");
  std::printf("* per-configuration checking timed on 16 random spans of 4,096 consecutive configurations, "
              "extrapolated to the grid\n");
  if (!json_path.empty()) {
    std::ofstream f(json_path);
    f << "{\"threads\": " << threads << ", \"rows\": [";
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const Row& r = rows[i];
      f << (i ? ", " : "") << "{\"step\": " << r.step << ", \"configurations\": " << r.configurations
        << ", \"blocks\": " << r.blocks << ", \"exact\": " << r.exact << ", \"in_contact\": " << r.contact << ", \"pair_answers\": " << r.pair_checks
        << ", \"witnessed\": " << r.witnessed << ", \"contact_boxes\": " << r.contact_boxes
        << ", \"point_tests\": " << r.point_tests
        << ", \"seconds\": " << r.seconds << ", \"per_configuration_seconds_estimated\": "
        << r.per_configuration_seconds << "}";
    }
    f << "]}\n";
  }
  return 0;
}
