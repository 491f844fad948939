// SPDX-License-Identifier: MIT
// Terrain from a DEM: the ESRI ASCII grid reader and the grid as a mesh.
#pragma once

#include "src/scene.h"

#include <filesystem>
#include <vector>

namespace plancheck {

// An ESRI ASCII grid, in metres. Samples sit at cell centres; row 0 is the
// southernmost (smallest y) row, i.e. the file's last data row.
struct Dem {
  int ncols = 0;
  int nrows = 0;
  double cellsize = 0.0;         // m
  double x0 = 0.0;               // x of column 0's centre, relative to xll (m)
  double y0 = 0.0;               // y of row 0's centre, relative to yll (m)
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

// The grid as triangles in the reference frame: sample (c, r) sits at
// origin + (x0 + c*cellsize, y0 + r*cellsize, z). Each cell between four valid
// samples gives two triangles; cells touching a NODATA sample are holes.
Mesh dem_mesh(const Dem& dem, const Vec3& origin);

}  // namespace plancheck
