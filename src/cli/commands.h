// SPDX-License-Identifier: MIT
// The bodies of the command-line subcommands; main.cpp only parses words.
#pragma once

#include "src/cli/distribute.h"
#include "src/output/report_html.h"
#include "src/scene/scene_loader.h"

#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace plancheck {

struct VerifyArgs {
  std::filesystem::path scene;
  SceneOptions scene_options;  // --srdf, --package
  std::vector<std::filesystem::path> plans;
  std::filesystem::path out = "plancheck-out";
  int threads = 0;           // 0: all hardware threads
  bool json = false;         // stdout: report.json instead of the plan lines
  bool dig_carry = false;    // the terrain dug by one plan is the next plan's start
  bool continuous = false;   // also certify the motion between consecutive states (src/checks/continuous.h)
  double continuous_tolerance = 0.0;  // clearance witness tolerance, scene length_unit; 0: the default
  bool html = false;         // also DIR/report.html (src/output/report_html.h)
  HtmlPlanChoice html_plans; // --html-plans: the plans report.html details besides the violating ones
  bool quiet = false;        // no progress on stderr
  bool verdict_only = false; // each state's verdict and first pair at fault; distances exact only below the margin
  std::optional<Shard> shard;  // --shard I/N: this part of the plans, a partial result in DIR (distribute.h)
  bool resume = false;       // --resume: reuse what an interrupted run (or shard) left in DIR
};

struct MergeArgs {
  std::vector<std::filesystem::path> parts;  // folders holding part-I-of-N.plancheck files
  std::filesystem::path out = "plancheck-out";
  int threads = 0;           // 0: all hardware threads (merge builds the scene's structures again)
  bool quiet = false;
};

struct DigArgs {
  std::filesystem::path scene;
  SceneOptions scene_options;  // --srdf, --package
  std::filesystem::path plan;
  std::filesystem::path out = "plancheck-dig";
  bool quiet = false;        // no progress on stderr
};

// Exit status per the contract: 0 all plans safe, 1 any violation. Input
// errors are thrown as InputError (main turns them into status 2).
// With args.shard: writes the shard's partial result only (exit 0). Under
// mpirun: the ranks share the plans, rank 0 writes the outputs (the other
// ranks exit 0).
int run_verify(const VerifyArgs& args, std::ostream& out, std::ostream& err);

// plancheck merge DIR... --out DIR: the files, stdout and exit status of the
// single run whose shards the folders hold. Throws InputError when they are
// not all the shards of one run, each complete.
int run_merge(const MergeArgs& args, std::ostream& out, std::ostream& err);

// Digs one plan and writes DIR/before.asc, DIR/after.asc and DIR/dig.png
// (src/cli/dig_command.cpp).
int run_dig(const DigArgs& args, std::ostream& out, std::ostream& err);

}  // namespace plancheck
