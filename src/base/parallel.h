// SPDX-License-Identifier: MIT
// The one place that knows the threading library. Algorithms call these
// wrappers and never include TBB themselves.
#pragma once

#include <cstddef>
#include <functional>

namespace plancheck {

// Number of hardware threads available to this process.
int hardware_threads();

// Runs body(begin, end, slot) over [0, n) split into contiguous chunks of at
// most `grain` items, on at most `threads` threads (threads <= 0: all).
// `slot` is in [0, threads) and is unique among concurrently running calls, so
// a caller can keep per-thread scratch indexed by it without locks.
void parallel_for(std::size_t n, int threads, std::size_t grain,
                  const std::function<void(std::size_t begin, std::size_t end, int slot)>& body);

}  // namespace plancheck
