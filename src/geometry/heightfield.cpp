// SPDX-License-Identifier: MIT
// Heightfield pyramid, refit, ray walk, and the part-vs-heightfield pair
// traversal. The traversal pairs part BVH nodes with pyramid blocks; node
// pairs are culled in the reference frame (the part node's oriented box
// posed by ta against the block's axis-aligned box, 15-axis separating axis
// test, widened for rounding), leaves run the float SIMD prefilters of
// kernels/leaf_bounds.h, then the exact kernels in the working frame
// described in heightfield.h.
#include "src/geometry/heightfield.h"

#include "kernels/box.h"
#include "kernels/leaf_bounds.h"
#include "kernels/obb.h"
#include "kernels/pair_traversal.h"
#include "kernels/tri_distance.h"
#include "kernels/tri_tri_overlap.h"
#include "src/geometry/bvh.h"
#include "src/geometry/query_frame.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>

namespace plancheck {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Heightfield::stamp(): from 1, never reused.
std::uint64_t next_stamp() {
  static std::atomic<std::uint64_t> next{1};
  return next.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace

Heightfield::Heightfield(const Dem& dem, const Vec3& origin)
    : ncols_(dem.ncols), nrows_(dem.nrows), origin_z_(origin.z()), stamp_(next_stamp()) {
  xs_.resize(static_cast<std::size_t>(ncols_));
  ys_.resize(static_cast<std::size_t>(nrows_));
  z_.resize(static_cast<std::size_t>(ncols_) * nrows_);
  for (int r = 0; r < nrows_; ++r)
    for (int c = 0; c < ncols_; ++c) {
      const Vec3 p = dem_point(dem, origin, c, r);
      if (r == 0) xs_[static_cast<std::size_t>(c)] = p.x();
      if (c == 0) ys_[static_cast<std::size_t>(r)] = p.y();
      z_[static_cast<std::size_t>(r) * ncols_ + c] = p.z();
    }
  const int cc = cell_cols(), cr = cell_rows();
  cell_tri_.assign(static_cast<std::size_t>(cc) * cr, kNoTriangle);
  // dem_mesh's order: cells row-major, two triangles per valid cell.
  for (int r = 0; r < cr; ++r)
    for (int c = 0; c < cc; ++c) {
      if (!dem.is_valid(c, r) || !dem.is_valid(c + 1, r) || !dem.is_valid(c, r + 1) || !dem.is_valid(c + 1, r + 1))
        continue;
      const std::size_t cell = static_cast<std::size_t>(r) * cc + c;
      cell_tri_[cell] = static_cast<std::uint32_t>(2 * tri_cell_.size());
      tri_cell_.push_back(static_cast<std::uint32_t>(cell));
    }
  // Pyramid shape, then a full fit.
  int nx = (cc + kLeafCells - 1) / kLeafCells, ny = (cr + kLeafCells - 1) / kLeafCells, cells = kLeafCells;
  while (true) {
    Level l;
    l.nx = std::max(nx, 1);
    l.ny = std::max(ny, 1);
    l.cells = cells;
    l.blocks.assign(static_cast<std::size_t>(l.nx) * l.ny, Block{kInf, -kInf});
    levels_.push_back(std::move(l));
    if (nx <= 1 && ny <= 1) break;
    nx = (nx + 1) / 2, ny = (ny + 1) / 2, cells *= 2;
  }
  for (int by = 0; by < levels_[0].ny; ++by)
    for (int bx = 0; bx < levels_[0].nx; ++bx) fit_leaf(bx, by);
  for (std::size_t k = 1; k < levels_.size(); ++k)
    for (int by = 0; by < levels_[k].ny; ++by)
      for (int bx = 0; bx < levels_[k].nx; ++bx) fit_inner(static_cast<int>(k), bx, by);
}

std::size_t Heightfield::memory_bytes() const {
  std::size_t n = sizeof(*this) + (xs_.capacity() + ys_.capacity() + z_.capacity()) * sizeof(double) +
                  (cell_tri_.capacity() + tri_cell_.capacity()) * sizeof(std::uint32_t);
  for (const Level& l : levels_) n += sizeof(Level) + l.blocks.capacity() * sizeof(Block);
  return n;
}

std::size_t Heightfield::block_count() const {
  std::size_t n = 0;
  for (const Level& l : levels_) n += l.blocks.size();
  return n;
}

void Heightfield::triangle_cell(std::uint32_t tri, int& c, int& r, int& k) const {
  const std::uint32_t cell = tri_cell_[tri / 2];
  c = static_cast<int>(cell % static_cast<std::uint32_t>(cell_cols()));
  r = static_cast<int>(cell / static_cast<std::uint32_t>(cell_cols()));
  k = static_cast<int>(tri % 2);
}

void Heightfield::cell_triangle(int c, int r, int k, double* out) const {
  // dem_mesh: {(c, r), (c+1, r), (c+1, r+1)} and {(c, r), (c+1, r+1), (c, r+1)}.
  static constexpr int kCorner[2][3][2] = {{{0, 0}, {1, 0}, {1, 1}}, {{0, 0}, {1, 1}, {0, 1}}};
  for (int v = 0; v < 3; ++v) {
    const int cc = c + kCorner[k][v][0], rr = r + kCorner[k][v][1];
    out[3 * v] = x(cc);
    out[3 * v + 1] = y(rr);
    out[3 * v + 2] = z(cc, rr);
  }
}

void Heightfield::fit_leaf(int bx, int by) {
  Block b{kInf, -kInf};
  const int c0 = bx * kLeafCells, r0 = by * kLeafCells;
  const int c1 = std::min(c0 + kLeafCells, cell_cols()), r1 = std::min(r0 + kLeafCells, cell_rows());
  for (int r = r0; r < r1; ++r)
    for (int c = c0; c < c1; ++c) {
      if (!cell_valid(c, r)) continue;
      for (int dr = 0; dr <= 1; ++dr)
        for (int dc = 0; dc <= 1; ++dc) {
          const double h = z(c + dc, r + dr);
          b.zmin = std::min(b.zmin, h);
          b.zmax = std::max(b.zmax, h);
        }
    }
  levels_[0].blocks[static_cast<std::size_t>(by) * levels_[0].nx + bx] = b;
}

void Heightfield::fit_inner(int level, int bx, int by) {
  const Level& below = levels_[static_cast<std::size_t>(level) - 1];
  Block b{kInf, -kInf};
  for (int dy = 0; dy <= 1; ++dy)
    for (int dx = 0; dx <= 1; ++dx) {
      const int cx = 2 * bx + dx, cy = 2 * by + dy;
      if (cx >= below.nx || cy >= below.ny) continue;
      const Block& k = below.blocks[static_cast<std::size_t>(cy) * below.nx + cx];
      b.zmin = std::min(b.zmin, k.zmin);
      b.zmax = std::max(b.zmax, k.zmax);
    }
  Level& l = levels_[static_cast<std::size_t>(level)];
  l.blocks[static_cast<std::size_t>(by) * l.nx + bx] = b;
}

bool Heightfield::block_box(int level, int bx, int by, double* lo, double* hi) const {
  const Level& l = levels_[static_cast<std::size_t>(level)];
  const Block& b = l.blocks[static_cast<std::size_t>(by) * l.nx + bx];
  if (!(b.zmin <= b.zmax)) return false;
  const int c0 = bx * l.cells, r0 = by * l.cells;
  const int c1 = std::min(c0 + l.cells, cell_cols()), r1 = std::min(r0 + l.cells, cell_rows());
  lo[0] = x(c0), hi[0] = x(c1);
  lo[1] = y(r0), hi[1] = y(r1);
  lo[2] = b.zmin, hi[2] = b.zmax;
  return true;
}

std::size_t Heightfield::refit(const Dem& grid, SampleRect changed) {
  changed.c0 = std::max(changed.c0, 0), changed.r0 = std::max(changed.r0, 0);
  changed.c1 = std::min(changed.c1, ncols_ - 1), changed.r1 = std::min(changed.r1, nrows_ - 1);
  if (changed.empty() || cell_cols() == 0 || cell_rows() == 0) return 0;
  stamp_ = next_stamp();
  for (int r = changed.r0; r <= changed.r1; ++r)
    for (int c = changed.c0; c <= changed.c1; ++c)
      z_[static_cast<std::size_t>(r) * ncols_ + c] = origin_z_ + grid.height(c, r);
  // Cells with a changed corner, then the leaf blocks over them.
  const int cc0 = std::max(changed.c0 - 1, 0), cc1 = std::min(changed.c1, cell_cols() - 1);
  const int cr0 = std::max(changed.r0 - 1, 0), cr1 = std::min(changed.r1, cell_rows() - 1);
  int bx0 = cc0 / kLeafCells, bx1 = cc1 / kLeafCells, by0 = cr0 / kLeafCells, by1 = cr1 / kLeafCells;
  std::size_t n = 0;
  for (int by = by0; by <= by1; ++by)
    for (int bx = bx0; bx <= bx1; ++bx, ++n) fit_leaf(bx, by);
  for (std::size_t k = 1; k < levels_.size(); ++k) {
    bx0 /= 2, bx1 /= 2, by0 /= 2, by1 /= 2;
    for (int by = by0; by <= by1; ++by)
      for (int bx = bx0; bx <= bx1; ++bx, ++n) fit_inner(static_cast<int>(k), bx, by);
  }
  return n;
}

namespace {

// Ray against box [lo, hi] (slabs), clipped to [t0, t1]; the entry t, or
// infinity when missed. Division by a zero direction gives infinities, which
// the min/max handle; 0 * inf (origin on a slab plane) is NaN, which the
// comparisons treat as "no information" through the fmin/fmax choice below.
double ray_box(const double* o, const double* inv, const double* lo, const double* hi, double t0, double t1) {
  for (int k = 0; k < 3; ++k) {
    double a = (lo[k] - o[k]) * inv[k], b = (hi[k] - o[k]) * inv[k];
    if (a > b) std::swap(a, b);
    t0 = std::fmax(t0, a);
    t1 = std::fmin(t1, b);
  }
  return t0 <= t1 ? t0 : kInf;
}

// Moller-Trumbore in double, edges included (a ray through a shared edge
// hits both neighbours rather than neither).
bool ray_triangle(const double* o, const double* d, const double* t, double& hit_t) {
  const double e1[3] = {t[3] - t[0], t[4] - t[1], t[5] - t[2]};
  const double e2[3] = {t[6] - t[0], t[7] - t[1], t[8] - t[2]};
  const double p[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]};
  const double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
  if (det == 0.0 || !std::isfinite(det)) return false;
  const double inv = 1.0 / det;
  const double s[3] = {o[0] - t[0], o[1] - t[1], o[2] - t[2]};
  const double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) * inv;
  constexpr double kEdge = 1e-12;
  if (u < -kEdge || u > 1.0 + kEdge) return false;
  const double q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0]};
  const double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) * inv;
  if (v < -kEdge || u + v > 1.0 + kEdge) return false;
  hit_t = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) * inv;
  return true;
}

}  // namespace

