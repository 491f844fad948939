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

// Runs job(0), job(1), ..., job(jobs - 1), each once, taken in that order
// by `threads` threads (the caller and threads - 1 of their own; threads <=
// 0: all) as they come free: for a few long, unequal jobs, the longest
// first, some of which run their own parallel work (a library's) or wait
// for another job. A thread out of jobs blocks until the rest are done
// (never spins, leaving the cores to the jobs still running). The first
// exception thrown is rethrown once every thread is done; a thread whose
// job threw takes no more jobs.
void run_queue(std::size_t jobs, int threads, const std::function<void(std::size_t job)>& job);

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
