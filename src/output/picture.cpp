#include <cairo.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "src/output/colour_scale.h"
#include "src/base/error.h"
#include "src/output/outputs.h"

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

// Categorical colours (matplotlib's tab10 without its grey, which marks particles of walls),
// repeated after nine.
std::array<double, 3> category_colour(size_t k) {
  static const double colours[9][3] = {{0.122, 0.467, 0.706}, {1.000, 0.498, 0.055}, {0.173, 0.627, 0.173},
                                       {0.839, 0.153, 0.157}, {0.580, 0.404, 0.741}, {0.549, 0.337, 0.294},
                                       {0.890, 0.467, 0.761}, {0.737, 0.741, 0.133}, {0.090, 0.745, 0.812}};
  const double* c = colours[k % 9];
  return {c[0], c[1], c[2]};
}

const std::array<double, 3> wall_grey = {0.6, 0.6, 0.6};

// The colour bar with its range: one swatch and one value for a constant field, and ">=" / "<="
// on an end that clips values beyond it. Returns the bar's bottom edge.
double draw_colour_bar(cairo_t* cr, const ColourScale& range, double bx, double by, int plot_h) {
  const double bh = range.constant ? 20 : std::max(40, plot_h - 110);
  for (int k = 0; k < static_cast<int>(bh); ++k) {
    const auto c = viridis(range.constant ? 0.5 : 1 - k / bh);
    cairo_set_source_rgb(cr, c[0], c[1], c[2]);
    cairo_rectangle(cr, bx, by + k, 20, 1);
    cairo_fill(cr);
  }
  cairo_set_source_rgb(cr, 0, 0, 0);
  char label[64];
  if (range.constant) {
    std::snprintf(label, sizeof label, "%.4g", range.low);
    cairo_move_to(cr, bx + 24, by + 15);
    cairo_show_text(cr, label);
  } else {
    const double span = range.high - range.low;
    std::snprintf(label, sizeof label, "%s%s", range.clipped_high ? ">= " : "", scale_label(range.high, span).c_str());
    cairo_move_to(cr, bx + 24, by + 10);
    cairo_show_text(cr, label);
    std::snprintf(label, sizeof label, "%s%s", range.clipped_low ? "<= " : "", scale_label(range.low, span).c_str());
    cairo_move_to(cr, bx + 24, by + bh);
    cairo_show_text(cr, label);
  }
  return by + bh;
}

// A swatch and a name per category. Returns the legend's bottom edge.
double draw_legend(cairo_t* cr, const std::vector<std::string>& categories, double bx, double by) {
  double y = by;
  for (size_t k = 0; k < categories.size(); ++k, y += 20) {
    const auto c = category_colour(k);
    cairo_set_source_rgb(cr, c[0], c[1], c[2]);
    cairo_rectangle(cr, bx, y, 14, 14);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_move_to(cr, bx + 20, y + 12);
    cairo_show_text(cr, categories[k].c_str());
  }
  return y;
}

// A scale bar of a round length of at most 90 pixels, its left end at (lx, ly).
void draw_scale_bar(cairo_t* cr, double scale, double lx, double ly) {
  const double length = round_length(90 / scale);
  cairo_set_line_width(cr, 3);
  cairo_move_to(cr, lx, ly);
  cairo_line_to(cr, lx + length * scale, ly);
  cairo_stroke(cr);
  char label[64];
  if (length >= 1) {
    std::snprintf(label, sizeof label, "%g m", length);
  } else if (length >= 1e-3) {
    std::snprintf(label, sizeof label, "%g mm", length * 1e3);
  } else {
    std::snprintf(label, sizeof label, "%g um", length * 1e6);
  }
  cairo_move_to(cr, lx, ly - 6);
  cairo_show_text(cr, label);
}

}  // namespace

PictureBounds picture_bounds(const PictureInput& in) {
  PictureBounds b;
  for (size_t i = 0; i < in.centre.size(); ++i) b.grow(in.centre[i], in.radius[i]);
  for (size_t s = 0; s < in.wall_a.size(); ++s) {
    b.grow(in.wall_a[s], 0);
    b.grow(in.wall_b[s], 0);
  }
  return b;
}

PictureView picture_view(const PictureBounds& b) {
  const double margin = 0.03 * std::max(b.x1 - b.x0, b.y1 - b.y0);
  PictureView v;
  v.plot_width = 900;
  v.bar_width = 120;
  v.title_height = 44;
  v.x0 = b.x0 - margin;
  v.y1 = b.y1 + margin;
  v.scale = v.plot_width / (b.x1 - b.x0 + 2 * margin);
  v.plot_height = std::clamp(static_cast<int>((b.y1 - b.y0 + 2 * margin) * v.scale), 160, 2400);
  return v;
}

PictureView picture_view(const PictureInput& in) { return in.view ? *in.view : picture_view(picture_bounds(in)); }

void write_picture(const std::string& path, const PictureInput& in) {
  const PictureView view = picture_view(in);
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, view.width(), view.height());
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);

  const bool categorical = !in.categories.empty();
  auto of_wall = [&](size_t i) { return !in.of_wall.empty() && in.of_wall[i]; };
  ColourScale range;
  if (in.scale) {
    range = *in.scale;
  } else if (!categorical) {
    std::vector<double> scaled;
    for (size_t i = 0; i < in.value.size(); ++i)
      if (!of_wall(i)) scaled.push_back(in.value[i]);
    range = colour_scale(scaled);
  }

  for (size_t i = 0; i < in.centre.size(); ++i) {
    const auto c = of_wall(i)      ? wall_grey
                   : categorical ? category_colour(static_cast<size_t>(in.value[i]))
                                 : viridis(range.position(in.value[i]));
    const Vec2 p = view.pixel(in.centre[i]);
    cairo_set_source_rgb(cr, c[0], c[1], c[2]);
    cairo_arc(cr, p.x, p.y, std::max(0.5, in.radius[i] * view.scale), 0, 2 * M_PI);
    cairo_fill(cr);
  }
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, 2);
  for (size_t s = 0; s < in.wall_a.size(); ++s) {
    const Vec2 a = view.pixel(in.wall_a[s]), b = view.pixel(in.wall_b[s]);
    cairo_move_to(cr, a.x, a.y);
    cairo_line_to(cr, b.x, b.y);
  }
  cairo_stroke(cr);

  // Beside the plot: the colour bar or the legend, its label, and the scale bar under them.
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, 12);
  const double bx = view.plot_width + 20, by = view.title_height + 20;
  const double bottom = categorical ? draw_legend(cr, in.categories, bx, by)
                                    : draw_colour_bar(cr, range, bx, by, view.plot_height);
  cairo_move_to(cr, bx - 10, bottom + 18);
  cairo_show_text(cr, in.value_label.c_str());
  draw_scale_bar(cr, view.scale, view.plot_width + 10, bottom + 50);

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