bool Heightfield::intersect_ray(const double* o, const double* d, double t_near, double& t_far,
                                std::uint32_t& tri) const {
  if (tri_cell_.empty()) return false;
  const double inv[3] = {1.0 / d[0], 1.0 / d[1], 1.0 / d[2]};
  struct Item {
    int level, bx, by;
    double t;
  };
  Item stack[128];
  int top = 0;
  const int root = static_cast<int>(levels_.size()) - 1;
  double lo[3], hi[3];
  if (!block_box(root, 0, 0, lo, hi)) return false;
  // Boxes are widened a little so rays along a face are not lost to rounding.
  auto entry = [&](int level, int bx, int by) {
    if (!block_box(level, bx, by, lo, hi)) return kInf;
    for (int k = 0; k < 3; ++k) {
      const double pad = 1e-9 * (std::abs(lo[k]) + std::abs(hi[k]) + 1.0);
      lo[k] -= pad, hi[k] += pad;
    }
    return ray_box(o, inv, lo, hi, t_near, t_far);
  };
  const double t_root = entry(root, 0, 0);
  if (t_root == kInf) return false;
  stack[top++] = {root, 0, 0, t_root};
  bool found = false;
  while (top > 0) {
    const Item it = stack[--top];
    if (it.t > t_far) continue;
    if (it.level == 0) {
      const int c0 = it.bx * kLeafCells, r0 = it.by * kLeafCells;
      const int c1 = std::min(c0 + kLeafCells, cell_cols()), r1 = std::min(r0 + kLeafCells, cell_rows());
      for (int r = r0; r < r1; ++r)
        for (int c = c0; c < c1; ++c) {
          const std::uint32_t first = cell_first_tri(c, r);
          if (first == kNoTriangle) continue;
          for (int k = 0; k < 2; ++k) {
            double t[9], h;
            cell_triangle(c, r, k, t);
            if (ray_triangle(o, d, t, h) && h >= t_near && h <= t_far &&
                (!found || h < t_far || first + k < tri)) {
              found = true;
              t_far = h;
              tri = first + static_cast<std::uint32_t>(k);
            }
          }
        }
      continue;
    }
    const Level& below = levels_[static_cast<std::size_t>(it.level) - 1];
    Item kids[4];
    int n = 0;
    for (int dy = 0; dy <= 1; ++dy)
      for (int dx = 0; dx <= 1; ++dx) {
        const int cx = 2 * it.bx + dx, cy = 2 * it.by + dy;
        if (cx >= below.nx || cy >= below.ny) continue;
        const double t = entry(it.level - 1, cx, cy);
        if (t <= t_far) kids[n++] = {it.level - 1, cx, cy, t};
      }
    // Nearest child on top of the stack.
    farthest_first(kids, n, [](const Item& a) { return a.t; });
    for (int i = 0; i < n; ++i) stack[top++] = kids[i];
  }
  return found;
}

