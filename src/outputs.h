// The other files of a run: XDMF index for ParaView, the PNG picture, and atomic file writing.
#pragma once
#include <string>
#include <vector>

#include "src/vec2.h"

namespace kiln {

// Writes `text` to path, every write checked: a full disk is an OutputError naming the file,
// and the partial file is removed.
void write_file(const std::string& path, const std::string& text);
// The same via path + ".tmp" and a rename, so no half-written file is left under `path`.
void write_file_atomically(const std::string& path, const std::string& text);
// Renames a finished temporary file to its final name (OutputError naming both on failure).
void publish(const std::string& tmp, const std::string& path);

// result.xdmf describing `frames` frames of `particles` points in the HDF5 file `h5_name`.
std::string xdmf_document(const std::string& h5_name, int particles, const std::vector<double>& times, bool thermal);

// A picture of one state: discs coloured by `value` (speed or temperature) with a colour bar,
// walls as lines. Written as PNG by cairo to `path` (checked: OutputError; give a temporary name).
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
