// SPDX-License-Identifier: MIT
// Micro benchmarks of the kernels, BM_<Component>_<Operation>. Each builds
// inputs whose answer is known by construction and checks it before timing
// (a benchmark that does not check its answer measures nothing); a wrong
// answer skips the benchmark with an error.
#include "kernels/box.h"
#include "kernels/leaf_bounds.h"
#include "kernels/tri_distance.h"
#include "kernels/tri_tri_overlap.h"
#include "src/geometry/bvh.h"

#include <benchmark/benchmark.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <string>
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

// Leaf pairs as BVH traversal meets them: two leaves of 16 triangles
// (size 2 cm, a patch of a curved surface each) a few centimetres apart
// down to touching, b placed by a rigid map, all 1.7e3 m from the origin.
struct LeafPairs {
  struct Leaf {
    std::vector<Tri9> own;    // own frame
    std::vector<float> soa;
    float lo[3], hi[3];
  };
  std::vector<Leaf> a, b;
  std::vector<std::array<double, 12>> map_b;  // l row-major, t
  std::vector<std::vector<Tri9>> working_b;   // b's triangles mapped in double
  std::vector<LeafPairInput> input;
};

LeafPairs make_leaf_pairs(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> g;
  LeafPairs lp;
  auto make_leaf = [&](const Eigen::Vector3d& c, const Eigen::Vector3d& normal) {
    LeafPairs::Leaf leaf;
    const Eigen::Vector3d e1 = normal.unitOrthogonal(), e2 = normal.cross(e1);
    for (int t = 0; t < kLeafLanes; ++t) {
      Tri9 tri;
      const double x = 0.01 * u(rng), y = 0.01 * u(rng);
      for (int v = 0; v < 3; ++v) {
        const double dx = x + 0.004 * u(rng), dy = y + 0.004 * u(rng);
        const Eigen::Vector3d p = c + dx * e1 + dy * e2 - 2.0 * (dx * dx + dy * dy) * normal;
        for (int k = 0; k < 3; ++k) tri[3 * v + k] = p[k];
      }
      leaf.own.push_back(tri);
    }
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (const Tri9& tri : leaf.own)
      for (int c2 = 0; c2 < 9; ++c2) {
        lo[c2 % 3] = std::min(lo[c2 % 3], tri[c2]);
        hi[c2 % 3] = std::max(hi[c2 % 3], tri[c2]);
      }
    for (int k = 0; k < 3; ++k) {
      leaf.lo[k] = round_down(lo[k]);
      leaf.hi[k] = round_up(hi[k]);
    }
    leaf.soa.assign(9 * (kLeafLanes + kSoaPadding), 0.0f);
    store_leaf_soa(leaf.soa.data(), kLeafLanes + kSoaPadding, 0, kLeafLanes, leaf.lo, leaf.hi,
                   [&](std::uint32_t s, int v) { return leaf.own[s].data() + 3 * v; });
    return leaf;
  };
  const Eigen::Vector3d base(1.7e3, -0.4e3, 0.2e3);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d ca = base + Eigen::Vector3d(u(rng), u(rng), u(rng));
    const Eigen::Vector3d na = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    lp.a.push_back(make_leaf(ca, na));
    // b: a patch facing a at 0 to 3 cm, built in the working frame, then
    // expressed in its own frame under a random rigid map.
    Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
    q.normalize();
    const Eigen::Matrix3d rot = q.toRotationMatrix();
    const Eigen::Vector3d shift(u(rng), u(rng), u(rng));
    const double gap = 0.015 * (u(rng) + 1.0);
    const Eigen::Vector3d cb_w = ca + (gap + 0.0005) * na;
    const Eigen::Vector3d cb_own = rot.transpose() * (cb_w - shift);
    lp.b.push_back(make_leaf(cb_own, rot.transpose() * (-na)));
    std::array<double, 12> m;
    for (int r = 0; r < 3; ++r) {
      for (int c2 = 0; c2 < 3; ++c2) m[3 * r + c2] = rot(r, c2);
      m[9 + r] = shift[r];
    }
    lp.map_b.push_back(m);
    std::vector<Tri9> w;
    for (const Tri9& tri : lp.b.back().own) {
      Tri9 o;
      for (int v = 0; v < 3; ++v)
        for (int r = 0; r < 3; ++r)
          o[3 * v + r] = m[3 * r] * tri[3 * v] + m[3 * r + 1] * tri[3 * v + 1] +
                         m[3 * r + 2] * tri[3 * v + 2] + m[9 + r];
      w.push_back(o);
    }
    lp.working_b.push_back(w);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const LeafSide sa = make_leaf_side(lp.a[i].soa.data(), kLeafLanes + kSoaPadding, nullptr, nullptr, 2e3);
    const LeafSide sb = make_leaf_side(lp.b[i].soa.data(), kLeafLanes + kSoaPadding, lp.map_b[i].data(),
                                       lp.map_b[i].data() + 9, 2e3);
    LeafPairInput in;
    make_leaf_pair(sa, 0, kLeafLanes, lp.a[i].lo, lp.a[i].hi, sb, 0, kLeafLanes, lp.b[i].lo,
                   lp.b[i].hi, in);
    lp.input.push_back(in);
  }
  return lp;
}