// ---------------------------------------------------------------------------
// Part vs heightfield.

namespace {

constexpr int kLeafTris = 2 * Heightfield::kLeafCells * Heightfield::kLeafCells;
constexpr int kLeafSamples = (Heightfield::kLeafCells + 1) * (Heightfield::kLeafCells + 1);
// A leaf block's triangles in the float prefilter: two views of at most
// kLeafLanes each (slots 0..15 and 16..31), stride kLeafTris, so a full
// register load at either stays inside the 9 rows.
constexpr std::size_t kTerrainSoaStride = kLeafTris;
static_assert(kLeafTris == 2 * kLeafLanes, "a leaf block is two prefilter views");

// A leaf block's triangles as the float prefilter reads them: in
// terrain_triangles' order, SoA (store_leaf_soa, reference frame) relative
// to the centre of the block box rounded outward to float [lo, hi], lanes
// past n zero. They depend on the heights alone, so a thread keeps the
// last few (t_leaf_soa) keyed by block and Heightfield::stamp().
struct TerrainLeafSoa {
  std::uint64_t stamp = 0;  // 0: empty
  int bx = -1, by = -1;
  int n = 0;
  float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  alignas(64) float soa[9 * kTerrainSoaStride];
};

// 8 x 8 neighbouring blocks in distinct entries (76 KB a thread).
thread_local std::array<TerrainLeafSoa, 64> t_leaf_soa;

void terrain_soa_build(const Heightfield& hf, int bx, int by, TerrainLeafSoa& e) {
  e.stamp = hf.stamp(), e.bx = bx, e.by = by, e.n = 0;
  std::fill(e.soa, e.soa + 9 * kTerrainSoaStride, 0.0f);
  double blo[3], bhi[3];
  if (!hf.block_box(0, bx, by, blo, bhi)) return;
  for (int k = 0; k < 3; ++k) e.lo[k] = round_down(blo[k]), e.hi[k] = round_up(bhi[k]);
  double tri[kLeafTris][9];
  const int L = Heightfield::kLeafCells;
  const int c0 = bx * L, r0 = by * L;
  const int c1 = std::min(c0 + L, hf.cell_cols()), r1 = std::min(r0 + L, hf.cell_rows());
  for (int r = r0; r < r1; ++r)
    for (int c = c0; c < c1; ++c)
      if (hf.cell_valid(c, r))
        for (int k = 0; k < 2; ++k) hf.cell_triangle(c, r, k, tri[e.n++]);
  store_leaf_soa(e.soa, kTerrainSoaStride, 0, e.n, e.lo, e.hi,
                 [&](std::uint32_t t, int v) -> const double* { return tri[t] + 3 * v; });
}

// A leaf pair's triangles (part, terrain) and their boxes (HfQuery::leaf_triangles).
struct LeafTriangles {
  double tri_p[kMaxLeafSize][9], tri_t[kLeafTris][9], box_p[kMaxLeafSize][6], box_t[kLeafTris][6];
  std::uint32_t ids[kLeafTris];
};

struct HfQuery {
  const CollisionModelData* part = nullptr;
  const Heightfield* hf = nullptr;
  // Working frame (see heightfield.h): rigid ta -> the part's frame, with
  // terrain corners mapped by ta^-1 (unless ta is the identity); otherwise
  // the reference frame with the part's corners mapped by ta, and the kernel
  // arguments in the mesh path's swapped order (terrain first).
  bool rigid = true;
  bool use_obb = true;  // cull with the part's oriented node boxes (rigid ta)
  bool map_terrain = false;
  bool map_part = false;
  AffineMap terrain_map, part_map;
  Affine to_world = Affine::Identity();
  // Culling in the reference frame: the part's pose and its rounding margin.
  AffineMap pose;
  double cull_margin[3] = {0, 0, 0};
  // Both sides for the float leaf prefilter (kernels/leaf_bounds.h): the
  // part's stored SoA, the terrain's built per leaf (terrain_soa); their
  // maps into the working frame and sizes as collision_model.cpp's
  // Side::leaf_side. kernel_slack as there: the double kernel's value for a
  // pair lies within it of the pair's exact distance.
  LeafSide side_p, side_t;
  double kernel_slack = 0.0;
  const LeafKernels& kernels = leaf_kernels();

