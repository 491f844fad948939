// SPDX-License-Identifier: MIT
// src/base/parallel.h: every item runs once, and a slot is never used by two
// bodies of one call at the same time, also when calls nest (callers index
// per-thread scratch by slot without locks).
#include "src/base/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <stdexcept>
#include <thread>
#include <vector>

namespace plancheck {
namespace {

// Marks a slot busy for the length of a body; a second body on the same
// slot of the same call while the first is running is counted.
struct SlotGuard {
  explicit SlotGuard(int threads) : busy(static_cast<std::size_t>(threads)) {}
  std::vector<std::atomic<int>> busy;
  std::atomic<int> clashes{0};
  std::atomic<int> out_of_range{0};
  void enter(int slot) {
    if (slot < 0 || static_cast<std::size_t>(slot) >= busy.size()) {
      ++out_of_range;
      return;
    }
    if (busy[static_cast<std::size_t>(slot)].exchange(1) != 0) ++clashes;
  }
  void leave(int slot) {
    if (slot >= 0 && static_cast<std::size_t>(slot) < busy.size()) busy[static_cast<std::size_t>(slot)].store(0);
  }
};

TEST(Parallel, EveryItemRunsOnce) {
  for (int threads : {1, 2, 4}) {
    std::vector<std::atomic<int>> hits(10007);
    parallel_for(hits.size(), threads, 3, [&](std::size_t b, std::size_t e, int) {
      for (std::size_t i = b; i < e; ++i) ++hits[i];
    });
    for (std::size_t i = 0; i < hits.size(); ++i) ASSERT_EQ(hits[i].load(), 1) << "item " << i << ", " << threads << " threads";
  }
}

TEST(Parallel, NestedCallsNeverShareASlotWithinACall) {
  // The inner loop has one slow chunk: the thread that finishes the fast
  // one waits, and a waiting thread looks for other work (without isolation
  // it could pick up a chunk of the outer loop it is already inside).
  constexpr int kThreads = 2;
  for (int round = 0; round < 10; ++round) {
    SlotGuard outer(kThreads);
    std::atomic<int> inner_items{0};
    parallel_for(32, kThreads, 1, [&](std::size_t b, std::size_t e, int slot) {
      outer.enter(slot);
      for (std::size_t i = b; i < e; ++i) {
        SlotGuard inner(kThreads);
        parallel_for(2, kThreads, 1, [&](std::size_t ib, std::size_t ie, int islot) {
          inner.enter(islot);
          if (ib == 1) std::this_thread::sleep_for(std::chrono::microseconds(300));
          inner_items += static_cast<int>(ie - ib);
          inner.leave(islot);
        });
        EXPECT_EQ(inner.clashes.load(), 0);
        EXPECT_EQ(inner.out_of_range.load(), 0);
      }
      outer.leave(slot);
    });
    ASSERT_EQ(outer.clashes.load(), 0) << "round " << round;
    ASSERT_EQ(outer.out_of_range.load(), 0);
    ASSERT_EQ(inner_items.load(), 32 * 2);
  }
}

TEST(Parallel, ConcurrentCallersGetDistinctSlots) {
  // Two threads of the caller's own run parallel loops at once (as two
  // verify calls in one process would); each call's slots stay distinct.
  std::atomic<int> clashes{0};
  auto run = [&] {
    for (int round = 0; round < 50; ++round) {
      SlotGuard g(2);
      parallel_for(100, 2, 1, [&](std::size_t, std::size_t, int slot) {
        g.enter(slot);
        volatile double x = 0;
        for (int k = 0; k < 1000; ++k) x = x + k;
        g.leave(slot);
      });
      clashes += g.clashes.load() + g.out_of_range.load();
    }
  };
  std::thread a(run), b(run);
  a.join();
  b.join();
  EXPECT_EQ(clashes.load(), 0);
}

// A BesideJob runs beside the caller, whose own parallel loops go on
// meanwhile; what the job wrote is the caller's after wait(), and what it
// threw is rethrown there; a job never waited for is joined on destruction.
TEST(Parallel, BesideJobRunsBesideTheCallersLoops) {
  std::vector<double> beside(5000, 0.0);
  std::vector<std::atomic<int>> hits(1000);
  BesideJob job([&] {
    for (std::size_t i = 0; i < beside.size(); ++i) beside[i] = 0.5 * static_cast<double>(i);
  });
  parallel_for(hits.size(), 2, 7, [&](std::size_t b, std::size_t e, int) {
    for (std::size_t i = b; i < e; ++i) ++hits[i];
  });
  job.wait();
  for (std::size_t i = 0; i < beside.size(); ++i) ASSERT_EQ(beside[i], 0.5 * static_cast<double>(i));
  for (const auto& h : hits) ASSERT_EQ(h.load(), 1);
  job.wait();  // a second wait returns at once

  BesideJob failing([] { throw std::runtime_error("beside"); });
  EXPECT_THROW(failing.wait(), std::runtime_error);

  std::atomic<bool> ran{false};
  {
    BesideJob dropped([&] {
      ran = true;
      throw std::runtime_error("dropped");
    });
  }
  EXPECT_TRUE(ran);
}

// run_queue: every job runs once, on at most `threads` threads at a time,
// also when the first (longest) job holds one thread throughout; a job's
// exception comes back after the other threads are done.
TEST(Parallel, RunQueueThreadsTakeEveryJobOnce) {
  for (int threads : {1, 2, 3}) {
    std::vector<std::atomic<int>> hits(200);
    std::atomic<int> running{0}, most{0};
    run_queue(hits.size(), threads, [&](std::size_t j) {
      const int now = ++running;
      for (int m = most.load(); now > m && !most.compare_exchange_weak(m, now);) {
      }
      if (j == 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
      ++hits[j];
      --running;
    });
    for (std::size_t i = 0; i < hits.size(); ++i) ASSERT_EQ(hits[i].load(), 1) << "job " << i << ", " << threads << " threads";
    EXPECT_LE(most.load(), threads);
  }
  std::atomic<int> ran{0};
  EXPECT_THROW(run_queue(50, 2,
                         [&](std::size_t j) {
                           ++ran;
                           if (j == 3) throw std::runtime_error("job 3");
                         }),
               std::runtime_error);
  EXPECT_GE(ran.load(), 4);
  run_queue(0, 2, [](std::size_t) { FAIL() << "no jobs"; });
}

}  // namespace
}  // namespace plancheck
