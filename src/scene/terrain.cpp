// SPDX-License-Identifier: MIT
// The ESRI ASCII reader (strict, streaming: memory follows the window, not
// the file), the window read common to every reader, and the grid as a mesh.
#include "src/scene/terrain.h"

#include "src/base/error.h"
#include "src/base/files.h"
#include "src/scene/dem_gdal.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
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
  if (ec == std::errc::result_out_of_range && ptr == last) {
    // Below double's range (1e-400) is its nearest double, as JSON reads it;
    // beyond it (1e400) is not finite.
    const double v = std::strtod(std::string(first, last).c_str(), nullptr);
    if (!std::isfinite(v)) return false;
    out = v;
    return true;
  }
  return ec == std::errc() && ptr == last && std::isfinite(out);
}

}  // namespace

std::string number_text(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

namespace {

// A token of an ESRI ASCII grid (a run of non-space bytes) and the line it
// is on. Tokens longer than any number or key are refused as they are read,
// so a file of one endless line (a zero-filled file) costs no memory.
constexpr std::size_t kMaxToken = 64;

class Tokens {
 public:
  Tokens(std::istream& in, const std::filesystem::path& file) : in_(in), file_(file) {}
  // False at the end of the stream.
  bool next(std::string& token, long& line) {
    std::streambuf* buf = in_.rdbuf();
    int ch = buf->sbumpc();
    while (ch != std::char_traits<char>::eof() && std::isspace(ch)) {
      if (ch == '\n') ++line_;
      ch = buf->sbumpc();
    }
    if (ch == std::char_traits<char>::eof()) return false;
    token.clear();
    while (ch != std::char_traits<char>::eof() && !std::isspace(ch)) {
      if (token.size() == kMaxToken)
        fail(file_, "a value longer than " + std::to_string(kMaxToken) + " characters (not an ESRI ASCII grid?)", line_);
      token.push_back(static_cast<char>(ch));
      ch = buf->sbumpc();
    }
    line = line_;
    if (ch == '\n') ++line_;
    return true;
  }
  void restart(std::streampos at, long line) {
    in_.clear();
    in_.seekg(at);
    line_ = line;
  }
  std::streampos position() { return in_.rdbuf()->pubseekoff(0, std::ios::cur, std::ios::in); }
  long line() const { return line_; }

 private:
  std::istream& in_;
  const std::filesystem::path& file_;
  long line_ = 1;
};

// The first token of a data row: a number, or a non-finite one named as
// such (so "nan" in the data is a bad cell, not a bad header key).
bool is_data_token(const std::string& t) {
  const unsigned char c = static_cast<unsigned char>(t[0]);
  if (std::isdigit(c) || c == '-' || c == '+' || c == '.') return true;
  const std::string l = lower(t);
  return l == "nan" || l == "inf" || l == "infinity";
}

class EsriReader final : public DemReader {
 public:
  EsriReader(std::unique_ptr<std::istream> owned, std::istream& in, const std::filesystem::path& file)
      : owned_(std::move(owned)), in_(in), tokens_(in, file) {
    header_.source.file = file;
    header_.source.driver = "ESRI ASCII";
    parse_header();
  }

 protected:
  void read_raw(const PixelWindow& w, std::vector<double>& raw, std::vector<unsigned char>& hole) override;

 private:
  void parse_header();
  std::unique_ptr<std::istream> owned_;
  std::istream& in_;
  Tokens tokens_;
  std::streampos data_start_;
  long data_line_ = 0;    // the first data token's line
  long resume_line_ = 0;  // the line at data_start_
  std::string first_data_;  // the data's first token, read with the header
};

void EsriReader::parse_header() {
  const std::filesystem::path& file = header_.source.file;
  // Header: "key value" lines until the first line that starts with a number.
  double ncols = -1, nrows = -1, xll = NAN, yll = NAN, cellsize = -1;
  bool x_center = false, y_center = false;
  std::map<std::string, long> seen;  // canonical key -> line
  std::string key, value;
  long line = 0, value_line = 0, last_line = 0;
  while (true) {
    if (!tokens_.next(key, line)) fail(file, "no data rows after the header");
    if (line == last_line) fail(file, "expected 'key value' in the header", line);
    if (is_data_token(key)) {
      data_line_ = line;
      first_data_ = key;
      break;
    }
    if (!tokens_.next(value, value_line) || value_line != line) fail(file, "expected 'key value' in the header", line);
    double v;
    if (!parse_number(value, v)) fail(file, "'" + value + "' is not a finite number", line);
    last_line = line;
    const std::string k = lower(key);
    std::string slot = k;
    if (k == "xllcenter") slot = "xllcorner";
    if (k == "yllcenter") slot = "yllcorner";
    if (k == "ncols") ncols = v;
    else if (k == "nrows") nrows = v;
    else if (k == "xllcorner" || k == "xllcenter") { xll = v; x_center = k == "xllcenter"; }
    else if (k == "yllcorner" || k == "yllcenter") { yll = v; y_center = k == "yllcenter"; }
    else if (k == "cellsize") cellsize = v;
    else if (k == "nodata_value") { header_.source.nodata = v; header_.source.has_nodata = true; }
    else fail(file, "unknown header key '" + key + "'", line);
    const auto [it, fresh] = seen.emplace(slot, line);
    if (!fresh) fail(file, "header key '" + key + "' repeats the one on line " + std::to_string(it->second), line);
  }
  data_start_ = tokens_.position();
  resume_line_ = tokens_.line();
  auto whole = [](double v) { return v >= 1 && v <= 1e7 && v == std::floor(v); };
  if (!whole(ncols)) fail(file, "ncols missing or not a positive whole number");
  if (!whole(nrows)) fail(file, "nrows missing or not a positive whole number");
  if (std::isnan(xll)) fail(file, "xllcorner or xllcenter missing");
  if (std::isnan(yll)) fail(file, "yllcorner or yllcenter missing");
  if (!(cellsize > 0)) fail(file, "cellsize missing or not positive");
  if (ncols * nrows > 1e9) fail(file, "grid too large");
  DemSource& s = header_.source;
  s.raster_cols = static_cast<int>(ncols);
  s.raster_rows = static_cast<int>(nrows);
  header_.cellsize = cellsize;
  header_.center_x = x_center;
  header_.center_y = y_center;
  const double half_x = x_center ? 0.5 * cellsize : 0.0, half_y = y_center ? 0.5 * cellsize : 0.0;
  s.geotransform = {xll - half_x, cellsize, 0.0, yll - half_y + nrows * cellsize, 0.0, -cellsize};
}

void EsriReader::read_raw(const PixelWindow& w, std::vector<double>& raw, std::vector<unsigned char>& hole) {
  const std::filesystem::path& file = header_.source.file;
  const int ncols = header_.source.raster_cols, nrows = header_.source.raster_rows;
  const bool has_nodata = header_.source.has_nodata;
  const double nodata = header_.source.nodata;
  // Data: nrows lines of ncols values, the first line is the top (largest y)
  // row. Every value is checked; those in the window are kept.
  tokens_.restart(data_start_, resume_line_);
  std::string token = first_data_;
  long line = data_line_, row_line = data_line_;
  int row = 0, col = 0;
  bool have = true;
  while (have) {
    if (line != row_line) {
      if (col != ncols)
        fail(file, "expected " + std::to_string(ncols) + " values, found " + std::to_string(col), row_line);
      ++row;
      col = 0;
      row_line = line;
    }
    if (row >= nrows) fail(file, "more data rows than nrows = " + std::to_string(nrows), line);
    if (col >= ncols) fail(file, "more than ncols = " + std::to_string(ncols) + " values", line);
    double v;
    if (!parse_number(token, v))
      fail(file, "'" + token + "' is not a finite number (cell row " + std::to_string(row + 1) + ", column " +
                     std::to_string(col + 1) + ")",
           line, col + 1);
    if (row >= w.row_off && row < w.row_off + w.rows && col >= w.col_off && col < w.col_off + w.cols) {
      raw.push_back(v);
      hole.push_back(has_nodata && v == nodata ? 1 : 0);
    }
    ++col;
    have = tokens_.next(token, line);
  }
  if (col != ncols) fail(file, "expected " + std::to_string(ncols) + " values, found " + std::to_string(col), row_line);
  if (row + 1 != nrows)
    fail(file, "expected " + std::to_string(nrows) + " data rows, found " + std::to_string(row + 1));
}

// The first token of the file, to tell an ESRI ASCII grid from anything else.
bool looks_esri(std::istream& in) {
  std::string t;
  int ch = in.rdbuf()->sbumpc();
  while (ch != std::char_traits<char>::eof() && std::isspace(ch)) ch = in.rdbuf()->sbumpc();
  while (ch != std::char_traits<char>::eof() && !std::isspace(ch) && t.size() < 16) {
    t.push_back(static_cast<char>(ch));
    ch = in.rdbuf()->sbumpc();
  }
  const std::string k = lower(t);
  return k == "ncols" || k == "nrows" || k == "xllcorner" || k == "xllcenter" || k == "yllcorner" ||
         k == "yllcenter" || k == "cellsize" || k == "nodata_value";
}

}  // namespace

std::array<double, 6> DemSource::window_geotransform() const {
  std::array<double, 6> g = geotransform;
  g[0] += col_off * g[1];
  g[3] += row_off * g[5];
  return g;
}

Dem DemReader::read(const PixelWindow& w, double length_scale) {
  const DemSource& s = header_.source;
  if (w.cols < 1 || w.rows < 1 || w.col_off < 0 || w.row_off < 0 || w.col_off + w.cols > s.raster_cols ||
      w.row_off + w.rows > s.raster_rows)
    fail(s.file, "internal: window outside the raster");
  std::vector<double> raw;
  std::vector<unsigned char> hole;
  const std::size_t count = static_cast<std::size_t>(w.cols) * static_cast<std::size_t>(w.rows);
  read_raw(w, raw, hole);
  pixels_read_ += static_cast<double>(count);
  if (raw.size() != count || hole.size() != count) fail(s.file, "internal: short window read");

  Dem dem;
  dem.source = s;
  dem.source.col_off = w.col_off;
  dem.source.row_off = w.row_off;
  dem.source.whole = w.col_off == 0 && w.row_off == 0 && w.cols == s.raster_cols && w.rows == s.raster_rows;
  dem.source.pixels_read = pixels_read_;
  dem.ncols = w.cols;
  dem.nrows = w.rows;
  dem.center_x = header_.center_x;
  dem.center_y = header_.center_y;
  const double cs = header_.cellsize;
  dem.cellsize = cs * length_scale;
  // The grid origin is the raster's lower-left corner (its lower-left
  // sample for xllcenter/yllcenter): column 0 of the window is col_off samples east of it.
  const int south_rows = s.raster_rows - w.row_off - w.rows;  // raster rows south of the window
  dem.x0 = (header_.center_x ? 0.0 : 0.5 * dem.cellsize) + w.col_off * dem.cellsize;
  dem.y0 = (header_.center_y ? 0.0 : 0.5 * dem.cellsize) + south_rows * dem.cellsize;
  const double half_x = header_.center_x ? 0.5 * cs : 0.0, half_y = header_.center_y ? 0.5 * cs : 0.0;
  dem.xll = (s.geotransform[0] + half_x + w.col_off * cs) * length_scale;
  dem.yll = (s.geotransform[3] + s.raster_rows * s.geotransform[5] + half_y + south_rows * cs) * length_scale;
  dem.z.resize(count);
  dem.valid.resize(count);
  for (int wr = 0; wr < w.rows; ++wr)
    for (int c = 0; c < w.cols; ++c) {
      const std::size_t from = static_cast<std::size_t>(wr) * w.cols + c;
      const std::size_t to = static_cast<std::size_t>(w.rows - 1 - wr) * w.cols + c;
      if (hole[from]) continue;  // z 0, valid 0
      const double h = (raw[from] * header_.scale + header_.offset) * length_scale;
      if (!std::isfinite(h) || std::abs(h) > kMaxDemHeight)
        fail(s.file, "cell (row " + std::to_string(w.row_off + wr + 1) + ", column " + std::to_string(w.col_off + c + 1) +
                         ", counted from 1 at the top left): height " + number_text(raw[from]) +
                         (std::isfinite(h) ? " is beyond what any real terrain has (|h| <= 1e7 m)" : " is not a finite number"));
      dem.z[to] = h;
      dem.valid[to] = 1;
    }
  return dem;
}

std::unique_ptr<DemReader> open_dem(const std::filesystem::path& file, int band) {
  std::error_code ec;
  const auto st = std::filesystem::status(file, ec);
  if (ec || !std::filesystem::exists(st)) fail(file, "cannot open the DEM file (it does not exist)");
  if (!std::filesystem::is_regular_file(st))
    fail(file, "not a regular file (a directory, device or FIFO cannot be a DEM)");
  auto in = std::make_unique<std::ifstream>(file, std::ios::binary);
  if (!*in) fail(file, "cannot open the DEM file");
  if (in->peek() == std::char_traits<char>::eof()) fail(file, "empty file, not a DEM");
  if (looks_esri(*in)) {
    if (band != 1) fail(file, "band " + std::to_string(band) + " out of range (an ESRI ASCII grid has one band)");
    in->clear();
    in->seekg(0);
    std::istream& ref = *in;
    return std::make_unique<EsriReader>(std::move(in), ref, file);
  }
  in.reset();
  return open_gdal_dem(file, band);
}

Dem load_dem(const std::filesystem::path& file, double length_scale) {
  auto reader = open_dem(file);
  const DemSource& s = reader->header().source;
  return reader->read({0, 0, s.raster_cols, s.raster_rows}, length_scale);
}

Dem read_dem(std::istream& in, const std::filesystem::path& file, double length_scale) {
  EsriReader reader(nullptr, in, file);
  const DemSource& s = reader.header().source;
  return reader.read({0, 0, s.raster_cols, s.raster_rows}, length_scale);
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
  std::string out;
  auto g = number_text;
  if (dem.source.has_nodata) nodata = dem.source.nodata;
  out += "ncols " + std::to_string(dem.ncols) + "\nnrows " + std::to_string(dem.nrows) + "\n";
  // A grid made in memory (no reader) says where its samples sit by x0/y0
  // alone: 0 is a sample at the origin, as xllcenter/yllcenter write it.
  const bool cx = dem.center_x || dem.x0 == 0.0, cy = dem.center_y || dem.y0 == 0.0;
  out += (cx ? "xllcenter " : "xllcorner ") + g(dem.xll / length_scale) + "\n";
  out += (cy ? "yllcenter " : "yllcorner ") + g(dem.yll / length_scale) + "\n";
  out += "cellsize " + g(dem.cellsize / length_scale) + "\nNODATA_value " + g(nodata) + "\n";
  for (int r = dem.nrows - 1; r >= 0; --r) {
    for (int c = 0; c < dem.ncols; ++c) {
      if (c) out += ' ';
      out += dem.is_valid(c, r) ? g(dem.height(c, r) / length_scale) : g(nodata);
    }
    out += '\n';
  }
  write_file_atomically(file, out);  // a fresh temporary renamed into place: never through a link
}

std::array<double, 4> window_extent(const Dem& dem) {
  const std::array<double, 6> g = dem.source.window_geotransform();
  return {g[0], g[3] + dem.nrows * g[5], g[0] + dem.ncols * g[1], g[3]};
}

std::optional<Vec3> map_point(const Dem& dem, const Vec3& origin, double length_scale, const Vec3& p) {
  if (dem.source.crs_wkt.empty()) return std::nullopt;
  const std::array<double, 6> g = dem.source.window_geotransform();
  // Column 0 / row 0 (south) of the window: their centres in map units.
  const double east0 = g[0] + 0.5 * g[1];
  const double north0 = g[3] + (dem.nrows - 0.5) * g[5];
  return Vec3(east0 + (p.x() - origin.x() - dem.x0) / length_scale, north0 + (p.y() - origin.y() - dem.y0) / length_scale,
              (p.z() - origin.z()) / length_scale);
}

}  // namespace plancheck
