// SPDX-License-Identifier: MIT
// The slow reference for verify --continuous: exact checks at n + 1 evenly
// spaced configurations of a segment (linear in the written values, as the
// contract's motion), with a rigorous lower bound on the true minimum from
// the samples and the motion bound between neighbours.
#pragma once

#include "src/checks/continuous.h"
#include "src/scene/plan.h"
#include "src/checks/verify.h"

#include <algorithm>
#include <limits>
#include <vector>

namespace plancheck::testing {

struct Dense {
  bool collision = false;                                     // some sample intersects
  double min_sampled = std::numeric_limits<double>::infinity();  // least sampled distance (0 on contact)
  double lower = std::numeric_limits<double>::infinity();        // proven lower bound on the true minimum
  double max_step_bound = 0.0;  // the largest motion bound between two neighbouring samples
};

inline Dense dense(const Checker& checker, const SegmentChecker& seg, const std::vector<double>& qa,
                   const std::vector<double>& qb, long n) {
  Dense out;
  std::vector<double> q, prev_q;
  double prev_d = 0.0;
  StateResult r;
  for (long j = 0; j <= n; ++j) {
    state_between(qa, qb, static_cast<double>(j) / static_cast<double>(n), q);
    checker.check_state(q, r);
    const double d = r.collision ? 0.0 : r.min_distance;
    out.collision |= r.collision;
    out.min_sampled = std::min(out.min_sampled, d);
    if (j > 0) {
      const double b = seg.pair_bound(prev_q, q);
      out.max_step_bound = std::max(out.max_step_bound, b);
      out.lower = std::min(out.lower, std::min({prev_d, d, 0.5 * (prev_d + d - b)}));
    }
    prev_q = q;
    prev_d = d;
  }
  return out;
}

}  // namespace plancheck::testing
