// SPDX-License-Identifier: MIT
// Pair queries: BVH-vs-BVH traversal in one working frame, exact triangle
// overlap at the leaves, Ericson triangle distance with box lower bounds.
//
// Culling: when both parts sit rigidly in the working frame (the common case)
// node pairs are tested with the per-node oriented boxes (15-axis separating
// axis test; face and centre axes for distance bounds); otherwise with the
// axis-aligned node boxes mapped into the working frame (Arvo's enclosing
// box), plus the reverse mapping into b's frame when b's map is rigid. Every
// test is widened by a margin that covers rounding, so no pair holding
// touching triangles is culled. Leaf pairs: an exact per-triangle box filter
// before the overlap kernel; for distance separating-axis bounds on the
// actual vertices (among them the direction of the closest pair so far,
// kernels/direction_bound.h) before the distance kernel. distance() first runs the
// collision traversal (stop at first hit), since distance bounds cannot cull
// anything among pairs at distance 0.
//
// Working frame: a's frame when ta is rigid (b mapped by ta^-1 tb, distances
// there equal world distances); else b's frame when tb is rigid (roles
// swapped, results swapped back); else the world frame (both mapped). Only
// leaf triangles are mapped, never a whole mesh. Collision is decided exactly
// on the working-frame double coordinates: a's vertices as stored and b's as
// M v rounded once (identity maps leave coordinates untouched).
#include "src/geometry/collision_model.h"

#include "kernels/box.h"
#include "kernels/direction_bound.h"
#include "kernels/leaf_bounds.h"
#include "kernels/tri_distance.h"
#include "kernels/tri_tri_overlap.h"
#include "kernels/obb.h"
#include "kernels/pair_traversal.h"
#include "src/geometry/bvh.h"
#include "src/geometry/query_frame.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace plancheck {

CollisionModel::CollisionModel(const Mesh& mesh)
    : data_(std::make_shared<const CollisionModelData>(build_collision_data(mesh))) {}
CollisionModel::CollisionModel(std::shared_ptr<const CollisionModelData> data) : data_(std::move(data)) {}
CollisionModel::~CollisionModel() = default;
CollisionModel::CollisionModel(CollisionModel&&) noexcept = default;
CollisionModel& CollisionModel::operator=(CollisionModel&&) noexcept = default;

std::size_t CollisionModel::triangle_count() const { return data_->triangle_count(); }

std::size_t CollisionModel::memory_bytes() const {
  return sizeof(CollisionModelData) + data_->bvh.nodes.capacity() * sizeof(BvhNode) +
         data_->bvh.prim_ids.capacity() * sizeof(std::uint32_t) +
         data_->vertices.capacity() * sizeof(data_->vertices[0]) +
         data_->corners.capacity() * sizeof(data_->corners[0]) +
         data_->obbs.capacity() * sizeof(NodeObb) + data_->soa.capacity() * sizeof(float);
}

namespace {

// Relative size of tight_box's rounding margin (Side::tight_box): 90 u,
// against the 1e-12 (9,000 u) of the culling margins, so that a box gap
// proves something at the scale of the tie tolerance (1e-12 m).
constexpr double kTightRel = 1e-14;

// Prune a node pair only when its lower bound clears the best distance by
// more than the rounding of the squared box gaps.
constexpr double kShrink = 1.0 - 1e-12;

// One side of a query: its data, its map into the working frame and the
// margin that covers rounding of that map.
struct Side {
  const CollisionModelData* data = nullptr;
  bool identity = true;
  AffineMap map;
  double margin[3] = {0, 0, 0};
  // The rounding margin of tight_box (0 for the identity; infinite when
  // the map or the part's size is not finite, so nothing is proven).
  double tight_margin[3] = {0, 0, 0};

  void set_map(const Affine& t) {
    identity = t.matrix() == Affine::Identity().matrix();
    map = to_map(t);
    for (int r = 0; r < 3; ++r) {
      double s = std::abs(map.t[r]);
      // Node boxes are rounded outward to float: allow twice the vertex bound.
      for (int c = 0; c < 3; ++c) s += map.abs_l[3 * r + c] * 2.0 * data->max_abs[c];
      margin[r] = identity ? 0.0 : kMarginRel * s + 1e-300;
      tight_margin[r] = identity ? 0.0 : std::isfinite(s) ? kTightRel * s + 1e-300 : std::numeric_limits<double>::infinity();
    }
  }

  // A working-frame box holding every vertex of node's triangles exactly as
  // triangle() computes it (so every triangle box of the leaves below).
  // The identity: the node's float box, rounded outward from the stored
  // doubles at build. Else the float box [lo, hi] mapped (Arvo: centre c,
  // half extents h) and widened by tight_margin, which must cover, with
  // u = 2^-53 and S = |t_r| + sum_c |l_rc| 2 max_abs_c (>= the same with
  // |lo_c|, |hi_c| or a vertex's |x_c|): a vertex's own mapping (gamma_4 S),
  // the rounding of c and h (u |lo_c + hi_c| / 2 and u (hi_c - lo_c) / 2
  // each, 2 u S through |L|), the centre's mapping (gamma_4 S), the half
  // extents' (gamma_3 S) and the two subtractions here (about 2 u S): about
  // 14 u S, which kTightRel S = 90 u S covers six times over.
  void tight_box(std::uint32_t node, double* lo, double* hi) const {
    const BvhNode& n = data->bvh.nodes[node];
    if (identity) {
      for (int k = 0; k < 3; ++k) {
        lo[k] = static_cast<double>(n.lo[k]);
        hi[k] = static_cast<double>(n.hi[k]);
      }
      return;
    }
    double c[3], h[3];
    for (int k = 0; k < 3; ++k) {
      c[k] = 0.5 * (static_cast<double>(n.lo[k]) + static_cast<double>(n.hi[k]));
      h[k] = 0.5 * (static_cast<double>(n.hi[k]) - static_cast<double>(n.lo[k]));
    }
    for (int r = 0; r < 3; ++r) {
      const double cr = map.l[3 * r] * c[0] + map.l[3 * r + 1] * c[1] + map.l[3 * r + 2] * c[2] + map.t[r];
      const double hr = map.abs_l[3 * r] * h[0] + map.abs_l[3 * r + 1] * h[1] + map.abs_l[3 * r + 2] * h[2];
      lo[r] = cr - hr - tight_margin[r];
      hi[r] = cr + hr + tight_margin[r];
    }
  }

  void box(std::uint32_t node, double* lo, double* hi) const {
    const BvhNode& n = data->bvh.nodes[node];
    if (identity)
      widen_box(n.lo, n.hi, margin, lo, hi);
    else
      map_box(map, n.lo, n.hi, margin, lo, hi);
  }

  // This side for the SIMD leaf prefilters (kernels/leaf_bounds.h).
  LeafSide leaf_side() const {
    double size = 0.0;
    for (int r = 0; r < 3; ++r) {
      double row = identity ? data->max_abs[r] : std::abs(map.t[r]);
      if (!identity)
        for (int c = 0; c < 3; ++c) row += map.abs_l[3 * r + c] * data->max_abs[c];
      size = std::max(size, row);
    }
    return make_leaf_side(data->soa.data(), data->soa_stride, identity ? nullptr : map.l,
                          identity ? nullptr : map.t, size * (1.0 + 1e-6));
  }

  // Working-frame coordinates of the triangle in slot s. The identity's
  // copy element by element: std::copy of three doubles compiled to a call
  // of memmove (1.6% of cold full checks, with its PLT stub).
  void triangle(std::uint32_t s, double* out) const {
    for (int v = 0; v < 3; ++v) {
      const double* src = data->vertex(s, v);
      if (identity)
        for (int k = 0; k < 3; ++k) out[3 * v + k] = src[k];
      else
        map.apply(src, out + 3 * v);
    }
  }
};

struct Setup {
  Side a, b;
  bool swapped = false;
  Affine to_world = Affine::Identity();
  // Second culling frame: a's boxes mapped into b's own frame, against b's
  // untouched boxes (the other three face axes of the box-vs-box separating
  // axis test). Used when b's map is rigid, so distances agree there too.
  bool reverse = false;
  AffineMap rev;         // working frame of a -> b's frame (b.map^-1 * a.map)
  double rev_margin_a[3] = {0, 0, 0};
  double rev_margin_b[3] = {0, 0, 0};

  // Oriented-box tests, when both parts are placed rigidly in the working
  // frame (a untouched, b by a rigid map): then b's node boxes stay boxes.
  bool obb = false;
  double obb_tol = 0.0;  // b's vertex-mapping rounding (m), added to every gap test
  // Every rounding margin of both frames finite (aabb_disjoint).
  bool finite_margins = false;