  void setup(const CollisionModel& a, const Affine& ta, const Heightfield& t) {
    part = &a.data();
    hf = &t;
    pose = to_map(ta);
    rigid = is_isometry(ta);
    use_obb = rigid && part->obbs.size() == part->bvh.nodes.size();
    if (rigid) {
      to_world = ta;
      if (!(ta.matrix() == Affine::Identity().matrix())) {
        map_terrain = true;
        terrain_map = to_map(ta.inverse() * Affine::Identity());
      }
    } else {
      map_part = !(ta.matrix() == Affine::Identity().matrix());
      part_map = pose;
    }
    for (int r = 0; r < 3; ++r) {
      double s = std::abs(pose.t[r]);
      for (int c = 0; c < 3; ++c) s += pose.abs_l[3 * r + c] * 2.0 * part->max_abs[c];
      cull_margin[r] = kMarginRel * s + 1e-300;
    }
    // The terrain's largest coordinates: its root block holds every vertex
    // of a valid cell.
    const int root = static_cast<int>(t.levels().size()) - 1;
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    t.block_box(root, 0, 0, lo, hi);
    const double terrain_abs[3] = {std::max(std::abs(lo[0]), std::abs(hi[0])),
                                   std::max(std::abs(lo[1]), std::abs(hi[1])),
                                   std::max(std::abs(lo[2]), std::abs(hi[2]))};
    side_p = leaf_side(part->soa.data(), part->soa_stride, map_part ? &part_map : nullptr, part->max_abs.data());
    side_t = leaf_side(nullptr, kTerrainSoaStride, map_terrain ? &terrain_map : nullptr, terrain_abs);
    kernel_slack = 1e-13 * std::max(side_p.size, side_t.size) + 1e-300;
  }

  // A side mapped by m (nullptr: the identity), its coordinates at most
  // max_abs per axis: size >= |l v| + |t| per coordinate.
  static LeafSide leaf_side(const float* soa, std::size_t stride, const AffineMap* m, const double* max_abs) {
    double size = 0.0;
    for (int r = 0; r < 3; ++r) {
      double row = m ? std::abs(m->t[r]) : max_abs[r];
      if (m)
        for (int c = 0; c < 3; ++c) row += m->abs_l[3 * r + c] * max_abs[c];
      size = std::max(size, row);
    }
    return make_leaf_side(soa, stride, m ? m->l : nullptr, m ? m->t : nullptr, size * (1.0 + 1e-6));
  }

  // Leaf block (bx, by)'s triangles for the float prefilter, from the
  // thread's cache (terrain_soa_build on a miss).
  const TerrainLeafSoa& terrain_soa(int bx, int by) const {
    TerrainLeafSoa& e = t_leaf_soa[static_cast<std::size_t>((bx & 7) | ((by & 7) << 3))];
    if (e.stamp != hf->stamp() || e.bx != bx || e.by != by) terrain_soa_build(*hf, bx, by, e);
    return e;
  }

  // fn(v, in) for each view v of leaf block (bx, by)'s triangles against
  // part leaf x (in: the prefilters' input); returns the triangle count.
  template <class Fn>
  int terrain_views(const BvhNode& x, int bx, int by, Fn&& fn) const {
    const TerrainLeafSoa& t = terrain_soa(bx, by);
    LeafSide side = side_t;
    side.soa = t.soa;
    for (int v = 0; v * kLeafLanes < t.n; ++v) {
      LeafPairInput in;
      make_leaf_pair(side_p, x.index, static_cast<int>(x.count), x.lo, x.hi, side,
                     static_cast<std::uint32_t>(v * kLeafLanes), std::min(kLeafLanes, t.n - v * kLeafLanes), t.lo,
                     t.hi, in);
      fn(v, in);
    }
    return t.n;
  }

  // Both views against part leaf x: lb[v] for view v, cand[i] bit j: (part
  // triangle i, terrain triangle j) not settled by the lower bounds
  // against cut2.
  void terrain_bounds(const BvhNode& x, int bx, int by, float cut2, LeafPairBounds* lb, std::uint32_t* cand) const {
    std::fill(cand, cand + x.count, 0u);
    terrain_views(x, bx, by, [&](int v, const LeafPairInput& in) {
      kernels.lower_bounds(in, cut2, lb[v]);
      for (std::uint32_t i = 0; i < x.count; ++i) cand[i] |= lb[v].candidates[i] << (v * kLeafLanes);
    });
  }

