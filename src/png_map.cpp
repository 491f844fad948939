// SPDX-License-Identifier: MIT
#include "src/png_map.h"

#include "src/error.h"

#include <png.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

namespace plancheck {

namespace {

using Rgb = std::array<unsigned char, 3>;

unsigned char byte(double v) { return static_cast<unsigned char>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)); }

// A perceptually ordered ramp (dark blue -> teal -> yellow) so low ground
// reads dark and the pit stands out in the "after" panel.
Rgb ramp(double t) {
  static constexpr double kStops[4][3] = {{0.08, 0.06, 0.30}, {0.13, 0.45, 0.55}, {0.40, 0.75, 0.40}, {0.98, 0.90, 0.20}};
  t = std::clamp(t, 0.0, 1.0) * 3.0;
  const int i = std::min(static_cast<int>(t), 2);
  const double f = t - i;
  Rgb c;
  for (int k = 0; k < 3; ++k) c[static_cast<std::size_t>(k)] = byte(kStops[i][k] * (1 - f) + kStops[i + 1][k] * f);
  return c;
}

Rgb diverging(double t) {  // t in [-1, 1]
  t = std::clamp(t, -1.0, 1.0);
  if (t < 0) return {byte(1 + t), byte(1 + t), 255};
  return {255, byte(1 - t), byte(1 - t)};
}

}  // namespace

MapScale write_dig_png(const std::filesystem::path& file, const Dem& before, const Dem& after, int pixels) {
  MapScale s;
  s.z_min = std::numeric_limits<double>::infinity();
  s.z_max = -s.z_min;
  for (const Dem* g : {&before, &after})
    for (std::size_t i = 0; i < g->z.size(); ++i)
      if (g->valid[i]) s.z_min = std::min(s.z_min, g->z[i]), s.z_max = std::max(s.z_max, g->z[i]);
  for (std::size_t i = 0; i < after.z.size(); ++i)
    if (after.valid[i]) s.diff_max = std::max(s.diff_max, std::abs(after.z[i] - before.z[i]));
  const double span = s.z_max > s.z_min ? s.z_max - s.z_min : 1.0;
  const double dspan = s.diff_max > 0 ? s.diff_max : 1.0;

  const int gap = 4;
  const int pw = before.ncols * pixels, ph = before.nrows * pixels;
  const int width = 3 * pw + 2 * gap, height = ph;
  std::vector<unsigned char> image(static_cast<std::size_t>(width) * height * 3, 255);
  for (int panel = 0; panel < 3; ++panel)
    for (int y = 0; y < ph; ++y)
      for (int x = 0; x < pw; ++x) {
        const int c = x / pixels, r = before.nrows - 1 - y / pixels;  // north up
        const std::size_t i = static_cast<std::size_t>(r) * before.ncols + c;
        Rgb rgb{0, 0, 0};  // NODATA: black
        if (before.valid[i]) {
          if (panel == 0) rgb = ramp((before.z[i] - s.z_min) / span);
          else if (panel == 1) rgb = ramp((after.z[i] - s.z_min) / span);
          else rgb = diverging((after.z[i] - before.z[i]) / dspan);
        }
        unsigned char* px = &image[(static_cast<std::size_t>(y) * width + panel * (pw + gap) + x) * 3];
        px[0] = rgb[0], px[1] = rgb[1], px[2] = rgb[2];
      }

  FILE* f = std::fopen(file.string().c_str(), "wb");
  if (!f) fail(file, "cannot write");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::fclose(f);
    fail(file, "PNG encoding failed");
  }
  png_init_io(png, f);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8, PNG_COLOR_TYPE_RGB,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < height; ++y) png_write_row(png, &image[static_cast<std::size_t>(y) * width * 3]);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  if (std::fclose(f) != 0) fail(file, "write failed");
  return s;
}

}  // namespace plancheck
