// SPDX-License-Identifier: MIT
// The paper's Table 3 reproduced beside FCL (plancheck_bench table3 ...).
#pragma once

namespace plancheck::bench {

// argv[0] is "table3"; returns the process exit status (0 ok, 2 bad input,
// 3 when an answer check fails, so nothing is timed).
int run_table3(int argc, char** argv);

}  // namespace plancheck::bench
