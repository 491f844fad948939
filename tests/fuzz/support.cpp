// SPDX-License-Identifier: MIT
#include "tests/fuzz/support.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

namespace plancheck::fuzz {
namespace {

void remove_scratch() {
  std::error_code ec;
  std::filesystem::remove_all(scratch(), ec);
}

// One axis-aligned box as an OBJ object (8 vertices, 12 triangles); `base`
// is the number of vertices written before it (OBJ indices are global).
void box(std::ostream& out, const char* name, double x0, double y0, double z0, double x1, double y1, double z1,
         int base) {
  out << "o " << name << "\n";
  for (int i = 0; i < 8; ++i)
    out << "v " << (i & 1 ? x1 : x0) << " " << (i & 2 ? y1 : y0) << " " << (i & 4 ? z1 : z0) << "\n";
  static const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    out << "f " << base + q[0] + 1 << " " << base + q[1] + 1 << " " << base + q[2] + 1 << "\n";
    out << "f " << base + q[0] + 1 << " " << base + q[2] + 1 << " " << base + q[3] + 1 << "\n";
  }
}

}  // namespace

const std::filesystem::path& scratch() {
  static const std::filesystem::path dir = [] {
    const auto d = std::filesystem::temp_directory_path() / ("plancheck-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    std::atexit(remove_scratch);
    return d;
  }();
  return dir;
}

void write_file(const std::filesystem::path& file, std::string_view bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  require(static_cast<bool>(out.flush()), "cannot write a scratch file");
}

std::filesystem::path write_scene() {
  std::ostringstream obj;
  box(obj, "Slab", -3, -1, -1, 3, 1, 0, 0);
  box(obj, "Bar", 0, -0.1, 0.9, 2, 0.1, 1.1, 8);
  box(obj, "Tip", 1.8, -0.05, 1.2, 1.9, 0.05, 1.4, 16);
  box(obj, "Block", -2.5, -0.2, 0.1, -2, 0.2, 0.5, 24);
  box(obj, "Mast", -1, -0.1, 0.05, -0.8, 0.1, 2, 32);
  write_file(scratch() / "model.obj", obj.str());
  write_file(scratch() / "dem.asc",
             "ncols 3\nnrows 2\nxllcorner -3\nyllcorner -1\ncellsize 2\nNODATA_value -9999\n-2 -2 -2\n-2 -9999 -2\n");
  write_file(scratch() / "scene.json", R"({
  "format": "plancheck-scene/1", "model": "model.obj", "length_unit": "m", "angle_unit": "deg",
  "safety_margin": 0.01,
  "actions": [
    {"name": "J1", "node": "Bar", "type": "rotate", "pivot": [0, 0, 1], "axis": [0, 1, 0], "limits": [-90, 30]},
    {"name": "T", "node": "Tip", "type": "translate", "limits": [-1, 1]},
    {"name": "Lift", "node": "Block", "type": "translate", "axis": [0, 0, 1], "limits": [-0.5, 2]},
    {"name": "Grow", "node": "Block", "type": "scale", "fixed_point": [-2.25, 0, 0.1], "limits": [0.5, 2]},
    {"name": "Yaw", "node": "Mast", "type": "rotate", "pivot": [-0.9, 0, 0], "axis": [0, 0, 1]}
  ],
  "allowed_collisions": [["Mast", "Slab"]]
})");
  return scratch() / "scene.json";
}

std::size_t plan_rows(std::string_view text) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  bool header = false;
  bool quoted = false;  // inside a quoted field: the line goes on the record before it
  std::size_t rows = 0;
  while (!text.empty()) {
    const std::size_t nl = text.find('\n');
    std::string_view line = text.substr(0, nl);
    text.remove_prefix(nl == std::string_view::npos ? text.size() : nl + 1);
    const bool continued = quoted;
    while (!line.empty() && (line.front() == ' ' || line.front() == '\t')) line.remove_prefix(1);
    while (!line.empty() && (line.back() == ' ' || line.back() == '\t' || line.back() == '\r')) line.remove_suffix(1);
    if (!header && !continued && (line.empty() || line.front() == '#')) continue;  // comments before the header
    if (!continued && line.empty()) continue;
    for (char c : line)
      if (c == '"') quoted = !quoted;
    if (continued) continue;
    if (!header) {
      header = true;
      continue;
    }
    ++rows;
  }
  return rows;
}

void require(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "fuzz invariant broken: %s\n", what);
  std::abort();
}

}  // namespace plancheck::fuzz
