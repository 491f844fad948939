// SPDX-License-Identifier: MIT
#include "src/output/dig_png.h"

#include "src/base/error.h"
#include "src/base/files.h"

#include <cairo.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace plancheck {

namespace {

using Rgb = std::array<double, 3>;

// A perceptually ordered ramp (dark blue -> teal -> yellow) so low ground
// reads dark and the pit stands out in the "after" panel.
Rgb ramp(double t) {
  static constexpr double kStops[4][3] = {{0.08, 0.06, 0.30}, {0.13, 0.45, 0.55}, {0.40, 0.75, 0.40}, {0.98, 0.90, 0.20}};
  t = std::clamp(t, 0.0, 1.0) * 3.0;
  const int i = std::min(static_cast<int>(t), 2);
  const double f = t - i;
  Rgb c;
  for (int k = 0; k < 3; ++k) c[static_cast<std::size_t>(k)] = kStops[i][k] * (1 - f) + kStops[i + 1][k] * f;
  return c;
}

Rgb diverging(double t) {  // t in [-1, 1]
  t = std::clamp(t, -1.0, 1.0);
  if (t < 0) return {1 + t, 1 + t, 1};
  return {1, 1 - t, 1 - t};
}

std::uint32_t argb(const Rgb& c) {
  auto b = [](double v) { return static_cast<std::uint32_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)); };
  return 0xff000000u | (b(c[0]) << 16) | (b(c[1]) << 8) | b(c[2]);
}

struct SurfaceFree {
  void operator()(cairo_surface_t* s) const { cairo_surface_destroy(s); }
};
struct ContextFree {
  void operator()(cairo_t* c) const { cairo_destroy(c); }
};
using Surface = std::unique_ptr<cairo_surface_t, SurfaceFree>;
using Context = std::unique_ptr<cairo_t, ContextFree>;

// One sample per pixel, north up (row 0 of the grid is the southern row).
template <class Color>
Surface grid_image(const Dem& g, Color color) {
  Surface s(cairo_image_surface_create(CAIRO_FORMAT_RGB24, g.ncols, g.nrows));
  const int stride = cairo_image_surface_get_stride(s.get());
  unsigned char* data = cairo_image_surface_get_data(s.get());
  for (int y = 0; y < g.nrows; ++y) {
    auto* row = reinterpret_cast<std::uint32_t*>(data + static_cast<std::ptrdiff_t>(y) * stride);
    const int r = g.nrows - 1 - y;
    for (int c = 0; c < g.ncols; ++c) row[c] = g.is_valid(c, r) ? argb(color(c, r)) : 0xff000000u;  // NODATA black
  }
  cairo_surface_mark_dirty(s.get());
  return s;
}

void text(cairo_t* cr, double x, double y, const std::string& s, double size, double align = 0.0,
          bool bold = false) {
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  cairo_text_extents_t e;
  cairo_text_extents(cr, s.c_str(), &e);
  cairo_move_to(cr, x - align * e.x_advance, y);
  cairo_show_text(cr, s.c_str());
}

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", std::abs(v) < 1e-12 ? 0.0 : v);
  return buf;
}

// A horizontal colour bar at (x, y) of w x h with labels under its ends and middle.
template <class Color>
void colour_bar(cairo_t* cr, double x, double y, double w, double h, Color color, double lo, double hi,
                const std::string& title) {
  constexpr int kSteps = 128;
  for (int i = 0; i < kSteps; ++i) {
    const Rgb c = color((i + 0.5) / kSteps);
    cairo_set_source_rgb(cr, c[0], c[1], c[2]);
    cairo_rectangle(cr, x + w * i / kSteps, y, w / kSteps + 0.5, h);
    cairo_fill(cr);
  }
  cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
  cairo_set_line_width(cr, 1.0);
  cairo_rectangle(cr, x + 0.5, y + 0.5, w - 1, h - 1);
  cairo_stroke(cr);
  for (int k = 0; k <= 2; ++k) {
    const double t = k / 2.0;
    cairo_move_to(cr, x + t * w, y + h);
    cairo_line_to(cr, x + t * w, y + h + 4);
    cairo_stroke(cr);
    text(cr, x + t * w, y + h + 16, fmt(lo + t * (hi - lo)), 11, 0.5);
  }
  text(cr, x + w / 2, y - 5, title, 12, 0.5);
}

}  // namespace

