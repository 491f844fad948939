// SPDX-License-Identifier: MIT
// The plancheck command line (contract: shared/spec/plan-and-report-format.md).
// Bad input of any kind ends in one "plancheck: ..." line on stderr and exit 2.
#include "src/cli/bench_command.h"
#include "src/cli/commands.h"
#include "src/base/error.h"
#include "src/base/text.h"
#include "src/scene/scene_loader.h"
#include "src/output/scene_summary.h"
#include "src/cli/sweep.h"

#include <CLI/CLI.hpp>

#if defined(__GLIBC__)
#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>
#include <cstdint>
#include <cstdlib>
#endif

#include <charconv>
#include <cmath>
#include <exception>
#include <iostream>
#include <new>
#include <string>

namespace {

constexpr int kExitBadInput = 2;

#if defined(__GLIBC__)
// Memory for the run in 2 MiB pages where the kernel offers them. Loading
// and building the default scene touch ~120 MB of fresh heap, one page
// fault per 4 KiB page: 31,000-34,000 faults, and on a VM where a fault
// costs 11 us (measured on a 2-core AMD EPYC KVM guest, 2026-11-27) they
// were half of the load and a third of the CPU before the first answer.
// So: one arena for every thread (a worker thread's own arena is an mmap'd
// heap the advice below does not cover: with it, 17,000 faults were left),
// the heap grown once by kHeapReserve (address space only: nothing is
// touched or counted in RSS until used), that range advised
// MADV_HUGEPAGE, then the ordinary top pad again. Faults in it then come a
// 2 MiB page at a time. Where transparent huge pages are off the advice
// does nothing; where the heap cannot grow, malloc takes another mapping
// and nothing is advised. The checking itself allocates nothing per state
// (one arena costs it nothing measurable: the ten plans, a 25-step sweep).
// No answer depends on where memory comes from.
void reserve_heap() {
  constexpr std::size_t kHeapReserve = std::size_t{512} << 20;
  constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20;
  if (!getenv("XA")) mallopt(M_ARENA_MAX, 1);
  mallopt(M_TOP_PAD, static_cast<int>(kHeapReserve));
  void* block = std::malloc(std::size_t{1} << 20);  // under M_MMAP_THRESHOLD: from the heap, which grows
  const auto at = reinterpret_cast<std::uintptr_t>(block);
  const auto top = reinterpret_cast<std::uintptr_t>(sbrk(0));
  if (block != nullptr && at < top && top - at <= 2 * kHeapReserve) {
    const std::uintptr_t lo = (at + kHuge - 1) & ~(kHuge - 1), hi = top & ~(kHuge - 1);
    if (hi > lo) madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_HUGEPAGE);
  }
  std::free(block);
  mallopt(M_TOP_PAD, 128 * 1024);  // glibc's default
}
#endif

// Option values checked with messages a person reads (CLI11's own range
// check prints the largest double in full for an unbounded range).
constexpr int kMaxThreads = 4096;
const CLI::Validator kThreadCount(
    [](std::string& text) -> std::string {
      int v = -1;
      const auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
      if (ec != std::errc() || p != text.data() + text.size() || v < 0 || v > kMaxThreads)
        return "expected a whole number from 0 (all cores) to " + std::to_string(kMaxThreads) + ", not '" +
               plancheck::printable(text) + "'";
      return {};
    },
    "0..4096");
const CLI::Validator kFinitePositive(
    [](std::string& text) -> std::string {
      double v = 0;
      const auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
      if (ec != std::errc() || p != text.data() + text.size() || !std::isfinite(v) || !(v > 0))
        return "expected a finite number > 0, not '" + plancheck::printable(text) + "'";
      return {};
    },
    "> 0");

// `--srdf FILE` and `--package NAME=DIR` on every command that reads a scene
// (a bare .urdf is a scene too). Each --package takes one value, so options
// may stand before, between or after the positional arguments.
void add_robot_options(CLI::App* cmd, std::string& srdf, std::vector<std::string>& packages) {
  cmd->add_option("--srdf", srdf, "SRDF of a bare .urdf: its disable_collisions pairs are allowed");
  cmd->add_option("--package", packages, "NAME=DIR: where package://NAME/ meshes are (repeatable)")
      ->allow_extra_args(false);
}

