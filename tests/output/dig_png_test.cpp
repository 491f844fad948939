// SPDX-License-Identifier: MIT
// plancheck dig's PNG (src/output/dig_png.h), decoded again with cairo: its
// size, the three panels' colours, titles and colour bars drawn, the target
// where the grid puts it.
#include "src/output/dig_png.h"

#include "support/fixtures.h"

#include <cairo.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

namespace plancheck {
namespace {

struct Image {
  cairo_surface_t* s = nullptr;
  explicit Image(const std::filesystem::path& f) : s(cairo_image_surface_create_from_png(f.string().c_str())) {}
  ~Image() { cairo_surface_destroy(s); }
  bool ok() const { return cairo_surface_status(s) == CAIRO_STATUS_SUCCESS; }
  int width() const { return cairo_image_surface_get_width(s); }
  int height() const { return cairo_image_surface_get_height(s); }
  // 0xRRGGBB at (x, y).
  std::uint32_t at(int x, int y) const {
    const unsigned char* d = cairo_image_surface_get_data(s);
    const auto* row = reinterpret_cast<const std::uint32_t*>(d + static_cast<std::ptrdiff_t>(y) * cairo_image_surface_get_stride(s));
    return row[x] & 0xffffffu;
  }
  int dark_pixels(int x0, int y0, int x1, int y1) const {
    int n = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const std::uint32_t c = at(x, y);
        if (((c >> 16) & 255) + ((c >> 8) & 255) + (c & 255) < 300) ++n;
      }
    return n;
  }
};

// A tilted 40 x 30 plane (m) with a 2 x 2 pit dug 0.1 m at columns 10..11, rows 20..21.
Dem plane() {
  Dem d;
  d.ncols = 40;
  d.nrows = 30;
  d.cellsize = 0.05;
  for (int r = 0; r < d.nrows; ++r)
    for (int c = 0; c < d.ncols; ++c) d.z.push_back(0.01 * c);
  d.valid.assign(d.z.size(), 1);
  return d;
}

TEST(DigPng, DrawsThreeTitledPanelsBarsAndTheTarget) {
  testing::TempDir dir("dig_png");
  const Dem before = plane();
  Dem after = before;
  for (int r = 20; r <= 21; ++r)
    for (int c = 10; c <= 11; ++c) after.z[static_cast<std::size_t>(r) * after.ncols + c] -= 0.1;
  DigMapRequest rq;
  rq.before = &before;
  rq.after = &after;
  rq.origin = Vec3(1.0, 2.0, 0.0);
  rq.target = Vec3(1.0 + 30 * 0.05, 2.0 + 5 * 0.05, 0.0);  // column 30, row 5
  rq.plan_name = "planX";
  const DigMapResult m = write_dig_png(dir / "dig.png", rq);
  EXPECT_NEAR(m.z_min, -0.1 + 0.1, 1e-12);
  EXPECT_NEAR(m.z_max, 0.39, 1e-12);
  EXPECT_NEAR(m.diff_max, 0.1, 1e-12);

  const Image img(dir / "dig.png");
  ASSERT_TRUE(img.ok());
  EXPECT_EQ(img.width(), m.width);
  EXPECT_EQ(img.height(), m.height);
  EXPECT_EQ(m.panel_w * 30, m.panel_h * 40);  // the grid's aspect
  const double sx = static_cast<double>(m.panel_w) / 40, sy = static_cast<double>(m.panel_h) / 30;
  auto pixel = [&](int k, double c, double r) {  // north up: row 0 at the bottom
    return img.at(m.panel_x[k] + static_cast<int>((c + 0.5) * sx), m.panel_y + static_cast<int>((30 - 0.5 - r) * sy));
  };
  // Before and after share the height ramp: equal away from the pit, different in it.
  EXPECT_EQ(pixel(0, 3, 3), pixel(1, 3, 3));
  EXPECT_NE(pixel(0, 10.5, 20.5), pixel(1, 10.5, 20.5));
  EXPECT_NE(pixel(0, 3, 3), pixel(0, 36, 3));  // the slope shows
  // The difference: white where unchanged, full blue in the pit.
  EXPECT_EQ(pixel(2, 3, 3), 0xffffffu);
  EXPECT_EQ(pixel(2, 10.5, 20.5), 0x0000ffu);
  // The target's cross (magenta over black) at column 30, row 5 in every panel.
  for (int k = 0; k < 3; ++k) {
    const std::uint32_t c = pixel(k, 30 + 0.25, 5);  // on the cross's horizontal arm, off its centre
    EXPECT_GT((c >> 16) & 255, 200u) << k;
    EXPECT_LT((c >> 8) & 255, 80u) << k;
    EXPECT_GT(c & 255, 180u) << k;
  }
  // Titles above each panel and labels under the bars: text is drawn there.
  for (int k = 0; k < 3; ++k) EXPECT_GT(img.dark_pixels(m.panel_x[k], 0, m.panel_x[k] + m.panel_w, m.panel_y), 20) << k;
  EXPECT_GT(img.dark_pixels(0, m.panel_y + m.panel_h + 1, m.width, m.height), 100);
}

TEST(DigPng, NiceLengthsAreOneTwoOrFiveTimesAPowerOfTen) {
  EXPECT_DOUBLE_EQ(nice_length(0.7), 0.5);
  EXPECT_DOUBLE_EQ(nice_length(1.0), 1.0);
  EXPECT_DOUBLE_EQ(nice_length(3.9), 2.0);
  EXPECT_DOUBLE_EQ(nice_length(120.0), 100.0);
  EXPECT_DOUBLE_EQ(nice_length(0.0), 0.0);
}

}  // namespace
}  // namespace plancheck