  // The same for the collision test: touch[i] bit j, the pair not proven
  // disjoint (the exact test must decide).
  void terrain_touch(const BvhNode& x, int bx, int by, std::uint32_t* touch) const {
    std::fill(touch, touch + x.count, 0u);
    terrain_views(x, bx, by, [&](int v, const LeafPairInput& in) {
      std::uint32_t m[kLeafLanes];
      kernels.touch_masks(in, m);
      for (std::uint32_t i = 0; i < x.count; ++i) touch[i] |= m[i] << (v * kLeafLanes);
    });
  }

  // The part node's reference-frame box (Arvo), widened by cull_margin.
  void part_box(std::uint32_t node, double* lo, double* hi) const {
    const BvhNode& n = part->bvh.nodes[node];
    map_box(pose, n.lo, n.hi, cull_margin, lo, hi);
  }

  // Posed oriented box of a part node (rigid ta only), in the reference frame.
  void posed_obb(std::uint32_t node, PosedObb& o) const {
    const NodeObb& b = part->obbs[node];
    for (int j = 0; j < 3; ++j)
      for (int r = 0; r < 3; ++r)
        o.axis[3 * j + r] = pose.l[3 * r] * b.axis[3 * j] + pose.l[3 * r + 1] * b.axis[3 * j + 1] +
                            pose.l[3 * r + 2] * b.axis[3 * j + 2];
    pose.apply(b.center, o.center);
    o.half = b.half;
  }

  // Rounding tolerance of the oriented-box tests (kernels/obb.h) of o against a block box.
  double tolerance(const PosedObb& o, const double* blo, const double* bhi) const {
    double s = o.half[0] + o.half[1] + o.half[2] + std::abs(o.center[0]) + std::abs(o.center[1]) +
               std::abs(o.center[2]);
    for (int k = 0; k < 3; ++k) s += std::abs(blo[k]) + std::abs(bhi[k]);
    return 1e-12 * s + cull_margin[0] + cull_margin[1] + cull_margin[2];
  }

  // Working-frame triangles of a part leaf: those whose bit is set in
  // `which` (all by default; the others are not written).
  void part_triangles(const BvhNode& x, double (*out)[9], std::uint32_t which = ~std::uint32_t{0}) const {
    for (std::uint32_t i = 0; i < x.count; ++i) {
      if (!(which >> i & 1)) continue;
      for (int v = 0; v < 3; ++v) {
        const double* src = part->vertex(x.index + i, v);
        if (map_part)
          part_map.apply(src, out[i] + 3 * v);
        else
          std::copy(src, src + 3, out[i] + 3 * v);
      }
    }
  }

  // A terrain point (reference frame) in the working frame: what every
  // terrain corner a search reads goes through, so that the same sample
  // gives the same doubles wherever it is read.
  void terrain_point(const double* p, double* out) const {
    if (map_terrain)
      terrain_map.apply(p, out);
    else
      std::copy(p, p + 3, out);
  }

  // Working-frame triangles of a leaf block: returns how many; ids are the
  // dem_mesh indices. Each sample is mapped once (the same doubles the mesh
  // path gets by mapping each corner).
  int terrain_triangles(int bx, int by, double (*out)[9], std::uint32_t* ids,
                        std::uint32_t which = ~std::uint32_t{0}) const {
    const int L = Heightfield::kLeafCells;
    const int c0 = bx * L, r0 = by * L;
    const int c1 = std::min(c0 + L, hf->cell_cols()), r1 = std::min(r0 + L, hf->cell_rows());
    double s[kLeafSamples][3];
    bool mapped[kLeafSamples] = {};
    auto sample = [&](int c, int r) -> const double* {
      const int k = (r - r0) * (L + 1) + (c - c0);
      if (!mapped[k]) {
        const double p[3] = {hf->x(c), hf->y(r), hf->z(c, r)};
        terrain_point(p, s[k]);
        mapped[k] = true;
      }
      return s[k];
    };
    static constexpr int kCorner[2][3][2] = {{{0, 0}, {1, 0}, {1, 1}}, {{0, 0}, {1, 1}, {0, 1}}};
    int n = 0;
    for (int r = r0; r < r1; ++r)
      for (int c = c0; c < c1; ++c) {
        const std::uint32_t first = hf->cell_first_tri(c, r);
        if (first == Heightfield::kNoTriangle) continue;
        for (int k = 0; k < 2; ++k, ++n) {
          if (!(which >> n & 1)) continue;
          for (int v = 0; v < 3; ++v) {
            const double* p = sample(c + kCorner[k][v][0], r + kCorner[k][v][1]);
            std::copy(p, p + 3, out[n] + 3 * v);
          }
          ids[n] = first + static_cast<std::uint32_t>(k);
        }
      }
    return n;
  }

  // Both sides of a leaf pair (part leaf x, terrain leaf block (bx, by)) in
  // the working frame with their boxes; returns the terrain triangle count.
  // Only the triangles a pair of `pairs` (bit j of pairs[i]: part triangle
  // i, terrain triangle j) names: the others are not written (a leaf pair
  // the float prefilter leaves a few pairs of maps a few triangles).
  int leaf_triangles(const BvhNode& x, int bx, int by, const std::uint32_t* pairs, LeafTriangles& l) const {
    std::uint32_t parts = 0, terrain = 0;
    for (std::uint32_t i = 0; i < x.count; ++i) {
      parts |= (pairs[i] != 0 ? std::uint32_t{1} : 0u) << i;
      terrain |= pairs[i];
    }
    part_triangles(x, l.tri_p, parts);
    const int nt = terrain_triangles(bx, by, l.tri_t, l.ids, terrain);
    for (std::uint32_t m = parts; m != 0; m &= m - 1) {
      const int i = __builtin_ctz(m);
      triangle_box(l.tri_p[i], l.box_p[i]);
    }
    for (std::uint32_t m = terrain; m != 0; m &= m - 1) {
      const int j = __builtin_ctz(m);
      if (j < nt) triangle_box(l.tri_t[j], l.box_t[j]);
    }
    return nt;
  }

