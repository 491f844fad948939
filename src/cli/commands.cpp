// SPDX-License-Identifier: MIT
#include "src/cli/commands.h"

#include "src/checks/continuous.h"
#include "src/base/error.h"

#include "src/output/report_html.h"
#include "src/base/parallel.h"
#include "src/base/progress.h"
#include "src/scene/plan.h"
#include "src/output/report.h"
#include "src/scene/scene_loader.h"
#include "src/checks/verify.h"

#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>

namespace plancheck {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int run_verify(const VerifyArgs& args, std::ostream& out, std::ostream& err) {
  // An old report in DIR must not pass for this run's if this run fails.
  std::error_code ec;
  std::filesystem::remove(args.out / "report.json", ec);

  RunInfo info;
  info.scene_arg = args.scene;
  info.threads = args.threads > 0 ? args.threads : hardware_threads();
  info.verdict_only = args.verdict_only;

  auto t0 = std::chrono::steady_clock::now();
  err << "plancheck: loading " << args.scene.string() << "\n";
  const Scene scene = load_scene(args.scene, args.scene_options);
  ContinuousOptions options;
  if (args.continuous_tolerance > 0.0) options.tolerance = args.continuous_tolerance * scene.length_scale;
  if (!(options.tolerance >= 10.0 * kDistanceTolerance) || !std::isfinite(options.tolerance))
    throw InputError("--continuous-tolerance: must be a finite length of at least 1e-8 m");
  // Every plan is read before anything is checked: a bad plan fails the run
  // before any report is written.
  std::vector<Plan> plans;
  plans.reserve(args.plans.size());
  for (const auto& p : args.plans) plans.push_back(load_plan(scene, p));
  info.load_seconds = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  err << "plancheck: building collision structures\n";
  const Checker checker(scene, info.threads);
  info.build_seconds = seconds_since(t0);
  info.left_out_static_triangles = checker.left_out_static_triangles();

  std::size_t states = 0;
  for (const Plan& p : plans) states += p.states.size();
  err << "plancheck: checking " << states << " states of " << plans.size() << " plans on " << info.threads
      << " threads\n";
  t0 = std::chrono::steady_clock::now();
  std::vector<PlanResult> results;
  {
    Progress progress("verify", states, "states", ProgressOptions{.quiet = args.quiet}, &err);
    VerifyOptions verify_options;
    verify_options.threads = info.threads;
    verify_options.dig_carry = args.dig_carry;
    verify_options.progress = &progress;
    verify_options.verdict_only = args.verdict_only;
    results = verify_plans(checker, scene, plans, verify_options);
  }
  if (args.continuous) {
    const auto tc = std::chrono::steady_clock::now();
    options.threads = info.threads;
    options.dig_carry = args.dig_carry;  // segments see the terrain the states saw
    err << "plancheck: certifying " << (states - plans.size()) << " segments between states\n";
    verify_segments(checker, scene, plans, results, options);
    info.continuous_tolerance = options.tolerance;
    info.contact_tolerance = options.contact_tolerance;
    info.continuous_seconds = seconds_since(tc);
  }
  info.check_seconds = seconds_since(t0);

  write_reports(checker, scene, results, info, args.out);
  if (args.html) {
    const auto th = std::chrono::steady_clock::now();
    write_report_html(checker, scene, results, args.out, ReportPageOptions{args.dig_carry});
    err << "plancheck: wrote " << (args.out / "report.html").string() << " (" << seconds_since(th) << " s)\n";
  } else {
    std::filesystem::remove(args.out / "report.html", ec);  // not this run's
  }
  if (args.json) {
    // Machine-readable stdout: the report itself, nothing else.
    std::ifstream f(args.out / "report.json");
    out << f.rdbuf();
  } else {
    print_plan_lines(checker, scene, results, info, out);
  }
  for (const PlanResult& r : results)
    if (r.verdict != Verdict::kSafe) return 1;
  return 0;
}

}  // namespace plancheck
