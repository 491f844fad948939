// SPDX-License-Identifier: MIT
// The one place that knows the threading library. Algorithms call these
// wrappers and never include TBB themselves.
#pragma once

#include <cstddef>
#include <exception>
#include <functional>
#include <thread>

namespace plancheck {

// Number of hardware threads available to this process.
int hardware_threads();

// Runs body(begin, end, slot) over [0, n) split into contiguous chunks of at
// most `grain` items, on at most `threads` threads (threads <= 0: all).
// `slot` is in [0, threads) and is unique among concurrently running calls, so
// a caller can keep per-thread scratch indexed by it without locks.
void parallel_for(std::size_t n, int threads, std::size_t grain,
                  const std::function<void(std::size_t begin, std::size_t end, int slot)>& body);

// Runs `work` on a thread of its own, beside the caller, from construction
// until wait(): for one long job that should start before the caller's own
// work (and its parallel_for loops) and be joined later. wait() joins and
// rethrows what `work` threw; the destructor joins too (dropping that), so
// what `work` reads must outlive this object.
class BesideJob {
 public:
  explicit BesideJob(std::function<void()> work);
  ~BesideJob();
  BesideJob(const BesideJob&) = delete;
  BesideJob& operator=(const BesideJob&) = delete;
  void wait();

 private:
  std::exception_ptr error_;
  std::thread thread_;  // after error_, which it writes
};

}  // namespace plancheck