  // Overlap and distance kernels in the mesh path's argument order.
  bool overlap(const double* p, const double* t) const {
    if (rigid) return tri_tri_overlap(p, p + 3, p + 6, t, t + 3, t + 6);
    return tri_tri_overlap(t, t + 3, t + 6, p, p + 3, p + 6);
  }
  // tri_distance_disjoint2 bitwise, in the dispatched kernels' double lanes.
  double distance2(const double* p, const double* t, Vec3& on_p, Vec3& on_t) const {
    const LeafKernels& k = leaf_kernels();
    if (rigid) return k.tri_distance2(p, t, on_p.data(), on_t.data());
    return k.tri_distance2(t, p, on_t.data(), on_p.data());
  }
  TriDistance common_point(const double* p, const double* t) const {
    if (rigid) return tri_distance(p, t);
    TriDistance d = tri_distance(t, p);
    std::swap(d.point_p, d.point_q);
    return d;
  }

  // A block's box and size for the traversal; false when empty.
  bool block(int level, int bx, int by, double* lo, double* hi) const {
    return hf->block_box(level, bx, by, lo, hi);
  }
};

// A part node and a pyramid block.
struct Pair {
  std::uint32_t node;
  int level, bx, by;
  double lower2;
};

thread_local std::vector<Pair> t_hf_stack;

double half_sum(const double* lo, const double* hi) {
  return 0.5 * ((hi[0] - lo[0]) + (hi[1] - lo[1]) + (hi[2] - lo[2]));
}

// Children of a block at level > 0 that hold a valid cell: up to 4.
int block_children(const Heightfield& hf, int level, int bx, int by, int (*kids)[2]) {
  const Heightfield::Level& below = hf.levels()[static_cast<std::size_t>(level) - 1];
  int n = 0;
  for (int dy = 0; dy <= 1; ++dy)
    for (int dx = 0; dx <= 1; ++dx) {
      const int cx = 2 * bx + dx, cy = 2 * by + dy;
      if (cx >= below.nx || cy >= below.ny) continue;
      const auto& b = below.blocks[static_cast<std::size_t>(cy) * below.nx + cx];
      if (!(b.zmin <= b.zmax)) continue;
      kids[n][0] = cx, kids[n][1] = cy;
      ++n;
    }
  return n;
}

// A pair whose part node is split when it is the larger (or the block is a leaf).
bool split_part(const BvhNode& x, int level, double part_size, const double* blo, const double* bhi) {
  return !x.is_leaf() && (level == 0 || part_size >= half_sum(blo, bhi));
}

struct Hit {
  bool found = false;
  std::uint32_t slot = 0, tri = 0;
};

// Collision against the terrain, for overlap_descent (kernels/pair_traversal.h);
// stops after `limit` pairs (>= 1).
struct HfOverlap {
  using Pair = plancheck::Pair;
  struct Cull {
    double blo[3], bhi[3], part_size;
  };

  const HfQuery& q;
  std::size_t limit;
  CollideResult& result;
  Hit* hit;

  void visited() { ++result.node_pairs_visited; }

  bool disjoint(const Pair& p, Cull& c) const {
    if (!q.block(p.level, p.bx, p.by, c.blo, c.bhi)) return true;
    if (q.use_obb) {
      PosedObb o;
      q.posed_obb(p.node, o);
      c.part_size = o.half[0] + o.half[1] + o.half[2];
      return obb_box_disjoint(o, c.blo, c.bhi, q.tolerance(o, c.blo, c.bhi));
    }
    double plo[3], phi[3];
    q.part_box(p.node, plo, phi);
    c.part_size = half_sum(plo, phi);
    return !boxes_overlap(plo, phi, c.blo, c.bhi);
  }

  bool leaf_pair(const Pair& p) const { return q.part->bvh.nodes[p.node].is_leaf() && p.level == 0; }

  bool leaves(const Pair& p) {
    const BvhNode& x = q.part->bvh.nodes[p.node];
    // SIMD float disjointness first (kernels/leaf_bounds.h): a pair it
    // proves disjoint is one the exact test would refuse, so the pairs
    // listed and their order are those without it.
    std::uint32_t touch[kMaxLeafSize];
    q.terrain_touch(x, p.bx, p.by, touch);
    std::uint32_t any = 0;
    for (std::uint32_t i = 0; i < x.count; ++i) any |= touch[i];
    if (any == 0) return true;
    LeafTriangles l;
    const int nt = q.leaf_triangles(x, p.bx, p.by, touch, l);
    auto& [tri_p, tri_t, box_p, box_t, ids] = l;
    for (std::uint32_t i = 0; i < x.count; ++i)
      for (std::uint32_t m = touch[i]; m != 0; m &= m - 1) {
        const int j = __builtin_ctz(m);
        if (j >= nt) continue;
        if (!boxes_overlap(box_p[i], box_p[i] + 3, box_t[j], box_t[j] + 3)) continue;
        ++result.triangle_pairs_tested;
        if (!q.overlap(tri_p[i], tri_t[j])) continue;
        if (hit && !hit->found) *hit = Hit{true, x.index + i, ids[j]};
        result.collide = true;
        result.triangle_pairs.emplace_back(q.part->bvh.prim_ids[x.index + i], ids[j]);
        if (result.triangle_pairs.size() >= limit) return false;
      }
    return true;
  }

