// SPDX-License-Identifier: MIT
#include "src/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <map>
#include <memory>
#include <mutex>

namespace plancheck {

int hardware_threads() { return std::max(1, tbb::info::default_concurrency()); }

namespace {

// One arena per thread count, made on first use and kept for the process:
// an arena made per call paid its set-up and the workers' first wake-up on
// every call, which showed on single-plan runs of a few milliseconds.
// Several threads may execute in one arena at once; TBB gives each a
// distinct slot, which is what `slot` promises.
tbb::task_arena& arena_for(int threads) {
  static std::mutex mutex;
  static std::map<int, std::unique_ptr<tbb::task_arena>> arenas;
  const std::lock_guard<std::mutex> lock(mutex);
  auto& arena = arenas[threads];
  if (!arena) {
    arena = std::make_unique<tbb::task_arena>(threads);
    arena->initialize();
  }
  return *arena;
}

}  // namespace

void parallel_for(std::size_t n, int threads, std::size_t grain,
                  const std::function<void(std::size_t, std::size_t, int)>& body) {
  if (n == 0) return;
  if (threads <= 0) threads = hardware_threads();
  grain = std::max<std::size_t>(1, grain);
  if (threads == 1 || n <= grain) {
    body(0, n, 0);
    return;
  }
  // Isolated: a thread waiting inside this loop takes only this loop's
  // chunks. In a shared arena it could otherwise steal a chunk of an outer
  // loop whose body it is already running, on the same slot, and a caller's
  // per-slot scratch would be used twice at once.
  arena_for(threads).execute([&] {
    tbb::this_task_arena::isolate([&] {
      tbb::parallel_for(
          tbb::blocked_range<std::size_t>(0, n, grain),
          [&](const tbb::blocked_range<std::size_t>& r) {
            // The arena's slot index is unique among the threads working in it.
            const int slot = tbb::this_task_arena::current_thread_index();
            body(r.begin(), r.end(), slot);
          },
          tbb::simple_partitioner());
    });
  });
}

}  // namespace plancheck
