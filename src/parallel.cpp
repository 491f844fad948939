// SPDX-License-Identifier: MIT
#include "src/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>

namespace plancheck {

int hardware_threads() { return std::max(1, tbb::info::default_concurrency()); }

void parallel_for(std::size_t n, int threads, std::size_t grain,
                  const std::function<void(std::size_t, std::size_t, int)>& body) {
  if (n == 0) return;
  if (threads <= 0) threads = hardware_threads();
  grain = std::max<std::size_t>(1, grain);
  if (threads == 1 || n <= grain) {
    body(0, n, 0);
    return;
  }
  tbb::task_arena arena(threads);
  arena.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, n, grain),
        [&](const tbb::blocked_range<std::size_t>& r) {
          // The arena's slot index is unique among the threads working in it.
          const int slot = tbb::this_task_arena::current_thread_index();
          body(r.begin(), r.end(), slot);
        },
        tbb::simple_partitioner());
  });
}

}  // namespace plancheck
