// SPDX-License-Identifier: MIT
#include "src/scene/terrain.h"

#include "src/base/error.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

namespace plancheck {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

bool parse_number(const std::string& token, double& out) {
  const char* first = token.data();
  const char* last = token.data() + token.size();
  if (first != last && *first == '+') ++first;
  const auto [ptr, ec] = std::from_chars(first, last, out);
  return ec == std::errc() && ptr == last && std::isfinite(out);
}

}  // namespace

Dem load_dem(const std::filesystem::path& file, double length_scale) {
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, "cannot open the DEM file");
  return read_dem(in, file, length_scale);
}

Dem read_dem(std::istream& in, const std::filesystem::path& file, double length_scale) {
  // Header: "key value" lines until the first line that starts with a number.
  double ncols = -1, nrows = -1, xll = NAN, yll = NAN, cellsize = -1, nodata = NAN;
  bool x_center = false, y_center = false, has_nodata = false;
  std::string line;
  long line_no = 0;
  std::streampos data_start = 0;
  long data_line = 0;
  while (true) {
    data_start = in.tellg();
    if (!std::getline(in, line)) break;
    ++line_no;
    std::istringstream ls(line);
    std::string key, value, extra;
    if (!(ls >> key)) continue;  // blank line
    if (std::isdigit(static_cast<unsigned char>(key[0])) || key[0] == '-' || key[0] == '+' || key[0] == '.') {
      data_line = line_no;
      break;
    }
    if (!(ls >> value) || (ls >> extra)) fail(file, "expected 'key value' in the header", line_no);
    double v;
    if (!parse_number(value, v)) fail(file, "'" + value + "' is not a finite number", line_no);
    const std::string k = lower(key);
    if (k == "ncols") ncols = v;
    else if (k == "nrows") nrows = v;
    else if (k == "xllcorner" || k == "xllcenter") { xll = v; x_center = k == "xllcenter"; }
    else if (k == "yllcorner" || k == "yllcenter") { yll = v; y_center = k == "yllcenter"; }
    else if (k == "cellsize") cellsize = v;
    else if (k == "nodata_value") { nodata = v; has_nodata = true; }
    else fail(file, "unknown header key '" + key + "'", line_no);
  }
  auto whole = [](double v) { return v >= 1 && v <= 1e7 && v == std::floor(v); };
  if (!whole(ncols)) fail(file, "ncols missing or not a positive whole number");
  if (!whole(nrows)) fail(file, "nrows missing or not a positive whole number");
  if (std::isnan(xll)) fail(file, "xllcorner or xllcenter missing");
  if (std::isnan(yll)) fail(file, "yllcorner or yllcenter missing");
  if (!(cellsize > 0)) fail(file, "cellsize missing or not positive");
  if (data_line == 0) fail(file, "no data rows after the header");
  if (ncols * nrows > 1e9) fail(file, "grid too large");

  Dem dem;
  dem.ncols = static_cast<int>(ncols);
  dem.nrows = static_cast<int>(nrows);
  dem.cellsize = cellsize * length_scale;
  dem.x0 = x_center ? 0.0 : 0.5 * dem.cellsize;
  dem.y0 = y_center ? 0.0 : 0.5 * dem.cellsize;
  dem.xll = xll * length_scale;
  dem.yll = yll * length_scale;
  // Samples are stored as they are read, in file order (top row first), and
  // the rows turned round at the end: memory follows the data the file
  // holds, not what its header claims (a header of 30000 x 30000 in a
  // 100-byte file must be an error, not a 7 GB allocation).
  std::vector<double> z;
  std::vector<unsigned char> valid;

  // Data: nrows lines of ncols values, the first line is the top (largest y) row.
  in.clear();
  in.seekg(data_start);
  line_no = data_line - 1;
  int file_row = 0;
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream ls(line);
    std::string token;
    int col = 0;
    bool any = false;
    while (ls >> token) {
      any = true;
      if (file_row >= dem.nrows) fail(file, "more data rows than nrows = " + std::to_string(dem.nrows), line_no);
      if (col >= dem.ncols) fail(file, "more than ncols = " + std::to_string(dem.ncols) + " values", line_no);
      double v;
      if (!parse_number(token, v)) fail(file, "'" + token + "' is not a finite number", line_no, col + 1);
      const bool hole = has_nodata && v == nodata;
      z.push_back(hole ? 0.0 : v * length_scale);
      valid.push_back(hole ? 0 : 1);
      ++col;
    }
    if (!any) continue;
    if (col != dem.ncols)
      fail(file, "expected " + std::to_string(dem.ncols) + " values, found " + std::to_string(col), line_no);
    ++file_row;
  }
  if (file_row != dem.nrows)
    fail(file, "expected " + std::to_string(dem.nrows) + " data rows, found " + std::to_string(file_row));
  const std::size_t count = static_cast<std::size_t>(dem.ncols) * static_cast<std::size_t>(dem.nrows);
  dem.z.resize(count);
  dem.valid.resize(count);
  for (int file_r = 0; file_r < dem.nrows; ++file_r) {
    const std::size_t from = static_cast<std::size_t>(file_r) * dem.ncols;
    const std::size_t to = static_cast<std::size_t>(dem.nrows - 1 - file_r) * dem.ncols;
    std::copy_n(z.begin() + static_cast<long>(from), dem.ncols, dem.z.begin() + static_cast<long>(to));
    std::copy_n(valid.begin() + static_cast<long>(from), dem.ncols, dem.valid.begin() + static_cast<long>(to));
  }
  return dem;
}

