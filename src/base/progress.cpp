// SPDX-License-Identifier: MIT
#include "src/base/progress.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>

namespace plancheck {

bool stderr_is_terminal() { return isatty(STDERR_FILENO) != 0; }

std::string format_duration(double seconds) {
  char buf[48];
  if (!std::isfinite(seconds) || seconds < 0) return "?";
  if (seconds < 60) {
    std::snprintf(buf, sizeof buf, "%.1f s", seconds);
  } else if (seconds < 3600) {
    const long s = std::lround(seconds);
    std::snprintf(buf, sizeof buf, "%ld min %02ld s", s / 60, s % 60);
  } else {
    const long m = std::lround(seconds / 60);
    std::snprintf(buf, sizeof buf, "%ld h %02ld min", m / 60, m % 60);
  }
  return buf;
}

Progress::Progress(std::string what, std::size_t total, std::string unit, const ProgressOptions& options,
                   std::ostream* err)
    : what_(std::move(what)), unit_(std::move(unit)), total_(total), options_(options),
      err_(err ? err : &std::cerr), start_(std::chrono::steady_clock::now()) {
  if (options_.quiet) return;
  terminal_ = options_.terminal < 0 ? stderr_is_terminal() : options_.terminal == 1;
  reporter_ = std::thread([this] { run(); });
}

Progress::~Progress() { finish(); }

std::string Progress::line(std::size_t done, double seconds) const {
  const double rate = seconds > 0 ? static_cast<double>(done) / seconds : 0.0;
  char buf[256];
  if (total_ > 0) {
    const double pct = 100.0 * static_cast<double>(done) / static_cast<double>(total_);
    std::snprintf(buf, sizeof buf, "%s: %zu/%zu %s (%.0f%%), %.4g/s", what_.c_str(), done, total_, unit_.c_str(), pct,
                  rate);
  } else {
    std::snprintf(buf, sizeof buf, "%s: %zu %s, %.4g/s", what_.c_str(), done, unit_.c_str(), rate);
  }
  std::string s = buf;
  if (total_ > 0 && done < total_)
    s += ", ETA " + (rate > 0 ? format_duration(static_cast<double>(total_ - done) / rate) : std::string("?"));
  else
    s += ", " + format_duration(seconds);
  return s;
}

void Progress::run() {
  using namespace std::chrono;
  const auto period = terminal_ ? duration<double>(0.25) : duration<double>(options_.interval);
  std::unique_lock lock(mutex_);
  while (!stop_) {
    if (wake_.wait_for(lock, period, [this] { return stop_; })) break;
    const double t = duration<double>(steady_clock::now() - start_).count();
    const std::string l = line(done(), t);
    if (terminal_)
      *err_ << "\r\x1b[K" << l << std::flush;  // clear to the end of the line, redraw
    else
      *err_ << l << "\n" << std::flush;
  }
}

void Progress::finish() {
  if (options_.quiet) return;
  {
    std::lock_guard lock(mutex_);
    if (finished_) return;
    finished_ = true;
    stop_ = true;
  }
  wake_.notify_all();
  if (reporter_.joinable()) reporter_.join();
  const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (terminal_) *err_ << "\r\x1b[K";
  *err_ << line(done(), t) << "\n" << std::flush;
}

}  // namespace plancheck
