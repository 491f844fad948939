// SPDX-License-Identifier: MIT
// DIR/report.html (verify --html): the scene's geometry once, then per plan
// and state only what changes (one transform per action chain, distances,
// closest points, contacts, the terrain dug, probe readings), beside the
// report.json just written, which the page shows as it is.
#pragma once

#include "src/output/report.h"
#include "src/checks/verify.h"

#include <filesystem>
#include <vector>

namespace plancheck {

struct ReportPageOptions {
  bool dig_carry = false;  // as verify ran: plans dig from where the previous one left the terrain
};

// Writes dir/report.html; dir/report.json must exist (write_reports).
void write_report_html(const Checker& checker, const Scene& scene, const std::vector<PlanResult>& results,
                       const std::filesystem::path& dir, const ReportPageOptions& options = {});

}  // namespace plancheck
