// SPDX-License-Identifier: MIT
// Verification results -> stdout lines, DIR/report.json, DIR/<plan>.csv
// (contract: README "Reports"). Lengths are written in the scene's length_unit.
#pragma once

#include "src/checks/verify.h"

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace plancheck {

// One chunk of work an MPI run handed out (report.json "seconds"."chunks").
struct ChunkSeconds {
  int rank = 0;
  std::size_t begin = 0, end = 0;  // work items [begin, end): verify's plans
  double seconds = 0.0;            // compute time on that rank
};

struct RunInfo {
  std::filesystem::path scene_arg;  // the scene path as given on the command line
  int threads = 1;
  std::size_t left_out_static_triangles = 0;
  double load_seconds = 0.0;
  double build_seconds = 0.0;
  double check_seconds = 0.0;
  double continuous_tolerance = 0.0;  // m; 0: --continuous was not asked for
  double contact_tolerance = 0.0;     // m
  double continuous_seconds = 0.0;    // part of check_seconds spent between states
  bool verdict_only = false;          // verify --verdict-only: distances may be lower bounds, a verdict column
  int ranks = 0;                      // MPI ranks (0: no MPI; report.json "ranks" only under MPI)
  std::vector<std::string> hosts;     // MPI: the ranks' hosts, each once
  std::vector<ChunkSeconds> chunks;   // MPI: per chunk, who computed it and how long
};

// A number as the CSVs print it: 12 significant digits ("" when not finite).
std::string csv_number(double v);

// One line per plan, then a summary line.
void print_plan_lines(const Checker& checker, const Scene& scene, const std::vector<PlanResult>& results,
                      const RunInfo& info, std::ostream& out);

// Writes `text` to PATH.tmp and renames it into place, so a reader never sees
// a half-written file. Throws InputError naming the file.
void write_atomically(const std::filesystem::path& path, const std::string& text);

// Writes DIR/<plan>.csv for every plan and DIR/report.json last, each through
// a temporary file renamed into place, so a report that exists is complete.
void write_reports(const Checker& checker, const Scene& scene, const std::vector<PlanResult>& results,
                   const RunInfo& info, const std::filesystem::path& dir);

}  // namespace plancheck
