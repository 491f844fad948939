// SPDX-License-Identifier: MIT
// DIR/report.html (verify --html): the scene's geometry and kinematics once,
// report.json as it is, then per plan what its review needs. Every plan
// carries its parameters per state (posed in the page by the scene's
// kinematics, src/viewer/kinematics.js, checked there against the checker's
// transforms the page carries at some states), its distance and verdict per
// state; the plans with detail (every violating plan, the safe plans closest
// to the margin, any plan asked for) also carry the closest points, the
// pair, the contacts, probe readings, segments and the terrain dug. The page
// is streamed out plan by plan: its data is never whole in memory.
#pragma once

#include "src/output/report.h"
#include "src/checks/verify.h"

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace plancheck {

// --html-plans N|NAME,...: which plans carry per-state detail besides the
// violating ones (which always do): the `closest` plans nearest the margin
// among the others, or the plans named.
struct HtmlPlanChoice {
  // 2,000 candidates with a third violating give a page under 40 MB
  // (docs/visual-review-scaling.md); ten plans all carry detail.
  static constexpr std::size_t kDefaultClosest = 20;
  std::size_t closest = kDefaultClosest;
  std::vector<std::string> names;  // when not empty: these, not the closest
};

// Parses --html-plans' value: a whole number, or plan names separated by
// commas. Throws InputError on an empty value or an empty name.
HtmlPlanChoice parse_html_plans(std::string_view text);

// Throws InputError naming a plan name of `choice` that no plan has.
void check_html_plans(const HtmlPlanChoice& choice, const std::vector<Plan>& plans);

// Per plan, whether it carries detail: violating, chosen by name, or among
// the `closest` others with the smallest minimum distance (ties: plan order).
std::vector<bool> html_detail_plans(const std::vector<PlanResult>& results, const HtmlPlanChoice& choice);

struct ReportPageOptions {
  bool dig_carry = false;  // as verify ran: plans dig from where the previous one left the terrain
  HtmlPlanChoice plans;
};

// Writes dir/report.html; dir/report.json must exist (write_reports).
void write_report_html(const Checker& checker, const Scene& scene, const std::vector<PlanResult>& results,
                       const std::filesystem::path& dir, const ReportPageOptions& options = {});

}  // namespace plancheck
