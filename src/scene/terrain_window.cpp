// SPDX-License-Identifier: MIT
// The terrain window. Every use of the terrain happens within a horizontal
// distance of the moving parts' reach (scene/reach.h: each part stays within
// r_max of its chain's first pivot c in every state):
//  - terrain pairs: a sample farther than r_max + max(margin, D) from c
//    horizontally is farther than the margin and than D from the part in
//    every pose, where D = r_min + min |s - c| over the window's valid
//    samples s bounds the part's distance to the terrain from above in every
//    pose. So contacts, clearance verdicts and the terrain distances
//    themselves are those of the whole raster. D is known after a first read
//    of radius r_max + margin; a wider second read (never a third: a wider
//    window only lowers D) takes what D asks for.
//  - probes: a ray from a point within R of c, at most max_range long.
//  - the scoop: its part's reach plus the template's width; slopes relaxed
//    after a swept dig spread from there (a few cells of pad below; relaxing
//    that reaches the window's edge stops there, see docs/terrain-gdal.md).
// Each reach is a disc around c; the window is the pixels whose samples fall
// in the discs' bounding box, grown by kPadCells so every cell touching a
// disc is whole.
#include "src/scene/terrain_window.h"

#include "src/base/error.h"
#include "src/scene/reach.h"
#include "src/scene/terrain.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace plancheck {

namespace {

constexpr int kPadCells = 3;

struct Disc {
  Vec3 centre = Vec3::Zero();
  double reach = 0.0;       // r_max (m)
  double extra = 0.0;       // margin, ray length, scoop width (m)
  bool distance = false;    // a terrain pair: widen by D (see above)
  double r_min = 0.0;
  double radius(double d) const { return reach + std::max(extra, distance ? d : 0.0); }
};

double units_of(const std::string& unit) {
  if (unit == "m" || unit == "metre" || unit == "meter" || unit == "metres" || unit == "meters") return 1.0;
  if (unit == "cm") return 0.01;
  if (unit == "mm") return 0.001;
  if (unit == "km") return 1000.0;
  return 0.0;
}

void check_units(const DemHeader& h, const Scene& scene) {
  const auto& file = h.source.file;
  const double ls = scene.length_scale;
  if (h.linear_unit_m > 0.0 && std::abs(h.linear_unit_m - ls) > 1e-9 * ls)
    fail(file, "the CRS's unit is " + std::to_string(h.linear_unit_m) + " m but the scene's length_unit " +
                   scene.length_unit + " is " + std::to_string(ls) +
                   " m: set length_unit to the raster's unit (or reproject it: gdalwarp -t_srs ...)");
  if (!h.height_unit.empty()) {
    const double u = units_of(h.height_unit);
    if (u == 0.0) fail(file, "band " + std::to_string(h.source.band) + ": unknown height unit '" + h.height_unit + "'");
    if (std::abs(u - ls) > 1e-9 * ls)
      fail(file, "band " + std::to_string(h.source.band) + ": heights are in " + h.height_unit +
                     " but the scene's length_unit is " + scene.length_unit);
  }
}

// False when some part that uses the terrain has no reach bound.
bool reach_discs(const Scene& scene, std::vector<Disc>& discs) {
  if (scene.terrain->collide) {
    const auto& allowed = scene.terrain_allowed_parts;
    for (std::size_t i = 0; i < scene.parts.size(); ++i) {
      const Part& p = scene.parts[i];
      if (!p.moving() || p.mesh.triangles.empty()) continue;
      if (std::find(allowed.begin(), allowed.end(), static_cast<int>(i)) != allowed.end()) continue;
      const Reach r = part_reach(scene, p.chain, p.mesh);
      if (!r.bounded) return false;
      discs.push_back({r.centre, r.r_max, scene.safety_margin, true, r.r_min});
    }
  }
  for (const ProbeConfig& pr : scene.probes) {
    const Part& p = scene.parts[static_cast<std::size_t>(pr.part_index)];
    if (!p.moving()) {
      discs.push_back({pr.origin, 0.0, pr.max_range, false, 0.0});
      continue;
    }
    const double r = point_reach(scene, p.chain, pr.origin);
    if (r < 0.0) return false;
    discs.push_back({scene.actions[static_cast<std::size_t>(p.chain.front())].pivot, r, pr.max_range, false, 0.0});
  }
  if (scene.scoop) {
    const Part& p = scene.parts[static_cast<std::size_t>(scene.scoop->part_index)];
    const Reach r = part_reach(scene, p.chain, p.mesh);
    const double m = point_reach(scene, p.chain, scene.scoop->bottom_point);
    if (!r.bounded || m < 0.0) return false;
    discs.push_back({r.centre, std::max(r.r_max, m), scene.scoop->width, false, 0.0});
  }
  return true;
}

// The pixels (GDAL order) whose samples lie within the discs' bounding box,
// grown by kPadCells; empty (cols 0) when it misses the raster.
PixelWindow window_of(const std::vector<Disc>& discs, double d, const DemHeader& h, const Vec3& origin, double ls) {
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo, y_lo = x_lo, y_hi = -x_lo;
  for (const Disc& disc : discs) {
    const double r = disc.radius(d);
    x_lo = std::min(x_lo, disc.centre.x() - r);
    x_hi = std::max(x_hi, disc.centre.x() + r);
    y_lo = std::min(y_lo, disc.centre.y() - r);
    y_hi = std::max(y_hi, disc.centre.y() + r);
  }
  const double cs = h.cellsize * ls;
  const double base_x = h.center_x ? 0.0 : 0.5 * cs, base_y = h.center_y ? 0.0 : 0.5 * cs;
  const int cols = h.source.raster_cols, rows = h.source.raster_rows;
  // Sample column c sits at origin.x + base + c*cs; south row r at origin.y + base + r*cs.
  auto clamp = [](double v, int hi) { return static_cast<int>(std::clamp(v, -1.0, static_cast<double>(hi))); };
  const int c0 = clamp(std::floor((x_lo - origin.x() - base_x) / cs) - kPadCells, cols);
  const int c1 = clamp(std::ceil((x_hi - origin.x() - base_x) / cs) + kPadCells, cols);
  const int s0 = clamp(std::floor((y_lo - origin.y() - base_y) / cs) - kPadCells, rows);
  const int s1 = clamp(std::ceil((y_hi - origin.y() - base_y) / cs) + kPadCells, rows);
  PixelWindow w;
  const int cl = std::max(c0, 0), ch = std::min(c1, cols - 1), sl = std::max(s0, 0), sh = std::min(s1, rows - 1);
  if (cl > ch || sl > sh) return w;
  w.col_off = cl;
  w.cols = ch - cl + 1;
  w.row_off = rows - 1 - sh;
  w.rows = sh - sl + 1;
  return w;
}

// D of the comment above: the nearest valid sample to the disc's centre, plus r_min.
double distance_bound(const Dem& dem, const Vec3& origin, const Disc& disc) {
  double nearest = std::numeric_limits<double>::infinity();
  for (int r = 0; r < dem.nrows; ++r)
    for (int c = 0; c < dem.ncols; ++c)
      if (dem.is_valid(c, r)) nearest = std::min(nearest, (dem_point(dem, origin, c, r) - disc.centre).norm());
  return disc.r_min + nearest;
}

std::string window_text(const PixelWindow& w) {
  return std::to_string(w.cols) + " x " + std::to_string(w.rows) + " pixels from column " +
         std::to_string(w.col_off + 1) + ", row " + std::to_string(w.row_off + 1);
}

}  // namespace