  // Relative placement of b's node box in a's node box frame (Gottschalk's
  // R and T, kernels/obb.h), the centres' distance and the rounding
  // tolerance of the gap tests.
  struct ObbPair {
    ObbRelative rel;
    double dist_centres, tol;
  };
  // b's node ib in the working frame: its centre, and its axes once asked
  // for. A traversal step that splits a tests both children against the same
  // b node, and the ball test and the box test both need the centre, so one
  // mapping serves them all (the same operations, so the same values).
  struct MappedB {
    std::uint32_t node = 0;
    double cb[3];
    double bw[9];
    bool axes = false;
  };
  void map_b(std::uint32_t ib, MappedB& mb) const {
    mb.node = ib;
    mb.axes = false;
    b.map.apply(b.data->obbs[ib].center, mb.cb);
  }
  void map_b_axes(MappedB& mb) const {
    if (mb.axes) return;
    const NodeObb& ob = b.data->obbs[mb.node];
    const AffineMap& m = b.map;
    for (int j = 0; j < 3; ++j)  // b's axes in the working frame: rows of (L B^T)^T
      for (int r = 0; r < 3; ++r)
        mb.bw[3 * j + r] = m.l[3 * r] * ob.axis[3 * j] + m.l[3 * r + 1] * ob.axis[3 * j + 1] +
                           m.l[3 * r + 2] * ob.axis[3 * j + 2];
    mb.axes = true;
  }
  void obb_pair(std::uint32_t ia, std::uint32_t ib, ObbPair& p) const {
    MappedB mb;
    map_b(ib, mb);
    obb_pair(ia, mb, p);
  }
  void obb_pair(std::uint32_t ia, MappedB& mb, ObbPair& p) const {
    map_b_axes(mb);
    const NodeObb& oa = a.data->obbs[ia];
    const NodeObb& ob = b.data->obbs[mb.node];
    const double* bw = mb.bw;
    const double* cb = mb.cb;
    const double d[3] = {cb[0] - oa.center[0], cb[1] - oa.center[1], cb[2] - oa.center[2]};
    ObbRelative& q = p.rel;
    for (int i = 0; i < 3; ++i) {
      const double* ai = &oa.axis[3 * i];
      q.t[i] = ai[0] * d[0] + ai[1] * d[1] + ai[2] * d[2];
      for (int j = 0; j < 3; ++j) {
        const double* bj = &bw[3 * j];
        q.r[3 * i + j] = ai[0] * bj[0] + ai[1] * bj[1] + ai[2] * bj[2];
        // The epsilon keeps near-parallel edge-cross axes from false separation.
        q.abs_r[3 * i + j] = std::abs(q.r[3 * i + j]) + 1e-12;
      }
    }
    p.dist_centres = std::sqrt(q.t[0] * q.t[0] + q.t[1] * q.t[1] + q.t[2] * q.t[2]);
    const double ha = oa.half[0] + oa.half[1] + oa.half[2];
    const double hb = ob.half[0] + ob.half[1] + ob.half[2];
    p.tol = obb_tol + 1e-12 * (p.dist_centres + ha + hb +
                               std::abs(oa.center[0]) + std::abs(oa.center[1]) +
                               std::abs(oa.center[2]) + std::abs(cb[0]) + std::abs(cb[1]) +
                               std::abs(cb[2]));
  }

  // True when the nodes' axis-aligned boxes are proven apart, widened by
  // the rounding margins as the box-only culling uses them. Collide alone
  // (reach2 = 0) tests them in b's own frame only: a's box mapped there
  // (Arvo's enclosing box) against b's own. With reach2 > 0 (proven at
  // least sqrt(reach2) apart, by the bound the distance descent prunes
  // with, DistanceQuery::lower2), and for a pose whose rounding margins are
  // not finite, b's box mapped into the working frame is tested first too.
  // Why (2026-12-02): on random poses the working-frame test proved little
  // the reverse test and the oriented boxes did not, at half the cost
  // (callgrind, 2,000 random states, collide only: two meshes 61.9 -> 57.3
  // M instructions, the default arm 172.3 -> 163.0 M); but dropped for the
  // reach questions too it made the verdict-only checks of states along
  // planned paths (the OMPL bench's discrete validator, 5 cm margin) 10-14%
  // slower (default arm 40 -> 44 us a segment, URDF arm 29 -> 33 us). A
  // pose past the range of doubles keeps both: its working-frame boxes come
  // out NaN, which that test takes as apart, so no such pair reaches the
  // exact predicates (whose GMP fallback traps on an infinity; a state
  // check refuses such poses, tests ask them of collide() directly).
  bool aabb_disjoint(std::uint32_t ia, std::uint32_t ib, double reach2 = 0.0) const {
    if (!finite_margins || reach2 > 0.0) {
      double alo[3], ahi[3], blo[3], bhi[3];
      a.box(ia, alo, ahi);
      b.box(ib, blo, bhi);
      if (reach2 > 0.0) return reach_apart(box_distance_squared(alo, ahi, blo, bhi), ia, ib, reach2);
      return !boxes_overlap(alo, ahi, blo, bhi) || reverse_lower2(ia, ib) > 0.0;
    }
    return reverse_lower2(ia, ib) > 0.0;
  }

  // std::max(forward2, reverse_lower2(ia, ib)) * kShrink >= reach2, the
  // reverse frame's bound computed only when the forward one does not
  // settle it: the product with kShrink is monotone under rounding, so
  // fl(max(f, r) k) = max(fl(f k), fl(r k)); std::max keeps a NaN first
  // argument (false then) and drops a NaN second one (the forward test).
  // (The box-only descent's cull, OverlapQuery::disjoint.)
  bool reach_apart(double forward2, std::uint32_t ia, std::uint32_t ib, double reach2) const {
    if (forward2 * kShrink >= reach2) return true;
    if (std::isnan(forward2)) return false;
    return reverse_lower2(ia, ib) * kShrink >= reach2;
  }

  // True when the node boxes are proven disjoint (kernels/obb.h); with
  // reach > 0, farther apart than reach (obb_widen).
  bool obb_disjoint(std::uint32_t ia, std::uint32_t ib, double reach = 0.0) const {
    ObbPair p;
    obb_pair(ia, ib, p);
    return plancheck::obb_disjoint(p.rel, a.data->obbs[ia].half, b.data->obbs[ib].half, p.tol + obb_widen(reach));
  }

  // What a separating-axis test's tolerance grows by so that "disjoint"
  // proves the boxes more than reach apart: a gap on a face axis (unit, up
  // to rounding) is a distance; on an edge-cross axis a_i x b_j, of length
  // at most 1 (up to rounding) and projections of radii widened by abs_r's
  // epsilon, the gap as computed is at most the distance times that length.
  // The factor covers those roundings many times over.
  static double obb_widen(double reach) { return reach > 0.0 ? reach * (1.0 + 1e-9) : 0.0; }

  // Distance lower bound of the node boxes (kernels/obb.h).
  double obb_lower(std::uint32_t ia, MappedB& mb) const {
    ObbPair p;
    obb_pair(ia, mb, p);
    return plancheck::obb_lower(p.rel, p.dist_centres, a.data->obbs[ia].half, b.data->obbs[mb.node].half,
                                p.tol);
  }

  double obb_size(std::uint32_t ia, bool side_a) const {
    const NodeObb& o = side_a ? a.data->obbs[ia] : b.data->obbs[ia];
    return o.half[0] + o.half[1] + o.half[2];
  }

  // Squared lower bound from the reverse frame (0 when not in use).
  double reverse_lower2(std::uint32_t ia, std::uint32_t ib) const {
    if (!reverse) return 0.0;
    double alo[3], ahi[3], blo[3], bhi[3];
    const BvhNode& x = a.data->bvh.nodes[ia];
    const BvhNode& y = b.data->bvh.nodes[ib];
    map_box(rev, x.lo, x.hi, rev_margin_a, alo, ahi);
    widen_box(y.lo, y.hi, rev_margin_b, blo, bhi);
    return box_distance_squared(alo, ahi, blo, bhi);
  }
};

Setup make_setup(const CollisionModel& ma, const Affine& ta, const CollisionModel& mb,
                 const Affine& tb) {
  Setup s;
  const CollisionModelData* da = &ma.data();
  const CollisionModelData* db = &mb.data();
  Affine frame = Affine::Identity();
  Affine first = ta, second = tb;
  if (is_isometry(ta)) {
    frame = ta;
  } else if (is_isometry(tb)) {
    s.swapped = true;
    std::swap(da, db);
    std::swap(first, second);
    frame = first;
  }
  s.a.data = da;
  s.b.data = db;
  if (frame.matrix() == Affine::Identity().matrix()) {
    s.a.set_map(first);
    s.b.set_map(second);
  } else {
    const Affine inv = frame.inverse();
    s.a.set_map(Affine::Identity());
    s.b.set_map(inv * second);
  }
  s.to_world = frame;
  // Reverse frame when a is untouched and b's map is rigid (the common case:
  // two rigid parts); its rounding margins mirror those of the forward maps.
  if (s.a.identity && !s.b.identity) {
    Affine mb = Affine::Identity();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) mb.linear()(r, c) = s.b.map.l[3 * r + c];
      mb.translation()(r) = s.b.map.t[r];
    }
    if (is_isometry(mb)) {
      s.reverse = true;
      const Affine inv = mb.inverse();
      s.rev = to_map(inv);
      for (int r = 0; r < 3; ++r) {
        double sa = std::abs(s.rev.t[r]), sb = 0.0;
        for (int c = 0; c < 3; ++c) {
          sa += s.rev.abs_l[3 * r + c] * 2.0 * s.a.data->max_abs[c];
          // b's mapped vertices err by b.margin in the working frame; pulled
          // back through the rigid inverse that is at most the same again.
          sb += s.rev.abs_l[3 * r + c] * s.b.margin[c];
        }
        s.rev_margin_a[r] = kMarginRel * sa + 1e-300;
        s.rev_margin_b[r] = 2.0 * sb + 1e-300;
      }
      s.finite_margins = true;
      for (int r = 0; r < 3; ++r)
        s.finite_margins = s.finite_margins && std::isfinite(s.b.margin[r]) && std::isfinite(s.rev_margin_a[r]) &&
                           std::isfinite(s.rev_margin_b[r]);
      s.obb = !s.a.data->obbs.empty() && !s.b.data->obbs.empty();
      s.obb_tol = 2.0 * std::sqrt(s.b.margin[0] * s.b.margin[0] + s.b.margin[1] * s.b.margin[1] +
                                  s.b.margin[2] * s.b.margin[2]);
    }
  }
  return s;
}

double box_size(const double* lo, const double* hi) {
  return (hi[0] - lo[0]) + (hi[1] - lo[1]) + (hi[2] - lo[2]);
}

