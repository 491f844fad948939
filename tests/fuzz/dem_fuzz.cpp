// SPDX-License-Identifier: MIT
// ESRI ASCII DEM: the reader (hand-written and strict; GDAL reads every
// other raster format), then the mesh and surface height of what it read.
#include "src/base/error.h"
#include "src/scene/terrain.h"
#include "tests/fuzz/support.h"

#include <cmath>
#include <sstream>
#include <string>

using namespace plancheck;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    const Dem dem = read_dem(in, "fuzz.asc", 1.0);
    const std::size_t count = static_cast<std::size_t>(dem.ncols) * static_cast<std::size_t>(dem.nrows);
    fuzz::require(dem.ncols >= 1 && dem.nrows >= 1 && dem.cellsize > 0, "positive grid");
    fuzz::require(dem.z.size() == count && dem.valid.size() == count, "one sample per cell");
    for (std::size_t i = 0; i < count; ++i)
      fuzz::require(!dem.valid[i] || (std::isfinite(dem.z[i]) && std::abs(dem.z[i]) <= kMaxDemHeight),
                    "heights finite and within kMaxDemHeight");
    const Mesh mesh = dem_mesh(dem, Vec3::Zero());
    fuzz::require(mesh.vertices.size() == count, "one vertex per sample");
    for (const auto& t : mesh.triangles)
      for (auto i : t) fuzz::require(i < count, "triangle index in range");
    // Heights across the grid and just outside it.
    const double w = dem.ncols * dem.cellsize, h = dem.nrows * dem.cellsize;
    for (double fx : {-0.1, 0.0, 0.37, 0.5, 0.99, 1.0, 1.1})
      for (double fy : {-0.1, 0.0, 0.61, 1.0, 1.1}) {
        const auto z = dem_surface(dem, Vec3::Zero(), fx * w, fy * h);
        fuzz::require(!z || std::isfinite(*z), "finite surface height");
      }
  } catch (const InputError&) {
  }
  return 0;
}
