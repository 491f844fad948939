// SPDX-License-Identifier: MIT
// run_isolated: whatever the child does (returns, throws, crashes, hangs,
// exits, eats memory), the parent gets the result or one exception saying
// what happened, and the parent's own state is untouched by the child.
#include "src/scene/isolate.h"

#include "src/base/error.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace plancheck {
namespace {

template <class E>
std::string message_of(const std::function<std::string()>& work, const IsolationLimits& limits = {}) {
  try {
    run_isolated(work, limits);
  } catch (const E& e) {
    return e.what();
  }
  return "<nothing thrown>";
}

TEST(Isolate, ReturnsTheChildsBytesWhole) {
  // Larger than a pipe's buffer many times over, every byte value present.
  std::string expected(20 << 20, '\0');
  for (std::size_t i = 0; i < expected.size(); ++i) expected[i] = static_cast<char>((i * 2654435761u) >> 13);
  EXPECT_EQ(run_isolated([&] { return expected; }), expected);
  EXPECT_EQ(run_isolated([] { return std::string(); }), "");
}

// `meanwhile` runs in the parent while the child works, sees `stop` turn
// true once the child has answered, is joined before run_isolated returns, and
// its exceptions are no failure; a child's failure is still reported.
TEST(Isolate, MeanwhileRunsOnAParentThreadWhileTheChildWorks) {
  std::atomic<int> rounds{0};
  bool saw_stop = false;
  const std::string got = run_isolated(
      [] {
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
        return std::string("done");
      },
      {}, [&](const std::atomic<bool>& stop) {
        while (!stop) {
          ++rounds;
          std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        saw_stop = true;
      });
  EXPECT_EQ(got, "done");
  EXPECT_TRUE(saw_stop);  // joined: its writes are visible here
  EXPECT_GT(rounds.load(), 5);  // it ran while the child slept
  EXPECT_EQ(run_isolated([] { return std::string("x"); }, {},
                         [](const std::atomic<bool>&) { throw std::runtime_error("dropped"); }),
            "x");
  bool ran = false;
  EXPECT_THROW(run_isolated([]() -> std::string { throw InputError("bad input"); }, {},
                            [&](const std::atomic<bool>&) { ran = true; }),
               InputError);
  EXPECT_TRUE(ran);
  // In-process work: nothing runs beside it.
  ran = false;
  IsolationLimits inside;
  inside.isolate = false;
  EXPECT_EQ(run_isolated([] { return std::string("y"); }, inside, [&](const std::atomic<bool>&) { ran = true; }), "y");
  EXPECT_FALSE(ran);
}

TEST(Isolate, TheChildCannotChangeTheParent) {
  int touched = 0;
  run_isolated([&] {
    touched = 1;
    return std::string("x");
  });
  EXPECT_EQ(touched, 0);
  IsolationLimits in_process;
  in_process.isolate = false;
  run_isolated(
      [&] {
        touched = 1;
        return std::string("x");
      },
      in_process);
  EXPECT_EQ(touched, 1);
}

TEST(Isolate, ExceptionsComeBackWithTheirMessages) {
  EXPECT_EQ(message_of<InputError>([]() -> std::string { throw InputError("model.obj:3: bad face"); }),
            "model.obj:3: bad face");
  const std::string other = message_of<std::runtime_error>([]() -> std::string { throw std::logic_error("odd"); });
  EXPECT_EQ(other, "odd");
}

TEST(Isolate, CrashesAreReportedWithTheirSignal) {
  const std::string segv = message_of<IsolationError>([]() -> std::string {
    std::raise(SIGSEGV);
    return "survived";
  });
  EXPECT_NE(segv.find("crashed (signal 11"), std::string::npos) << segv;
  const std::string abrt = message_of<IsolationError>([]() -> std::string { std::abort(); });
  EXPECT_NE(abrt.find("crashed (signal 6"), std::string::npos) << abrt;
}

TEST(Isolate, TheLastLineTheChildWroteToStderrSaysWhy) {
  const std::string why = message_of<IsolationError>([]() -> std::string {
    std::fputs("reading header\nassert failed: count <= size  \n\n", stderr);
    std::abort();
  });
  EXPECT_NE(why.find("crashed (signal 6, Aborted): assert failed: count <= size"), std::string::npos) << why;
  EXPECT_EQ(why.find("reading header"), std::string::npos) << why;
}

TEST(Isolate, AHangIsKilledAtTheLimit) {
  IsolationLimits limits;
  limits.seconds = 0.5;
  const std::string hang = message_of<IsolationError>(
      []() -> std::string {
        for (;;) ::pause();
      },
      limits);
  EXPECT_EQ(hang, "did not finish within 0.5 s");
}

TEST(Isolate, AnExitWithoutAResultIsReported) {
  const std::string exited = message_of<IsolationError>([]() -> std::string { std::_Exit(5); });
  EXPECT_EQ(exited, "exited with status 5 without a result");
}

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif

TEST(Isolate, MemoryBeyondTheBudgetIsRefused) {
  if (kSanitized) GTEST_SKIP() << "no address-space limit under sanitizers (their shadow memory)";
  IsolationLimits limits;
  limits.memory_mb = 256;
  const std::string oom = message_of<std::runtime_error>(
      []() -> std::string {
        std::vector<std::vector<char>> hog;
        for (int i = 0; i < 64; ++i) hog.emplace_back(std::size_t{64} << 20, 'x');  // 4 GB in all
        return std::to_string(hog.size());
      },
      limits);
  EXPECT_EQ(oom, "ran out of memory (limit 256 MB)");
}

}  // namespace
}  // namespace plancheck
