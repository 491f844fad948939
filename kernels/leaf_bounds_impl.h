// SPDX-License-Identifier: MIT
// The leaf-pair prefilters of kernels/leaf_bounds.h written once over the lane
// type; included only by kernels/leaf_bounds_<isa>.cpp, each of which
// instantiates them with its own width and a private tag. The error bounds
// are derived in kernels/leaf_bounds.h.
#pragma once

#include "kernels/lanes.h"
#include "kernels/leaf_bounds.h"
#include "kernels/tri_distance_lanes.h"

#include <bit>

namespace plancheck::leaf_bounds_detail {
// Internal linkage for everything here, templates or not: each including
// file is compiled with different instruction-set flags (see lanes.h).
namespace {

inline constexpr float kUnit = 0x1p-24f;           // u, unit roundoff of float
inline constexpr float kBoxSlack = 8.0f * kUnit;    // box-axis gap error / extent
inline constexpr float kAxisSlack = 40.0f * kUnit;  // scaled-axis gap error / extent
inline constexpr float kPerturbFactor = 1.0f + 0x1p-10f;
inline constexpr float kRoundUp = 1.0f + 0x1p-20f;  // covers the rounding of the slacks' sums
inline constexpr float kShrink = 1.0f - 0x1p-18f;   // covers squaring and division
inline constexpr float kTiny = 1e-30f;              // below: reported as 0
inline constexpr float kMaxExtent = 1e9f;           // above: no bound at all

// One leaf's triangles in the working frame (minus O), lanes over triangles.
struct Mapped {
  alignas(64) float c[9][kLeafLanes];
};

// x = L v + off per lane, in this order (the bound counts four roundings).
template <class F>
inline void map_leaf(const LeafView& v, Mapped& out) noexcept {
  constexpr int W = F::kWidth;
  F m[12];
  for (int k = 0; k < 12; ++k) m[k] = F::broadcast(v.map[k]);
  for (int t = 0; t < v.count; t += W) {
    for (int vert = 0; vert < 3; ++vert) {
      const F x = F::load(v.soa + static_cast<std::size_t>(3 * vert) * v.stride + t);
      const F y = F::load(v.soa + static_cast<std::size_t>(3 * vert + 1) * v.stride + t);
      const F z = F::load(v.soa + static_cast<std::size_t>(3 * vert + 2) * v.stride + t);
      for (int r = 0; r < 3; ++r)
        (m[3 * r] * x + m[3 * r + 1] * y + m[3 * r + 2] * z + m[9 + r]).store(&out.c[3 * vert + r][t]);
    }
  }
}

// Per-triangle data of one leaf, lanes over its triangles.
struct LeafData {
  alignas(64) float lo[3][kLeafLanes], hi[3][kLeafLanes];  // box
  alignas(64) float n[3][kLeafLanes];                     // normal scaled to max |n_k| = 1, or 0
  alignas(64) float inv_n2[kLeafLanes];                   // 1 / |n|^2 rounded (<= 1), 1 when n = 0
  alignas(64) float own_lo[kLeafLanes], own_hi[kLeafLanes];    // span of its vertices on n
  alignas(64) float axis_lo[kLeafLanes], axis_hi[kLeafLanes];  // span on the extra axis
};

template <class F>
inline F dot(F nx, F ny, F nz, F x, F y, F z) noexcept {
  return nx * x + ny * y + nz * z;
}

// The extra axis scaled so its largest component is 1 (or all zero), and its
// squared length (1 for the zero axis).
inline void scale_axis(const float* in, float* out, float& len2) noexcept {
  float s = 0.0f;
  for (int k = 0; k < 3; ++k) {
    const float a = in[k] < 0.0f ? -in[k] : in[k];
    s = a > s ? a : s;
  }
  if (!(s > kTiny) || !(s < 1e30f)) {
    out[0] = out[1] = out[2] = 0.0f;
    len2 = 1.0f;
    return;
  }
  for (int k = 0; k < 3; ++k) out[k] = in[k] / s;
  len2 = out[0] * out[0] + out[1] * out[1] + out[2] * out[2];
}

// The triangles' boxes only (LeafData::lo, hi).
template <class F>
inline void leaf_boxes(const Mapped& leaf, int count, LeafData& d) noexcept {
  constexpr int W = F::kWidth;
  for (int t = 0; t < count; t += W)
    for (int k = 0; k < 3; ++k) {
      const F x = F::load(&leaf.c[k][t]), y = F::load(&leaf.c[3 + k][t]), z = F::load(&leaf.c[6 + k][t]);
      min(min(x, y), z).store(&d.lo[k][t]);
      max(max(x, y), z).store(&d.hi[k][t]);
    }
}

// The rest of LeafData (normals, spans), after leaf_boxes.
template <class F>
inline void leaf_normals(const Mapped& leaf, int count, const float* axis, LeafData& d) noexcept {
  constexpr int W = F::kWidth;
  const F ax = F::broadcast(axis[0]), ay = F::broadcast(axis[1]), az = F::broadcast(axis[2]);
  const F zero = F::broadcast(0.0f), one = F::broadcast(1.0f), tiny = F::broadcast(kTiny);
  for (int t = 0; t < count; t += W) {
    F v[9];
    for (int c = 0; c < 9; ++c) v[c] = F::load(&leaf.c[c][t]);
    const F ux = v[3] - v[0], uy = v[4] - v[1], uz = v[5] - v[2];
    const F wx = v[6] - v[0], wy = v[7] - v[1], wz = v[8] - v[2];
    F nx = uy * wz - uz * wy, ny = uz * wx - ux * wz, nz = ux * wy - uy * wx;
    const F s = max(max(abs(nx), abs(ny)), abs(nz));
    const auto proper = s.v > tiny.v;
    const F safe = select(proper, s, one);
    nx = select(proper, nx / safe, zero);
    ny = select(proper, ny / safe, zero);
    nz = select(proper, nz / safe, zero);
    nx.store(&d.n[0][t]);
    ny.store(&d.n[1][t]);
    nz.store(&d.n[2][t]);
    // One division per triangle, not per pair; its rounding (u) is
    // covered by kShrink.
    (one / select(proper, nx * nx + ny * ny + nz * nz, one)).store(&d.inv_n2[t]);
    const F p0 = dot(nx, ny, nz, v[0], v[1], v[2]);
    const F p1 = dot(nx, ny, nz, v[3], v[4], v[5]);
    const F p2 = dot(nx, ny, nz, v[6], v[7], v[8]);
    min(min(p0, p1), p2).store(&d.own_lo[t]);
    max(max(p0, p1), p2).store(&d.own_hi[t]);
    const F q0 = dot(ax, ay, az, v[0], v[1], v[2]);
    const F q1 = dot(ax, ay, az, v[3], v[4], v[5]);
    const F q2 = dot(ax, ay, az, v[6], v[7], v[8]);
    min(min(q0, q1), q2).store(&d.axis_lo[t]);
    max(max(q0, q1), q2).store(&d.axis_hi[t]);
  }
}

template <class F>
inline void leaf_data(const Mapped& leaf, int count, const float* axis, LeafData& d) noexcept {
  leaf_boxes<F>(leaf, count, d);
  leaf_normals<F>(leaf, count, axis, d);
}

inline std::uint32_t lane_mask(int count) noexcept {
  return count >= 32 ? ~0u : ((1u << count) - 1u);
}

// Lane l of the result is true when bit t + l of m is set.
template <class F>
inline typename F::M lanes_in(std::uint32_t m, int t) noexcept {
  using M = typename F::M;
  alignas(64) static constexpr std::int32_t kIota[kLeafLanes] = {0, 1, 2,  3,  4,  5,  6,  7,
                                                                 8, 9, 10, 11, 12, 13, 14, 15};
  M idx;
  __builtin_memcpy(&idx, kIota, sizeof(M));
  const M bits = ((M{} + static_cast<std::int32_t>(m >> t)) >> idx) & 1;
  return bits != 0;
}

// Smallest (kMax false) or largest lane: a tree of shuffles (the serial
// scalar loops these replace were ~20% of touch_masks, bound by the latency
// of their min/max chains).
template <bool kMax, class F>
inline float lane_extreme(F x) noexcept {
  constexpr int W = F::kWidth;
  const auto pick = [](F a, F b) {
    if constexpr (kMax)
      return max(a, b);
    else
      return min(a, b);
  };
  auto v = x.v;
  if constexpr (W >= 16)
    v = pick(F{v}, F{__builtin_shufflevector(v, v, 8, 9, 10, 11, 12, 13, 14, 15, 0, 1, 2, 3, 4, 5, 6, 7)}).v;
  if constexpr (W >= 8) {
    if constexpr (W == 8)
      v = pick(F{v}, F{__builtin_shufflevector(v, v, 4, 5, 6, 7, 0, 1, 2, 3)}).v;
    else
      v = pick(F{v}, F{__builtin_shufflevector(v, v, 4, 5, 6, 7, 0, 1, 2, 3, 12, 13, 14, 15, 8, 9, 10, 11)}).v;
  }
  if constexpr (W >= 4) {
    float r = v[0];
    for (int l = 1; l < 4; ++l) r = (kMax ? v[l] > r : v[l] < r) ? v[l] : r;
    return r;
  }
  return v[0];
}

template <class F>
inline float lane_min(F x) noexcept {
  return lane_extreme<false>(x);
}

template <class F>
inline float lane_max(F x) noexcept {
  return lane_extreme<true>(x);
}

// Union of the boxes of the triangles in mask m (not empty). The same set
// of finite floats as a scalar loop would take its minimum and maximum of,
// so the same values (a zero may come out with the other sign, which no
// comparison in near_union can tell apart).
template <class F>
inline void masked_union_box(const LeafData& d, std::uint32_t m, float* lo, float* hi) noexcept {
  constexpr int W = F::kWidth;
  const int first = std::countr_zero(m), last = 32 - std::countl_zero(m);
  for (int k = 0; k < 3; ++k) {
    F l = F::broadcast(d.lo[k][first]), h = F::broadcast(d.hi[k][first]);
    for (int t = first / W * W; t < last; t += W) {
      const auto in = lanes_in<F>(m, t);
      l = min(l, select(in, F::load(&d.lo[k][t]), l));
      h = max(h, select(in, F::load(&d.hi[k][t]), h));
    }
    lo[k] = lane_min(l);
    hi[k] = lane_max(h);
  }
}

// Bit t set when triangle t's box is not separated from the box [lo, hi]
// by more than slack on any axis, computed as pair_gaps computes a box gap.
// Float subtraction is monotonic, so a triangle of one leaf separated from
// the union of the other leaf's triangle boxes is separated, by the very
// same test, from each of those triangles' boxes: such a row or column of
// touch_masks is all clear, and skipping it changes no bit.
template <class F>
inline std::uint32_t near_union(const LeafData& d, int count, const float* lo, const float* hi,
                                float slack) noexcept {
  constexpr int W = F::kWidth;
  const F s = F::broadcast(slack), zero = F::broadcast(0.0f);
  std::uint32_t apart = 0;
  for (int t = 0; t < count; t += W) {
    F sep = zero;
    for (int k = 0; k < 3; ++k) {
      const F g1 = F::broadcast(lo[k]) - F::load(&d.hi[k][t]), g2 = F::load(&d.lo[k][t]) - F::broadcast(hi[k]);
      const F gap = max(g1, g2) - s;
      sep = k == 0 ? gap : max(sep, gap);
    }
    apart |= lanes::movemask<F>(sep.v > zero.v) << t;
  }
  return ~apart & lane_mask(count);
}

// Gaps of a_i against the lanes t.. of b, each already reduced by its error
// bound (so > 0 proves separation on that axis): the three box axes, b's
// normals, a_i's normal and the extra axis.
template <class F>
struct Gaps {
  F box[3], nb, na, ax;
};

// kColumns false: a's triangle `one` (broadcast) against b's lanes t.. ;
// true: b's triangle `one` (broadcast) against a's lanes t.. . Every gap is
// the same expression on the same operands either way (only which operand
// is broadcast differs), so each pair's separation has the same bits
// whichever way touch_masks computes it.
template <class F, bool kColumns = false>
inline Gaps<F> pair_gaps(const Mapped& ma, const Mapped& mb, const LeafData& da,
                         const LeafData& db, int one, int t, float box_slack_s,
                         float axis_slack_s) noexcept {
  const auto a = [&](const float* row) {
    if constexpr (kColumns)
      return F::load(row + t);
    else
      return F::broadcast(row[one]);
  };
  const auto b = [&](const float* row) {
    if constexpr (kColumns)
      return F::broadcast(row[one]);
    else
      return F::load(row + t);
  };
  const F box_slack = F::broadcast(box_slack_s);
  const F axis_slack = F::broadcast(axis_slack_s);
  Gaps<F> g;
  for (int k = 0; k < 3; ++k) {
    const F blo = b(db.lo[k]), bhi = b(db.hi[k]);
    const F alo = a(da.lo[k]), ahi = a(da.hi[k]);
    g.box[k] = max(blo - ahi, alo - bhi) - box_slack;
  }
  // a's vertices on b's normals.
  {
    const F nx = b(db.n[0]), ny = b(db.n[1]), nz = b(db.n[2]);
    F p[3];
    for (int v = 0; v < 3; ++v) p[v] = dot(nx, ny, nz, a(ma.c[3 * v]), a(ma.c[3 * v + 1]), a(ma.c[3 * v + 2]));
    const F lo = min(min(p[0], p[1]), p[2]), hi = max(max(p[0], p[1]), p[2]);
    g.nb = max(lo - b(db.own_hi), b(db.own_lo) - hi) - axis_slack;
  }
  // b's vertices on a's normals.
  {
    const F nx = a(da.n[0]), ny = a(da.n[1]), nz = a(da.n[2]);
    F p[3];
    for (int v = 0; v < 3; ++v) p[v] = dot(nx, ny, nz, b(mb.c[3 * v]), b(mb.c[3 * v + 1]), b(mb.c[3 * v + 2]));
    const F lo = min(min(p[0], p[1]), p[2]), hi = max(max(p[0], p[1]), p[2]);
    g.na = max(lo - a(da.own_hi), a(da.own_lo) - hi) - axis_slack;
  }
  g.ax = max(b(db.axis_lo) - a(da.axis_hi), a(da.axis_lo) - b(db.axis_hi)) - axis_slack;
  return g;
}

template <class F>
inline F separation(const Gaps<F>& g) noexcept {
  return max(max(max(g.box[0], g.box[1]), max(g.box[2], g.nb)), max(g.na, g.ax));
}

inline bool usable_extent(float extent) noexcept { return extent <= kMaxExtent; }  // false for NaN

// kRows: first find the columns whose triangle box meets a's union box and
// the rows whose triangle box meets the union of those columns' boxes
// (near_union; a row is needed only against columns that can still touch);
// only those are tested, and a leaf pair with none left is done before any
// normal is computed. The pairs left are then tested row by row (a_i against
// b's lanes) or column by column (b_j against a's lanes), whichever takes
// fewer register passes: on the default scene's colliding cold states the
// leaf pairs that reach the pair test have ~11 rows but ~3 columns left.
// Every bit is the same as without any of this (kRows false: the reference
// the tests compare with).
template <class F, bool kRows>
void touch_masks(const LeafPairInput& in, std::uint32_t* touch) noexcept {
  constexpr int W = F::kWidth;
  const std::uint32_t valid = lane_mask(in.b.count);
  if (!usable_extent(in.extent)) {
    for (int i = 0; i < in.a.count; ++i) touch[i] = valid;
    return;
  }
  const float perturb = (in.a.perturb + in.b.perturb) * kPerturbFactor;
  const float box_slack = (perturb + kBoxSlack * in.extent) * kRoundUp;
  const float axis_slack = (3.0f * perturb + kAxisSlack * in.extent) * kRoundUp;
  float axis[3], axis2;
  scale_axis(in.axis, axis, axis2);
  Mapped ma, mb;
  map_leaf<F>(in.a, ma);
  map_leaf<F>(in.b, mb);
  LeafData da, db;
  leaf_boxes<F>(ma, in.a.count, da);
  leaf_boxes<F>(mb, in.b.count, db);
  std::uint32_t rows = lane_mask(in.a.count), cols = valid;
  if constexpr (kRows) {
    float lo[3], hi[3];
    masked_union_box<F>(da, rows, lo, hi);
    cols = near_union<F>(db, in.b.count, lo, hi, box_slack);
    if (cols != 0) {
      masked_union_box<F>(db, cols, lo, hi);
      rows = near_union<F>(da, in.a.count, lo, hi, box_slack);
    }
    if (rows == 0 || cols == 0) {
      for (int i = 0; i < in.a.count; ++i) touch[i] = 0;
      return;
    }
  }
  leaf_normals<F>(ma, in.a.count, axis, da);
  leaf_normals<F>(mb, in.b.count, axis, db);
  const F zero = F::broadcast(0.0f);
  const int passes_a = (in.a.count + W - 1) / W, passes_b = (in.b.count + W - 1) / W;
  if (kRows && std::popcount(cols) * passes_a < std::popcount(rows) * passes_b) {
    for (int i = 0; i < in.a.count; ++i) touch[i] = 0;
    for (std::uint32_t c = cols; c != 0; c &= c - 1) {
      const int j = std::countr_zero(c);
      for (int t = 0; t < kLeafLanes && t < in.a.count; t += W) {
        const F sep = separation(pair_gaps<F, true>(ma, mb, da, db, j, t, box_slack, axis_slack));
        for (std::uint32_t m = (lanes::movemask<F>(sep.v <= zero.v) << t) & rows; m != 0; m &= m - 1)
          touch[std::countr_zero(m)] |= 1u << j;
      }
    }
    return;
  }
  for (int i = 0; i < in.a.count; ++i) {
    std::uint32_t m = 0;
    if ((rows >> i) & 1u)
      for (int t = 0; t < kLeafLanes && t < in.b.count; t += W) {
        const F sep = separation(pair_gaps<F>(ma, mb, da, db, i, t, box_slack, axis_slack));
        m |= lanes::movemask<F>(sep.v <= zero.v) << t;
      }
    touch[i] = m & cols;
  }
}

template <class F>
void lower_bounds(const LeafPairInput& in, float cut2, LeafPairBounds& out) noexcept {
  constexpr int W = F::kWidth;
  const std::uint32_t valid = lane_mask(in.b.count);
  if (!usable_extent(in.extent)) {
    for (int i = 0; i < in.a.count; ++i) {
      for (int t = 0; t < kLeafLanes; ++t) out.lower2[i][t] = 0.0f;
      out.candidates[i] = valid;
    }
    return;
  }
  float axis[3], axis2;
  scale_axis(in.axis, axis, axis2);
  Mapped ma, mb;
  map_leaf<F>(in.a, ma);
  map_leaf<F>(in.b, mb);
  LeafData da, db;
  leaf_data<F>(ma, in.a.count, axis, da);
  leaf_data<F>(mb, in.b.count, axis, db);
  const float perturb = (in.a.perturb + in.b.perturb) * kPerturbFactor;
  const float box_slack = (perturb + kBoxSlack * in.extent) * kRoundUp;
  const float axis_slack = (3.0f * perturb + kAxisSlack * in.extent) * kRoundUp;
  const F zero = F::broadcast(0.0f), tiny = F::broadcast(kTiny), shrink = F::broadcast(kShrink);
  const F cut = F::broadcast(cut2), inv_ax2 = F::broadcast(1.0f / axis2);
  for (int i = 0; i < in.a.count; ++i) {
    std::uint32_t m = 0;
    const F inv_na2 = F::broadcast(da.inv_n2[i]);
    for (int t = 0; t < kLeafLanes && t < in.b.count; t += W) {
      // Box bound first. A lane whose box bound reaches the cut keeps it
      // (a valid, if weaker, bound; the lane is no candidate either way);
      // the rule is per lane, so every width stores the same values, and a
      // register whose valid lanes all reach the cut skips the rest.
      F box_lb;
      {
        F bsum = zero;
        const F slack = F::broadcast(box_slack);
        for (int k = 0; k < 3; ++k) {
          const F blo = F::load(&db.lo[k][t]), bhi = F::load(&db.hi[k][t]);
          const F alo = F::broadcast(da.lo[k][i]), ahi = F::broadcast(da.hi[k][i]);
          const F gk = max(max(blo - ahi, alo - bhi) - slack, zero);
          bsum = bsum + gk * gk;
        }
        box_lb = bsum * shrink;
        box_lb = select(box_lb.v < tiny.v, zero, box_lb);
      }
      const auto box_far = box_lb.v >= cut.v;
      const std::uint32_t lanes_here = (valid >> t) & lane_mask(W);
      if ((lanes::movemask<F>(box_far) & lanes_here) == lanes_here) {
        box_lb.store(&out.lower2[i][t]);
        continue;
      }
      const Gaps<F> g = pair_gaps<F>(ma, mb, da, db, i, t, box_slack, axis_slack);
      const F bx = max(g.box[0], zero), by = max(g.box[1], zero), bz = max(g.box[2], zero);
      F lb = bx * bx + by * by + bz * bz;
      const F nb = max(g.nb, zero), na = max(g.na, zero), ax = max(g.ax, zero);
      lb = max(lb, nb * nb * F::load(&db.inv_n2[t]));
      lb = max(lb, na * na * inv_na2);
      lb = max(lb, ax * ax * inv_ax2);
      lb = lb * shrink;
      lb = select(lb.v < tiny.v, zero, lb);
      lb = select(box_far, box_lb, lb);
      lb.store(&out.lower2[i][t]);
      m |= lanes::movemask<F>(lb.v < cut.v) << t;
    }
    out.candidates[i] = m & valid;
  }
}

// F: float lanes of the prefilters; D: double lanes of the triangle distance.
template <class F, class D>
constexpr LeafKernels make_kernels(const char* name) noexcept {
  return LeafKernels{name, F::kWidth, &touch_masks<F, true>, &lower_bounds<F>, &touch_masks<F, false>,
                     &tri_distance_lanes::disjoint2<D>};
}

}  // namespace
}  // namespace plancheck::leaf_bounds_detail
