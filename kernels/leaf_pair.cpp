// SPDX-License-Identifier: MIT
// The per-leaf-pair set-up of the SIMD prefilters in baseline double
// arithmetic: float maps, perturbation bounds and extent as derived in
// kernels/leaf_bounds.h.
#include "kernels/leaf_bounds.h"

#include <bit>
#include <cmath>
#include <cstdint>

namespace plancheck {

namespace {

constexpr double kU = 0x1p-24;

// x >= 0 (every value rounded here is) rounded up to float. The next float
// up from a non-negative finite one is its bit pattern plus one (0 to the
// smallest subnormal, the largest finite to infinity): nextafter's answer
// without its out-of-line call.
float float_up(double x) noexcept {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) < x) f = std::bit_cast<float>(std::bit_cast<std::uint32_t>(f) + 1u);
  return f;
}

double amax(const double* x) noexcept {
  double m = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double a = x[k] < 0.0 ? -x[k] : x[k];
    m = a > m ? a : m;
  }
  return m;
}

void apply(const LeafSide& s, const double* x, double* out) noexcept {
  if (s.l == nullptr) {
    for (int k = 0; k < 3; ++k) out[k] = x[k];
    return;
  }
  for (int r = 0; r < 3; ++r)
    out[r] = s.l[3 * r] * x[0] + s.l[3 * r + 1] * x[1] + s.l[3 * r + 2] * x[2] + s.t[r];
}

// Fills v for one side whose leaf centre maps to w; returns its contribution
// to the extent.
double view(const LeafSide& s, std::uint32_t first, int count, const float* lo, const float* hi,
            const double* w, const double* origin, LeafView& v) noexcept {
  v.soa = s.soa + first;
  v.stride = s.stride;
  v.count = count;
  double radius = 0.0, big = 0.0;  // R >= |x - o| for the leaf's vertices x
  for (int k = 0; k < 3; ++k) {
    const double h = 0.5 * (static_cast<double>(hi[k]) - static_cast<double>(lo[k]));
    radius = h > radius ? h : radius;
    const double a = std::fabs(static_cast<double>(lo[k])) + std::fabs(static_cast<double>(hi[k]));
    big = a > big ? a : big;
  }
  radius = radius * (1.0 + 1e-15) + 1e-15 * big + 1e-300;
  double off[3];
  for (int k = 0; k < 3; ++k) off[k] = w[k] - origin[k];
  for (int c = 0; c < 9; ++c) v.map[c] = s.l_float[c];
  const double row = s.row;
  for (int k = 0; k < 3; ++k) v.map[9 + k] = static_cast<float>(off[k]);
  const double off_max = amax(off);
  const double p = kU * (6.1 * row * radius + 5.1 * off_max) + 2e-15 * (s.size + amax(origin)) + 1e-300;
  v.perturb = float_up(p);
  return (row * radius * (1.0 + 1e-6) + off_max + p) * (1.0 + 1e-6);
}

}  // namespace

LeafSide make_leaf_side(const float* soa, std::size_t stride, const double* l, const double* t,
                        double size) noexcept {
  LeafSide s;
  s.soa = soa;
  s.stride = stride;
  s.size = size;
  if (l == nullptr) return s;
  s.l = l;
  s.t = t;
  for (int c = 0; c < 9; ++c) s.l_float[c] = static_cast<float>(l[c]);
  s.row = 0.0;
  for (int r = 0; r < 3; ++r) {
    const double sum = std::fabs(l[3 * r]) + std::fabs(l[3 * r + 1]) + std::fabs(l[3 * r + 2]);
    s.row = sum > s.row ? sum : s.row;
  }
  return s;
}

void make_leaf_pair(const LeafSide& a, std::uint32_t first_a, int count_a, const float* lo_a,
                    const float* hi_a, const LeafSide& b, std::uint32_t first_b, int count_b,
                    const float* lo_b, const float* hi_b, LeafPairInput& in) noexcept {
  double oa[3], ob[3], wa[3], wb[3];
  leaf_origin(lo_a, hi_a, oa);
  leaf_origin(lo_b, hi_b, ob);
  apply(a, oa, wa);
  apply(b, ob, wb);
  const double ea = view(a, first_a, count_a, lo_a, hi_a, wa, wa, in.a);
  const double eb = view(b, first_b, count_b, lo_b, hi_b, wb, wa, in.b);
  in.extent = float_up(ea > eb ? ea : eb);
  for (int k = 0; k < 3; ++k) in.axis[k] = in.b.map[9 + k];
}

}  // namespace plancheck
