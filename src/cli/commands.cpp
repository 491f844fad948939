// SPDX-License-Identifier: MIT
#include "src/cli/commands.h"
#include "src/cli/run_setup.h"
#include "src/cli/sweep.h"

#include "src/checks/continuous.h"
#include "src/base/error.h"
#include "src/base/files.h"

#include "src/output/report_html.h"
#include "src/output/result_blob.h"
#include "src/base/parallel.h"
#include "src/base/progress.h"
#include "src/scene/plan.h"
#include "src/output/report.h"
#include "src/scene/scene_loader.h"
#include "src/checks/verify.h"
#include "src/checks/built_ahead.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>

namespace plancheck {

namespace {

using Json = nlohmann::ordered_json;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// What decides verify's results and files, as text: a shard writes it into
// its partial result and `plancheck merge` sets the run up again from it.
// Paths as given (report.json echoes them), so merge runs where the shards
// ran. --threads, --quiet, --shard and --resume are not in it: results do
// not depend on them.
std::string verify_setup(const VerifyArgs& a) {
  Json plans = Json::array();
  for (const auto& p : a.plans) plans.push_back(p.string());
  Json s = Json::object();
  put_scene_setup(s, a.scene, a.scene_options);
  s["plans"] = plans;
  s["dig_carry"] = a.dig_carry;
  s["continuous"] = a.continuous;
  s["continuous_tolerance"] = a.continuous_tolerance;
  s["verdict_only"] = a.verdict_only;
  s["html"] = a.html;
  s["html_plans"] = {{"closest", a.html_plans.closest}, {"names", a.html_plans.names}};
  s["json"] = a.json;
  return s.dump();
}

VerifyArgs verify_args_from_setup(const std::string& text, const std::filesystem::path& file) {
  VerifyArgs a;
  try {
    const Json s = Json::parse(text);
    get_scene_setup(s, a.scene, a.scene_options);
  for (const auto& p : s.at("plans")) a.plans.emplace_back(p.get<std::string>());
    a.dig_carry = s.at("dig_carry").get<bool>();
    a.continuous = s.at("continuous").get<bool>();
    a.continuous_tolerance = s.at("continuous_tolerance").get<double>();
    a.verdict_only = s.at("verdict_only").get<bool>();
    a.html = s.at("html").get<bool>();
    const Json& closest = s.at("html_plans").at("closest");
    if (!closest.is_number_unsigned()) fail(file, "its verify setup is not readable (corrupt)");
    a.html_plans.closest = closest.get<std::size_t>();
    a.html_plans.names = s.at("html_plans").at("names").get<std::vector<std::string>>();
    a.json = s.at("json").get<bool>();
  } catch (const nlohmann::json::exception&) {
    fail(file, "its verify setup is not readable (corrupt)");
  }
  return a;
}

// The run's fingerprint: the setup, and the bytes it reads (scene file,
// model, terrain, the parts' meshes as loaded, the plans).
std::string verify_fingerprint(const std::string& setup, const Scene& scene, const std::vector<Plan>& plans) {
  Fingerprint fp;
  fp.add("verify");
  fp.add(setup);
  fingerprint_scene(fp, scene);
  for (const Plan& p : plans) fp.add_file(p.file);
  return fp.hex();
}

// verify for a single run, a shard, an MPI rank (merge == nullptr), or
// plancheck merge (merge: the partial results to write the outputs from).
int verify_run(const VerifyArgs& args, std::ostream& out, std::ostream& err, const PartialSet* merge) {
  const bool mpi = !merge && under_mpi();
  const int rank = mpi ? mpi_rank() : 0;
  std::ostream silent(nullptr);
  std::ostream& log = rank == 0 ? err : silent;  // one rank speaks
  const bool may_write = rank == 0 && !args.shard;
  // An old report in DIR must not pass for this run's if this run fails.
  std::error_code ec;
  if (may_write) {
    std::filesystem::remove(args.out / "report.json", ec);
    remove_stale_temporaries(args.out);  // what a killed run left half-written
  }

  RunInfo info;
  info.scene_arg = args.scene;
  info.threads = args.threads > 0 ? args.threads : hardware_threads();
  info.verdict_only = args.verdict_only;

  auto t0 = std::chrono::steady_clock::now();
  log << "plancheck: loading " << args.scene.string() << "\n";
  // With a second thread in the budget, the collision structures of the
  // model's drawn objects are built from the time it is imported (beside
  // assimp's child, or beside the native 3ds reader's part tree, from the
  // objects it has read) on a thread of their own, which goes on beside the
  // checker until every object is built or claimed by it: the checker takes
  // those its parts match, waits for one in hand, builds the others itself.
  BuiltAhead ahead;
  SceneOptions scene_options = args.scene_options;
  if (info.threads >= 2)
    scene_options.while_importing = [&ahead](const std::function<std::vector<Mesh>()>& drawn,
                                             const std::atomic<bool>&) { ahead.start(drawn); };
  const Scene scene = load_scene(args.scene, scene_options);
  ContinuousOptions options;
  if (args.continuous_tolerance > 0.0) options.tolerance = args.continuous_tolerance * scene.length_scale;
  if (!(options.tolerance >= 10.0 * kDistanceTolerance) || !std::isfinite(options.tolerance))
    throw InputError("--continuous-tolerance: must be a finite length of at least 1e-8 m");
  options.threads = info.threads;
  options.dig_carry = args.dig_carry;  // segments see the terrain the states saw
  if (args.continuous) {
    info.continuous_tolerance = options.tolerance;
    info.contact_tolerance = options.contact_tolerance;
  }
  // Every plan is read before anything is checked: a bad plan fails the run
  // before any report is written.
  std::vector<Plan> plans;
  plans.reserve(args.plans.size());
  for (const auto& p : args.plans) plans.push_back(load_plan(scene, p));
  check_plan_csv_names(plans);  // two plans, one DIR/<name>.csv: refused before any checking
  check_html_plans(args.html_plans, plans);
  const std::string setup = verify_setup(args);
  // The fingerprint hashes every byte the run reads (some 20 MB on the
  // default scene, one byte at a time): merge compares it now, a run needs
  // it only once checking starts (the journal's header), so with a second
  // thread it is computed beside the collision structures.
  std::string fingerprint;
  std::optional<BesideJob> fingerprinting;
  if (merge || info.threads < 2) {
    fingerprint = verify_fingerprint(setup, scene, plans);
    if (merge && merge->first().fingerprint != fingerprint)
      fail(merge->first().file, "merge: the scene or the plans read now differ from those the shards checked "
                                "(files changed since, or merge run from another folder)");
  } else {
    fingerprinting.emplace([&] { fingerprint = verify_fingerprint(setup, scene, plans); });
  }
  info.load_seconds = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  log << "plancheck: building collision structures\n";
  const Checker checker(scene, info.threads, &ahead);
  ahead.finish();  // the checker shares what it took; the rest (pruned parts) is not kept
  if (fingerprinting) fingerprinting->wait();
  info.build_seconds = seconds_since(t0);
  info.left_out_static_triangles = checker.left_out_static_triangles();

  std::size_t states = 0;
  for (const Plan& p : plans) states += p.states.size();

  // Work items: one per plan, weighed by its states. With --dig-carry a
  // plan starts on the terrain the previous ones dug: one item holds them all.
  std::vector<std::uint64_t> weights;
  if (args.dig_carry)
    weights.push_back(states);
  else
    for (const Plan& p : plans) weights.push_back(p.states.size());
  auto item_plans = [&](std::size_t item) -> std::pair<std::size_t, std::size_t> {
    return args.dig_carry ? std::pair<std::size_t, std::size_t>{0, plans.size()} : std::pair{item, item + 1};
  };

  // Every result goes through its bytes (result_blob.h), in a single run
  // too: the files of a run, a merge and an MPI run come from the same bytes.
  std::vector<PlanResult> results;
  results.reserve(plans.size());
  const ConsumeItem consume = [&](std::size_t item, std::string_view blob) {
    if (results.size() != item_plans(item).first) throw std::logic_error("verify: results out of order");
    try {
      read_plan_results(blob, plans, results);
    } catch (const std::runtime_error& e) {
      throw InputError("verify: item " + std::to_string(item) + ": " + e.what());
    }
  };

  t0 = std::chrono::steady_clock::now();
  DistResult dist;
  if (merge) {
    log << "plancheck: merging " << merge->parts.size() << " partial results of " << plans.size() << " plans\n";
    read_partials(*merge, consume);
  } else {
    DistOptions dist_options;
    dist_options.command = "verify";
    dist_options.fingerprint = fingerprint;
    dist_options.setup = setup;
    dist_options.out = args.out;
    dist_options.shard = args.shard;
    dist_options.resume = args.resume;
    dist_options.log = &log;
    log << "plancheck: checking " << states << " states of " << plans.size() << " plans on " << info.threads
        << " threads" << (mpi ? " per rank, " + std::to_string(mpi_size()) + " MPI ranks" : std::string()) << "\n";
    Progress progress("verify", states, "states", ProgressOptions{.quiet = args.quiet || rank != 0}, &log);
    double continuous_seconds = 0.0;
    const ComputeItems compute = [&](std::size_t begin, std::size_t end) {
      // The items' plans are checked together (threads across them);
      // results do not depend on which plans share a call.
      const std::size_t first = item_plans(begin).first, last = item_plans(end - 1).second;
      const std::vector<Plan> group(plans.begin() + static_cast<std::ptrdiff_t>(first),
                                    plans.begin() + static_cast<std::ptrdiff_t>(last));
      VerifyOptions verify_options;
      verify_options.threads = info.threads;
      verify_options.dig_carry = args.dig_carry;
      verify_options.progress = &progress;
      verify_options.verdict_only = args.verdict_only;
      // report.json lists the first kMaxCollisionStatesListed colliding
      // states of a plan; report.html all of them.
      if (!args.html) verify_options.listed_collisions = kMaxCollisionStatesListed;
      std::vector<PlanResult> group_results = verify_plans(checker, scene, group, verify_options);
      if (args.continuous) {
        const auto tc = std::chrono::steady_clock::now();
        verify_segments(checker, scene, group, group_results, options);
        continuous_seconds += seconds_since(tc);
      }
      std::vector<std::string> blobs(end - begin);
      if (args.dig_carry) {
        append_plan_results(group_results, blobs[0]);
      } else {
        for (std::size_t k = 0; k < group_results.size(); ++k) append_plan_results({group_results[k]}, blobs[k]);
      }
      return blobs;
    };
    if (args.continuous) log << "plancheck: and " << (states - plans.size()) << " segments between states\n";
    dist = run_items(dist_options, weights, compute, consume);
    progress.finish();
    info.continuous_seconds = continuous_seconds;
    if (dist.role == DistRole::kWorker) return 0;
    if (dist.role == DistRole::kShard) {
      log << "plancheck: wrote " << dist.partial.string() << " (shard " << args.shard->index << " of "
          << args.shard->count << ": " << (dist.chunks.empty() && dist.reused == 0 ? "no" : "its")
          << " items; plancheck merge joins the shards)\n";
      return 0;
    }
  }
  info.check_seconds = seconds_since(t0);
  if (results.size() != plans.size()) throw std::logic_error("verify: not every plan has its results");
  info.ranks = dist.ranks;
  info.hosts = dist.hosts;
  if (dist.ranks > 0)
    for (const ChunkTime& c : dist.chunks) info.chunks.push_back(ChunkSeconds{c.rank, c.begin, c.end, c.seconds});

  write_reports(checker, scene, results, info, args.out);
  if (args.html) {
    const auto th = std::chrono::steady_clock::now();
    write_report_html(checker, scene, results, args.out, ReportPageOptions{args.dig_carry, args.html_plans});
    log << "plancheck: wrote " << (args.out / "report.html").string() << " (" << seconds_since(th) << " s)\n";
  } else {
    std::filesystem::remove(args.out / "report.html", ec);  // not this run's
  }
  if (!merge) {
    DistOptions o;
    o.out = args.out;
    finish_items(o);  // the outputs are written: the journal goes
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

}  // namespace

int run_verify(const VerifyArgs& args, std::ostream& out, std::ostream& err) {
  return verify_run(args, out, err, nullptr);
}

int run_merge(const MergeArgs& args, std::ostream& out, std::ostream& err) {
  if (args.parts.empty()) throw InputError("merge: no folder of partial results given");
  const PartialSet set = open_partials(args.parts);
  if (set.first().command == "verify") {
    VerifyArgs verify = verify_args_from_setup(set.first().setup, set.first().file);
    verify.out = args.out;
    verify.threads = args.threads;
    verify.quiet = args.quiet;
    return verify_run(verify, out, err, &set);
  }
  if (set.first().command == "sweep") {
    SweepArgs sweep;
    sweep.out = args.out;
    sweep.threads = args.threads;
    sweep.quiet = args.quiet;
    return run_sweep_merge(set, sweep, out, err);
  }
  fail(set.first().file, "merge: partial results of `" + set.first().command + "`, which this plancheck cannot merge");
}

}  // namespace plancheck
