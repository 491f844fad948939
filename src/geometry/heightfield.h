// SPDX-License-Identifier: MIT
// The terrain as a heightfield: the DEM's samples in double, placed per
// terrain.origin, with a min/max pyramid over blocks of cells, and exact
// collision and distance queries of a posed part against it.
//
// Surface: the very triangles dem_mesh draws (two per cell between four valid
// samples, split along (c, r)-(c+1, r+1)), with the same vertex doubles and
// the same triangle indices, so on undisturbed ground every answer here is
// the mesh path's answer; no BVH over the terrain's triangles is built.
//
// Pyramid: level 0 holds one block per kLeafCells x kLeafCells cells; each
// level above halves the block count per axis, up to one root block. A block
// stores the least and greatest height of the valid cells under it; its box
// is the cells' x, y extent times [zmin, zmax], which contains every
// triangle of those cells exactly (the box corners are sample coordinates).
// refit() updates the blocks over changed samples and their ancestors only.
#pragma once

#include "src/geometry/collision_model.h"
#include "src/scene/scene.h"
#include "src/scene/terrain.h"

#include <cstdint>
#include <vector>

namespace plancheck {

// Samples [c0, c1] x [r0, r1] (inclusive, grid indices); empty when c0 > c1 or r0 > r1.
struct SampleRect {
  int c0 = 0, r0 = 0, c1 = -1, r1 = -1;
  bool empty() const { return c0 > c1 || r0 > r1; }
  void add(const SampleRect& o) {
    if (o.empty()) return;
    if (empty()) {
      *this = o;
      return;
    }
    c0 = std::min(c0, o.c0), r0 = std::min(r0, o.r0), c1 = std::max(c1, o.c1), r1 = std::max(r1, o.r1);
  }
};

class Heightfield {
 public:
  static constexpr int kLeafCells = 4;  // cells per leaf block side: up to 32 triangles per leaf
  static constexpr std::uint32_t kNoTriangle = 0xFFFFFFFFu;

  Heightfield(const Dem& dem, const Vec3& origin);

  struct Block {
    double zmin, zmax;  // reference frame (m); zmin > zmax: no valid cell under the block
  };
  struct Level {
    int nx = 0, ny = 0;  // blocks per axis
    int cells = 0;       // cells per block side at this level
    std::vector<Block> blocks;  // row-major
  };

  int sample_cols() const { return ncols_; }
  int sample_rows() const { return nrows_; }
  int cell_cols() const { return std::max(ncols_ - 1, 0); }
  int cell_rows() const { return std::max(nrows_ - 1, 0); }
  std::size_t triangle_count() const { return tri_cell_.size() * 2; }
  std::size_t memory_bytes() const;
  std::size_t block_count() const;
  const std::vector<Level>& levels() const { return levels_; }
  // Differs between any two heightfields built or refit apart (copies
  // share it until one is refit): what caches of a leaf block's contents key on.
  std::uint64_t stamp() const { return stamp_; }

  // Reference-frame coordinates of sample (c, r): identical doubles to dem_mesh's vertices.
  double x(int c) const { return xs_[static_cast<std::size_t>(c)]; }
  double y(int r) const { return ys_[static_cast<std::size_t>(r)]; }
  double z(int c, int r) const { return z_[static_cast<std::size_t>(r) * ncols_ + c]; }

  bool cell_valid(int c, int r) const { return cell_first_tri(c, r) != kNoTriangle; }
  // dem_mesh's index of the cell's first triangle (the second is +1), or kNoTriangle.
  std::uint32_t cell_first_tri(int c, int r) const {
    return cell_tri_[static_cast<std::size_t>(r) * cell_cols() + c];
  }
  // The cell of a dem_mesh triangle index (k: 0 or 1, which of its two).
  void triangle_cell(std::uint32_t tri, int& c, int& r, int& k) const;
  // Corners of triangle k of cell (c, r), in dem_mesh's corner order: 9 doubles.
  void cell_triangle(int c, int r, int k, double* out) const;

  // Block box (reference frame); false when the block has no valid cell.
  bool block_box(int level, int bx, int by, double* lo, double* hi) const;

  // Copies the heights of samples `changed` from grid (the DEM this field was
  // built from, dug) and refits the blocks whose cells touch them, then their
  // ancestors. Returns the number of blocks recomputed. Holes stay holes.
  std::size_t refit(const Dem& grid, SampleRect changed);

  // First intersection of the ray o + t d, t in [t_near, t_far], with the
  // surface (double, Moller-Trumbore with edges included); on a hit t_far
  // becomes the hit's t and tri its dem_mesh index.
  bool intersect_ray(const double* o, const double* d, double t_near, double& t_far, std::uint32_t& tri) const;

 private:
  void fit_leaf(int bx, int by);
  void fit_inner(int level, int bx, int by);

  int ncols_ = 0, nrows_ = 0;
  double origin_z_ = 0.0;
  std::uint64_t stamp_ = 0;
  std::vector<double> xs_, ys_, z_;       // z_: reference-frame heights, row-major samples
  std::vector<std::uint32_t> cell_tri_;   // per cell: first dem_mesh triangle or kNoTriangle
  std::vector<std::uint32_t> tri_cell_;   // per triangle pair (index / 2): cell index
  std::vector<Level> levels_;             // levels_[0]: leaves; back(): the root
};

// Exact queries of a posed part against the heightfield (which stays in the
// reference frame). Same conventions as collide()/distance() in
// collision_model.h with the part as a and the terrain as b: triangle_b and
// the second index of triangle_pairs are dem_mesh triangle indices; slot_b
// and seed_slot_b are those indices too. The working frame is the one the
// mesh path would pick for (part, ta, terrain mesh, identity): the part's
// frame when ta is rigid (terrain corners mapped by ta^-1, rounded once),
// else the reference frame; the exact tests run on those doubles with the
// same kernels and argument order, so every decision equals the mesh path's.
void collide(const CollisionModel& a, const Affine& ta, const Heightfield& terrain,
             const CollideRequest& request, CollideResult& result);

void distance(const CollisionModel& a, const Affine& ta, const Heightfield& terrain,
              const DistanceRequest& request, DistanceResult& result);

}  // namespace plancheck
