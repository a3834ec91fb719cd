// result.h5: one frame per output time, written as the run goes (chunked, extendible datasets).
//   time (F), position (F x N x 2), velocity (F x N x 2), angle (F x N), angular_velocity (F x N),
//   temperature (F x N) in thermal scenes, radius (N), id (N); attributes scene, integrator, dt,
//   kiln_version, run_id.
// Every HDF5 call is checked where it is made, and the file is flushed after each frame: a write
// that fails (a full disk) is an OutputError naming the file at that frame, and a run killed
// between frames leaves a file whose finished frames HDF5 reads.
#pragma once
#include <hdf5.h>

#include <string>
#include <vector>

namespace kiln {

class H5Frames {
 public:
  // A new file (replacing any of that name).
  H5Frames(const std::string& path, int particles, bool thermal);
  // An existing file of a run being resumed: frames after the first `keep` are dropped (those a
  // killed run wrote after its checkpoint), and new frames follow them.
  H5Frames(const std::string& path, int particles, bool thermal, int keep);
  ~H5Frames();
  H5Frames(const H5Frames&) = delete;
  H5Frames& operator=(const H5Frames&) = delete;

  void attribute(const std::string& name, const std::string& value);
  void attribute(const std::string& name, double value);
  std::string text_attribute(const std::string& name) const;  // "" when absent
  void write_constant(const std::vector<double>& radius);
  // Fields of one frame (angle and omega may be null: written as zeros), then a flush.
  void append(double t, const double* x, const double* y, const double* vx, const double* vy, const double* angle,
              const double* omega, const double* temperature);
  int frames() const { return frames_; }
  // The frames of run `run_id` that the file at `path` holds, read only; -1 when it cannot be read
  // or is another run's.
  static int frames_of_run(const std::string& path, const std::string& run_id);
  std::vector<double> times() const;  // the time of every frame
  void close();    // checked: the last writes may fail here
  void abandon();  // closes without checking (a run that failed: the file is removed)

 private:
  hid_t create(const char* name, int rank, const hsize_t* frame_dims);
  hid_t open(const char* name, int rank, const hsize_t* frame_dims, int keep);
  void extend_and_write(hid_t ds, int rank, const hsize_t* frame_dims, const double* data);
  std::string path_;
  hid_t file_ = -1;
  hid_t time_ = -1, position_ = -1, velocity_ = -1, angle_ = -1, omega_ = -1, temperature_ = -1;
  int n_ = 0, frames_ = 0;
  std::vector<double> pair_buffer_, zeros_;
};

}  // namespace kiln