void load_terrain(Scene& scene) {
  TerrainConfig& t = *scene.terrain;
  auto reader = open_dem(t.dem, t.band);
  const DemHeader& h = reader->header();
  const auto& file = h.source.file;
  check_units(h, scene);
  const double ls = scene.length_scale;
  if (t.map_origin) {
    if (!h.projected)
      fail(file, std::string("terrain.map_origin needs a raster with a projected CRS; this one has ") +
                     (h.source.crs_wkt.empty() ? "none (use terrain.origin, or assign one: gdal_edit.py -a_srs ...)"
                                               : "a local one (use terrain.origin)"));
    const auto& g = h.source.geotransform;
    // Sample (c, south row r) is at map (g0 + (c + 1/2) cs, south + (r + 1/2) cs) and at
    // origin + (base + c cs, base + r cs) in the frame (base: cs/2, GDAL's rasters being corner-based).
    const Vec3& m = *t.map_origin;
    const double south = g[3] + h.source.raster_rows * g[5];
    t.origin = Vec3((g[0] - m.x()) * ls, (south - m.y()) * ls, -m.z() * ls);
  }
  std::vector<Disc> discs;
  const bool bounded = reach_discs(scene, discs) && !discs.empty();
  const DemSource& s = h.source;
  PixelWindow w{0, 0, s.raster_cols, s.raster_rows};
  if (bounded) w = window_of(discs, 0.0, h, t.origin, ls);
  auto no_data = [&](const std::string& what) {
    fail(file, what + " within reach of the moving parts: check terrain." +
                   (t.map_origin ? std::string("map_origin") : std::string("origin")) +
                   " (the raster covers map x " + std::to_string(s.geotransform[0]) + " .. " +
                   std::to_string(s.geotransform[0] + s.raster_cols * s.geotransform[1]) + ", y " +
                   std::to_string(s.geotransform[3] + s.raster_rows * s.geotransform[5]) + " .. " +
                   std::to_string(s.geotransform[3]) + ")");
  };
  if (w.cols == 0) no_data("the raster has no pixel");
  Dem dem = reader->read(w, ls);
  if (std::find(dem.valid.begin(), dem.valid.end(), 1) == dem.valid.end())
    no_data("the window (" + window_text(w) + ") holds only nodata, so no terrain is");
  if (bounded) {
    // Widen the terrain pairs' discs by D where it exceeds their margin.
    double d = 0.0;
    for (const Disc& disc : discs)
      if (disc.distance) d = std::max(d, distance_bound(dem, t.origin, disc));
    const PixelWindow wide = window_of(discs, d, h, t.origin, ls);
    if (wide.col_off < w.col_off || wide.row_off < w.row_off || wide.col_off + wide.cols > w.col_off + w.cols ||
        wide.row_off + wide.rows > w.row_off + w.rows)
      dem = reader->read(wide, ls);
  }
  t.grid = std::make_shared<const Dem>(std::move(dem));
}

}  // namespace plancheck
