// SPDX-License-Identifier: MIT
// sort_by_key (the order of a state's distance search, check_pairs) against
// std::sort itself: the same permutation on every input, from any previous
// order: distinct keys drifting from state to state as a plan's bounds do,
// keys jumping (a new run), equal keys (where only std::sort's own
// arrangement is the answer), NaN and infinities, subsets of the pairs,
// and previous orders naming pairs that no longer exist.
#include "src/checks/pair_order.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace plancheck {
namespace {

TEST(PairOrder, SortByKeyIsStdSort) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<std::size_t> last, work;
  std::vector<std::uint8_t> in;
  int fast = 0, equal_keys = 0, rounds = 0;
  for (int plan = 0; plan < 60; ++plan) {
    const std::size_t n = 1 + static_cast<std::size_t>(u(rng) * 180.0);
    std::vector<double> key(n);
    for (double& k : key) k = u(rng);
    if (plan % 7 == 3) last = {n + 5, 0, n + 100};  // another scene's pairs
    for (int state = 0; state < 40; ++state, ++rounds) {
      SCOPED_TRACE("plan " + std::to_string(plan) + " state " + std::to_string(state));
      // Bounds drift a little; now and then a jump, equal keys or NaN.
      for (double& k : key) k += 0.01 * (u(rng) - 0.5);
      if (state % 13 == 5)
        for (double& k : key) k = u(rng);
      const int kind = (plan + state) % 9;
      if (kind == 1) key[static_cast<std::size_t>(u(rng) * n)] = key[static_cast<std::size_t>(u(rng) * n)];
      if (kind == 2)  // many equal keys: pairs with the same bound (0 or infinite)
        for (std::size_t k = 0; k < n; k += 3) key[k] = plan % 2 ? 0.0 : std::numeric_limits<double>::infinity();
      if (kind == 3) key[static_cast<std::size_t>(u(rng) * n)] = std::numeric_limits<double>::quiet_NaN();
      // A subset of the pairs, in index order as check_pairs lists them,
      // or shuffled.
      std::vector<std::size_t> order;
      for (std::size_t k = 0; k < n; ++k)
        if (u(rng) < 0.9) order.push_back(k);
      if (kind == 4) std::shuffle(order.begin(), order.end(), rng);
      std::vector<std::size_t> want = order;
      std::sort(want.begin(), want.end(), [&](std::size_t x, std::size_t y) { return key[x] < key[y]; });
      std::vector<std::size_t> got = order;
      sort_by_key(got, key, last, in, work);
      ASSERT_EQ(got, want);
      ASSERT_EQ(last, want);
      bool distinct = true;
      for (std::size_t i = 1; i < want.size(); ++i) distinct = distinct && key[want[i - 1]] < key[want[i]];
      fast += distinct;
      equal_keys += !distinct;
      // Restore the NaN / equal keys for the next state's drift.
      for (double& k : key)
        if (!std::isfinite(k) || k == 0.0) k = u(rng);
    }
  }
  // Both paths taken, for the comparison to mean something.
  EXPECT_GT(fast, rounds / 2);
  EXPECT_GT(equal_keys, rounds / 10);
}

}  // namespace
}  // namespace plancheck
