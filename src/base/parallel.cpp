// SPDX-License-Identifier: MIT
#include "src/base/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace plancheck {

int hardware_threads() { return std::max(1, tbb::info::default_concurrency()); }

#if defined(PLANCHECK_TSAN)
// ThreadSanitizer sees only synchronisation done in instrumented code or in
// the pthread calls it intercepts. TBB's scheduler is an uninstrumented system
// library, so every result a TBB worker hands back to the caller would be
// reported as a race. The TSan build runs the same chunks on std::threads
// instead (started and joined: synchronisation TSan sees), with the same
// contract (chunks of at most `grain`, a unique slot per thread, the first
// exception rethrown), so what it reports are races in the bodies: ours.
void parallel_for(std::size_t n, int threads, std::size_t grain,
                  const std::function<void(std::size_t, std::size_t, int)>& body) {
  if (n == 0) return;
  if (threads <= 0) threads = hardware_threads();
  grain = std::max<std::size_t>(1, grain);
  if (threads == 1 || n <= grain) {
    body(0, n, 0);
    return;
  }
  const std::size_t chunks = (n + grain - 1) / grain;
  const int workers = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(threads), chunks));
  std::atomic<std::size_t> next{0};
  std::mutex error_mutex;
  std::exception_ptr error;
  auto run = [&](int slot) {
    for (std::size_t c; (c = next.fetch_add(1)) < chunks;) {
      try {
        body(c * grain, std::min(n, (c + 1) * grain), slot);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (int slot = 1; slot < workers; ++slot) pool.emplace_back(run, slot);
  run(0);
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}
#else
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

#endif

void run_queue(std::size_t jobs, int threads, const std::function<void(std::size_t job)>& job) {
  if (threads <= 0) threads = hardware_threads();
  std::atomic<std::size_t> next{0};
  const auto drain = [&] {
    for (std::size_t j; (j = next.fetch_add(1)) < jobs;) job(j);
  };
  std::vector<std::unique_ptr<BesideJob>> helpers;
  const std::size_t more = std::min<std::size_t>(static_cast<std::size_t>(threads - 1), jobs > 0 ? jobs - 1 : 0);
  for (std::size_t t = 0; t < more; ++t) helpers.push_back(std::make_unique<BesideJob>(drain));
  std::exception_ptr error;
  try {
    drain();
  } catch (...) {
    error = std::current_exception();
  }
  for (auto& h : helpers) {
    try {
      h->wait();
    } catch (...) {
      if (!error) error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
}

BesideJob::BesideJob(std::function<void()> work)
    : thread_([this, work = std::move(work)] {
        try {
          work();
        } catch (...) {
          error_ = std::current_exception();
        }
      }) {}

BesideJob::~BesideJob() {
  if (thread_.joinable()) thread_.join();
}

void BesideJob::wait() {
  if (thread_.joinable()) thread_.join();
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
}

}  // namespace plancheck