plancheck::SceneOptions scene_options(const std::string& srdf, const std::vector<std::string>& packages) {
  plancheck::SceneOptions o;
  o.srdf = srdf;
  for (const std::string& p : packages) {
    const std::size_t eq = p.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == p.size())
      throw plancheck::InputError("--package " + p + ": expected NAME=DIR");
    o.packages[p.substr(0, eq)] = p.substr(eq + 1);
  }
  return o;
}

}  // namespace

int main(int argc, char** argv) {
#if defined(__GLIBC__)
  // A verify run allocates and frees many large blocks (the model, meshes,
  // boxes, trees) in a short time: glibc maps each block over 128 KiB anew
  // and hands it back when freed, and every fresh page costs a fault and a
  // clearing (about a tenth of the run's CPU time before the first answer).
  // Kept on the heap (up to 32 MiB per block) and not trimmed, freed memory
  // is reused instead. Set for this one-shot process only, here: verify_run
  // is also called in process (tests, the library), whose heap is theirs.
  // No answer depends on where memory comes from.
  mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
  mallopt(M_TRIM_THRESHOLD, 1024 * 1024 * 1024);
  reserve_heap();
#endif
  CLI::App app{"plancheck: verify robot-arm motion plans against a scene"};
  app.require_subcommand(1);
  app.footer("Exit status: 2 on bad input or any other error (one line on stderr naming the file and what is wrong);\n"
             "otherwise as each command's --help says. Docs: README.md and docs/ in the source tree.");
  app.set_version_flag("--version", std::string("plancheck ") + PLANCHECK_VERSION);  // project(VERSION), src/api/CMakeLists.txt

  std::string scene_file;
  std::string srdf;
  std::vector<std::string> packages;
  CLI::App* scene_cmd = app.add_subcommand("scene", "list parts, actions, checked pairs and reference contacts");
  scene_cmd->add_option("SCENE", scene_file, "scene file (plancheck-scene/1 JSON, or a robot alone: .urdf)")->required();
  add_robot_options(scene_cmd, srdf, packages);
  scene_cmd->footer("Exit status: 0 listed, 2 bad input.");

  plancheck::VerifyArgs verify;
  std::vector<std::string> plan_files;
  std::string out_dir = "plancheck-out";
  CLI::App* verify_cmd = app.add_subcommand("verify", "check every state of every plan; exit 0 all safe, 1 a violation");
  verify_cmd->add_option("SCENE", scene_file, "scene file (plancheck-scene/1 JSON, or a robot alone: .urdf)")->required();
  add_robot_options(verify_cmd, srdf, packages);
  verify_cmd->footer("Exit status: 0 every plan safe, 1 a violation in any plan, 2 bad input or any other error\n"
                     "(then no report.json is left). A shard (--shard) exits 0 once its partial result is written.");
  verify_cmd->add_option("PLAN", plan_files, "plan files (CSV)")->required();
  verify_cmd->add_option("--out", out_dir, "folder for report.json and one CSV per plan")->capture_default_str();
  verify_cmd->add_option("--threads", verify.threads, "worker threads (0: all cores)")->check(kThreadCount);
  verify_cmd->add_flag("--json", verify.json, "print report.json on stdout instead of the plan lines");
  CLI::Option* html_flag =
      verify_cmd->add_flag("--html", verify.html, "also write DIR/report.html: the plans replayed in 3D, one self-contained file");
  std::string html_plans;
  CLI::Option* html_plans_opt = verify_cmd->add_option("--html-plans", html_plans,
      "N|NAME,...: the plans whose every state report.html details besides the violating ones: the N closest to "
      "the margin (default 20), or those named")->needs(html_flag);
  verify_cmd->add_flag("--quiet", verify.quiet, "no progress or status lines on stderr");
  verify_cmd->add_flag("--verdict-only", verify.verdict_only,
                       "each state's verdict and first pair at fault only: the first contact, and exact distances only "
                       "below the margin (min_distance is otherwise a certified lower bound); verdicts as a full verify");
  verify_cmd->add_flag("--dig-carry", verify.dig_carry, "the terrain dug by one plan is where the next one starts");
  CLI::Option* continuous = verify_cmd->add_flag("--continuous", verify.continuous,
                       "also certify the motion between states (joints linear in driving parameters)");
  verify_cmd
      ->add_option("--continuous-tolerance", verify.continuous_tolerance,
                   "clearance witness tolerance between states, in the scene's length unit: at least 1e-8 m; "
                   "default 1e-5 m")
      ->check(kFinitePositive)
      ->needs(continuous);
  std::string verify_shard;
  CLI::Option* shard_opt = verify_cmd->add_option(
      "--shard", verify_shard, "I/N: check only the I-th (from 0) of N parts of the plans and write a partial result "
                               "to DIR; plancheck merge joins the N parts");
  verify_cmd->add_flag("--resume", verify.resume,
                       "reuse what an interrupted run (or shard) with the same --out left there; redo only the rest");

  plancheck::MergeArgs merge;
  std::vector<std::string> merge_parts;
  std::string merge_out = "plancheck-out";
  CLI::App* merge_cmd = app.add_subcommand(
      "merge", "join the partial results of verify or sweep --shard I/N (all N) into the files, lines and exit status of one run");
  merge_cmd->add_option("DIR", merge_parts, "folders holding part-I-of-N.plancheck files")->required();
  merge_cmd->add_option("--out", merge_out, "folder for the joined outputs")->capture_default_str();
  merge_cmd->add_option("--threads", merge.threads, "worker threads (0: all cores)")->check(kThreadCount);
  merge_cmd->add_flag("--quiet", merge.quiet, "no status lines on stderr");
  merge_cmd->footer("Exit status: as the single run of verify or sweep would (verify: 0 safe, 1 a violation), 2 bad input\n"
                    "(a shard missing, repeated, cut short or of another run).");

  plancheck::DigArgs dig;
  std::string dig_plan;
  std::string dig_out = "plancheck-dig";
  CLI::App* dig_cmd = app.add_subcommand("dig", "dig one plan; write the terrain before/after (ESRI ASCII) and a PNG map");
  dig_cmd->add_option("SCENE", scene_file, "scene file (plancheck-scene/1 JSON, or a robot alone: .urdf)")->required();
  add_robot_options(dig_cmd, srdf, packages);
  dig_cmd->footer("Exit status: 0 dug and written, 2 bad input (the scene needs a terrain and a scoop block).");
  dig_cmd->add_option("PLAN", dig_plan, "plan file (CSV)")->required();
  dig_cmd->add_flag("--quiet", dig.quiet, "no progress or status lines on stderr");
  dig_cmd->add_option("--out", dig_out, "folder for before.asc, after.asc and dig.png")->capture_default_str();

  plancheck::SweepArgs sweep;
  long sweep_steps = 0;
  std::string sweep_grid;
  std::string sweep_out = "plancheck-sweep";
  CLI::App* sweep_cmd = app.add_subcommand(
      "sweep", "check a grid of configurations: DIR/verdict.npy, DIR/distance.npy (NumPy), DIR/sweep.json summary");
  sweep_cmd->add_option("SCENE", scene_file, "scene file (plancheck-scene/1 JSON, or a robot alone: .urdf)")->required();
  add_robot_options(sweep_cmd, srdf, packages);
  sweep_cmd->footer("Exit status: 0 when it ran (a sweep maps the space, it judges no plan), 2 bad input or any other error.");
  CLI::Option* steps_opt = sweep_cmd->add_option(
      "--steps", sweep_steps, "values per driving parameter with limits, ends included (default 9)");
  CLI::Option* grid_opt = sweep_cmd->add_option(
      "--grid", sweep_grid, "NAME=FROM:TO:STEP,... in plan units; parameters not named keep their reference value");
  steps_opt->excludes(grid_opt);
  sweep_cmd->add_option("--out", sweep_out, "folder for the outputs")->capture_default_str();
  sweep_cmd->add_flag("--csv", sweep.csv, "also write DIR/sweep.csv, one row per configuration (each checked on its own)");
  sweep_cmd->add_flag("--exact-distance", sweep.exact_distance,
                      "check every configuration on its own: distance.npy exact everywhere (slower; --csv implies it)");
  sweep_cmd->add_flag("--html", sweep.html, "also write DIR/sweep.html: verdict heat maps, the arm, safe targets; one self-contained file");
  sweep_cmd->add_flag("--quiet", sweep.quiet, "no progress or status lines on stderr");
  sweep_cmd->add_option("--threads", sweep.threads, "worker threads (0: all cores)")->check(kThreadCount);
  std::string sweep_shard;
  CLI::Option* sweep_shard_opt = sweep_cmd->add_option(
      "--shard", sweep_shard, "I/N: check only the I-th (from 0) of N parts of the grid and write a partial result "
                              "to DIR; plancheck merge joins the N parts");
  sweep_cmd->add_flag("--resume", sweep.resume,
                      "reuse what an interrupted run (or shard) with the same --out left there; redo only the rest");

  CLI::App* bench_cmd = app.add_subcommand(
      "bench", "reproduce the paper's Table 3 beside FCL: SCENE [PLAN... | --random N [--seed S]] [--json FILE] [--fcl]; --two-mesh [--poses N] (runs plancheck_bench)");
  bench_cmd->allow_extras();
  bench_cmd->prefix_command();
  bench_cmd->footer(
      "Arguments go to plancheck_bench (built beside plancheck):\n"
      "  SCENE [PLAN.csv...]     the plans (default: the scene folder's plans/*.csv)\n"
      "  --random N [--seed S]   N cold configurations drawn within the limits instead of plans\n"
      "  --fcl                   time FCL 0.7 on the same states, answers checked against it first\n"
      "  --repetitions N         timed repetitions of plancheck (median; default 5)\n"
      "  --fcl-repetitions N     timed repetitions of FCL (median; default 1)\n"
      "  --tolerances R,...      relative distance tolerances of the error table\n"
      "  --json FILE             also write the tables as JSON\n"
      "  --two-mesh [--poses N] [--seed S] [--json FILE]   one mesh at random poses over another\n"
      "Exit status: 0 answers agreed and timed, 2 bad input or no plancheck_bench, 3 answers that disagree (nothing timed).");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help and the like
    std::cerr << "plancheck: " << plancheck::printable(e.what()) << " (run plancheck --help)\n";
    return kExitBadInput;
  }

  // --quiet: status and progress go nowhere (errors still reach std::cerr).
  std::ostream quiet_err(nullptr);
  try {
    if (scene_cmd->parsed()) {
      const plancheck::Scene scene = plancheck::load_scene(scene_file, scene_options(srdf, packages));
      plancheck::print_scene_summary(scene, std::cout);
    } else if (verify_cmd->parsed()) {
      verify.scene = scene_file;
      verify.scene_options = scene_options(srdf, packages);
      verify.plans.assign(plan_files.begin(), plan_files.end());
      verify.out = out_dir;
      if (*shard_opt) verify.shard = plancheck::parse_shard(verify_shard);
      if (*html_plans_opt) verify.html_plans = plancheck::parse_html_plans(html_plans);
      return plancheck::run_verify(verify, std::cout, verify.quiet ? quiet_err : std::cerr);
    } else if (merge_cmd->parsed()) {
      merge.parts.assign(merge_parts.begin(), merge_parts.end());
      merge.out = merge_out;
      return plancheck::run_merge(merge, std::cout, merge.quiet ? quiet_err : std::cerr);
    } else if (dig_cmd->parsed()) {
      dig.scene = scene_file;
      dig.scene_options = scene_options(srdf, packages);
      dig.plan = dig_plan;
      dig.out = dig_out;
      return plancheck::run_dig(dig, std::cout, dig.quiet ? quiet_err : std::cerr);
    } else if (sweep_cmd->parsed()) {
      sweep.scene = scene_file;
      sweep.scene_options = scene_options(srdf, packages);
      if (*steps_opt) sweep.steps = sweep_steps;
      if (*grid_opt) sweep.grid = sweep_grid;
      sweep.out = sweep_out;
      if (*sweep_shard_opt) sweep.shard = plancheck::parse_shard(sweep_shard);
      return plancheck::run_sweep(sweep, std::cout, sweep.quiet ? quiet_err : std::cerr);
    } else if (bench_cmd->parsed()) {
      return plancheck::run_bench(bench_cmd->remaining(), std::cerr);
    }
  } catch (const plancheck::InputError& e) {
    // One line, whatever names the message quotes (text.h).
    std::cerr << "plancheck: " << plancheck::printable(e.what()) << "\n";
    return kExitBadInput;
  } catch (const std::bad_alloc&) {
    // The loaders name their file (load_scene, load_plan); what is left is the run's.
    std::cerr << "plancheck: " << plancheck::printable(scene_file.empty() ? std::string("the run") : scene_file)
              << ": out of memory (the inputs need more than this machine has)\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "plancheck: error: " << plancheck::printable(e.what()) << "\n";
    return kExitBadInput;
  }
  return 0;
}
