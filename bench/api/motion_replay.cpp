// SPDX-License-Identifier: MIT
// Certified motion checks replayed on fixed edges (issues 32 and 33): the
// edges a planner tried (plancheck_ompl_bench --edges DIR writes them), each
// checked by Checker::check_motion (verdict-only, first violation: what the
// OMPL adapter's motion validator asks) and by OMPL's DiscreteMotionValidator
// at its default resolution emulated over verdict-only point checks (the end
// state, then the states between at 1% of the space's extent). Answers are
// checked first: every edge check_motion certifies, the discrete states pass.
// One function per workload, for callgrind's --toggle-collect:
//
//   plancheck_motion_replay SCENE EDGES.csv [--passes 5] [--threads 0] [--per-edge]
//   valgrind --tool=callgrind --toggle-collect='*replay_motion*'
//       plancheck_motion_replay SCENE EDGES.csv --passes 1 --threads 1
// (one command; '*replay_discrete*' for the discrete states). The answer
// check runs each workload once more: callgrind's count is for passes + 1
// runs of the edges.
//
// --per-edge: first one CSV row an edge (edge,length,states,certified,
// motion_us,discrete_us: its length in plan units, the discrete states it
// takes, each time the median of the passes), to see how the costs grow
// with the edge's length and where they go.
//
// EDGES.csv: one edge a line, the start's parameters then the end's (plan
// units, the scene's parameter order), comma-separated.
#include <plancheck/plancheck.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

struct Edges {
  std::vector<std::vector<double>> from, to;
};

[[noreturn]] void die(const std::string& what) {
  std::fprintf(stderr, "plancheck_motion_replay: %s\n", what.c_str());
  std::exit(2);
}

Edges read_edges(const std::string& path, std::size_t n) {
  std::ifstream f(path);
  if (!f) die(path + ": cannot be read");
  Edges e;
  std::string line;
  for (std::size_t row = 1; std::getline(f, line); ++row) {
    if (line.empty()) continue;
    std::vector<double> v;
    std::stringstream ss(line);
    std::string x;
    while (std::getline(ss, x, ',')) {
      char* end = nullptr;
      const double d = std::strtod(x.c_str(), &end);
      if (end == x.c_str() || *end != '\0' || !std::isfinite(d))
        die(path + ":" + std::to_string(row) + ": not a finite number: '" + x + "'");
      v.push_back(d);
    }
    if (v.size() != 2 * n)
      die(path + ":" + std::to_string(row) + ": " + std::to_string(v.size()) + " values, expected " +
          std::to_string(2 * n));
    e.from.emplace_back(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n));
    e.to.emplace_back(v.begin() + static_cast<std::ptrdiff_t>(n), v.end());
  }
  if (e.from.empty()) die(path + ": no edges");
  return e;
}

// The workloads (not inlined, so that callgrind can toggle on them): how
// many edges pass.
using Clock = std::chrono::steady_clock;

// Each edge's time into seconds[i] when given.
__attribute__((noinline)) std::size_t replay_motion(const plancheck::Checker& c, const Edges& e,
                                                    std::vector<char>* safe, std::vector<double>* seconds = nullptr) {
  std::size_t ok = 0;
  for (std::size_t i = 0; i < e.from.size(); ++i) {
    const auto t0 = seconds ? Clock::now() : Clock::time_point{};
    const bool s = c.check_motion(e.from[i], e.to[i], plancheck::MotionOptions{true, true}).verdict ==
                   plancheck::Verdict::kSafe;
    if (seconds) (*seconds)[i] = std::chrono::duration<double>(Clock::now() - t0).count();
    ok += s;
    if (safe) (*safe)[i] = s;
  }
  return ok;
}

// The discrete states edge i takes at resolution `step`: as
// DiscreteMotionValidator, ceil(distance / step) (the end state and those
// between).
int discrete_states(const std::vector<double>& a, const std::vector<double>& b, double step) {
  double d2 = 0.0;
  for (std::size_t j = 0; j < a.size(); ++j) d2 += (b[j] - a[j]) * (b[j] - a[j]);
  return std::max(1, static_cast<int>(std::ceil(std::sqrt(d2) / step)));
}