// Projects the leaves' triangles on the unit axis n from the centroid of a's
// vertices to b's: hi_a[i] = max over triangle i of a, lo_b[j] = min over
// triangle j of b. Then lo_b[j] - hi_a[i] - slack is a lower bound of the
// distance of the pair (a separating-axis gap); slack covers the rounding of
// the dot products. Returns slack (infinity when the axis is degenerate, so
// nothing is skipped).
double leaf_axis_bounds(const double (*ta)[9], std::uint32_t na, const double (*tb)[9],
                        std::uint32_t nb, double* hi_a, double* lo_b) {
  double ca[3] = {0, 0, 0}, cb[3] = {0, 0, 0}, big = 0.0;
  for (std::uint32_t i = 0; i < na; ++i)
    for (int v = 0; v < 3; ++v)
      for (int k = 0; k < 3; ++k) {
        ca[k] += ta[i][3 * v + k];
        big = std::max(big, std::abs(ta[i][3 * v + k]));
      }
  for (std::uint32_t j = 0; j < nb; ++j)
    for (int v = 0; v < 3; ++v)
      for (int k = 0; k < 3; ++k) {
        cb[k] += tb[j][3 * v + k];
        big = std::max(big, std::abs(tb[j][3 * v + k]));
      }
  double n[3];
  for (int k = 0; k < 3; ++k) n[k] = cb[k] / (3 * nb) - ca[k] / (3 * na);
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (!(len > 0.0) || !std::isfinite(len)) {
    std::fill(hi_a, hi_a + na, 0.0);
    std::fill(lo_b, lo_b + nb, 0.0);
    return std::numeric_limits<double>::infinity();
  }
  for (double& c : n) c /= len;
  for (std::uint32_t i = 0; i < na; ++i) {
    double h = -std::numeric_limits<double>::infinity();
    for (int v = 0; v < 3; ++v)
      h = std::max(h, n[0] * ta[i][3 * v] + n[1] * ta[i][3 * v + 1] + n[2] * ta[i][3 * v + 2]);
    hi_a[i] = h;
  }
  for (std::uint32_t j = 0; j < nb; ++j) {
    double l = std::numeric_limits<double>::infinity();
    for (int v = 0; v < 3; ++v)
      l = std::min(l, n[0] * tb[j][3 * v] + n[1] * tb[j][3 * v + 1] + n[2] * tb[j][3 * v + 2]);
    lo_b[j] = l;
  }
  // |n| = 1 to a few ulps; each dot product errs by < 4 eps * sqrt(3) * big,
  // and the difference of two by twice that: 1e-14 * big is ample.
  return 1e-14 * big + 1e-300;
}

// n[0..2]: the triangle's unit normal (zero for a zero-area triangle, so
// its gap is never positive); n[3], n[4]: the span of its own vertices on it.
void triangle_normal_span(const double* t, double* n) {
  const double ux = t[3] - t[0], uy = t[4] - t[1], uz = t[5] - t[2];
  const double vx = t[6] - t[0], vy = t[7] - t[1], vz = t[8] - t[2];
  double c[3] = {uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx};
  const double len = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
  if (!(len > 0.0) || !std::isfinite(len)) {
    std::fill(n, n + 5, 0.0);
    return;
  }
  // Any unit axis gives a valid bound; the rounding of this one only makes
  // it slightly less than the true normal, never wrong.
  for (int k = 0; k < 3; ++k) n[k] = c[k] / len;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int v = 0; v < 3; ++v) {
    const double d = n[0] * t[3 * v] + n[1] * t[3 * v + 1] + n[2] * t[3 * v + 2];
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  n[3] = lo;
  n[4] = hi;
}

// Gap between the spans of the normal's triangle and triangle t on the
// normal (a separating-axis lower bound of their distance before slack).
double normal_gap(const double* n, const double* t) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int v = 0; v < 3; ++v) {
    const double d = n[0] * t[3 * v] + n[1] * t[3 * v + 1] + n[2] * t[3 * v + 2];
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  return std::max(lo - n[4], n[3] - hi);
}

struct NodePair {
  std::uint32_t a, b;
  double lower2;  // squared distance lower bound (distance queries)
};

thread_local std::vector<NodePair> t_stack;


}  // namespace

namespace {

// Working-frame slots of the first intersecting pair found.
struct FirstHit {
  bool found = false;
  std::uint32_t slot_a = 0, slot_b = 0;
};

// One leaf's triangles in the working frame (the very doubles the exact
// test sees) with each one's plane, for box_clear_of_leaf.
struct LeafPlanes {
  std::uint32_t node = std::numeric_limits<std::uint32_t>::max();  // none yet
  std::uint32_t count = 0;
  double tri[kMaxLeafSize][9];
  double n[kMaxLeafSize][5];                  // normal (not unit; 0 if degenerate), its |.|_1, its |.|_2
  double lo[kMaxLeafSize], hi[kMaxLeafSize];  // span of the triangle's vertices on n
  double big = 0.0;                           // largest |coordinate| of the vertices
  bool finite = true;                         // every vertex coordinate and normal finite

