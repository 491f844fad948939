// SPDX-License-Identifier: MIT
#include "bench/random_states.h"

#include "src/base/error.h"

#include <algorithm>

namespace plancheck::bench {

namespace {

// Per parameter: its action's limits, or none.
struct Range {
  bool drawn = false;
  double lo = 0.0, hi = 0.0;
};

std::vector<Range> ranges(const Scene& scene) {
  std::vector<Range> out(scene.parameter_names.size());
  for (const Action& a : scene.actions) {
    if (!a.has_limits) continue;
    for (int k = 0; k < a.parameter_count; ++k) out[static_cast<std::size_t>(a.first_parameter + k)] = {true, a.lower, a.upper};
  }
  return out;
}

}  // namespace

double uniform_between(std::mt19937_64& rng, double lo, double hi) {
  return std::clamp(lo + unit_uniform(rng) * (hi - lo), lo, hi);
}

std::vector<std::vector<double>> random_states(const Scene& scene, std::size_t n, std::uint64_t seed) {
  const std::vector<Range> r = ranges(scene);
  if (std::none_of(r.begin(), r.end(), [](const Range& x) { return x.drawn; }))
    throw InputError("--random: no action of the scene has limits to draw states within");
  std::mt19937_64 rng(seed);
  std::vector<std::vector<double>> states(n, scene.reference_parameters);
  for (auto& s : states)
    for (std::size_t p = 0; p < s.size(); ++p)
      if (r[p].drawn) s[p] = uniform_between(rng, r[p].lo, r[p].hi);
  return states;
}

std::vector<std::string> drawn_parameters(const Scene& scene) {
  const std::vector<Range> r = ranges(scene);
  std::vector<std::string> out;
  for (std::size_t p = 0; p < r.size(); ++p)
    if (r[p].drawn) out.push_back(scene.parameter_names[p]);
  return out;
}

}  // namespace plancheck::bench
