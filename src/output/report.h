// SPDX-License-Identifier: MIT
// Verification results -> stdout lines, DIR/report.json, DIR/<plan>.csv
// (contract: docs/formats.md "Reports"). Lengths are written in the scene's length_unit.
#pragma once

#include "src/checks/verify.h"

#include <filesystem>
#include <iosfwd>
#include <string>
#include <string_view>
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

// A text field of a CSV as RFC 4180 writes it: in double quotes (a quote
// doubled) when it holds a comma, a quote, a line break or blanks at its
// ends; as it is otherwise. Names are the ones that need it.
std::string csv_field(std::string_view text);

// The file name of a plan's CSV in DIR, from its name: the name itself where
// it is a plain file name; otherwise every '/' and '\\' becomes '_' and a
// leading '.' too (no folder is ever named, no hidden file, no "..").
// Names are checked text already (plan.cpp: UTF-8, no control characters,
// at most kMaxPlanNameBytes), so the result is a short, plain file name.
std::string plan_csv_name(std::string_view plan_name);

// Throws InputError, naming both plan files, when two plans would write the
// same DIR/<name>.csv: called before anything is checked.
void check_plan_csv_names(const std::vector<Plan>& plans);

// One line per plan, then a summary line.
void print_plan_lines(const Checker& checker, const Scene& scene, const std::vector<PlanResult>& results,
                      const RunInfo& info, std::ostream& out);

// Writes `text` to a fresh temporary beside PATH and renames it into place
// (files.h: never through a link), so a reader never sees a half-written
// file. Throws InputError naming the file.
void write_atomically(const std::filesystem::path& path, const std::string& text);

// Writes DIR/<plan>.csv for every plan and DIR/report.json last, each through
// a temporary file renamed into place, so a report that exists is complete.
void write_reports(const Checker& checker, const Scene& scene, const std::vector<PlanResult>& results,
                   const RunInfo& info, const std::filesystem::path& dir);

}  // namespace plancheck
