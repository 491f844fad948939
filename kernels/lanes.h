// SPDX-License-Identifier: MIT
// Float lanes of one width, for kernels written once over the width (as
// Embree's vfloat4/8/16). W = 1 is the scalar reference; 4, 8 and 16 map to
// SSE, AVX and AVX-512 registers when the including file is compiled with
// those instruction sets (kernels/*_sse42.cpp, *_avx2.cpp, *_avx512.cpp).
//
// Tag is a type private to the including file (anonymous namespace), so each
// instruction set's instantiations have internal linkage: the linker can never
// hand an AVX-512 copy of a helper to code running on a baseline CPU. For the
// same reason nothing here calls an out-of-line library function.
//
// Every operation is one IEEE operation per lane, in the same order at every
// width; the kernel files are built with -ffp-contract=off, so all widths give
// bitwise the same lane values.
#pragma once

#include <immintrin.h>

#include <cstdint>

namespace plancheck::lanes {

template <int W, class Tag>
struct VFloat {
  static_assert(W == 1 || W == 4 || W == 8 || W == 16, "lane width");
  static constexpr int kWidth = W;
  typedef float V __attribute__((vector_size(4 * W)));
  typedef std::int32_t M __attribute__((vector_size(4 * W)));
  V v;

  // x - 0 is x for every x (a -0 stays -0), so the compiler drops the
  // subtraction and emits a bare broadcast; V{} + x, as before, turned -0
  // into +0 and so cost an add per broadcast (324 of them in the AVX-512
  // build's prefilters; 3% of two-mesh distance and cold full checks,
  // thread CPU). No bound here depends on the sign of a zero: every gap
  // has a positive slack taken off.
  static VFloat broadcast(float x) noexcept {
    VFloat r;
    r.v = x - V{};
    return r;
  }
  static VFloat load(const float* p) noexcept {  // p aligned to 4 W bytes
    VFloat r;
    __builtin_memcpy(&r.v, p, sizeof(V));
    return r;
  }
  void store(float* p) const noexcept { __builtin_memcpy(p, &v, sizeof(V)); }

  friend VFloat operator+(VFloat a, VFloat b) noexcept { return {a.v + b.v}; }
  friend VFloat operator-(VFloat a, VFloat b) noexcept { return {a.v - b.v}; }
  friend VFloat operator*(VFloat a, VFloat b) noexcept { return {a.v * b.v}; }
  friend VFloat operator/(VFloat a, VFloat b) noexcept { return {a.v / b.v}; }
  friend VFloat operator-(VFloat a) noexcept { return {-a.v}; }
  // min/max by comparison: with finite inputs (the kernels' precondition)
  // no NaN reaches them.
  friend VFloat min(VFloat a, VFloat b) noexcept { return {a.v < b.v ? a.v : b.v}; }
  friend VFloat max(VFloat a, VFloat b) noexcept { return {a.v > b.v ? a.v : b.v}; }
  friend VFloat abs(VFloat a) noexcept { return {a.v < V{} ? -a.v : a.v}; }
  // a where m, else b.
  friend VFloat select(M m, VFloat a, VFloat b) noexcept { return {m ? a.v : b.v}; }
};

// Double lanes of one width (W = 2, 4, 8: SSE2, AVX, AVX-512 registers), for
// the exact triangle distance written once over the width
// (kernels/tri_distance_lanes.h). Same rules as VFloat.
template <int W, class Tag>
struct VDouble {
  static_assert(W == 1 || W == 2 || W == 4 || W == 8, "lane width");
  static constexpr int kWidth = W;
  using One = VDouble<1, Tag>;  // one lane of the same instruction set
  typedef double V __attribute__((vector_size(8 * W)));
  typedef std::int64_t M __attribute__((vector_size(8 * W)));
  V v;

  static VDouble broadcast(double x) noexcept {
    VDouble r;
    r.v = V{} + x;
    return r;
  }
  static VDouble load(const double* p) noexcept {
    VDouble r;
    __builtin_memcpy(&r.v, p, sizeof(V));
    return r;
  }
  void store(double* p) const noexcept { __builtin_memcpy(p, &v, sizeof(V)); }

  friend VDouble operator+(VDouble a, VDouble b) noexcept { return {a.v + b.v}; }
  friend VDouble operator-(VDouble a, VDouble b) noexcept { return {a.v - b.v}; }
  friend VDouble operator*(VDouble a, VDouble b) noexcept { return {a.v * b.v}; }
  friend VDouble operator/(VDouble a, VDouble b) noexcept { return {a.v / b.v}; }
  friend VDouble operator-(VDouble a) noexcept { return {-a.v}; }
  // a where m, else b.
  friend VDouble select(M m, VDouble a, VDouble b) noexcept { return {m ? a.v : b.v}; }
};

// Bit k set when lane k of m is true.
template <class F>
inline std::uint32_t movemask(typename F::M m) noexcept {
  constexpr int W = F::kWidth;
  if constexpr (W == 1) {
    return m[0] != 0 ? 1u : 0u;
  } else if constexpr (W == 4) {
    return static_cast<std::uint32_t>(_mm_movemask_ps(reinterpret_cast<__m128>(m)));
  } else if constexpr (W == 8) {
    return static_cast<std::uint32_t>(_mm256_movemask_ps(reinterpret_cast<__m256>(m)));
  } else {
    return static_cast<std::uint32_t>(_mm512_movepi32_mask(reinterpret_cast<__m512i>(m)));
  }
}

}  // namespace plancheck::lanes
