// SPDX-License-Identifier: MIT
// Running untrusted parsing in a child process. assimp reads dozens of
// formats and is fuzzed in the wild; crashes, hangs and memory bombs in it
// are found faster than they are fixed (our own fuzzing found four, and the
// CI's fuzz run a fifth that crashed the process). A model file is input, and
// bad input must end in one clear message and exit status 2, never a crash
// or a hang. So the import runs in a forked child with a time limit and
// (outside sanitizer builds) an address-space limit; the child hands back a
// flat byte string over a pipe, and whatever happens to the child becomes an
// IsolationError in the parent.
#pragma once

#include "src/base/parallel.h"

#include <atomic>
#include <cstddef>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>

namespace plancheck {

struct IsolationLimits {
  double seconds = 120.0;      // wall clock for the child, then SIGKILL
  std::size_t memory_mb = 0;   // address space the child may add; 0: half the machine's memory
  bool isolate = true;         // false: run `work` in this process (tests compare both)
  // For model loading (model_loader.h): false sends every 3ds file to assimp,
  // even one the strict native reader (tds_native.h) takes (tests compare both).
  bool native_3ds = true;
};

// The child did not hand back a result: killed by a signal, over its time,
// or exited without a result. what() reads as a phrase after "the importer",
// e.g. "crashed (signal 11, Segmentation fault)".
class IsolationError : public std::runtime_error {
 public:
  explicit IsolationError(const std::string& what) : std::runtime_error(what) {}
};

// Runs `work` in a forked child and returns what it returned. An InputError
// thrown by `work` is rethrown here as an InputError with the same message;
// any other exception as std::runtime_error with its what(). If the process
// cannot fork, `work` runs in this process.
//
// `meanwhile`, if given, runs in this process on a thread of its own while
// the child works (started after the fork, joined before run_isolated
// returns or throws); its argument turns true once the child has answered,
// and it should stop soon after (the caller waits for it). It is for work
// worth having but not needed: what it throws is dropped, and it does not
// run at all when `work` runs in this process (limits.isolate false, no
// fork). The caller counts its thread in its own thread budget.
std::string run_isolated(const std::function<std::string()>& work, const IsolationLimits& limits = {},
                         const std::function<void(const std::atomic<bool>& stop)>& meanwhile = {});

// A `meanwhile` (as above) on a thread of its own from construction; the
// destructor sets its stop flag and joins it, on every way out of the
// caller's scope. What it throws is dropped. An empty function starts
// nothing. (run_isolated and load_model's native 3ds path both use it.)
class SideWork {
 public:
  explicit SideWork(const std::function<void(const std::atomic<bool>& stop)>& work);
  ~SideWork();
  SideWork(const SideWork&) = delete;
  SideWork& operator=(const SideWork&) = delete;
  // Tells the work to stop (without waiting for it).
  void stop() { stop_ = true; }

 private:
  std::atomic<bool> stop_{false};
  std::unique_ptr<BesideJob> job_;  // the thread (src/base/parallel.h); after stop_, which it reads
};

// True in the child process run_isolated forked (which ends with _exit:
// what it allocates need not be freed).
bool in_isolated_child();

}  // namespace plancheck
