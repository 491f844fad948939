// SPDX-License-Identifier: MIT
// What the Table 3 and two-mesh benches share: wall-clock medians, number
// formatting and the machine's name for their tables.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace plancheck::bench {

template <class F>
double seconds_of(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Median of `reps` timings of f (reps >= 1).
template <class F>
double median_seconds(int reps, F&& f) {
  std::vector<double> t;
  for (int i = 0; i < reps; ++i) t.push_back(seconds_of(f));
  std::sort(t.begin(), t.end());
  const std::size_t n = t.size();
  return n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
}

// Writes a bench's JSON text to `file` (--json); throws naming the file.
inline void write_json_text(const std::string& file, const std::string& text) {
  std::ofstream f(file);
  f << text << "\n";
  if (!f) throw std::runtime_error("cannot write " + file);
}

inline std::string fmt(double x, const char* f = "%.3f") {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, x);
  return buf;
}

// The CPU's model name from /proc/cpuinfo, for the tables' headers.
inline std::string cpu_model() {
  std::ifstream f("/proc/cpuinfo");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("model name", 0) == 0) {
      const auto p = line.find(':');
      return p == std::string::npos ? line : line.substr(p + 2);
    }
  return "unknown";
}

}  // namespace plancheck::bench