// Checks a kernel table on every pair: bitwise the scalar answer, and
// conservative against the exact double kernels. Empty string when right.
std::string check_leaf_kernels(const LeafKernels& k, const LeafPairs& lp) {
  const LeafKernels& scalar = *leaf_kernels_for(Isa::kScalar);
  for (std::size_t n = 0; n < lp.input.size(); ++n) {
    std::uint32_t touch[kLeafLanes], touch_ref[kLeafLanes];
    LeafPairBounds lb, lb_ref;
    k.touch_masks(lp.input[n], touch);
    k.lower_bounds(lp.input[n], 1e30f, lb);
    scalar.touch_masks(lp.input[n], touch_ref);
    scalar.lower_bounds(lp.input[n], 1e30f, lb_ref);
    for (int i = 0; i < kLeafLanes; ++i) {
      if (touch[i] != touch_ref[i]) return "touch mask differs from scalar";
      for (int j = 0; j < kLeafLanes; ++j) {
        if (std::bit_cast<std::uint32_t>(lb.lower2[i][j]) !=
            std::bit_cast<std::uint32_t>(lb_ref.lower2[i][j]))
          return "lower bound differs from scalar";
        const double* p = lp.a[n].own[static_cast<std::size_t>(i)].data();
        const double* q = lp.working_b[n][static_cast<std::size_t>(j)].data();
        const bool touching = tri_tri_overlap(p, p + 3, p + 6, q, q + 3, q + 6);
        if (touching && !((touch[i] >> j) & 1u)) return "rejected a touching pair";
        if (std::sqrt(static_cast<double>(lb.lower2[i][j])) > tri_distance(p, q).distance + 1e-9)
          return "lower bound above the distance";
      }
    }
  }
  return "";
}

const LeafPairs& bench_leaf_pairs() {
  static const LeafPairs lp = make_leaf_pairs(256, 21);
  return lp;
}

// One leaf pair (16 x 16 triangle pairs) per iteration.
void BM_LeafBounds_Touch(benchmark::State& state, const LeafKernels* k) {
  const LeafPairs& lp = bench_leaf_pairs();
  const std::string error = check_leaf_kernels(*k, lp);
  if (!error.empty()) {
    state.SkipWithError(error.c_str());
    return;
  }
  std::uint32_t touch[kLeafLanes];
  std::size_t n = 0, kept = 0;
  for (auto _ : state) {
    k->touch_masks(lp.input[n], touch);
    kept += static_cast<std::size_t>(std::popcount(touch[0]));
    benchmark::DoNotOptimize(touch);
    n = (n + 1) % lp.input.size();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * kLeafLanes * kLeafLanes);
  state.counters["kept_row0"] = static_cast<double>(kept) / static_cast<double>(state.iterations());
}

