// SPDX-License-Identifier: MIT
// Progress of long work on stderr (verify, sweep, dig, dataset generation).
// Workers only add to an atomic counter (relaxed, one instruction; call it
// per state or per block, never per triangle); a reporter thread wakes a few
// times a second and prints:
//   - on a terminal, one line redrawn in place: done/total, rate, ETA;
//   - otherwise (CI logs, files), a plain line every `interval` seconds;
//   - nothing at all when quiet.
// finish() (or the destructor) prints the final line: "what: done/total
// unit, rate/s, seconds" (on a terminal it ends the redrawn line).
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <iosfwd>
#include <mutex>
#include <string>
#include <thread>

namespace plancheck {

struct ProgressOptions {
  bool quiet = false;      // print nothing
  int terminal = -1;       // 1: redraw in place, 0: plain lines, -1: ask isatty(stderr)
  double interval = 5.0;   // seconds between plain lines (terminal: 0.25 s redraws)
};

// Whether stderr is a terminal.
bool stderr_is_terminal();

// "1.2 s", "3 min 05 s", "1 h 02 min".
std::string format_duration(double seconds);

class Progress {
 public:
  // Reports on `err` (nullptr: std::cerr). total 0: unknown (no ETA).
  Progress(std::string what, std::size_t total, std::string unit, const ProgressOptions& options = {},
           std::ostream* err = nullptr);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void add(std::size_t n = 1) noexcept { done_.fetch_add(n, std::memory_order_relaxed); }
  std::size_t done() const noexcept { return done_.load(std::memory_order_relaxed); }
  // Stops the reporter and prints the final line (once).
  void finish();

  // One line of progress (no newline), as printed.
  std::string line(std::size_t done, double seconds) const;

 private:
  void run();
  std::string what_, unit_;
  std::size_t total_;
  ProgressOptions options_;
  std::ostream* err_;
  bool terminal_ = false;
  std::atomic<std::size_t> done_{0};
  std::chrono::steady_clock::time_point start_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  bool finished_ = false;
  std::thread reporter_;
};

}  // namespace plancheck
