// SPDX-License-Identifier: MIT
// Seeded random draws that give the same numbers with any standard library:
// std::mt19937_64's output is fixed by the C++ standard, the distributions
// of <random> are not, so the mapping to [0, 1) is our own.
#pragma once

#include "src/scene/scene.h"

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace plancheck::bench {

// Uniform in [0, 1): the top 53 bits of one draw.
inline double unit_uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

// Uniform in [lo, hi] (never outside it, whatever the rounding).
double uniform_between(std::mt19937_64& rng, double lo, double hi);

// n configurations drawn uniformly and independently within the scene's
// action limits (plan units, as written), state after state, parameters in
// order. A parameter whose action has no limits keeps its reference value.
// Throws InputError when no parameter has limits.
std::vector<std::vector<double>> random_states(const Scene& scene, std::size_t n, std::uint64_t seed);

// The parameters random_states draws (the others stay at their reference value).
std::vector<std::string> drawn_parameters(const Scene& scene);

}  // namespace plancheck::bench
