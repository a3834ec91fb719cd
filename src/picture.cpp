#include <cairo.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "src/colour_scale.h"
#include "src/error.h"
#include "src/outputs.h"

namespace kiln {

namespace {

// Viridis, sampled at nine points and interpolated linearly.
std::array<double, 3> viridis(double s) {
  static const double stops[9][3] = {{0.267, 0.005, 0.329}, {0.283, 0.141, 0.458}, {0.254, 0.265, 0.530},
                                     {0.207, 0.372, 0.553}, {0.164, 0.471, 0.558}, {0.128, 0.567, 0.551},
                                     {0.135, 0.659, 0.518}, {0.478, 0.821, 0.318}, {0.993, 0.906, 0.144}};
  s = std::clamp(std::isfinite(s) ? s : 0.0, 0.0, 1.0) * 8;
  const int k = std::min(7, static_cast<int>(s));
  const double f = s - k;
  return {stops[k][0] + f * (stops[k + 1][0] - stops[k][0]), stops[k][1] + f * (stops[k + 1][1] - stops[k][1]),
          stops[k][2] + f * (stops[k + 1][2] - stops[k][2])};
}

}  // namespace

PictureView picture_view(const PictureInput& in) {
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  auto grow = [&](Vec2 p, double r) {
    x0 = std::min(x0, p.x - r);
    y0 = std::min(y0, p.y - r);
    x1 = std::max(x1, p.x + r);
    y1 = std::max(y1, p.y + r);
  };
  for (size_t i = 0; i < in.centre.size(); ++i) grow(in.centre[i], in.radius[i]);
  for (size_t s = 0; s < in.wall_a.size(); ++s) {
    grow(in.wall_a[s], 0);
    grow(in.wall_b[s], 0);
  }
  const double margin = 0.03 * std::max(x1 - x0, y1 - y0);
  x0 -= margin;
  y0 -= margin;
  x1 += margin;
  y1 += margin;
  PictureView v;
  v.plot_width = 900;
  v.bar_width = 120;
  v.title_height = 44;
  v.x0 = x0;
  v.y1 = y1;
  v.scale = v.plot_width / (x1 - x0);
  v.plot_height = std::clamp(static_cast<int>((y1 - y0) * v.scale), 160, 2400);
  return v;
}

void write_picture(const std::string& path, const PictureInput& in) {
  const PictureView view = picture_view(in);
  const int plot_w = view.plot_width, plot_h = view.plot_height, title_h = view.title_height;
  const double scale = view.scale;
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, view.width(), view.height());
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);

  std::vector<double> scaled;
  for (size_t i = 0; i < in.value.size(); ++i)
    if (in.of_wall.empty() || !in.of_wall[i]) scaled.push_back(in.value[i]);
  const ColourScale range = colour_scale(scaled);
  auto sx = [&](double x) { return view.pixel({x, 0}).x; };
  auto sy = [&](double y) { return view.pixel({0, y}).y; };

  for (size_t i = 0; i < in.centre.size(); ++i) {
    const bool of_wall = !in.of_wall.empty() && in.of_wall[i];
    const auto c = of_wall ? std::array<double, 3>{0.6, 0.6, 0.6} : viridis(range.position(in.value[i]));
    cairo_set_source_rgb(cr, c[0], c[1], c[2]);
    cairo_arc(cr, sx(in.centre[i].x), sy(in.centre[i].y), std::max(0.5, in.radius[i] * scale), 0, 2 * M_PI);
    cairo_fill(cr);
  }
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, 2);
  for (size_t s = 0; s < in.wall_a.size(); ++s) {
    cairo_move_to(cr, sx(in.wall_a[s].x), sy(in.wall_a[s].y));
    cairo_line_to(cr, sx(in.wall_b[s].x), sy(in.wall_b[s].y));
  }
  cairo_stroke(cr);

  // Colour bar with its range and label: one swatch and one value for a constant field, and
  // ">=" / "<=" on an end that clips values beyond it.
  const double bx = plot_w + 20, by = title_h + 20, bh = range.constant ? 20 : std::max(40, plot_h - 110);
  for (int k = 0; k < static_cast<int>(bh); ++k) {
    const auto c = viridis(range.constant ? 0.5 : 1 - k / bh);
    cairo_set_source_rgb(cr, c[0], c[1], c[2]);
    cairo_rectangle(cr, bx, by + k, 20, 1);
    cairo_fill(cr);
  }
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, 12);
  char label[64];
  if (range.constant) {
    std::snprintf(label, sizeof label, "%.4g", range.low);
    cairo_move_to(cr, bx + 24, by + 15);
    cairo_show_text(cr, label);
  } else {
    std::snprintf(label, sizeof label, "%s%.3g", range.clipped_high ? ">= " : "", range.high);
    cairo_move_to(cr, bx + 24, by + 10);
    cairo_show_text(cr, label);
    std::snprintf(label, sizeof label, "%s%.3g", range.clipped_low ? "<= " : "", range.low);
    cairo_move_to(cr, bx + 24, by + bh);
    cairo_show_text(cr, label);
  }
  cairo_move_to(cr, bx - 10, by + bh + 18);
  cairo_show_text(cr, in.value_label.c_str());

  // Scale bar, beside the plot under the colour bar: a round length of at most 90 pixels.
  const double length = round_length(90 / scale);
  const double lx = plot_w + 10, ly = by + bh + 50;
  cairo_set_line_width(cr, 3);
  cairo_move_to(cr, lx, ly);
  cairo_line_to(cr, lx + length * scale, ly);
  cairo_stroke(cr);
  if (length >= 1) {
    std::snprintf(label, sizeof label, "%g m", length);
  } else if (length >= 1e-3) {
    std::snprintf(label, sizeof label, "%g mm", length * 1e3);
  } else {
    std::snprintf(label, sizeof label, "%g um", length * 1e6);
  }
  cairo_move_to(cr, lx, ly - 6);
  cairo_show_text(cr, label);

  cairo_set_font_size(cr, 16);
  cairo_move_to(cr, 10, 20);
  cairo_show_text(cr, in.title.c_str());
  cairo_set_font_size(cr, 12);
  cairo_move_to(cr, 10, 36);
  cairo_show_text(cr, in.subtitle.c_str());

  cairo_destroy(cr);
  const cairo_status_t status = cairo_surface_write_to_png(surface, path.c_str());
  cairo_surface_destroy(surface);
  if (status != CAIRO_STATUS_SUCCESS) {
    std::remove(path.c_str());
    throw OutputError("cannot write " + path + ": " + cairo_status_to_string(status));
  }
}

}  // namespace kiln