double nice_length(double limit) {
  if (!(limit > 0) || !std::isfinite(limit)) return 0.0;
  const double p = std::pow(10.0, std::floor(std::log10(limit)));
  for (double m : {5.0, 2.0, 1.0})
    if (m * p <= limit) return m * p;
  return p;
}

DigMapResult write_dig_png(const std::filesystem::path& file, const DigMapRequest& rq) {
  const Dem& before = *rq.before;
  const Dem& after = *rq.after;
  const double u = rq.length_scale;
  DigMapResult m;
  m.z_min = std::numeric_limits<double>::infinity();
  m.z_max = -m.z_min;
  for (const Dem* g : {&before, &after})
    for (std::size_t i = 0; i < g->z.size(); ++i)
      if (g->valid[i]) m.z_min = std::min(m.z_min, g->z[i]), m.z_max = std::max(m.z_max, g->z[i]);
  if (!(m.z_min <= m.z_max)) m.z_min = m.z_max = 0.0;  // no valid sample
  for (std::size_t i = 0; i < after.z.size(); ++i)
    if (after.valid[i]) m.diff_max = std::max(m.diff_max, std::abs(after.z[i] - before.z[i]));
  const double span = m.z_max > m.z_min ? m.z_max - m.z_min : 1.0;
  const double dspan = m.diff_max > 0 ? m.diff_max : 1.0;

  // Layout: titles, three panels, colour bars.
  const double px_per_sample = static_cast<double>(rq.panel_pixels) / std::max(before.ncols, before.nrows);
  m.panel_w = std::max(1, static_cast<int>(std::lround(before.ncols * px_per_sample)));
  m.panel_h = std::max(1, static_cast<int>(std::lround(before.nrows * px_per_sample)));
  constexpr int kPad = 16, kTitle = 30, kBars = 88;
  m.panel_y = kTitle;
  for (int k = 0; k < 3; ++k) m.panel_x[k] = kPad + k * (m.panel_w + kPad);
  m.width = 3 * m.panel_w + 4 * kPad;
  m.height = kTitle + m.panel_h + kBars;

  Surface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, m.width, m.height));
  Context ctx(cairo_create(surface.get()));
  cairo_t* cr = ctx.get();
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);

  const Surface panels[3] = {
      grid_image(before, [&](int c, int r) { return ramp((before.height(c, r) - m.z_min) / span); }),
      grid_image(after, [&](int c, int r) { return ramp((after.height(c, r) - m.z_min) / span); }),
      grid_image(after, [&](int c, int r) { return diverging((after.height(c, r) - before.height(c, r)) / dspan); })};
  const std::string titles[3] = {"before", "after " + rq.plan_name, "after - before"};
  for (int k = 0; k < 3; ++k) {
    cairo_save(cr);
    cairo_translate(cr, m.panel_x[k], m.panel_y);
    cairo_scale(cr, static_cast<double>(m.panel_w) / before.ncols, static_cast<double>(m.panel_h) / before.nrows);
    cairo_set_source_surface(cr, panels[k].get(), 0, 0);
    cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);  // one square per sample
    cairo_paint(cr);
    cairo_restore(cr);
    cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
    cairo_set_line_width(cr, 1.0);
    cairo_rectangle(cr, m.panel_x[k] - 0.5, m.panel_y - 0.5, m.panel_w + 1, m.panel_h + 1);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    text(cr, m.panel_x[k] + m.panel_w / 2.0, kTitle - 9, titles[k], 14, 0.5, true);
  }

  // Sample (c, r) centre -> image coordinates of panel k.
  const double sx = static_cast<double>(m.panel_w) / before.ncols, sy = static_cast<double>(m.panel_h) / before.nrows;
  auto to_image = [&](int k, double x, double y) {
    const double c = (x - rq.origin.x() - before.x0) / before.cellsize;
    const double r = (y - rq.origin.y() - before.y0) / before.cellsize;
    return std::pair{m.panel_x[k] + (c + 0.5) * sx, m.panel_y + (before.nrows - 0.5 - r) * sy};
  };

  // Markers, black under colour so they read on any background: the target
  // a ringed cross, the deepest point a ring.
  bool target_on_map = false;
  auto mark = [&](const Vec3& p, bool cross, double red, double green, double blue) {
    bool on = false;
    for (int k = 0; k < 3; ++k) {
      const auto [x, y] = to_image(k, p.x(), p.y());
      if (x < m.panel_x[k] || x > m.panel_x[k] + m.panel_w || y < m.panel_y || y > m.panel_y + m.panel_h) continue;
      on = true;
      for (int pass = 0; pass < 2; ++pass) {
        cairo_set_line_width(cr, pass == 0 ? 4.0 : 2.0);
        if (pass == 0) cairo_set_source_rgb(cr, 0, 0, 0);
        else cairo_set_source_rgb(cr, red, green, blue);
        cairo_new_path(cr);
        cairo_arc(cr, x, y, cross ? 7 : 10, 0, 2 * M_PI);
        if (cross) {
          cairo_move_to(cr, x - 11, y);
          cairo_line_to(cr, x + 11, y);
          cairo_move_to(cr, x, y - 11);
          cairo_line_to(cr, x, y + 11);
        }
        cairo_stroke(cr);
      }
    }
    return on;
  };
  if (rq.deepest) mark(*rq.deepest, false, 1, 1, 1);
  if (rq.target) target_on_map = mark(*rq.target, true, 1, 0.1, 0.9);

  // Scale bar in the first panel's lower left, with a north arrow.
  {
    const double metres_per_px = before.cellsize / sx;
    const double len = nice_length(0.3 * m.panel_w * metres_per_px / u) * u;  // metres, a round number of units
    if (len > 0) {
      const double w = len / metres_per_px, x = m.panel_x[0] + 10, y = m.panel_y + m.panel_h - 12;
      cairo_set_source_rgba(cr, 1, 1, 1, 0.85);
      cairo_rectangle(cr, x - 5, y - 18, w + 10, 24);
      cairo_fill(cr);
      cairo_set_source_rgb(cr, 0, 0, 0);
      cairo_rectangle(cr, x, y - 4, w, 4);
      cairo_fill(cr);
      text(cr, x + w / 2, y - 7, fmt(len / u) + " " + rq.length_unit, 11, 0.5);
    }
    const double nx = m.panel_x[0] + m.panel_w - 16, ny = m.panel_y + 10;
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_move_to(cr, nx, ny);
    cairo_line_to(cr, nx - 6, ny + 14);
    cairo_line_to(cr, nx + 6, ny + 14);
    cairo_close_path(cr);
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 1);
    cairo_stroke(cr);
    text(cr, nx, ny + 27, "N", 11, 0.5, true);
  }

  // Colour bars: heights under the first two panels, the difference under the third.
  const double bar_y = m.panel_y + m.panel_h + 24;
  cairo_set_source_rgb(cr, 0, 0, 0);
  colour_bar(cr, m.panel_x[0] + m.panel_w * 0.25, bar_y, m.panel_w * 1.5 + kPad, 14, ramp, m.z_min / u, m.z_max / u,
             "height (" + rq.length_unit + ")");
  cairo_set_source_rgb(cr, 0, 0, 0);
  colour_bar(cr, m.panel_x[2] + m.panel_w * 0.1, bar_y, m.panel_w * 0.8, 14,
             [](double t) { return diverging(2 * t - 1); }, -m.diff_max / u, m.diff_max / u,
             "height change (" + rq.length_unit + "; blue lowered)");

  // What the markers are.
  std::string key = rq.deepest ? "white ring: deepest scoop point" : "";
  if (rq.target) {
    key += key.empty() ? "" : "; ";
    key += "magenta cross: target";
    if (!target_on_map)
      key += " (off the map: " + fmt(rq.target->x() / u) + ", " + fmt(rq.target->y() / u) + ", " + fmt(rq.target->z() / u) + " " +
             rq.length_unit + ")";
  }
  cairo_set_source_rgb(cr, 0.25, 0.25, 0.25);
  text(cr, kPad, m.height - 8, key, 11);

  cairo_surface_flush(surface.get());
  // Encoded in memory, then written as every output is (files.h: a fresh
  // temporary renamed into place; cairo's own writer would follow a link).
  std::string png;
  const auto append = [](void* closure, const unsigned char* data, unsigned int length) {
    static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
    return CAIRO_STATUS_SUCCESS;
  };
  if (cairo_surface_write_to_png_stream(surface.get(), append, &png) != CAIRO_STATUS_SUCCESS)
    fail(file, "cannot encode the PNG");
  write_file_atomically(file, png);
  return m;
}

}  // namespace plancheck
