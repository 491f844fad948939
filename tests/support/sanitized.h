// SPDX-License-Identifier: MIT
// Case counts for tests whose cost is their number of random cases.
// Release runs the full count. The sanitizer builds (ASan+UBSan, TSan) look
// for memory, undefined-behaviour and race errors along the same code paths,
// at 5-20x the time per case: they run a share of the cases, so `make test`
// stays inside CI's budget (issue 13) while every path is still walked.
#pragma once

namespace plancheck::testing {

#ifdef PLANCHECK_SANITIZED
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif

// `release` cases in Release, `sanitized` under the sanitizers.
constexpr int case_count(int release, int sanitized) { return kSanitized ? sanitized : release; }

}  // namespace plancheck::testing