__attribute__((noinline)) std::size_t replay_discrete(const plancheck::Checker& c, const Edges& e, double step,
                                                      std::vector<char>* safe, std::vector<double>* seconds = nullptr) {
  const std::size_t n = c.parameter_count();
  std::vector<double> q(n);
  std::size_t ok = 0;
  auto valid = [&](const std::vector<double>& s) {
    return c.check(s, plancheck::CheckOptions{true}).verdict == plancheck::Verdict::kSafe;
  };
  for (std::size_t i = 0; i < e.from.size(); ++i) {
    const std::vector<double>& a = e.from[i];
    const std::vector<double>& b = e.to[i];
    // As DiscreteMotionValidator::checkMotion: the end state first, then
    // the states between at j / nd.
    const auto t0 = seconds ? Clock::now() : Clock::time_point{};
    const int nd = discrete_states(a, b, step);
    bool s = valid(b);
    for (int k = 1; s && k < nd; ++k) {
      const double t = static_cast<double>(k) / nd;
      for (std::size_t j = 0; j < n; ++j) q[j] = a[j] + (b[j] - a[j]) * t;
      s = valid(q);
    }
    if (seconds) (*seconds)[i] = std::chrono::duration<double>(Clock::now() - t0).count();
    ok += s;
    if (safe) (*safe)[i] = s;
  }
  return ok;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> pos;
  int passes = 5, threads = 0;
  bool per_edge = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--per-edge")
      per_edge = true;
    else if (a == "--passes" && i + 1 < argc)
      passes = std::atoi(argv[++i]);
    else if (a == "--threads" && i + 1 < argc)
      threads = std::atoi(argv[++i]);
    else
      pos.push_back(a);
  }
  if (pos.size() != 2 || passes < 1 || threads < 0)
    die("usage: plancheck_motion_replay SCENE EDGES.csv [--passes N] [--threads N] [--per-edge]");
  const plancheck::Scene scene = plancheck::Scene::load(pos[0]);
  const plancheck::Checker checker(scene, threads);
  const std::size_t n = checker.parameter_count();
  const Edges edges = read_edges(pos[1], n);
  // OMPL's default resolution: 1% of the space's extent (the limits' box).
  const std::vector<double> lo = scene.lower_limits(), hi = scene.upper_limits();
  double extent2 = 0.0;
  for (std::size_t j = 0; j < n; ++j) extent2 += (hi[j] - lo[j]) * (hi[j] - lo[j]);
  const double step = 0.01 * std::sqrt(extent2);
  if (!(step > 0.0) || !std::isfinite(step)) die(pos[0] + ": every parameter needs finite limits");

  // Answers first: a certified edge has every discrete state safe.
  std::vector<char> cert(edges.from.size()), disc(edges.from.size());
  replay_motion(checker, edges, &cert);
  replay_discrete(checker, edges, step, &disc);
  std::size_t certified = 0, missed = 0;
  for (std::size_t i = 0; i < cert.size(); ++i) {
    certified += cert[i];
    missed += cert[i] && !disc[i];
  }
  if (missed) die(std::to_string(missed) + " edges certified safe have a discrete state that is not");

  const std::size_t count = edges.from.size();
  std::vector<double> motion, discrete;
  // Per edge and pass (--per-edge): edge i's times at [i * passes + p].
  std::vector<double> edge_motion(per_edge ? count * passes : 0), edge_discrete(edge_motion.size());
  std::vector<double> one(per_edge ? count : 0), other(one.size());
  for (int p = 0; p < passes; ++p) {
    auto t0 = Clock::now();
    replay_motion(checker, edges, nullptr, per_edge ? &one : nullptr);
    motion.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
    t0 = Clock::now();
    replay_discrete(checker, edges, step, nullptr, per_edge ? &other : nullptr);
    discrete.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
    for (std::size_t i = 0; per_edge && i < count; ++i) {
      edge_motion[i * passes + p] = one[i];
      edge_discrete[i * passes + p] = other[i];
    }
  }
  if (per_edge) {
    std::printf("edge,length,states,certified,motion_us,discrete_us\n");
    for (std::size_t i = 0; i < count; ++i) {
      const auto at = [&](const std::vector<double>& v) {
        return median(std::vector<double>(v.begin() + i * passes, v.begin() + (i + 1) * passes)) * 1e6;
      };
      double d2 = 0.0;
      for (std::size_t j = 0; j < n; ++j) d2 += (edges.to[i][j] - edges.from[i][j]) * (edges.to[i][j] - edges.from[i][j]);
      std::printf("%zu,%.6g,%d,%d,%.3f,%.3f\n", i, std::sqrt(d2), discrete_states(edges.from[i], edges.to[i], step),
                  static_cast<int>(cert[i]), at(edge_motion), at(edge_discrete));
    }
  }
  const double m = median(motion) / edges.from.size() * 1e6, d = median(discrete) / edges.from.size() * 1e6;
  std::printf("%zu edges, %zu certified safe; medians of %d passes, alternating: check_motion %.2f us an edge, "
              "discrete (1%% of the extent) %.2f us; ratio %.2f\n",
              edges.from.size(), certified, passes, m, d, m / d);
  return 0;
}
