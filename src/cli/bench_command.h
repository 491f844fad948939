// SPDX-License-Identifier: MIT
// `plancheck bench ...`: the Table 3 reproduction lives in the separate
// plancheck_bench executable (it links FCL, which plancheck itself must not),
// so this command runs that executable from the same folder.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

namespace plancheck {

// args: everything after "bench" (SCENE [PLAN...] [--json FILE] [--fcl] ...).
// Replaces the process with plancheck_bench when it is found beside argv0's
// executable; otherwise prints how to build and run it and returns 2.
int run_bench(const std::vector<std::string>& args, std::ostream& err);

}  // namespace plancheck