void BM_LeafBounds_Lower(benchmark::State& state, const LeafKernels* k) {
  const LeafPairs& lp = bench_leaf_pairs();
  const std::string error = check_leaf_kernels(*k, lp);
  if (!error.empty()) {
    state.SkipWithError(error.c_str());
    return;
  }
  LeafPairBounds lb;
  std::size_t n = 0;
  for (auto _ : state) {
    k->lower_bounds(lp.input[n], 1e-4f, lb);
    benchmark::DoNotOptimize(lb);
    n = (n + 1) % lp.input.size();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * kLeafLanes * kLeafLanes);
}

// The same leaf pairs on the double path alone (b already mapped, which the
// float kernels' time includes): exact box filter, then the exact overlap test.
void BM_LeafBounds_DoubleOverlapReference(benchmark::State& state) {
  const LeafPairs& lp = bench_leaf_pairs();
  std::size_t n = 0;
  for (auto _ : state) {
    int hits = 0;
    for (int i = 0; i < kLeafLanes; ++i) {
      const double* p = lp.a[n].own[static_cast<std::size_t>(i)].data();
      double pb[6];
      for (int k = 0; k < 3; ++k) {
        pb[k] = std::min({p[k], p[3 + k], p[6 + k]});
        pb[3 + k] = std::max({p[k], p[3 + k], p[6 + k]});
      }
      for (int j = 0; j < kLeafLanes; ++j) {
        const double* q = lp.working_b[n][static_cast<std::size_t>(j)].data();
        double qb[6];
        for (int k = 0; k < 3; ++k) {
          qb[k] = std::min({q[k], q[3 + k], q[6 + k]});
          qb[3 + k] = std::max({q[k], q[3 + k], q[6 + k]});
        }
        if (!boxes_overlap(pb, pb + 3, qb, qb + 3)) continue;
        hits += tri_tri_overlap(p, p + 3, p + 6, q, q + 3, q + 6);
      }
    }
    benchmark::DoNotOptimize(hits);
    n = (n + 1) % lp.input.size();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * kLeafLanes * kLeafLanes);
}
BENCHMARK(BM_LeafBounds_DoubleOverlapReference);

// The exact distance of disjoint triangles (tri_distance_disjoint2) through
// one instruction set's double lanes (kernels/tri_distance_lanes.h), after
// checking every answer equals the scalar kernel's bit for bit.
void BM_TriDistance_Lanes(benchmark::State& state, const LeafKernels* k) {
  const KnownPairs pairs = make_pairs(4096, Kind::kSeparated, 11);
  for (std::size_t i = 0; i < pairs.p.size(); ++i) {
    Eigen::Vector3d a, b;
    const double want = tri_distance_disjoint2(pairs.p[i].data(), pairs.q[i].data(), a, b);
    double pa[3], pb[3];
    const double got = k->tri_distance2(pairs.p[i].data(), pairs.q[i].data(), pa, pb);
    if (std::memcmp(&want, &got, sizeof want) != 0 || pa[0] != a[0] || pa[1] != a[1] || pa[2] != a[2] ||
        pb[0] != b[0] || pb[1] != b[1] || pb[2] != b[2]) {
      state.SkipWithError("differs from the scalar kernel");
      return;
    }
  }
  std::size_t i = 0;
  for (auto _ : state) {
    double pa[3], pb[3];
    benchmark::DoNotOptimize(k->tri_distance2(pairs.p[i].data(), pairs.q[i].data(), pa, pb));
    i = (i + 1) % pairs.p.size();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

// One registration per instruction set this CPU has (names end in /<isa>).
const bool registered = [] {
  for (int i = 0; i < kIsaCount; ++i) {
    const LeafKernels* k = leaf_kernels_for(static_cast<Isa>(i));
    if (k == nullptr) continue;
    benchmark::RegisterBenchmark((std::string("BM_LeafBounds_Touch/") + k->name).c_str(),
                                 BM_LeafBounds_Touch, k);
    benchmark::RegisterBenchmark((std::string("BM_LeafBounds_Lower/") + k->name).c_str(),
                                 BM_LeafBounds_Lower, k);
    benchmark::RegisterBenchmark((std::string("BM_TriDistance_Lanes/") + k->name).c_str(),
                                 BM_TriDistance_Lanes, k);
  }
  return true;
}();

}  // namespace
}  // namespace plancheck::bench
