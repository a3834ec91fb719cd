// The other files of a run: XDMF index for ParaView, the PNG picture, and atomic file writing.
#pragma once
#include <string>
#include <vector>

#include "src/vec2.h"

namespace kiln {

// Writes `text` to path via a temporary name and a rename, so no half-written file is left.
void write_file_atomically(const std::string& path, const std::string& text);

// result.xdmf describing `frames` frames of `particles` points in the HDF5 file `h5_name`.
std::string xdmf_document(const std::string& h5_name, int particles, const std::vector<double>& times, bool thermal);

// A picture of one state: discs coloured by `value` (speed or temperature) with a colour bar,
// walls as lines. Written as PNG by cairo.
struct PictureInput {
  std::vector<Vec2> centre;
  std::vector<double> radius;
  std::vector<double> value;
  std::string value_label;
  std::vector<Vec2> wall_a, wall_b;
  std::string title;
};
void write_picture(const std::string& path, const PictureInput& in);

}  // namespace kiln
