// SPDX-License-Identifier: MIT
// `plancheck sweep`: the configuration space of a scene, checked on a grid.
// Every configuration of the grid gets the verdict of `verify`'s state check
// (collision, minimum distance against the margin, limits), certified in
// blocks (src/checks/sweep_certify.h) or, with --exact-distance or --csv,
// checked on its own; so the safe set it reports is the set of states
// `verify` would call safe.
#pragma once

#include "src/checks/sweep_grid.h"
#include "src/cli/distribute.h"
#include "src/scene/scene_loader.h"

#include <cstddef>
#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace plancheck {

struct SweepArgs {
  std::filesystem::path scene;
  SceneOptions scene_options;        // --srdf, --package
  std::optional<long> steps;         // --steps N
  bool quiet = false;                // no progress on stderr
  bool html = false;                 // also DIR/sweep.html (src/output/sweep_html.h)
  bool csv = false;                  // also DIR/sweep.csv (one row per configuration)
  bool exact_distance = false;       // --exact-distance: every configuration checked on its own (distance.npy exact everywhere)
  std::optional<std::string> grid;   // --grid SPEC
  std::filesystem::path out = "plancheck-sweep";
  int threads = 0;                   // 0: all hardware threads
  std::optional<Shard> shard;        // --shard I/N: a partial result in DIR (src/cli/distribute.h)
  bool resume = false;               // --resume: reuse DIR's journal (or partial result)
};

// Writes DIR/verdict.npy and DIR/distance.npy (the grid's shape), DIR/sweep.json
// (the summary) and with --csv DIR/sweep.csv (one row per configuration),
// prints the summary; returns 0. Input errors throw InputError.
int run_sweep(const SweepArgs& args, std::ostream& out, std::ostream& err);

// plancheck merge of sweep's partial results (open_partials): the run set up
// again from their setup, with options' out, threads and quiet; the files,
// stdout and status of the single run.
int run_sweep_merge(const PartialSet& set, const SweepArgs& options, std::ostream& out, std::ostream& err);

}  // namespace plancheck