  void fill(const Side& side, std::uint32_t node_index, const BvhNode& leaf) {
    node = node_index;
    count = leaf.count;
    big = 0.0;
    double sum = 0.0;  // finite only when every term is (an overflow to inf is refused as well)
    for (std::uint32_t i = 0; i < count; ++i) {
      double* t = tri[i];
      side.triangle(leaf.index + i, t);
      double* c = n[i];
      const double ux = t[3] - t[0], uy = t[4] - t[1], uz = t[5] - t[2];
      const double vx = t[6] - t[0], vy = t[7] - t[1], vz = t[8] - t[2];
      c[0] = uy * vz - uz * vy;
      c[1] = uz * vx - ux * vz;
      c[2] = ux * vy - uy * vx;
      c[3] = std::abs(c[0]) + std::abs(c[1]) + std::abs(c[2]);
      c[4] = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
      lo[i] = std::numeric_limits<double>::infinity();
      hi[i] = -lo[i];
      for (int v = 0; v < 3; ++v) {
        const double d = c[0] * t[3 * v] + c[1] * t[3 * v + 1] + c[2] * t[3 * v + 2];
        lo[i] = std::min(lo[i], d);
        hi[i] = std::max(hi[i], d);
        for (int k = 0; k < 3; ++k) big = std::max(big, std::abs(t[3 * v + k]));
      }
      sum += c[3] + c[4] + lo[i] - hi[i] + std::abs(t[0]) + std::abs(t[1]) + std::abs(t[2]) + std::abs(t[3]) +
             std::abs(t[4]) + std::abs(t[5]) + std::abs(t[6]) + std::abs(t[7]) + std::abs(t[8]);
    }
    finite = std::isfinite(sum);
  }
};

// The point of triangle t (9 doubles) closest to p, as Ericson's
// "Real-Time Collision Detection" (2005, 5.1.5) finds it by Voronoi regions,
// when it lies on an edge or a corner; false (q untouched) when it lies
// inside the face, where the triangle's plane is the better axis anyway.
// Only an axis for box_clear_of_leaf comes of it, and any axis is valid
// there, so its rounding (or a wrong region near a boundary) only weakens
// the bound, never makes it wrong.
bool closest_on_boundary(const double* p, const double* t, double* q) {
  const double* a = t;
  const double* b = t + 3;
  const double* c = t + 6;
  const double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double ac[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
  auto dot = [](const double* u, const double* v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; };
  auto set = [q](const double* o, const double* d, double w) {
    for (int k = 0; k < 3; ++k) q[k] = o[k] + w * d[k];
  };
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) {
    set(a, ab, 0.0);
    return true;
  }
  const double bp[3] = {p[0] - b[0], p[1] - b[1], p[2] - b[2]};
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) {
    set(b, ab, 0.0);
    return true;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    set(a, ab, d1 / (d1 - d3));
    return true;
  }
  const double cp[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) {
    set(c, ab, 0.0);
    return true;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    set(a, ac, d2 / (d2 - d6));
    return true;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    const double bc[3] = {c[0] - b[0], c[1] - b[1], c[2] - b[2]};
    set(b, bc, (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    return true;
  }
  return false;
}

// The axis from the triangle's point nearest the box centre c to c: where
// that point is on an edge or a corner (a small box beside a long
// triangle's rim), neither the plane nor the box's faces separate them,
// but this axis does once the box is small beside the gap. On n = c - q
// (not unit) the box reaches down to n . c - r, r = sum_k h_k |n . a_k|,
// and the triangle up to max_v n . v, so min_v n . (c - v) - r, over |n|,
// bounds their distance from below. The rounding as for the plane's normal in
// box_clear_of_leaf: slack (relative 1e-12) times |n|_1 on the
// projections, reach times |n|_2 (far: with its factor 1 + 1e-12). Each
// vertex is compared on its own, so a NaN projection fails.
bool clear_on_closest_axis(const double* t, const double* c, const double* ax, const double* h, double slack,
                           double far) {
  double q[3];
  if (!closest_on_boundary(c, t, q)) return false;
  const double n[3] = {c[0] - q[0], c[1] - q[1], c[2] - q[2]};
  const double n1 = std::abs(n[0]) + std::abs(n[1]) + std::abs(n[2]);
  const double n2 = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  double r = 0.0;
  for (int k = 0; k < 3; ++k) r += h[k] * std::abs(n[0] * ax[3 * k] + n[1] * ax[3 * k + 1] + n[2] * ax[3 * k + 2]);
  const double need = r + slack * n1 + far * n2;
  if (!std::isfinite(need) || !(n2 > 0.0)) return false;
  for (int v = 0; v < 3; ++v) {
    const double p = n[0] * (c[0] - t[3 * v]) + n[1] * (c[1] - t[3 * v + 1]) + n[2] * (c[2] - t[3 * v + 2]);
    if (!(p > need)) return false;
  }
  return true;
}

// True when every triangle of the leaf is proven farther than reach (m; 0:
// apart) from the oriented box (centre c, orthonormal axes as the rows of
// ax, half extents h; working frame) on its own plane's normal or on one of
// the box's face axes (separating axes: a gap on an axis bounds the
// distance from below). The box bounds the other node's vertices as the
// exact kernels see them to within tol (m). Any vector is a valid axis, so
// the normal's rounding only weakens the test, once its gap is divided by
// its length (|n|_2 rounded: reach is scaled by it and 1 + 1e-12, as the
// box axes' by 1 + 1e-12 for their deviation from unit length); the
// projections of vertices, centre and box err by a few ulps of
// |c|_1 + |h|_1 + 3 big, far below the 1e-12 of that (times |n|_1 on the
// unnormalised normal) allowed here. Nothing is dropped unless every input
// is finite: a NaN fails the comparisons, but the spans' min and max would
// pass over a NaN projection (std::min keeps its first argument), and a
// triangle with NaN in all three would get an empty span, clear of anything.
// closest_axis: a triangle none of those axes clears may still be cleared
// on the axis through its point nearest the box (clear_on_closest_axis).
bool box_clear_of_leaf(const LeafPlanes& leaf, const double* c, const double* ax, const double* h,
                       double tol, double reach = 0.0, bool closest_axis = false) {
  const double far = reach * (1.0 + 1e-12);
  const double slack =
      tol + 1e-12 * (std::abs(c[0]) + std::abs(c[1]) + std::abs(c[2]) + h[0] + h[1] + h[2] + 3.0 * leaf.big);
  double axes = 0.0;
  for (int k = 0; k < 9; ++k) axes += std::abs(ax[k]);
  if (!leaf.finite || !std::isfinite(slack + far + axes)) return false;
  for (std::uint32_t i = 0; i < leaf.count; ++i) {
    const double* n = leaf.n[i];
    const double nc = n[0] * c[0] + n[1] * c[1] + n[2] * c[2];
    double r = 0.0;
    for (int k = 0; k < 3; ++k)
      r += h[k] * std::abs(n[0] * ax[3 * k] + n[1] * ax[3 * k + 1] + n[2] * ax[3 * k + 2]);
    const double sn = slack * n[3] + far * n[4];
    if (nc - r > leaf.hi[i] + sn || nc + r < leaf.lo[i] - sn) continue;
    bool apart = false;
    const double* t = leaf.tri[i];
    for (int k = 0; k < 3 && !apart; ++k) {
      const double* a = ax + 3 * k;
      double pmin = std::numeric_limits<double>::infinity(), pmax = -pmin;
      for (int v = 0; v < 3; ++v) {
        const double p = a[0] * (t[3 * v] - c[0]) + a[1] * (t[3 * v + 1] - c[1]) + a[2] * (t[3 * v + 2] - c[2]);
        pmin = std::min(pmin, p);
        pmax = std::max(pmax, p);
      }
      apart = pmin > h[k] + slack + far || pmax < -h[k] - slack - far;
    }
    if (!apart && closest_axis) apart = clear_on_closest_axis(t, c, ax, h, slack, far);
    if (!apart) return false;
  }
  return true;
}

thread_local LeafPlanes t_planes[2];

// Whether the leaf cull is worth its cost for this pair: a leaf's planes
// clear whole sub-trees of a node far smaller than it; against a node of
// its own size they seldom do, and mapping the leaf's triangles and testing
// them is then pure cost. Two-mesh bench, collision only: 2.04-2.09 us a
// pose before the cull, 2.37-2.50 us culling at every size, 2.09-2.16 us
// from a ratio of 4; cold states, verdict-only: 0.0213-0.0215 s at every
// size, 0.0207-0.0208 s from 4 (thread CPU, min of 3 runs each; 2 and 8
// are no better).
constexpr double kLeafCullRatio = 4.0;
bool dwarfs(const NodeObb& leaf, const NodeObb& node) { return leaf.radius > kLeafCullRatio * node.radius; }

// Collision in a prepared working frame, for overlap_descent
// (kernels/pair_traversal.h); stops after `limit` pairs (>= 1).
struct OverlapQuery {
  using Pair = NodePair;
  struct Cull {
    double size_a, size_b;
  };

  const Setup& s;
  std::size_t limit;
  CollideResult& result;
  FirstHit* hit;
  bool box_cull = true;  // CollideRequest::box_cull
  bool leaf_cull = true;  // CollideRequest::leaf_cull
  const BvhNode* na = s.a.data->bvh.nodes.data();
  const BvhNode* nb = s.b.data->bvh.nodes.data();
  const LeafKernels& kernels = leaf_kernels();
  const LeafSide side_a = s.a.leaf_side(), side_b = s.b.leaf_side();
  // CollideRequest::near_below (0: not asked). While its answer is open,
  // every cull is widened to reach = near_below + the kernel's rounding
  // slack (as DistanceQuery::kernel_slack): a node pair is dropped only
  // when every triangle pair below it is proven at least reach apart, so
  // the distance kernel would give it at least near_below, and a pair
  // that may touch is never dropped. Once a pair closer than near_below
  // (or a contact) is found, reach is 0 and the culls are the plain ones.
  // Either way only pairs holding no contact are dropped, in the order of
  // the rest, so the contacts are found in the same order as without it.
  bool near_asked = false;
  double near_below = 0.0;
  double reach = 0.0, reach2 = 0.0;
  float near_cut2 = 0.0f;  // reach^2 rounded up to float: the leaves' float cut

  void ask_near(double below) {
    near_asked = true;
    near_below = below;
    const double r = below + 1e-13 * std::max(side_a.size, side_b.size) + 1e-300;
    if (!std::isfinite(r * r)) {  // (NaN, or too far to square): nothing proven
      result.near = true;
      return;
    }
    reach = r;
    reach2 = r * r;
    near_cut2 = round_up(reach2 * (1.0 + 1e-15));
  }
  // A pair closer than near_below, or a contact, was found.
  void near_found() {
    result.near = near_asked;
    reach = reach2 = 0.0;
  }

  void visited() { ++result.node_pairs_visited; }

  bool disjoint(const Pair& p, Cull& c) const {
    if (s.obb) {
      // A negative lower2 marks a pair split() already tested (kept: not disjoint).
      if (!(p.lower2 < 0.0) && s.obb_disjoint(p.a, p.b, reach)) return true;
      c.size_a = s.obb_size(p.a, true);
      c.size_b = s.obb_size(p.b, false);
      return false;
    }
    double alo[3], ahi[3], blo[3], bhi[3];
    s.a.box(p.a, alo, ahi);
    s.b.box(p.b, blo, bhi);
    if (reach > 0.0) {
      if (s.reach_apart(box_distance_squared(alo, ahi, blo, bhi), p.a, p.b, reach2)) return true;
    } else {
      if (!boxes_overlap(alo, ahi, blo, bhi)) return true;
      if (s.reverse_lower2(p.a, p.b) > 0.0) return true;
    }
    c.size_a = box_size(alo, ahi);
    c.size_b = box_size(blo, bhi);
    return false;
  }

  // Contact at working-frame slots (sa, sb): listed, and true when the
  // listing is full (stop).
  bool record(std::uint32_t sa, std::uint32_t sb) {
    std::uint32_t ia = s.a.data->bvh.prim_ids[sa];
    std::uint32_t ib = s.b.data->bvh.prim_ids[sb];
    if (s.swapped) std::swap(ia, ib);
    if (hit && !hit->found) *hit = FirstHit{true, sa, sb};
    result.collide = true;
    result.triangle_pairs.emplace_back(ia, ib);
    near_found();
    return result.triangle_pairs.size() >= limit;
  }

  // Leaves x and y in double, with each triangle's box: only the triangles
  // some pair still needs (row i of masks: a_i's pairs; any: their union)
  // are mapped (a triangle's coordinates do not depend on which others are).
  void map_leaves(const BvhNode& x, const BvhNode& y, const std::uint32_t* masks, std::uint32_t any,
                  double (*tri_a)[9], double (*tri_b)[9], double (*box_a)[6], double (*box_b)[6]) const {
    for (std::uint32_t i = 0; i < x.count; ++i) {
      if (masks[i] == 0) continue;
      s.a.triangle(x.index + i, tri_a[i]);
      triangle_box(tri_a[i], box_a[i]);
    }
    for (std::uint32_t m = any; m != 0; m &= m - 1) {
      const std::uint32_t j = static_cast<std::uint32_t>(__builtin_ctz(m));
      s.b.triangle(y.index + j, tri_b[j]);
      triangle_box(tri_b[j], box_b[j]);
    }
  }

  // The leaves while near_below is open: the float distance bounds against
  // near_cut2 instead of the touch masks. Every pair that may touch is
  // among their candidates (a bound is at most the exact distance), so the
  // exact overlap tests meet the touching pairs in the same order; the
  // other candidates then get the distance kernel (they are disjoint),
  // until one comes closer than near_below.
  bool leaves_near(const Pair& p) {
    const BvhNode& x = na[p.a];
    const BvhNode& y = nb[p.b];
    LeafPairInput in;
    make_leaf_pair(side_a, x.index, static_cast<int>(x.count), x.lo, x.hi, side_b, y.index,
                   static_cast<int>(y.count), y.lo, y.hi, in);
    LeafPairBounds lb;
    kernels.lower_bounds(in, near_cut2, lb);
    std::uint32_t any = 0;
    for (std::uint32_t i = 0; i < x.count; ++i) any |= lb.candidates[i];
    if (any == 0) return true;
    double tri_a[kMaxLeafSize][9], tri_b[kMaxLeafSize][9];
    double box_a[kMaxLeafSize][6], box_b[kMaxLeafSize][6];
    map_leaves(x, y, lb.candidates, any, tri_a, tri_b, box_a, box_b);
    double norm_a[kMaxLeafSize][5], norm_b[kMaxLeafSize][5];
    bool have_a[kMaxLeafSize] = {}, have_b[kMaxLeafSize] = {};
    for (std::uint32_t i = 0; i < x.count; ++i)
      for (std::uint32_t m = lb.candidates[i]; m != 0; m &= m - 1) {
        const std::uint32_t j = static_cast<std::uint32_t>(__builtin_ctz(m));
        const double* p0 = tri_a[i];
        const double* q0 = tri_b[j];
        if (boxes_overlap(box_a[i], box_a[i] + 3, box_b[j], box_b[j] + 3)) {
          ++result.triangle_pairs_tested;
          if (tri_tri_overlap(p0, p0 + 3, p0 + 6, q0, q0 + 3, q0 + 6)) {
            if (record(x.index + i, y.index + j)) return false;
            continue;
          }
        }
        if (!(reach > 0.0) ||
            box_distance_squared(box_a[i], box_a[i] + 3, box_b[j], box_b[j] + 3) * kShrink >= reach2)
          continue;
        // Disjoint (the exact test said so, or their boxes are apart). The
        // separating axes DistanceQuery::leaves tries before its kernel, with
        // the same slacks (1e-14 of the pair's largest coordinate), here
        // against reach: the edge-edge axes, then each triangle's normal.
        double big = 0.0;
        for (int k = 0; k < 6; ++k) big = std::max({big, std::abs(box_a[i][k]), std::abs(box_b[j][k])});
        const double slack = 1e-14 * big + 1e-300;
        if (edge_axes_reach(p0, q0, reach, slack)) continue;
        if (!have_a[i]) {
          triangle_normal_span(p0, norm_a[i]);
          have_a[i] = true;
        }
        if (!have_b[j]) {
          triangle_normal_span(q0, norm_b[j]);
          have_b[j] = true;
        }
        if (normal_gap(norm_a[i], q0) - slack >= reach || normal_gap(norm_b[j], p0) - slack >= reach) continue;
        // The kernel distance() would run on them.
        double pp[3], qq[3];
        if (std::sqrt(kernels.tri_distance2(p0, q0, pp, qq)) < near_below) near_found();
      }
    return true;
  }

  bool leaf_pair(const Pair& p) const { return na[p.a].is_leaf() && nb[p.b].is_leaf(); }

  bool leaves(const Pair& p) {
    if (reach > 0.0) return leaves_near(p);
    const BvhNode& x = na[p.a];
    const BvhNode& y = nb[p.b];
    // SIMD float prefilter on the stored float triangles
    // (kernels/leaf_bounds.h): a pair it proves apart cannot touch, so only
    // the rest reach the exact test, in the same order as without it, and
    // a leaf pair with none left is never mapped in double.
    LeafPairInput in;
    make_leaf_pair(side_a, x.index, static_cast<int>(x.count), x.lo, x.hi, side_b, y.index,
                   static_cast<int>(y.count), y.lo, y.hi, in);
    std::uint32_t touch[kLeafLanes];
    kernels.touch_masks(in, touch);
    std::uint32_t any = 0;
    for (std::uint32_t i = 0; i < x.count; ++i) any |= touch[i];
    if (any == 0) return true;
    double tri_a[kMaxLeafSize][9], tri_b[kMaxLeafSize][9];
    // Exact per-triangle box prefilter: the boxes come from the very
    // doubles the exact test sees, so disjoint boxes prove disjointness.
    double box_a[kMaxLeafSize][6], box_b[kMaxLeafSize][6];
    map_leaves(x, y, touch, any, tri_a, tri_b, box_a, box_b);
    for (std::uint32_t i = 0; i < x.count; ++i)
      for (std::uint32_t m = touch[i]; m != 0; m &= m - 1) {
        const std::uint32_t j = static_cast<std::uint32_t>(__builtin_ctz(m));
        if (!boxes_overlap(box_a[i], box_a[i] + 3, box_b[j], box_b[j] + 3)) continue;
        const double* p0 = tri_a[i];
        const double* q0 = tri_b[j];
        ++result.triangle_pairs_tested;
        if (!tri_tri_overlap(p0, p0 + 3, p0 + 6, q0, q0 + 3, q0 + 6)) continue;
        if (record(x.index + i, y.index + j)) return false;
      }
    return true;
  }

  // The leaf last tested against the other side's boxes, per side (per
  // thread, reset per query: ~2 KB each, not cleared for every pair).
  LeafPlanes& planes_a = t_planes[0];
  LeafPlanes& planes_b = t_planes[1];

  int split(const Pair& p, const Cull& c, Pair* kids) {
    const BvhNode& x = na[p.a];
    const BvhNode& y = nb[p.b];
    const bool split_a = !x.is_leaf() && (y.is_leaf() || c.size_a >= c.size_b);
    if (split_a) {
      kids[0] = {x.index, p.b, 0.0};
      kids[1] = {x.index + 1, p.b, 0.0};
    } else {
      kids[0] = {p.a, y.index, 0.0};
      kids[1] = {p.a, y.index + 1, 0.0};
    }
    if (!s.obb) return 2;
    // With oriented boxes the children are tested here rather than when
    // popped (the same test on the same values, so the same pairs survive;
    // splitting a, both meet one b node, mapped once), and the one whose
    // boxes overlap more deeply, by centre distance over the smaller radius,
    // is visited first: a contact, where there is one, tends to lie there,
    // and a first-contact query stops on it sooner. (Seed 1's 2,000 cold
    // states, first contact only: this key 0.0253 s, centres over the sum of
    // the radii 0.0305 s, the fixed order 0.032 s.)
    Setup::MappedB shared;
    if (split_a) s.map_b(p.b, shared);
    double key[2];
    int n = 0;
    for (int k = 0; k < 2; ++k) {
      // The oriented boxes are the tighter bound of a node, yet a fifth of
      // the child pairs they keep on cold states of the default scene have
      // axis-aligned boxes apart (in one part's frame or the other's), and
      // that test is a third of the work; either proof drops the pair.
      // Dropping a pair that holds no contact changes neither the order of
      // the rest nor which contact is found first.
      if (box_cull && s.aabb_disjoint(kids[k].a, kids[k].b, reach2)) continue;
      Setup::MappedB own;
      Setup::MappedB& mb = split_a ? shared : own;
      if (!split_a) s.map_b(kids[k].b, own);
      const NodeObb& oa = s.a.data->obbs[kids[k].a];
      const NodeObb& ob = s.b.data->obbs[kids[k].b];
      Setup::ObbPair op;
      s.obb_pair(kids[k].a, mb, op);
      if (plancheck::obb_disjoint(op.rel, oa.half, ob.half, op.tol + Setup::obb_widen(reach))) continue;
      // A leaf against the other side's inner node: its few triangles,
      // each against that node's box. Large parts meshed coarsely (the
      // lander's and the ascender's bodies) have leaves of a few triangles
      // a metre long, whose boxes hold whole sub-trees of a finely meshed
      // arm that lies inside the body's hull but tenths of a metre from its
      // faces; the descent took each such arm node down to its leaves, where
      // the leaf prefilter rejected every triangle pair (seed 1's 2,000 cold
      // states, ArmJ3-LanderBody state 1409: 1,270 node pairs, 631 of its
      // 632 leaf pairs with no pair left). Their planes clear the arm's
      // nodes high up: first contact only 0.0668 -> 0.0240 s over all pairs.
      const BvhNode& ka = na[kids[k].a];
      const BvhNode& kb = nb[kids[k].b];
      //
      // The axis through the triangle's point nearest the box joins them
      // only while near_below's answer is open (reach 0): a pair it drops
      // holds no contact, so the listing, its order and the contact are
      // the same, and `near` is decided as before (it would only read
      // false more often). Sweep slab (2.5 degrees, J1 90-92.5, one
      // thread): 17.6 -> 15.2 G instructions; a small arm node beside a
      // deck's rim is clear of its long faces on that axis alone.
      const bool closest_axis = reach == 0.0;
      if (leaf_cull && kb.is_leaf() && !ka.is_leaf() && dwarfs(ob, oa)) {
        if (planes_b.node != kids[k].b) planes_b.fill(s.b, kids[k].b, kb);
        if (box_clear_of_leaf(planes_b, oa.center, oa.axis, oa.half, 0.0, reach, closest_axis)) continue;
      } else if (leaf_cull && ka.is_leaf() && !kb.is_leaf() && dwarfs(oa, ob)) {
        if (planes_a.node != kids[k].a) planes_a.fill(s.a, kids[k].a, ka);
        if (box_clear_of_leaf(planes_a, mb.cb, mb.bw, ob.half, s.obb_tol, reach, closest_axis)) continue;
      }
      key[n] = op.dist_centres / (std::min(oa.radius, ob.radius) + 1e-300);
      kids[n] = kids[k];
      kids[n].lower2 = -1.0;  // tested: disjoint() skips it
      ++n;
    }
    if (n == 2 && key[1] < key[0]) std::swap(kids[0], kids[1]);
    return n;
  }
};

void collide_in(const Setup& s, std::size_t limit, CollideResult& result, FirstHit* hit, bool box_cull = true,
                bool leaf_cull = true, double near_below = 0.0) {
  t_planes[0].node = t_planes[1].node = std::numeric_limits<std::uint32_t>::max();
  OverlapQuery q{s, limit, result, hit, box_cull, leaf_cull};
  if (!(near_below <= 0.0)) q.ask_near(near_below);
  overlap_descent(q, t_stack, NodePair{0, 0, 0.0});
}

// Distance in a prepared working frame once no pair intersects, for
// distance_descent (kernels/pair_traversal.h).
struct DistanceQuery {
  using Pair = NodePair;

  const Setup& s;
  DistanceResult& result;
  const BvhNode* na = s.a.data->bvh.nodes.data();
  const BvhNode* nb = s.b.data->bvh.nodes.data();
  double best;
  // Pruning threshold: best / (1 + rel_tolerance) (best itself when exact).
  double shrink_rel;
  double tie;
  double cut = std::max(0.0, best * shrink_rel - tie);
  double best2_ = cut * cut;
  bool first_below = false;
  bool found = false;
  DescentFloor dropped{};  // what a search that finds nothing proved (beyond)
  void pruned(double l2) { dropped.pruned(l2); }
  std::uint32_t best_sa = 0, best_sb = 0;
  Vec3 best_pa = Vec3::Zero(), best_pb = Vec3::Zero();
  const LeafKernels& kernels = leaf_kernels();
  const LeafSide side_a = s.a.leaf_side(), side_b = s.b.leaf_side();
  const double kernel_slack = 1e-13 * std::max(side_a.size, side_b.size) + 1e-300;
  // The skip test on the direction of the best pair (kernels/direction_bound.h);
  // dir_gen counts improvements (what the leaves' cached spans are valid for).
  DirectionBound dir{};
  bool dir_set = false;
  std::uint32_t dir_gen = 0;
  bool leaf_cull = true;  // DistanceRequest::leaf_cull
  bool tie_cull = true;   // DistanceRequest::tie_cull
  // The leaf last tested against the other side's boxes, per side (as in
  // OverlapQuery; distance() resets them after its collision pass).
  LeafPlanes& planes_a = t_planes[0];
  LeafPlanes& planes_b = t_planes[1];

  double best2() const { return best2_; }
  void visited() { ++result.node_pairs_visited; }
  bool leaf_pair(const Pair& p) const { return na[p.a].is_leaf() && nb[p.b].is_leaf(); }

  // A closer pair (slots in the working frame, points there too).
  void improve(double dist, std::uint32_t sa, std::uint32_t sb, const Vec3& pa, const Vec3& pb) {
    found = true;
    best = dist;
    cut = std::max(0.0, best * shrink_rel - tie);
    best2_ = cut * cut;
    best_sa = sa;
    best_sb = sb;
    best_pa = pa;
    best_pb = pb;
    dir_set = dir.set(pa.data(), pb.data(), best, kernel_slack);
    ++dir_gen;
  }

  // Squared lower bound of node pair (ia, ib); sizes (when asked) get the
  // two nodes' sizes; mb: b's node ib already mapped (Setup::map_b), or nullptr.
  double lower2(std::uint32_t ia, std::uint32_t ib, double* sizes, Setup::MappedB* mb = nullptr) const {
    if (s.obb) {
      if (sizes) {
        sizes[0] = s.obb_size(ia, true);
        sizes[1] = s.obb_size(ib, false);
      }
      Setup::MappedB own;
      if (!mb) {
        s.map_b(ib, own);
        mb = &own;
      }
      // Balls around the boxes first (centre distance minus circumradii):
      // a tenth of the work of the box bound, enough to prune children far
      // beyond the best distance. Their rounding: b's centre mapping
      // (obb_tol) and a few ulps of every term.
      const NodeObb& oa = s.a.data->obbs[ia];
      const double* cb = mb->cb;
      const double dx = cb[0] - oa.center[0], dy = cb[1] - oa.center[1], dz = cb[2] - oa.center[2];
      const double ra = oa.radius;
      const double rb = s.b.data->obbs[ib].radius;
      const double d2 = dx * dx + dy * dy + dz * dz;
      // On cold states 94% of the pairs here have balls within reach of
      // each other (the default scene's 2,000 states: 431 of 458 a state;
      // the two-mesh poses: 96%), so the ball test fails for them; that is
      // proven first from d2 alone (kernels/obb.h), without the square root
      // and the tolerance, and the same pairs prune as before.
      if (!balls_within(d2, ra, rb, cut)) {
        const double ball = ball_gap(d2, oa.center, cb, ra, rb, s.obb_tol);
        if (ball > 0.0 && ball * ball * kShrink >= best2_) return ball * ball * kShrink;
      }
      const double lb = s.obb_lower(ia, *mb);
      return lb * lb * kShrink;
    }
    double alo[3], ahi[3], blo[3], bhi[3];
    s.a.box(ia, alo, ahi);
    s.b.box(ib, blo, bhi);
    if (sizes) {
      sizes[0] = box_size(alo, ahi);
      sizes[1] = box_size(blo, bhi);
    }
    const double forward = box_distance_squared(alo, ahi, blo, bhi);
    return std::max(forward, s.reverse_lower2(ia, ib)) * kShrink;
  }

  // True when no triangle pair under node pair (ia, ib) can reach the
  // kernel: once a pair is found, leaves() settles a triangle pair only
  // after its test on the two triangle boxes (box_distance_squared times
  // kShrink against best2_, which only falls). The tight boxes hold those
  // triangle boxes, and box_distance_squared is non-decreasing in each
  // gap (a difference, its maximum with 0, a square, a sum: each rounded
  // monotonically), so a gap of the node boxes that passes the test proves
  // that every triangle pair below would be skipped there: dropping the
  // node pair changes neither the answer nor the order of the rest. Unlike
  // the node bounds (lower2), whose rounding tolerances are 1e-12 of the
  // parts' size, these boxes err by 1e-14 of it, so they settle pairs tied
  // with the best within the tie tolerance: parallel faces at one distance
  // (the arm's base over the deck), whose search otherwise visits every
  // node pair along the faces to find nothing. Before a pair is found (the
  // probe of leaves() settles a pair without the box test) nothing is
  // dropped. NaN anywhere fails the comparison: nothing is dropped. (Only
  // once a pair is found, so DescentFloor, read only when nothing is, needs
  // no at_cut for these drops.)
  bool box_settled(std::uint32_t ia, std::uint32_t ib) const {
    if (!found || !tie_cull) return false;
    double alo[3], ahi[3], blo[3], bhi[3];
    s.a.tight_box(ia, alo, ahi);
    s.b.tight_box(ib, blo, bhi);
    return box_distance_squared(alo, ahi, blo, bhi) * kShrink >= best2_;
  }

  // (best + kernel_slack)^2 rounded up to float: a float bound at or above
  // it proves the pair cannot improve on best.
  float float_cut2() const {
    const double c = best + kernel_slack;
    return round_up(c * c * (1.0 + 1e-15));
  }

  bool leaves(const Pair& p) {
    dropped.at_cut = true;
    // Pushed when the best was farther: it may be settled now.
    if (box_settled(p.a, p.b)) return true;
    const BvhNode& x = na[p.a];
    const BvhNode& y = nb[p.b];
    // SIMD float lower bounds first, on the stored float triangles
    // (kernels/leaf_bounds.h). A pair is skipped only when its bound
    // reaches best + kernel_slack: the double kernel's value for it would
    // then be >= best (its closest points lie within a few ulps of `size`
    // of the triangles, far less than kernel_slack), so it could not have
    // changed the answer. The double bounds below still settle every
    // remaining pair as before, so the result is the same as without this
    // filter, at every width; a leaf pair with no pair left is never
    // mapped in double.
    LeafPairInput in;
    make_leaf_pair(side_a, x.index, static_cast<int>(x.count), x.lo, x.hi, side_b, y.index,
                   static_cast<int>(y.count), y.lo, y.hi, in);
    float cut2_f = float_cut2();
    LeafPairBounds lb;
    kernels.lower_bounds(in, cut2_f, lb);
    std::uint32_t any = 0;
    for (std::uint32_t i = 0; i < x.count; ++i) any |= lb.candidates[i];
    if (any == 0) return true;
    double tri_a[kMaxLeafSize][9], tri_b[kMaxLeafSize][9];
    // The double path, computed as far as the pairs need it: most pairs
    // left here sit within the float rounding of the best distance (ties,
    // as parallel faces), and their own triangle boxes settle them, so a
    // triangle is mapped only when a pair needs it and the leaf-wide axis
    // only when a box does not settle a pair. The tests are independent
    // skip conditions, so their order does not change which pairs reach
    // the kernel.
    bool mapped_a[kMaxLeafSize] = {}, mapped_b[kMaxLeafSize] = {};
    double box_a[kMaxLeafSize][6], box_b[kMaxLeafSize][6];
    // Separating-axis lower bound with the actual vertices, on the axis
    // through the two leaves' vertex centroids: near the closest pair that
    // axis is almost the optimal one, and unlike boxes the vertices carry
    // no slack beyond the patches' own curvature.
    double hi_a[kMaxLeafSize], lo_b[kMaxLeafSize];
    double slack = 0.0, normal_slack = 0.0;
    bool whole = false;
    auto need_a = [&](std::uint32_t i) {
      if (mapped_a[i]) return;
      s.a.triangle(x.index + i, tri_a[i]);
      triangle_box(tri_a[i], box_a[i]);
      mapped_a[i] = true;
    };
    auto need_b = [&](std::uint32_t j) {
      if (mapped_b[j]) return;
      s.b.triangle(y.index + j, tri_b[j]);
      triangle_box(tri_b[j], box_b[j]);
      mapped_b[j] = true;
    };
    auto need_whole = [&] {
      if (whole) return;
      for (std::uint32_t i = 0; i < x.count; ++i) need_a(i);
      for (std::uint32_t j = 0; j < y.count; ++j) need_b(j);
      slack = leaf_axis_bounds(tri_a, x.count, tri_b, y.count, hi_a, lo_b);
      double big = 0.0;
      for (std::uint32_t i = 0; i < x.count; ++i)
        for (int k = 0; k < 6; ++k) big = std::max(big, std::abs(box_a[i][k]));
      for (std::uint32_t j = 0; j < y.count; ++j)
        for (int k = 0; k < 6; ++k) big = std::max(big, std::abs(box_b[j][k]));
      // Dot products with a unit vector err by < 4 eps sqrt(3) big each;
      // a gap is a difference of two: 1e-14 big is ample.
      normal_slack = 1e-14 * big + 1e-300;
      whole = true;
    };
    // The exact distance of pair (i, j). The collision pass found no
    // intersecting pair, so these triangles are disjoint: the feature pairs
    // alone give the exact tri_distance answer, without its overlap test.
    // True: stop the search (nothing is closer, or a yes is enough).
    const auto settle = [&](std::uint32_t i, std::uint32_t j) {
      ++result.triangle_pairs_tested;
      Vec3 pp, qq;
      const double dist = std::sqrt(kernels.tri_distance2(tri_a[i], tri_b[j], pp.data(), qq.data()));
      if (!(dist < best)) return false;
      improve(dist, x.index + i, y.index + j, pp, qq);
      cut2_f = float_cut2();
      return best == 0.0 || first_below;
    };
    // Until the search has found a pair, the pair with the smallest float
    // bound first: its distance bounds the rest of the leaf (and search)
    // at once, where the pairs in slot order would each tighten it a
    // little. Its exact value is what the loop below would compute, so the
    // loop skips it. Cold states (2,000, the row request): 0.200 -> 0.184 s
    // thread CPU, min of 7, three alternations; the first-below searches of
    // the coarse pass find their pair sooner, and searches that find
    // nothing settle each leaf's nearest pair first.
    std::uint32_t probe_i = kMaxLeafSize, probe_j = 0;
    if (!found) {
      float nearest = cut2_f;
      for (std::uint32_t i = 0; i < x.count; ++i)
        for (std::uint32_t m = lb.candidates[i]; m != 0; m &= m - 1) {
          const std::uint32_t j = static_cast<std::uint32_t>(__builtin_ctz(m));
          if (lb.lower2[i][j] < nearest) {
            nearest = lb.lower2[i][j];
            probe_i = i;
            probe_j = j;
          }
        }
      if (probe_i < x.count) {
        need_a(probe_i);
        need_b(probe_j);
        if (settle(probe_i, probe_j)) return false;
      }
    }
    // Each triangle's own unit normal as a separating axis for the pairs
    // it is in: facing patches (an arm's flat underside over a deck) are
    // told apart by a few dot products instead of the 15-feature kernel.
    // Computed on first use: most pairs fall to the cheaper bounds first.
    double norm_a[kMaxLeafSize][5], norm_b[kMaxLeafSize][5];
    bool have_a[kMaxLeafSize] = {}, have_b[kMaxLeafSize] = {};
    // Spans on dir: a's highest, b's lowest projection (valid while gen_* == dir_gen).
    double dir_a[kMaxLeafSize], dir_b[kMaxLeafSize];
    std::uint32_t gen_a[kMaxLeafSize] = {}, gen_b[kMaxLeafSize] = {};
    for (std::uint32_t i = 0; i < x.count; ++i)
      for (std::uint32_t m = lb.candidates[i]; m != 0; m &= m - 1) {
        const std::uint32_t j = static_cast<std::uint32_t>(__builtin_ctz(m));
        if (lb.lower2[i][j] >= cut2_f || (i == probe_i && j == probe_j)) continue;
        need_a(i);
        need_b(j);
        // Triangle boxes: a cheap lower bound (axis-aligned gaps).
        if (box_distance_squared(box_a[i], box_a[i] + 3, box_b[j], box_b[j] + 3) * kShrink >= best2_)
          continue;
        // The best pair's direction: cheap once each triangle's span on
        // it is known, and it settles most pairs around a curved contact.
        if (dir_set) {
          if (gen_a[i] != dir_gen) {
            dir_a[i] = dir.high(tri_a[i]);
            gen_a[i] = dir_gen;
          }
          if (gen_b[j] != dir_gen) {
            dir_b[j] = dir.low(tri_b[j]);
            gen_b[j] = dir_gen;
          }
          if (dir_b[j] - dir_a[i] >= dir.cut) continue;
        }
        // The edge-edge axes (kernels/tri_distance.h): on cold states of the
        // default scene 80% of the pairs the kernel would get lie far beyond
        // the best (twice the cut or more), mostly edge-edge configurations
        // no normal separates, and one of these axes does. Tried before the
        // leaf-wide axis, which maps every triangle of both leaves. Skipped
        // only at best + kernel_slack, as the float filter skips: the
        // kernel's value would be >= best, so it could not have changed the
        // answer, tie or not. Its slack: 1e-14 of the pair's own largest
        // coordinate (the triangle boxes are the very doubles). Only until
        // the search finds its first pair: after that the pairs reaching
        // here lie near the best, few are proven beyond it, and the test
        // costs more than it saves (cold full checks, coarse-seeded: 1-4%
        // slower with it throughout, 2-6% faster than without it this way).
        if (!found) {
          double pair_big = 0.0;
          for (int k = 0; k < 6; ++k) pair_big = std::max({pair_big, std::abs(box_a[i][k]), std::abs(box_b[j][k])});
          if (edge_axes_reach(tri_a[i], tri_b[j], best + kernel_slack, 1e-14 * pair_big + 1e-300)) continue;
        }
        need_whole();
        if (lo_b[j] - hi_a[i] - slack >= cut) continue;
        if (!have_a[i]) {
          triangle_normal_span(tri_a[i], norm_a[i]);
          have_a[i] = true;
        }
        if (!have_b[j]) {
          triangle_normal_span(tri_b[j], norm_b[j]);
          have_b[j] = true;
        }
        if (normal_gap(norm_a[i], tri_b[j]) - normal_slack >= cut ||
            normal_gap(norm_b[j], tri_a[i]) - normal_slack >= cut)
          continue;
        if (settle(i, j)) return false;
      }
    return true;
  }

  int split(const Pair& p, Pair* kids) {
    // Pushed when the best was farther: it may be settled now.
    if (box_settled(p.a, p.b)) return 0;
    const BvhNode& x = na[p.a];
    const BvhNode& y = nb[p.b];
    double sizes[2];
    if (s.obb) {
      sizes[0] = s.obb_size(p.a, true);
      sizes[1] = s.obb_size(p.b, false);
    } else {
      lower2(p.a, p.b, sizes);
    }
    if (!x.is_leaf() && (y.is_leaf() || sizes[0] >= sizes[1])) {
      // Both children meet the same b node: map it once.
      Setup::MappedB mb;
      Setup::MappedB* shared = nullptr;
      if (s.obb) {
        s.map_b(p.b, mb);
        shared = &mb;
      }
      kids[0] = {x.index, p.b, child_lower2(x.index, p.b, shared)};
      kids[1] = {x.index + 1, p.b, child_lower2(x.index + 1, p.b, shared)};
    } else {
      kids[0] = {p.a, y.index, child_lower2(p.a, y.index, nullptr)};
      kids[1] = {p.a, y.index + 1, child_lower2(p.a, y.index + 1, nullptr)};
    }
    if (s.obb && leaf_cull && std::isfinite(best))
      for (int k = 0; k < 2; ++k) cull_leaf(kids[k]);
    return 2;
  }

  // A child's lower2, or infinity (never pushed) when box_settled drops it:
  // of the two children only the kept one is pushed, in its place.
  double child_lower2(std::uint32_t ia, std::uint32_t ib, Setup::MappedB* mb) const {
    if (box_settled(ia, ib)) return std::numeric_limits<double>::infinity();
    return lower2(ia, ib, nullptr, mb);
  }

  // A leaf against the other side's inner node, as in the collision
  // descent (OverlapQuery::split): proven beyond best + kernel_slack by its
  // triangles' planes and the node box's face axes, no pair below can have
  // a kernel value under best (as for the leaves' float bounds), so none
  // can change the answer, and the pair is dropped (an infinite bound). The
  // bounds of the pairs kept are untouched, so they are visited in the same
  // order; best-first (no bound yet) is left alone, its heap's order among
  // equal bounds depending on every pair pushed. Seed 1's cold states: a
  // safe state's ArmJ4-TopDeck search below 5 cm ran 916 node pairs, 449 leaf
  // pairs against one TopDeck leaf of 8 triangles 2.4 m long.
  // Also on the axis from each triangle's nearest point to the box's centre
  // (clear_on_closest_axis), and against the other side's leaf too (its
  // oriented box bounds its triangles as a node's does): the wrist's hub
  // beside the deck's rim lies within the rim leaf's box, off its planes
  // and beside its faces' spans on the hub's axes, so every hub leaf went
  // to leaves(), whose float bounds (box, normals, centres) proved little
  // for those long triangles and whose edge axes then settled ~900 pairs a
  // search. Sweep slab (J1 90-97.5 by 2.5, the dumped ArmJ4-TopDeck
  // searches replayed): 42.5 leaf pairs, 1,111 float candidates and
  // 114 kernels a search -> 0.4, 11.5 and 1.6; 85 -> 2.2 us a search.
  void cull_leaf(Pair& kid) {
    if (!(kid.lower2 < best2_)) return;
    const BvhNode& ka = na[kid.a];
    const BvhNode& kb = nb[kid.b];
    const double reach = best + kernel_slack;
    bool beyond = false;
    if (kb.is_leaf() && dwarfs(s.b.data->obbs[kid.b], s.a.data->obbs[kid.a])) {
      if (planes_b.node != kid.b) planes_b.fill(s.b, kid.b, kb);
      const NodeObb& oa = s.a.data->obbs[kid.a];
      beyond = box_clear_of_leaf(planes_b, oa.center, oa.axis, oa.half, 0.0, reach, true);
    } else if (ka.is_leaf() && dwarfs(s.a.data->obbs[kid.a], s.b.data->obbs[kid.b])) {
      if (planes_a.node != kid.a) planes_a.fill(s.a, kid.a, ka);
      Setup::MappedB mb;
      s.map_b(kid.b, mb);
      s.map_b_axes(mb);
      beyond = box_clear_of_leaf(planes_a, mb.cb, mb.bw, s.b.data->obbs[kid.b].half, s.obb_tol, reach, true);
    }
    if (beyond) {
      kid.lower2 = std::numeric_limits<double>::infinity();
      dropped.at_cut = true;  // proven at least best, not infinitely far
    }
  }
};

}  // namespace

namespace {

// A triangle pair found in the setup's frame (slots of its a and b, points
// in a's frame) as the caller's answer: world points and triangle ids, with
// a and b as the caller passed them.
void report_pair(const Setup& s, std::uint32_t slot_a, std::uint32_t slot_b, const Vec3& local_a,
                 const Vec3& local_b, double distance, DistanceResult& result) {
  Vec3 pa = s.to_world * local_a, pb = s.to_world * local_b;
  std::uint32_t ia = s.a.data->bvh.prim_ids[slot_a];
  std::uint32_t ib = s.b.data->bvh.prim_ids[slot_b];
  if (s.swapped) {
    std::swap(ia, ib);
    std::swap(pa, pb);
  }
  result.found = true;
  result.distance = distance;
  result.point_a = pa;
  result.point_b = pb;
  result.triangle_a = ia;
  result.triangle_b = ib;
}

// distance()'s answer for a pose where collide_in found `hit`: a common
// point of that triangle pair (intersecting, so tri_distance gives one).
void contact_answer(const Setup& s, const FirstHit& hit, DistanceResult& result) {
  double p[9], q[9];
  s.a.triangle(hit.slot_a, p);
  s.b.triangle(hit.slot_b, q);
  const TriDistance d = tri_distance(p, q);
  report_pair(s, hit.slot_a, hit.slot_b, d.point_p, d.point_q, 0.0, result);
}

// A part's root box (its axis-aligned node box or its oriented box, both
// holding every triangle) posed in the world by a rigid map: centre, axes
// (rows) and half extents.
struct WorldBox {
  double axis[9], half[3];
  Vec3 centre;
};

WorldBox world_box(const NodeObb& o, const Affine& t) {
  WorldBox w;
  const auto l = t.linear();
  for (int i = 0; i < 3; ++i) {
    for (int r = 0; r < 3; ++r)
      w.axis[3 * i + r] = l(r, 0) * o.axis[3 * i] + l(r, 1) * o.axis[3 * i + 1] + l(r, 2) * o.axis[3 * i + 2];
    w.half[i] = o.half[i];
  }
  w.centre = t * Vec3(o.center[0], o.center[1], o.center[2]);
  return w;
}

WorldBox world_box(const BvhNode& n, const Affine& t) {
  WorldBox w;
  const auto l = t.linear();
  Vec3 c;
  for (int i = 0; i < 3; ++i) {
    for (int r = 0; r < 3; ++r) w.axis[3 * i + r] = l(r, i);
    c[i] = 0.5 * (static_cast<double>(n.lo[i]) + static_cast<double>(n.hi[i]));
    w.half[i] = 0.5 * (static_cast<double>(n.hi[i]) - static_cast<double>(n.lo[i]));
  }
  w.centre = t * c;
  return w;
}

// b in a's axes (ObbRelative), with the centres' offset d and `scale`, the
// size of the coordinates and extents involved (what RootBoxes' tolerance
// is a fraction of).
ObbRelative relative(const WorldBox& a, const WorldBox& b, Vec3& d, double& scale) {
  d = b.centre - a.centre;
  ObbRelative q;
  for (int i = 0; i < 3; ++i) {
    const double* ai = &a.axis[3 * i];
    q.t[i] = ai[0] * d[0] + ai[1] * d[1] + ai[2] * d[2];
    for (int j = 0; j < 3; ++j) {
      const double* bj = &b.axis[3 * j];
      q.r[3 * i + j] = ai[0] * bj[0] + ai[1] * bj[1] + ai[2] * bj[2];
      q.abs_r[3 * i + j] = std::abs(q.r[3 * i + j]) + 1e-12;
    }
  }
  scale = a.centre.cwiseAbs().sum() + b.centre.cwiseAbs().sum() + d.cwiseAbs().sum() + a.half[0] + a.half[1] +
          a.half[2] + b.half[0] + b.half[1] + b.half[2];
  return q;
}

// Two rigid parts' root boxes posed in the world, each box pair and its
// relative placement computed once for both questions below.
class RootBoxes {
 public:
  RootBoxes(const CollisionModelData& da, const Affine& ta, const CollisionModelData& db, const Affine& tb)
      : da_(da), ta_(ta), db_(db), tb_(tb),
        usable_(!da.bvh.nodes.empty() && !db.bvh.nodes.empty() && is_isometry(ta) && is_isometry(tb)),
        oriented_(!da.obbs.empty() && !db.obbs.empty()) {}

