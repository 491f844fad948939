// SPDX-License-Identifier: MIT
// Terrain from a DEM: the ESRI ASCII grid reader and the grid as a mesh.
#pragma once

#include "src/scene/scene.h"

#include <filesystem>
#include <istream>
#include <optional>
#include <vector>

namespace plancheck {

// An ESRI ASCII grid, in metres. Samples sit at cell centres; row 0 is the
// southernmost (smallest y) row, i.e. the file's last data row.
struct Dem {
  int ncols = 0;
  int nrows = 0;
  double cellsize = 0.0;         // m
  double x0 = 0.0;               // x of column 0's centre, relative to the grid origin (m)
  double y0 = 0.0;               // y of row 0's centre, relative to the grid origin (m)
  double xll = 0.0;              // the file's xllcorner/xllcenter value (m), for writing back;
  double yll = 0.0;              // the placement itself is terrain.origin (scene-format.md)
  std::vector<double> z;         // nrows * ncols, row-major from row 0; m
  std::vector<unsigned char> valid;  // 0 where the file has NODATA_value

  double height(int col, int row) const { return z[static_cast<std::size_t>(row) * ncols + col]; }
  bool is_valid(int col, int row) const { return valid[static_cast<std::size_t>(row) * ncols + col] != 0; }
};

// Reads an ESRI ASCII grid (ncols, nrows, xllcorner|xllcenter,
// yllcorner|yllcenter, cellsize, optional NODATA_value, then nrows rows of
// ncols values, top row first). Heights and cell size are multiplied by
// length_scale. Throws InputError naming the file and line.
Dem load_dem(const std::filesystem::path& file, double length_scale);

// The same from a seekable stream (an open file or a string); `file` names
// it in messages.
Dem read_dem(std::istream& in, const std::filesystem::path& file, double length_scale);

// Sample (c, r) in the reference frame: origin + (x0 + c*cellsize, y0 + r*cellsize, z).
// dem_mesh and the Heightfield both place samples with this one function, so
// their coordinates are the same doubles.
inline Vec3 dem_point(const Dem& dem, const Vec3& origin, int c, int r) {
  return origin + Vec3(dem.x0 + c * dem.cellsize, dem.y0 + r * dem.cellsize, dem.height(c, r));
}

// The grid as triangles in the reference frame: sample (c, r) at dem_point. Each cell between four valid
// samples gives two triangles; cells touching a NODATA sample are holes.
Mesh dem_mesh(const Dem& dem, const Vec3& origin);

// Height of the surface dem_mesh draws at the reference-frame point (x, y):
// the cell's two triangles interpolated linearly (the same split as
// dem_mesh), so "below the surface" here agrees with the collision mesh.
// Empty outside the grid's samples or over a NODATA hole.
std::optional<double> dem_surface(const Dem& dem, const Vec3& origin, double x, double y);

// Writes an ESRI ASCII grid that load_dem reads back to the same samples
// (17 significant digits), lengths divided by length_scale; xll/yll are
// written as xllcorner/yllcorner or xllcenter/yllcenter as they were read, so
// the scene's terrain.origin places the written grid where it placed the read one.
void write_dem(const std::filesystem::path& file, const Dem& dem, double length_scale, double nodata = -9999.0);

}  // namespace plancheck
