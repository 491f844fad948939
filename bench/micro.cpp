// SPDX-License-Identifier: MIT
// Micro benchmarks of the kernels, BM_<Component>_<Operation>. Each builds
// inputs whose answer is known by construction and checks it before timing
// (a benchmark that does not check its answer measures nothing); a wrong
// answer skips the benchmark with an error.
#include "kernels/box.h"
#include "kernels/tri_distance.h"
#include "kernels/tri_tri_overlap.h"

#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

namespace plancheck::bench {
namespace {

using Tri9 = std::array<double, 9>;

// Pairs with known answers: p is a large triangle in a plane z = const, q a
// small one above its interior: lifted by `gap` and tilted (separated, the
// distance is exactly the gap), crossing p's plane (intersecting), or lying
// in it (coplanar: every orientation is zero and the exact path decides).
enum class Kind { kSeparated = 0, kCrossing = 1, kCoplanar = 2 };

struct KnownPairs {
  std::vector<Tri9> p, q;
  std::vector<double> distance;
};

KnownPairs make_pairs(std::size_t n, Kind kind, std::uint64_t seed) {
  const bool separated = kind == Kind::kSeparated;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  KnownPairs k;
  for (std::size_t i = 0; i < n; ++i) {
    const double z = u(rng);
    // A big triangle p containing the origin's neighbourhood and a small q above it.
    Tri9 p = {-2 + 0.1 * u(rng), -2 + 0.1 * u(rng), z, 2 + 0.1 * u(rng), -2 + 0.1 * u(rng), z,
              0.1 * u(rng),      3 + 0.1 * u(rng),  z};
    const double gap = separated ? 0.01 + 0.5 * (u(rng) + 1.0) : 0.0;
    const double cx = 0.2 * u(rng), cy = 0.2 * u(rng);
    Tri9 q = {cx - 0.3, cy - 0.3, z + gap, cx + 0.3, cy - 0.3, z + gap, cx, cy + 0.3, z + gap};
    // Tilt q about its lowest edge when separated, so the closest feature is
    // that edge at height gap (still exact: the edge keeps z = z + gap).
    if (separated) q[8] += 0.5 * (u(rng) + 1.0);
    if (kind == Kind::kCrossing) {
      q[2] -= 0.2;
      q[5] -= 0.2;
      q[8] += 0.3;
    }
    k.p.push_back(p);
    k.q.push_back(q);
    k.distance.push_back(gap);
  }
  return k;
}

void BM_TriTriOverlap_Scalar(benchmark::State& state) {
  const Kind kind = static_cast<Kind>(state.range(0));
  const bool separated = kind == Kind::kSeparated;
  const KnownPairs k = make_pairs(4096, kind, 7);
  for (std::size_t i = 0; i < k.p.size(); ++i) {
    const double* a = k.p[i].data();
    const double* b = k.q[i].data();
    if (tri_tri_overlap(a, a + 3, a + 6, b, b + 3, b + 6) == separated) {
      state.SkipWithError("wrong overlap answer");
      return;
    }
  }
  std::size_t i = 0;
  for (auto _ : state) {
    const double* a = k.p[i].data();
    const double* b = k.q[i].data();
    benchmark::DoNotOptimize(tri_tri_overlap(a, a + 3, a + 6, b, b + 3, b + 6));
    i = (i + 1) % k.p.size();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
// 0 separated, 1 crossing, 2 coplanar (the exact GMP fallback's cost).
BENCHMARK(BM_TriTriOverlap_Scalar)->Arg(0)->Arg(1)->Arg(2)->ArgName("kind");

void BM_TriDistance_Scalar(benchmark::State& state) {
  const KnownPairs k = make_pairs(4096, Kind::kSeparated, 11);
  for (std::size_t i = 0; i < k.p.size(); ++i) {
    const TriDistance d = tri_distance(k.p[i].data(), k.q[i].data());
    if (!(std::abs(d.distance - k.distance[i]) <= 1e-12)) {
      state.SkipWithError("wrong distance");
      return;
    }
  }
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(tri_distance(k.p[i].data(), k.q[i].data()));
    i = (i + 1) % k.p.size();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_TriDistance_Scalar);

void BM_Box_Overlap(benchmark::State& state) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<std::array<double, 12>> boxes(4096);
  for (auto& b : boxes) {
    for (int k = 0; k < 3; ++k) {
      b[k] = u(rng);
      b[3 + k] = b[k] + 0.3 * u(rng);
      b[6 + k] = u(rng);
      b[9 + k] = b[6 + k] + 0.3 * u(rng);
    }
  }
  for (const auto& b : boxes) {
    bool expect = true;
    for (int k = 0; k < 3; ++k) expect = expect && b[k] <= b[9 + k] && b[6 + k] <= b[3 + k];
    if (boxes_overlap(b.data(), b.data() + 3, b.data() + 6, b.data() + 9) != expect) {
      state.SkipWithError("wrong box answer");
      return;
    }
  }
  std::size_t i = 0;
  for (auto _ : state) {
    const auto& b = boxes[i];
    benchmark::DoNotOptimize(boxes_overlap(b.data(), b.data() + 3, b.data() + 6, b.data() + 9));
    i = (i + 1) % boxes.size();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_Box_Overlap);

}  // namespace
}  // namespace plancheck::bench
