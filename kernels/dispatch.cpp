// SPDX-License-Identifier: MIT
// Run-time choice of the kernels' instruction set, made once. Baseline flags:
// this file only reads tables the ISA-specific files define.
#include "kernels/leaf_bounds.h"
#include "kernels/tri_distance.h"

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace plancheck {

extern const LeafKernels kLeafKernelsScalar;
extern const LeafKernels kLeafKernelsSse42;
extern const LeafKernels kLeafKernelsAvx2;
extern const LeafKernels kLeafKernelsAvx512;

namespace {

bool cpu_has(Isa isa) noexcept {
  __builtin_cpu_init();
  switch (isa) {
    case Isa::kScalar: return true;
    case Isa::kSse42: return __builtin_cpu_supports("sse4.2");
    case Isa::kAvx2: return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    case Isa::kAvx512:
      return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
             __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw");
  }
  return false;
}

void touch_none(const LeafPairInput& in, std::uint32_t* touch) noexcept {
  const std::uint32_t valid = (1u << in.b.count) - 1u;
  for (int i = 0; i < in.a.count; ++i) touch[i] = valid;
}

void lower_none(const LeafPairInput& in, float, LeafPairBounds& out) noexcept {
  const std::uint32_t valid = (1u << in.b.count) - 1u;
  for (int i = 0; i < in.a.count; ++i) {
    for (int j = 0; j < kLeafLanes; ++j) out.lower2[i][j] = 0.0f;
    out.candidates[i] = valid;
  }
}

// The scalar triangle distance itself (branching on the data).
double tri_distance2_scalar(const double* p, const double* q, double* p_out, double* q_out) noexcept {
  Eigen::Vector3d a, b;
  const double d2 = tri_distance_disjoint2(p, q, a, b);
  for (int k = 0; k < 3; ++k) p_out[k] = a[k], q_out[k] = b[k];
  return d2;
}

constexpr LeafKernels kLeafKernelsNone{"none", 1, &touch_none, &lower_none, &touch_none, &tri_distance2_scalar};

const LeafKernels* choose() noexcept {
  // Without SIMD lanes the prefilter costs more than it saves (Table 3
  // workload: 0.89 s with the scalar instantiation against 0.37 s without a
  // prefilter), so such CPUs run the double path alone; the scalar
  // instantiation stays the tests' reference and can still be forced.
  const LeafKernels* widest = &kLeafKernelsNone;
  for (int k = kIsaCount - 1; k >= 1; --k)
    if (const LeafKernels* t = leaf_kernels_for(static_cast<Isa>(k))) {
      widest = t;
      break;
    }
  const char* want = std::getenv("PLANCHECK_ISA");
  if (want == nullptr || *want == '\0') return widest;
  if (std::strcmp(want, kLeafKernelsNone.name) == 0) return &kLeafKernelsNone;
  for (int k = 0; k < kIsaCount; ++k) {
    const LeafKernels* t = leaf_kernels_for(static_cast<Isa>(k));
    if (t != nullptr && std::strcmp(t->name, want) == 0) return t;
  }
  std::fprintf(stderr, "plancheck: PLANCHECK_ISA=%s is not available here; using %s\n", want,
               widest->name);
  return widest;
}

}  // namespace

const LeafKernels* leaf_kernels_for(Isa isa) noexcept {
  if (!cpu_has(isa)) return nullptr;
  switch (isa) {
    case Isa::kScalar: return &kLeafKernelsScalar;
    case Isa::kSse42: return &kLeafKernelsSse42;
    case Isa::kAvx2: return &kLeafKernelsAvx2;
    case Isa::kAvx512: return &kLeafKernelsAvx512;
  }
  return nullptr;
}

const LeafKernels& leaf_kernels_none() noexcept { return kLeafKernelsNone; }

namespace {
std::atomic<const LeafKernels*> g_override{nullptr};
}  // namespace

const LeafKernels& leaf_kernels() noexcept {
  if (const LeafKernels* k = g_override.load(std::memory_order_relaxed)) return *k;
  static const LeafKernels* const chosen = choose();
  return *chosen;
}

const LeafKernels& set_leaf_kernels(const LeafKernels& k) noexcept {
  const LeafKernels& previous = leaf_kernels();
  g_override.store(&k, std::memory_order_relaxed);
  return previous;
}

}  // namespace plancheck
