// SPDX-License-Identifier: MIT
// The order in which a state's distance search visits its part pairs:
// by their lower bounds, exactly as std::sort orders them, from the
// previous state's order where that is cheaper (check_pairs, verify.cpp).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace plancheck {

// Sorts `order` (indices into `key`) by key ascending, the result equal to
// std::sort(order, key[x] < key[y]) on the same input. Among equal keys
// that order depends on std::sort's algorithm and on the input's
// arrangement (it decides which of equally close pairs a state reports),
// so std::sort itself runs whenever two keys are equal or one is NaN.
// Otherwise the ascending order is unique and any sort finds it: an
// insertion sort starting from `last` (the order this sorted before; the
// keys of consecutive states of a plan move little, so it is nearly
// sorted), given up for std::sort after a few shifts per element. `last`
// becomes the result; `in` and `work` are scratch. (std::sort of the ~140
// pairs of the default scene was 4% of a plan's check.)
inline void sort_by_key(std::vector<std::size_t>& order, const std::vector<double>& key, std::vector<std::size_t>& last,
                        std::vector<std::uint8_t>& in, std::vector<std::size_t>& work) {
  const auto by_key = [&](std::size_t x, std::size_t y) { return key[x] < key[y]; };
  in.assign(key.size(), 0);
  for (std::size_t k : order) in[k] = 1;
  work.clear();
  for (std::size_t k : last)
    if (k < in.size() && in[k] == 1) {
      work.push_back(k);
      in[k] = 2;
    }
  for (std::size_t k : order)
    if (in[k] == 1) work.push_back(k);
  // Insertion sort, counting the shifts; then whether the keys strictly
  // increase (false for equal keys and for any NaN).
  const std::size_t n = work.size(), budget = 4 * n + 16;
  std::size_t shifts = 0;
  bool unique = true;
  for (std::size_t i = 1; i < n && unique; ++i) {
    const std::size_t x = work[i];
    std::size_t j = i;
    while (j > 0 && by_key(x, work[j - 1])) {
      work[j] = work[j - 1];
      --j;
      if (++shifts > budget) unique = false;
    }
    work[j] = x;
  }
  for (std::size_t i = 1; i < n && unique; ++i) unique = by_key(work[i - 1], work[i]);
  if (unique && n > 0) unique = key[work[0]] == key[work[0]];  // a lone NaN
  if (unique)
    order.swap(work);
  else
    std::sort(order.begin(), order.end(), by_key);
  last.assign(order.begin(), order.end());
}

}  // namespace plancheck