  // True when the parts are proven apart (by more than reach): the
  // axis-aligned boxes of their own frames (as the descent's first box
  // cull), then the oriented ones (its first oriented test). The world image
  // of a box under a rigid map is a box with turned axes, so an axis
  // separating the posed boxes separates the posed parts, and a pair dropped
  // here is apart in the working frame too.
  bool apart(double reach) {
    if (reach < 0.0) reach = 0.0;  // (NaN stays: nothing is proven)
    if (!usable_) return false;
    if (apart(aligned(), reach)) return true;
    return oriented_ && apart(oriented(), reach);
  }

  // How far apart `apart` found them when it proved them apart by more
  // than `reach`: at least reach, and at least what the six face axes and
  // the centre axis of either root box pair show (obb_lower, less apart's
  // rounding tolerance, which covers these sums too).
  double beyond(double reach) {
    double best = reach;
    auto lower = [&](const Pair& p) {
      const double l = obb_lower(p.q, p.d.norm(), p.a.half, p.b.half, 1e-9 * p.scale + 1e-300);
      if (l > best) best = l;  // (NaN never)
    };
    lower(aligned());
    if (oriented_) lower(oriented());
    return best;
  }

 private:
  struct Pair {
    bool known = false;
    WorldBox a, b;
    ObbRelative q;  // b in a's axes (relative)
    Vec3 d;
    double scale = 0.0;
  };
  static void fill(Pair& p, const WorldBox& a, const WorldBox& b) {
    p.known = true;
    p.a = a;
    p.b = b;
    p.q = relative(p.a, p.b, p.d, p.scale);
  }
  const Pair& aligned() {
    if (!aligned_.known) fill(aligned_, world_box(da_.bvh.nodes[0], ta_), world_box(db_.bvh.nodes[0], tb_));
    return aligned_;
  }
  const Pair& oriented() {
    if (!oriented_pair_.known) fill(oriented_pair_, world_box(da_.obbs[0], ta_), world_box(db_.obbs[0], tb_));
    return oriented_pair_;
  }
  // True when an axis separates the pair's boxes by more than reach (m).
  // The tolerance, 1e-9 of the coordinates and extents involved, lies far
  // above every rounding here (the axes' and centres' products, the halving
  // of the float boxes, the poses' distance from orthonormal, kIsometryTol)
  // and far above the difference between these world poses and the working
  // frame collide_in reads (make_setup's inverse and product: a few ulps).
  static bool apart(const Pair& p, double reach) {
    const double tol = reach + 1e-9 * p.scale + 1e-300;
    // NaN or infinite poses: never apart here (collide_in decides them).
    return std::isfinite(tol) && obb_disjoint(p.q, p.a.half, p.b.half, tol);
  }

