// The datasets of frames in result.h5, declared once. Writing them (output_h5.cpp) and describing
// them for ParaView (output_xdmf.cpp) walk this table: a new field is its FrameField value and its
// row here, and the line of run_outputs.cpp that points the frame at its values.
#pragma once
#include <cstddef>

namespace kiln {

enum class FrameField {
  time, position, velocity, angle, angular_velocity, temperature,  // particles
  wall_segments,                                                   // when walls move
  wall_force, wall_torque, wall_power,                             // when there are walls
  count                                                            // (not a field: how many there are)
};
inline constexpr int frame_field_count = static_cast<int>(FrameField::count);

// What one frame of a field holds: its second dimension.
enum class FrameOf { run, particles, segments, walls };
// How the values a frame points at are laid out, and what the file holds:
//  - scalar: one value per item, as written;
//  - x_block_y_block: n x values then n y values (the state's layout), written (x, y, 0) per item;
//  - xy_pairs: (x, y) per item, written (x, y, 0);
//  - segment_rows: (x_a, y_a, x_b, y_b) per segment, as written.
// Three components make ParaView's vectors.
enum class FrameLayout { scalar, x_block_y_block, xy_pairs, segment_rows };
// When the field is in the file.
enum class FramePresence { always, thermal, moving_walls, walls };

struct FrameFieldInfo {
  FrameField field;
  const char* name;   // the dataset's name
  const char* units;  // its `units` attribute
  FrameOf of;
  FrameLayout layout;
  FramePresence when;
  bool zeros_when_absent;  // a frame may leave it null: zeros are written (scenes without rotation)
  // "Scalar" or "Vector": an attribute of result.xdmf (of each particle, or of the frame's walls grid
  // as field data); null: not one (the grids' geometry, the time)
  const char* xdmf_attribute;
};

inline constexpr FrameFieldInfo frame_fields[frame_field_count] = {
    {FrameField::time, "time", "s", FrameOf::run, FrameLayout::scalar, FramePresence::always, false, nullptr},
    {FrameField::position, "position", "m", FrameOf::particles, FrameLayout::x_block_y_block, FramePresence::always,
     false, nullptr},  // the particles' geometry
    {FrameField::velocity, "velocity", "m/s", FrameOf::particles, FrameLayout::x_block_y_block,
     FramePresence::always, false, "Vector"},
    {FrameField::angle, "angle", "rad", FrameOf::particles, FrameLayout::scalar, FramePresence::always, true,
     "Scalar"},
    {FrameField::angular_velocity, "angular_velocity", "rad/s", FrameOf::particles, FrameLayout::scalar,
     FramePresence::always, true, "Scalar"},
    {FrameField::temperature, "temperature", "degC", FrameOf::particles, FrameLayout::scalar,
     FramePresence::thermal, false, "Scalar"},
    {FrameField::wall_segments, "wall_segments", "m", FrameOf::segments, FrameLayout::segment_rows,
     FramePresence::moving_walls, false, nullptr},  // the walls' geometry
    {FrameField::wall_force, "wall_force", "N", FrameOf::walls, FrameLayout::xy_pairs, FramePresence::walls, false,
     "Vector"},
    {FrameField::wall_torque, "wall_torque", "N m", FrameOf::walls, FrameLayout::scalar, FramePresence::walls, false,
     "Scalar"},
    {FrameField::wall_power, "wall_power", "W", FrameOf::walls, FrameLayout::scalar, FramePresence::walls, false,
     "Scalar"},
};

constexpr const FrameFieldInfo& frame_field(FrameField f) { return frame_fields[static_cast<int>(f)]; }

// The table is indexed by its fields: a row out of place fails the build.
constexpr bool frame_fields_in_order() {
  for (int k = 0; k < frame_field_count; ++k)
    if (static_cast<int>(frame_fields[k].field) != k) return false;
  return true;
}
static_assert(frame_fields_in_order(), "frame_fields lists every FrameField once, in the enum's order");

}  // namespace kiln
