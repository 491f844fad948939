// SPDX-License-Identifier: MIT
// Float prefilters for the triangle pairs of two BVH leaves, several pairs at
// once in SIMD lanes: one triangle of leaf A against leaf B's triangles stored
// SoA. They never decide a verdict; they only prove pairs far enough apart to
// skip the exact double kernels (kernels/tri_tri_overlap.h, tri_distance.h).
//
// Data. Each model stores its triangles once as floats, SoA over the BVH's
// slot order, each leaf's vertices relative to the centre o of its node box
// (store_leaf_soa; derived from the canonical leaves, not a second builder).
// A query side maps them into the pair's working frame with x = L v + off in
// float, relative to O, the working-frame image of leaf A's centre; only
// pairs that survive are ever mapped in double.
//
// Bound. For ANY vector n, the gap between the spans of two triangles on n,
// divided by |n|, is a lower bound of their distance (separating axis). The
// kernels use the triangle boxes' axes (combined as the Euclidean box gap),
// both triangles' normals and the centre-to-centre axis. The normals are
// computed in float from float vertices, but since any n gives a valid bound,
// only the rounding of the inputs and of the projections must be covered.
// Let u = 2^-24, x the working-frame double coordinate the exact kernels see
// (minus O), x~ the kernel's float value, L (extent) >= |x|, |x~|:
//  - per side, |x~ - x| <= P (perturb): storage u' R (R >= |v - o|, u' = u (1
//    + 2^-29)), L's rounding u S R (S: the map's largest row |.|-sum), the
//    float map 4.001 u (S R + |off|), off's rounding u |off| and the double
//    rounding of the working coordinates and of off, 2e-15 (map size + |O|);
//    make_leaf_pair sets P = u (6.1 S R + 5.1 |off|) + that last term.
//  - box axes: a gap errs by <= P_a + P_b + 2 u L; the kernels subtract
//    (P_a + P_b)(1 + 2^-10) + 8 u L, which also covers that subtraction.
//  - other axes are scaled so max |n_k| = 1, so |n|_1 <= 3: a three-term dot
//    product errs by <= 9.01 u L + 3 P, a gap by the sum over both triangles
//    plus 6 u L; the kernels subtract 3 (P_a + P_b)(1 + 2^-10) + 40 u L.
//  - the squares and the product with 1 / |n|^2 (|n|^2 >= 1, reciprocal and
//    sum of squares rounded) err by < 8 u relative; the result is scaled by
//    (1 - 2^-18) = (1 - 64 u).
// Values below 1e-30 (distances below 1e-15) are reported as 0, so underflow
// never matters; extents above 1e9 or not finite give no bound at all (0),
// so nothing can overflow. Hence: lower2[i][j] <= the exact squared distance
// between the double triangles, and a positive gap proves them disjoint,
// hence not touching (the exact overlap test would say false).
#pragma once

#include <cstddef>
#include <cstdint>

