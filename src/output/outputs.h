// The other files of a run: the XDMF index for ParaView and the PNG picture.
#pragma once
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "src/base/atomic_write.h"
#include "src/output/colour_scale.h"
#include "src/base/vec2.h"
#include "src/output/frame_fields.h"

namespace kiln {

// What result.h5 holds (output_h5.h lists its datasets), which result.xdmf describes.
struct ResultLayout {
  int particles = 0;
  bool thermal = false;     // a temperature per particle and frame
  int walls = 0;            // 0: no wall datasets at all
  int segments = 0;         // the walls' straight segments
  bool walls_move = false;  // wall_segments per frame (F x S x 4), otherwise once (S x 4)
};

// Whether result.h5 holds the field (frame_fields.h) in a run of this layout.
inline bool in_result(const FrameFieldInfo& f, const ResultLayout& l) {
  switch (f.when) {
    case FramePresence::always: return true;
    case FramePresence::thermal: return l.thermal;
    case FramePresence::moving_walls: return l.walls > 0 && l.walls_move;
    case FramePresence::walls: return l.walls > 0;
  }
  return false;
}

// The dimensions of one frame of a field in result.h5: none for the run's (time), {n} for a
// scalar of n items, {n, 3} for a vector (x, y, 0), {n, 4} for segment rows.
inline std::vector<size_t> frame_dims(const FrameFieldInfo& f, const ResultLayout& l) {
  if (f.of == FrameOf::run) return {};
  const size_t n = static_cast<size_t>(f.of == FrameOf::particles ? l.particles
                                       : f.of == FrameOf::segments ? l.segments
                                                                   : l.walls);
  switch (f.layout) {
    case FrameLayout::scalar: return {n};
    case FrameLayout::x_block_y_block:
    case FrameLayout::xy_pairs: return {n, 3};
    case FrameLayout::segment_rows: return {n, 4};
  }
  return {};
}

// result.xdmf for ParaView: two time series (temporal collections, one uniform grid per frame),
// the particles (vertices at `position`, with radius, velocity as a vector, angle,
// angular_velocity, temperature, id) and, when there are walls, the walls (2 S points of XY read
// from the rows (x_a, y_a, x_b, y_b) of `wall_segments`, S two-node polylines by
// `wall_connectivity`, each with the index of its wall; the frame's wall_force, wall_torque and
// wall_power as field data). Every per-frame item is a view /frames/k/<name> of result.h5, read
// whole (H5Frames::write_frame_views), never a HyperSlab.
std::string xdmf_document(const std::string& h5_name, const ResultLayout& layout, const std::vector<double>& times);

// units.csv: ParaView has no units of its own and XDMF attributes carry none, so each array that
// result.xdmf shows gets a row (array, series, centre, unit, the result.h5 dataset it reads) that
// ParaView's CSV reader opens beside the run. The units are result.h5's `units` attributes.
std::string units_table(const ResultLayout& layout);

// Where write_picture draws: the image's size and the pixel (from its top left corner) of a point.
struct PictureView {
  double x0 = 0, y1 = 0, scale = 1;  // the left and top edges of the plot (m), pixels per metre
  int plot_width = 0, plot_height = 0, bar_width = 0, title_height = 0;
  Vec2 pixel(Vec2 p) const { return {(p.x - x0) * scale, title_height + (y1 - p.y) * scale}; }
  int width() const { return plot_width + bar_width; }
  int height() const { return plot_height + title_height; }
};

// The region of the plane a picture shows (m): grown by each disc and wall end it must hold.
struct PictureBounds {
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  void grow(Vec2 p, double r) {
    x0 = std::min(x0, p.x - r);
    y0 = std::min(y0, p.y - r);
    x1 = std::max(x1, p.x + r);
    y1 = std::max(y1, p.y + r);
  }
  void grow(const PictureBounds& b) {
    x0 = std::min(x0, b.x0);
    y0 = std::min(y0, b.y0);
    x1 = std::max(x1, b.x1);
    y1 = std::max(y1, b.y1);
  }
};
// The view of a region, with a margin of 3 % around it.
PictureView picture_view(const PictureBounds& b);

// A picture of one state: discs coloured by `value` (speed or temperature) with a colour bar,
// or by category (material) with a legend; walls as lines. Written as PNG by cairo to `path`
// (checked: OutputError; give a temporary name). The colour scale is robust (colour_scale.h): a
// few outliers are clipped, a constant field is one colour with one label. Particles of walls
// (attached or fixed) are drawn grey, outside the scale. A scale bar of a round length sits under
// the colour bar.
struct PictureInput {
  std::vector<Vec2> centre;
  std::vector<double> radius;
  std::vector<double> value;  // or, with categories, the index of each particle's category
  std::vector<char> of_wall;  // per particle, or empty: none
  std::string value_label;    // with its unit
  // Categorical colouring: a colour per category (never grey, which marks particles of walls),
  // named in a legend in place of the colour bar.
  std::vector<std::string> categories;
  // The frames of a movie share one colour scale and one view (those of the whole run), so that a
  // colour and a place mean the same in every frame; unset: the picture's own.
  std::optional<ColourScale> scale;
  std::optional<PictureView> view;
  std::vector<Vec2> wall_a, wall_b;
  std::string title;          // first line: the scene and time; second: how the run ended
  std::string subtitle;
};
void write_picture(const std::string& path, const PictureInput& in);

PictureBounds picture_bounds(const PictureInput& in);  // its particles and walls
PictureView picture_view(const PictureInput& in);      // in.view, else its bounds' view

}  // namespace kiln