  int split(const Pair& p, const Cull& c, Pair* kids) const {
    const BvhNode& x = q.part->bvh.nodes[p.node];
    if (split_part(x, p.level, c.part_size, c.blo, c.bhi)) {
      kids[0] = {x.index, p.level, p.bx, p.by, 0.0};
      kids[1] = {x.index + 1, p.level, p.bx, p.by, 0.0};
      return 2;
    }
    int cells[4][2];
    const int n = block_children(*q.hf, p.level, p.bx, p.by, cells);
    for (int k = 0; k < n; ++k) kids[k] = {p.node, p.level - 1, cells[k][0], cells[k][1], 0.0};
    return n;
  }
};

void collide_in(const HfQuery& q, std::size_t limit, CollideResult& result, Hit* hit) {
  HfOverlap o{q, limit, result, hit};
  overlap_descent(o, t_hf_stack, Pair{0, static_cast<int>(q.hf->levels().size()) - 1, 0, 0, 0.0});
}

constexpr double kShrink = 1.0 - 1e-12;

// Distance to the terrain once no pair intersects, for distance_descent
// (kernels/pair_traversal.h).
struct HfDistance {
  using Pair = plancheck::Pair;

  const HfQuery& q;
  DistanceResult& result;
  double best;
  double shrink_rel;
  double tie;
  double cut = std::max(0.0, best * shrink_rel - tie);
  double best2_ = cut * cut;
  bool found = false;
  bool first_below = false;
  DescentFloor dropped{};  // what a search that finds nothing proved (beyond)
  void pruned(double l2) { dropped.pruned(l2); }
  std::uint32_t best_slot = 0, best_tri = 0;
  Vec3 best_pp = Vec3::Zero(), best_pt = Vec3::Zero();

  double best2() const { return best2_; }
  void visited() { ++result.node_pairs_visited; }
  bool leaf_pair(const Pair& p) const { return q.part->bvh.nodes[p.node].is_leaf() && p.level == 0; }

  // The kernel on one triangle pair (part slot, dem_mesh index).
  // True when it improved the best.
  bool consider(const double* p, const double* t, std::uint32_t slot, std::uint32_t tri) {
    Vec3 pp, pt;
    const double dist = std::sqrt(q.distance2(p, t, pp, pt));
    if (!(dist < best)) return false;
    found = true;
    best = dist;
    cut = std::max(0.0, best * shrink_rel - tie);
    best2_ = cut * cut;
    best_slot = slot, best_tri = tri, best_pp = pp, best_pt = pt;
    return true;
  }

  // posed: node's posed box when the caller has it (use_obb only).
  double lower2(std::uint32_t node, const double* blo, const double* bhi, const PosedObb* posed = nullptr) const {
    if (q.use_obb) {
      PosedObb own;
      if (!posed) {
        q.posed_obb(node, own);
        posed = &own;
      }
      const PosedObb& o = *posed;
      const double lb = obb_box_lower(o, blo, bhi, q.tolerance(o, blo, bhi));
      return lb * lb * kShrink;
    }
    double plo[3], phi[3];
    q.part_box(node, plo, phi);
    return box_distance_squared(plo, phi, blo, bhi) * kShrink;
  }

  // (best + kernel_slack)^2 rounded up to float: a float lower bound at or
  // above it proves the kernel's value for the pair is at least best.
  float float_cut2() const {
    const double c = best + q.kernel_slack;
    return round_up(c * c * (1.0 + 1e-15));
  }

  bool leaves(const Pair& p) {
    dropped.at_cut = true;
    const BvhNode& x = q.part->bvh.nodes[p.node];
    // SIMD float lower bounds first (kernels/leaf_bounds.h), the terrain
    // leaf's triangles as two views of up to 16. A pair is skipped only
    // when its bound reaches best + kernel_slack: the kernel's value would
    // then be at least best, so consider() would not take it. Skipping
    // pairs that change nothing leaves every improvement, and so the
    // answer and the order of the rest, as without the filter; a leaf pair
    // with no pair left is never mapped in double.
    float cut2_f = float_cut2();
    LeafPairBounds lb[2];
    std::uint32_t cand[kMaxLeafSize];
    q.terrain_bounds(x, p.bx, p.by, cut2_f, lb, cand);
    std::uint32_t any = 0;
    for (std::uint32_t i = 0; i < x.count; ++i) any |= cand[i];
    if (any == 0) return true;
    LeafTriangles l;
    const int nt = q.leaf_triangles(x, p.bx, p.by, cand, l);
    auto& [tri_p, tri_t, box_p, box_t, ids] = l;
    for (std::uint32_t i = 0; i < x.count; ++i)
      for (std::uint32_t m = cand[i]; m != 0; m &= m - 1) {
        const int j = __builtin_ctz(m);
        if (j >= nt || lb[j / kLeafLanes].lower2[i][j % kLeafLanes] >= cut2_f) continue;
        if (box_distance_squared(box_p[i], box_p[i] + 3, box_t[j], box_t[j] + 3) * kShrink >= best2_) continue;
        ++result.triangle_pairs_tested;
        if (consider(tri_p[i], tri_t[j], x.index + i, ids[j])) cut2_f = float_cut2();
        if (found && first_below) return false;  // a yes is enough
      }
    return true;
  }