Mesh dem_mesh(const Dem& dem, const Vec3& origin) {
  Mesh mesh;
  mesh.vertices.reserve(dem.z.size());
  for (int r = 0; r < dem.nrows; ++r)
    for (int c = 0; c < dem.ncols; ++c)
      mesh.vertices.push_back(dem_point(dem, origin, c, r));
  auto id = [&](int c, int r) { return static_cast<std::uint32_t>(r * dem.ncols + c); };
  for (int r = 0; r + 1 < dem.nrows; ++r)
    for (int c = 0; c + 1 < dem.ncols; ++c) {
      if (!dem.is_valid(c, r) || !dem.is_valid(c + 1, r) || !dem.is_valid(c, r + 1) || !dem.is_valid(c + 1, r + 1))
        continue;
      mesh.triangles.push_back({id(c, r), id(c + 1, r), id(c + 1, r + 1)});
      mesh.triangles.push_back({id(c, r), id(c + 1, r + 1), id(c, r + 1)});
    }
  return mesh;
}

std::optional<double> dem_surface(const Dem& dem, const Vec3& origin, double x, double y) {
  const double u = (x - origin.x() - dem.x0) / dem.cellsize;
  const double v = (y - origin.y() - dem.y0) / dem.cellsize;
  if (!(u >= 0.0 && v >= 0.0 && u <= dem.ncols - 1 && v <= dem.nrows - 1)) return std::nullopt;
  int c = std::min(static_cast<int>(u), std::max(dem.ncols - 2, 0));
  int r = std::min(static_cast<int>(v), std::max(dem.nrows - 2, 0));
  if (dem.ncols == 1 || dem.nrows == 1) return std::nullopt;  // no triangles in a single row or column
  const double a = u - c, b = v - r;
  if (!dem.is_valid(c, r) || !dem.is_valid(c + 1, r) || !dem.is_valid(c, r + 1) || !dem.is_valid(c + 1, r + 1))
    return std::nullopt;
  const double z00 = dem.height(c, r), z10 = dem.height(c + 1, r);
  const double z01 = dem.height(c, r + 1), z11 = dem.height(c + 1, r + 1);
  // dem_mesh splits each cell along (c, r)-(c+1, r+1).
  if (a >= b) return origin.z() + z00 + a * (z10 - z00) + b * (z11 - z10);
  return origin.z() + z00 + b * (z01 - z00) + a * (z11 - z01);
}

void write_dem(const std::filesystem::path& file, const Dem& dem, double length_scale, double nodata) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  if (!out) fail(file, "cannot write");
  char buf[64];
  auto g = [&](double v) {
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return std::string(buf);
  };
  out << "ncols " << dem.ncols << "\nnrows " << dem.nrows << "\n";
  out << (dem.x0 == 0.0 ? "xllcenter " : "xllcorner ") << g(dem.xll / length_scale) << "\n";
  out << (dem.y0 == 0.0 ? "yllcenter " : "yllcorner ") << g(dem.yll / length_scale) << "\n";
  out << "cellsize " << g(dem.cellsize / length_scale) << "\nNODATA_value " << g(nodata) << "\n";
  for (int r = dem.nrows - 1; r >= 0; --r) {
    for (int c = 0; c < dem.ncols; ++c) {
      if (c) out << ' ';
      out << (dem.is_valid(c, r) ? g(dem.height(c, r) / length_scale) : g(nodata));
    }
    out << '\n';
  }
  if (!out.flush()) fail(file, "write failed");
}

}  // namespace plancheck