namespace plancheck {

inline constexpr int kLeafLanes = 16;  // the BVH's maximum leaf size (src/geometry/bvh.h)
// Slots of padding after each coordinate row of a model's SoA, so that a
// 16-lane load at any leaf stays inside the array.
inline constexpr std::size_t kSoaPadding = kLeafLanes;

// One leaf of one side as the kernels read it.
struct LeafView {
  const float* soa = nullptr;  // coordinate c of triangle t at soa[c * stride + t] (c = 3 v + k)
  std::size_t stride = 0;
  int count = 0;               // triangles (1..16); lanes past it are ignored
  float map[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};  // L row-major, then off: x = L v + off
  float perturb = 0.0f;        // P (m), see above
};

struct LeafPairInput {
  LeafView a, b;
  float extent = 0.0f;        // L (m), see above
  float axis[3] = {0, 0, 0};  // extra separating axis (centre to centre); 0: none
};

struct LeafPairBounds {
  // Squared distance lower bound of (a_i, b_j) (m^2); 0 when nothing is
  // proven. A pair whose box bound alone reaches cut2 gets that box bound.
  // Lanes j >= b.count are unspecified.
  alignas(64) float lower2[kLeafLanes][kLeafLanes];
  // Bit j of candidates[i]: (a_i, b_j) may be closer than the cut given
  // (lower2 < cut2); bits j >= b.count are clear.
  std::uint32_t candidates[kLeafLanes];
};

// One instruction set's kernels.
struct LeafKernels {
  const char* name;   // "scalar", "sse4.2", "avx2", "avx512"
  int width;          // lanes per register
  // touch[i] bit j: (a_i, b_j) not proven disjoint (the exact test must decide).
  void (*touch_masks)(const LeafPairInput& in, std::uint32_t* touch) noexcept;
  // lower2 for every pair and candidates against cut2 (squared, m^2).
  void (*lower_bounds)(const LeafPairInput& in, float cut2, LeafPairBounds& out) noexcept;
  // touch_masks without its row and column pre-pass (the same bits; tests
  // compare the two).
  void (*touch_masks_all)(const LeafPairInput& in, std::uint32_t* touch) noexcept;
  // tri_distance_disjoint2 (kernels/tri_distance.h) bitwise, its candidate
  // feature pairs in double lanes (kernels/tri_distance_lanes.h): squared
  // distance of triangles p, q (9 doubles each), closest points to p_out,
  // q_out (3 doubles each).
  double (*tri_distance2)(const double* p, const double* q, double* p_out, double* q_out) noexcept;
};

// A model's side of a query, for make_leaf_pair; made by make_leaf_side,
// which also fills the map's constants that do not depend on the leaf.
struct LeafSide {
  const float* soa = nullptr;  // the model's SoA (store_leaf_soa)
  std::size_t stride = 0;
  const double* l = nullptr;   // working-frame map x -> l x + t, l row-major; nullptr: identity
  const double* t = nullptr;
  double size = 0.0;           // >= |l v| + |t| per coordinate for every vertex v (m)
  float l_float[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};  // l rounded to float (LeafView::map's L)
  double row = 1.0;            // S: l's largest row |.|-sum (1 for the identity)
};

// The side for a query: l_float and row from l. A query makes it once; a
// leaf pair then only maps its leaves' centres (per leaf pair on cold
// states of the default scene these constants were 4% of the profile).
LeafSide make_leaf_side(const float* soa, std::size_t stride, const double* l, const double* t,
                        double size) noexcept;

// The input for leaves [first_a, first_a + count_a) of a (node box lo_a,
// hi_a) and likewise of b (baseline double arithmetic; see the bound above).
void make_leaf_pair(const LeafSide& a, std::uint32_t first_a, int count_a, const float* lo_a,
                    const float* hi_a, const LeafSide& b, std::uint32_t first_b, int count_b,
                    const float* lo_b, const float* hi_b, LeafPairInput& in) noexcept;

// Writes a leaf's triangles into a model's SoA: vertex v of slot first + t is
// corner(first + t, v) (3 doubles), stored as float(x - o), o the centre of the
// node box [lo, hi] (which must contain the vertices).
template <class Corner>
void store_leaf_soa(float* soa, std::size_t stride, std::uint32_t first, int count,
                    const float* lo, const float* hi, Corner corner) noexcept;

// Leaf origin o: the centre of the node box, in double.
inline void leaf_origin(const float* lo, const float* hi, double* o) noexcept {
  for (int k = 0; k < 3; ++k)
    o[k] = 0.5 * (static_cast<double>(lo[k]) + static_cast<double>(hi[k]));
}

template <class Corner>
void store_leaf_soa(float* soa, std::size_t stride, std::uint32_t first, int count,
                    const float* lo, const float* hi, Corner corner) noexcept {
  double o[3];
  leaf_origin(lo, hi, o);
  for (int t = 0; t < count; ++t)
    for (int v = 0; v < 3; ++v) {
      const double* x = corner(first + static_cast<std::uint32_t>(t), v);
      for (int k = 0; k < 3; ++k)
        soa[static_cast<std::size_t>(3 * v + k) * stride + first + static_cast<std::size_t>(t)] =
            static_cast<float>(x[k] - o[k]);
    }
}

enum class Isa { kScalar = 0, kSse42 = 1, kAvx2 = 2, kAvx512 = 3 };
inline constexpr int kIsaCount = 4;

// The kernels of one instruction set, or nullptr when this CPU (or this
// build) lacks it. kScalar is always there.
const LeafKernels* leaf_kernels_for(Isa isa) noexcept;

// Kernels that prove nothing: every pair goes on to the double path, as
// before these prefilters existed. The reference for "no answer changes"
// tests, and PLANCHECK_ISA=none for before/after measurements.
const LeafKernels& leaf_kernels_none() noexcept;

// The kernels every query uses: chosen once, on first call, as the widest the
// CPU supports (none when it has no SSE4.2: the scalar prefilter is slower
// than the double path alone), or as named by the environment variable
// PLANCHECK_ISA (none, scalar, sse4.2, avx2, avx512; an unsupported or
// unknown name falls back to the default, with a one-line warning on stderr).
const LeafKernels& leaf_kernels() noexcept;

// Tests and benchmarks only: makes leaf_kernels() return k from now on (and
// returns the previous choice). Not synchronised with running queries.
const LeafKernels& set_leaf_kernels(const LeafKernels& k) noexcept;

}  // namespace plancheck
