// SPDX-License-Identifier: MIT
// Plan results as bytes and back, bit for bit: what a verify shard, an MPI
// rank or a resumable run's journal carries (src/cli/distribute.h), so that
// the reports written from the bytes are those of a single run. Every
// verify run goes through these bytes (src/cli/commands.cpp), so a field
// left out here would change every report, not only merged ones.
#pragma once

#include "src/checks/verify.h"

#include <string>
#include <string_view>
#include <vector>

namespace plancheck {

// The results of consecutive plans, appended to `out` (little-endian
// fixed-width fields, doubles as their bits). PlanResult::plan is not
// written: the reader points it at the plan list it is given.
void append_plan_results(const std::vector<PlanResult>& results, std::string& out);

// Reads what append_plan_results wrote and appends the results to `out`,
// pointing each at plans[out.size()] before it is appended. Throws
// std::runtime_error on bytes that are cut short, too long or not of this
// layout, or when there are more results than plans.
void read_plan_results(std::string_view bytes, const std::vector<Plan>& plans, std::vector<PlanResult>& out);

}  // namespace plancheck