  const CollisionModelData& da_;
  const Affine& ta_;
  const CollisionModelData& db_;
  const Affine& tb_;
  bool usable_, oriented_;
  Pair aligned_, oriented_pair_;
};

}  // namespace

bool roots_apart(const CollisionModel& a, const Affine& ta, const CollisionModel& b, const Affine& tb,
                 double reach) {
  return a.triangle_count() > 0 && b.triangle_count() > 0 && RootBoxes(a.data(), ta, b.data(), tb).apart(reach);
}

void collide(const CollisionModel& a, const Affine& ta, const CollisionModel& b, const Affine& tb,
             const CollideRequest& request, CollideResult& result) {
  result.collide = result.near = false;
  result.triangle_pairs.clear();
  result.node_pairs_visited = result.triangle_pairs_tested = 0;
  if (a.triangle_count() == 0 || b.triangle_count() == 0) return;
  // Parts whose root boxes are apart in the world need no working frame:
  // cold states of the default scene reach here with 1,110 pairs whose
  // world boxes meet, 1,097 of them apart at the root pair (Table 3's
  // states), each costing make_setup's two inverses and the descent's set-up.
  if (request.root_cull && RootBoxes(a.data(), ta, b.data(), tb).apart(request.near_below)) {
    result.node_pairs_visited = 1;
    return;
  }
  const Setup s = make_setup(a, ta, b, tb);
  FirstHit hit;
  collide_in(s, std::max<std::size_t>(1, request.max_triangle_pairs), result, request.contact ? &hit : nullptr,
             request.box_cull, request.leaf_cull, request.near_below);
  if (request.contact && hit.found) {
    *request.contact = DistanceResult{};
    contact_answer(s, hit, *request.contact);
  }
}

void distance(const CollisionModel& a, const Affine& ta, const CollisionModel& b, const Affine& tb,
              const DistanceRequest& request, DistanceResult& result) {
  result = DistanceResult{};
  if (a.triangle_count() == 0 || b.triangle_count() == 0) return;
  // Nothing below upper_bound where the root boxes are that far apart (an
  // infinite or NaN bound proves nothing there): the motion checks' pair
  // samples on the default arm's planned edges ask 84,572 such questions of
  // mesh pairs, 47,579 of them this far apart.
  if (request.root_cull && request.upper_bound > 0.0 && request.upper_bound < std::numeric_limits<double>::infinity()) {
    RootBoxes roots(a.data(), ta, b.data(), tb);
    if (roots.apart(request.upper_bound)) {
      result.node_pairs_visited = 1;
      if (request.beyond) result.beyond = roots.beyond(request.upper_bound);
      return;
    }
  }
  const Setup s = make_setup(a, ta, b, tb);
  if (!(request.upper_bound > 0.0)) return;  // no distance is below 0
  if (!request.known_disjoint) {
    // Intersection first: the collision traversal stops at the first hit
    // and culls far harder than distance bounds, which cannot prune
    // anything once pairs are at distance 0.
    CollideResult c;
    FirstHit hit;
    collide_in(s, 1, c, &hit);
    result.node_pairs_visited += c.node_pairs_visited;
    result.triangle_pairs_tested += c.triangle_pairs_tested;
    if (hit.found) {
      contact_answer(s, hit, result);
      return;
    }
  }
  DistanceQuery q{s, result, s.a.data->bvh.nodes.data(), s.b.data->bvh.nodes.data(), request.upper_bound,
                  1.0 / (1.0 + std::max(0.0, request.rel_tolerance)), std::max(0.0, request.abs_tolerance)};
  const NodePair root{0, 0, q.lower2(0, 0, nullptr)};
  if (request.seed_slot_a >= 0 && request.seed_slot_b >= 0) {
    std::uint32_t sa = static_cast<std::uint32_t>(request.seed_slot_a);
    std::uint32_t sb = static_cast<std::uint32_t>(request.seed_slot_b);
    if (s.swapped) std::swap(sa, sb);
    if (sa < s.a.data->triangle_count() && sb < s.b.data->triangle_count()) {
      // Exactly what the traversal computes for this pair (same frame, same
      // kernel), so the minimum found is unchanged; only the bound is earlier.
      double p[9], t[9];
      s.a.triangle(sa, p);
      s.b.triangle(sb, t);
      Vec3 pp, qq;
      const double dist = std::sqrt(q.kernels.tri_distance2(p, t, pp.data(), qq.data()));
      if (dist < q.best) q.improve(dist, sa, sb, pp, qq);
    }
  }
  q.first_below = request.first_below;
  q.leaf_cull = request.leaf_cull;
  q.tie_cull = request.tie_cull && s.a.data->float_exact && s.b.data->float_exact;
  t_planes[0].node = t_planes[1].node = std::numeric_limits<std::uint32_t>::max();
  if (!(q.found && q.first_below)) {
    // Exact with nothing to start from (the first pair found would set the
    // bound): best-first until it has one (kernels/pair_traversal.h).
    // Two-mesh bench, apart poses: 50.4 -> 42.2 us best-first throughout,
    // 40.5 -> 38.7 us switching at the first bound. A coarse search
    // (rel_tolerance) or one with a bound or seed goes depth first:
    // best-first made cold states' coarse pass 3-8% slower.
    if (!q.found && !std::isfinite(q.best) && !(request.rel_tolerance > 0.0))
      distance_best_first(q, t_stack, root);
    else
      distance_descent(q, t_stack, root);
  }
  if (!q.found) {
    if (request.beyond) result.beyond = q.dropped.beyond(q.cut);
    return;
  }
  report_pair(s, q.best_sa, q.best_sb, q.best_pa, q.best_pb, q.best, result);
  result.slot_a = s.swapped ? q.best_sb : q.best_sa;
  result.slot_b = s.swapped ? q.best_sa : q.best_sb;
}

}  // namespace plancheck