  int split(const Pair& p, Pair* kids) const {
    const BvhNode& x = q.part->bvh.nodes[p.node];
    double blo[3], bhi[3];
    q.block(p.level, p.bx, p.by, blo, bhi);
    double part_size;
    if (q.use_obb) {
      const double* h = q.part->obbs[p.node].half;
      part_size = h[0] + h[1] + h[2];
    } else {
      double plo[3], phi[3];
      q.part_box(p.node, plo, phi);
      part_size = half_sum(plo, phi);
    }
    if (split_part(x, p.level, part_size, blo, bhi)) {
      for (std::uint32_t c = 0; c < 2; ++c) kids[c] = {x.index + c, p.level, p.bx, p.by, lower2(x.index + c, blo, bhi)};
      return 2;
    }
    int cells[4][2];
    const int m = block_children(*q.hf, p.level, p.bx, p.by, cells);
    // The children share the part node: pose its box once.
    PosedObb o{};
    if (q.use_obb) q.posed_obb(p.node, o);
    for (int k = 0; k < m; ++k) {
      double clo[3], chi[3];
      q.block(p.level - 1, cells[k][0], cells[k][1], clo, chi);
      kids[k] = {p.node, p.level - 1, cells[k][0], cells[k][1], lower2(p.node, clo, chi, q.use_obb ? &o : nullptr)};
    }
    return m;
  }
};

// The working-frame corners of part slot `slot` and of dem_mesh triangle
// `tri`, mapped as terrain_triangles maps its block's samples (the same
// doubles in, so the same out); false when tri is not found.
bool triangle_pair(const HfQuery& q, std::uint32_t slot, std::uint32_t tri, double* p, double* t) {
  int cc, cr, k;
  q.hf->triangle_cell(tri, cc, cr, k);
  const std::uint32_t first = q.hf->cell_first_tri(cc, cr);
  if (first == Heightfield::kNoTriangle || first + static_cast<std::uint32_t>(k) != tri) return false;
  BvhNode one{{0, 0, 0}, {0, 0, 0}, slot, 1};
  double tri_p[1][9];
  q.part_triangles(one, tri_p);
  std::copy(tri_p[0], tri_p[0] + 9, p);
  double raw[9];
  q.hf->cell_triangle(cc, cr, k, raw);
  for (int v = 0; v < 3; ++v) q.terrain_point(raw + 3 * v, t + 3 * v);
  return true;
}

// What distance() reports for a found pair: world points, mesh indices.
void finish_answer(const HfQuery& q, std::uint32_t slot, std::uint32_t tri, const Vec3& pp, const Vec3& pt,
                   double d, DistanceResult& result) {
  result.found = true;
  result.distance = d;
  result.point_a = q.to_world * pp;
  result.point_b = q.to_world * pt;
  result.triangle_a = q.part->bvh.prim_ids[slot];
  result.triangle_b = tri;
  result.slot_a = slot;
  result.slot_b = tri;
}

// distance()'s answer for a pose where collide_in found `hit`: a common
// point of that pair (nothing when its triangles cannot be rebuilt).
void contact_answer(const HfQuery& q, const Hit& hit, DistanceResult& result) {
  double p[9], t[9];
  if (!triangle_pair(q, hit.slot, hit.tri, p, t)) return;
  const TriDistance d = q.common_point(p, t);
  finish_answer(q, hit.slot, hit.tri, d.point_p, d.point_q, 0.0, result);
}

}  // namespace

void collide(const CollisionModel& a, const Affine& ta, const Heightfield& terrain, const CollideRequest& request,
             CollideResult& result) {
  result.collide = false;
  result.triangle_pairs.clear();
  result.node_pairs_visited = result.triangle_pairs_tested = 0;
  if (a.triangle_count() == 0 || terrain.triangle_count() == 0) return;
  HfQuery q;
  q.setup(a, ta, terrain);
  Hit hit;
  collide_in(q, std::max<std::size_t>(1, request.max_triangle_pairs), result, request.contact ? &hit : nullptr);
  if (request.contact && hit.found) {
    *request.contact = DistanceResult{};
    contact_answer(q, hit, *request.contact);
  }
}

void distance(const CollisionModel& a, const Affine& ta, const Heightfield& terrain, const DistanceRequest& request,
              DistanceResult& result) {
  result = DistanceResult{};
  if (a.triangle_count() == 0 || terrain.triangle_count() == 0) return;
  HfQuery q;
  q.setup(a, ta, terrain);
  if (!(request.upper_bound > 0.0)) return;
  const Heightfield& hf = terrain;
  auto finish = [&](std::uint32_t slot, std::uint32_t tri, const Vec3& pp, const Vec3& pt, double d) {
    finish_answer(q, slot, tri, pp, pt, d, result);
  };
  if (!request.known_disjoint) {
    // Intersection first, as the mesh path does: distance bounds cannot cull
    // anything among pairs at distance 0.
    CollideResult c;
    Hit hit;
    collide_in(q, 1, c, &hit);
    result.node_pairs_visited += c.node_pairs_visited;
    result.triangle_pairs_tested += c.triangle_pairs_tested;
    if (hit.found) {
      contact_answer(q, hit, result);
      return;
    }
  }
  HfDistance d{q, result, request.upper_bound, 1.0 / (1.0 + std::max(0.0, request.rel_tolerance)),
               std::max(0.0, request.abs_tolerance)};
  if (request.seed_slot_a >= 0 && request.seed_slot_b >= 0 &&
      static_cast<std::uint64_t>(request.seed_slot_a) < q.part->triangle_count() &&
      static_cast<std::uint64_t>(request.seed_slot_b) < hf.triangle_count()) {
    const auto slot = static_cast<std::uint32_t>(request.seed_slot_a);
    const auto tri = static_cast<std::uint32_t>(request.seed_slot_b);
    double p[9], t[9];
    if (triangle_pair(q, slot, tri, p, t)) d.consider(p, t, slot, tri);
  }
  d.first_below = request.first_below;
  const int root = static_cast<int>(hf.levels().size()) - 1;
  double blo[3], bhi[3];
  if (!q.block(root, 0, 0, blo, bhi)) return;
  if (!(d.found && d.first_below)) distance_descent(d, t_hf_stack, Pair{0, root, 0, 0, d.lower2(0, blo, bhi)});
  if (d.found)
    finish(d.best_slot, d.best_tri, d.best_pp, d.best_pt, d.best);
  else if (request.beyond)
    result.beyond = d.dropped.beyond(d.cut);
}

}  // namespace plancheck
