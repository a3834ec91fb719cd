// Reading a run's result.h5 (written by output_h5.h) one frame at a time: what a movie draws, in
// memory one frame at a time whatever the length of the run. A file that is missing, not a kiln
// result or unreadable is an InputError naming it.
#pragma once
#include <hdf5.h>

#include <string>
#include <vector>

#include "src/base/vec2.h"

namespace kiln {

class ResultReader {
 public:
  explicit ResultReader(const std::string& path);
  ~ResultReader();
  ResultReader(const ResultReader&) = delete;
  ResultReader& operator=(const ResultReader&) = delete;

  struct Frame {
    std::vector<Vec2> position, velocity;
    std::vector<double> temperature;   // thermal results only
    std::vector<Vec2> wall_a, wall_b;  // the wall segments where they are at this frame
  };
  int frames() const { return static_cast<int>(times_.size()); }
  int particles() const { return static_cast<int>(radius_.size()); }
  bool thermal() const { return thermal_; }
  const std::vector<double>& times() const { return times_; }
  const std::vector<double>& radius() const { return radius_; }
  void read(int frame, Frame& f) const;

 private:
  // Frame `frame` of a dataset of frames (its first dimension), or the whole of a constant one
  // (frame < 0).
  std::vector<double> values(const char* name, int frame) const;
  std::string path_;
  hid_t file_ = -1;
  std::vector<double> times_, radius_;
  bool thermal_ = false;
  bool walls_move_ = false;
  std::vector<double> fixed_segments_;  // x_a, y_a, x_b, y_b per segment, when no wall moves
};

}  // namespace kiln
