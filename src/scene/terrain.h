// SPDX-License-Identifier: MIT
// Terrain from a DEM: the raster readers (ESRI ASCII by hand, everything
// else through GDAL: scene/dem_gdal.cpp), the window read, and the grid as a
// mesh and a surface.
#pragma once

#include "src/scene/scene.h"

#include <array>
#include <filesystem>
#include <istream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace plancheck {

// Heights no real DEM has (|h| above this, metres, after scale, offset and
// length_unit): refused naming the cell. Planetary radius DEMs (the Moon
// 1.74e6 m, Mars 3.4e6 m) fit; 1e154 does not, and would wreck every bound.
constexpr double kMaxDemHeight = 1e7;
// The most samples one window read through GDAL holds (9 bytes each in a
// Dem): about 1.8 GB. (An ESRI ASCII grid's memory follows its text.)
constexpr double kMaxDemWindowPixels = 2e8;

// "%.17g": every double as it reads back.
std::string number_text(double v);

// Where a Dem's samples came from: the raster as a whole and the window of
// it that was read. Pixel indices are GDAL's: column 0 west, row 0 north.
struct DemSource {
  std::filesystem::path file;
  std::string driver;                  // "ESRI ASCII" (read here) or GDAL's short name ("GTiff", "PDS4", ...)
  int band = 1;
  int raster_cols = 0, raster_rows = 0;  // the whole raster
  int col_off = 0, row_off = 0;        // the window's north-west pixel
  bool whole = true;                   // the window is the whole raster
  std::array<double, 6> geotransform{};  // the raster's, GDAL order, map units (not the window's)
  std::string crs_wkt;                 // empty: the file has none
  bool has_nodata = false;
  double nodata = 0.0;                 // as stored in the file (before scale/offset)
  double pixels_read = 0.0;            // samples requested from the file, over every read
  // The window's geotransform: the raster's shifted to the window's corner.
  std::array<double, 6> window_geotransform() const;
};

// A DEM window in metres. Samples sit at cell centres; row 0 is the
// southernmost (smallest y) row.
struct Dem {
  int ncols = 0;
  int nrows = 0;
  double cellsize = 0.0;         // m
  double x0 = 0.0;               // x of column 0's centre, relative to the grid origin (m)
  double y0 = 0.0;               // y of row 0's centre, relative to the grid origin (m)
  double xll = 0.0;              // the file's xllcorner/xllcenter value (m), for writing back;
  double yll = 0.0;              // the placement itself is terrain.origin (scene-format.md)
  bool center_x = false;         // the grid origin's x is the lower-left sample's (xllcenter), not its corner's
  bool center_y = false;         // the same for y (yllcenter)
  std::vector<double> z;         // nrows * ncols, row-major from row 0; m
  std::vector<unsigned char> valid;  // 0 where the file has its nodata value
  DemSource source;

  double height(int col, int row) const { return z[static_cast<std::size_t>(row) * ncols + col]; }
  bool is_valid(int col, int row) const { return valid[static_cast<std::size_t>(row) * ncols + col] != 0; }
};

// What a raster is, read from its header alone (no samples).
struct DemHeader {
  DemSource source;              // window fields unset
  double cellsize = 0.0;         // map units (the raster's linear unit)
  bool center_x = false, center_y = false;  // ESRI xllcenter / yllcenter
  double scale = 1.0, offset = 0.0;  // the band's: height = raw * scale + offset
  bool projected = false;        // the CRS is a projected one
  double linear_unit_m = 0.0;    // metres per map unit of the CRS; 0: no CRS
  std::string height_unit;       // the band's unit type as written ("" when none)
};

// A pixel window, GDAL order (row 0 north).
struct PixelWindow {
  int col_off = 0, row_off = 0, cols = 0, rows = 0;
};

// An open raster: its header is read, its samples wait for read().
class DemReader {
 public:
  virtual ~DemReader() = default;
  const DemHeader& header() const { return header_; }
  // The window's samples in metres (length_scale: metres per map unit);
  // nodata as holes, scale and offset applied. Throws InputError naming the
  // file and cell for a height that is not finite or beyond kMaxDemHeight.
  Dem read(const PixelWindow& window, double length_scale);

 protected:
  // Raw samples of the window, row-major from its north row; `hole` set
  // where the file has its nodata value.
  virtual void read_raw(const PixelWindow& window, std::vector<double>& raw, std::vector<unsigned char>& hole) = 0;
  DemHeader header_;
  double pixels_read_ = 0.0;
};

// Opens `file` (a regular file: devices, FIFOs and directories are refused
// before opening): an ESRI ASCII grid is read by hand (strictly: GDAL's
// AAIGrid driver reads a short row or "nan" as 0 and keeps the first of two
// repeated keys), anything else through GDAL. Throws InputError naming the file.
std::unique_ptr<DemReader> open_dem(const std::filesystem::path& file, int band = 1);

// The whole raster, in metres (length_scale: metres per map unit).
Dem load_dem(const std::filesystem::path& file, double length_scale);

// An ESRI ASCII grid from a stream (an open file or a string), whole; `file`
// names it in messages.
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
// (17 significant digits), lengths divided by length_scale; the lower-left
// value is the window's own (xllcorner/yllcorner or xllcenter/yllcenter as
// read), so for a whole raster the scene's terrain.origin places the written
// grid where it placed the read one.
void write_dem(const std::filesystem::path& file, const Dem& dem, double length_scale, double nodata = -9999.0);

// The grid as a GeoTIFF file's bytes (float64, heights divided by
// length_scale): the CRS and the window's geotransform of dem.source, its
// nodata value (or `nodata` when the file had none) at holes. Written by
// the caller's safe writer; GDAL never opens an output path.
std::string geotiff_bytes(const Dem& dem, double length_scale, double nodata = -9999.0);

// The window's map extent: west, south, east, north (map units; the
// raster's lower-left corner based values for a file without CRS).
std::array<double, 4> window_extent(const Dem& dem);

// Map coordinates (east, north, height; map units) of a reference-frame
// point over `dem` placed at `origin`; empty when the raster has no CRS.
std::optional<Vec3> map_point(const Dem& dem, const Vec3& origin, double length_scale, const Vec3& p);

}  // namespace plancheck
