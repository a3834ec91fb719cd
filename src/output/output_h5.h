// result.h5: one frame per output time, written as the run goes (chunked, extendible datasets).
// F frames, N particles, W walls, S wall segments; every dataset has a text attribute `units`.
// The datasets of frames are those of frame_fields.h (time, position and velocity as (x, y, 0),
// angle, angular_velocity, temperature in thermal scenes; wall_segments when a wall moves,
// wall_force, wall_torque, wall_power with walls), each (F x ...). Written once:
//   radius            (N)          m
//   id                (N)          1      64-bit integers 0 .. N-1
// and in scenes with walls:
//   wall_segments     (S x 4) m, or (F x S x 4) when a wall moves: x_a, y_a, x_b, y_b of each
//                     segment, i.e. the 2 S points (x, y) of the segments' ends, a then b (in a
//                     periodic cell each segment shifted by whole periods to have its middle in it)
//   wall_of_segment   (S)          1      32-bit integers: the wall (index into wall_names)
//   wall_connectivity (S x 2)      1      32-bit integers 2s, 2s + 1: segment s joins those of the
//                                         2 S points (result.xdmf's polyline topology)
//   (wall_force (F x W x 3) is what the particles exert on each wall, z = 0; wall_torque its
//   torque about the wall's centre, counter-clockwise; wall_power the power the wall delivers)
// and, at the end of a run, per frame k a group /frames/k of views (HDF5 virtual datasets) of
// frame k of each dataset of frames but time: /frames/k/position (N x 3), ... (result.xdmf reads
// them: ParaView's Xdmf3 readers read no HyperSlab)
// and the tables case observers add at the end of a run (src/observers/observer.h), e.g.
//   impact_energy_histogram (W x B) 1, impact_energy_bin_edges (B + 1) J   (wall_impacts)
// Attributes of the file: scene, integrator, dt, kiln_version, run_id, and with walls
// wall_names (W variable-length UTF-8 strings, in the order of the walls).
// Every HDF5 call is checked where it is made, and the file is flushed after each frame: a write
// that fails (a full disk) is an OutputError naming the file at that frame, and a run killed
// between frames leaves a file whose finished frames HDF5 reads.
#pragma once
#include <hdf5.h>

#include <string>
#include <vector>

#include "src/output/frame_fields.h"
#include "src/output/outputs.h"

namespace kiln {

// A table a case adds to result.h5 at the end of a run: row-major values of the given shape.
struct ResultTable {
  std::string name, units;
  std::vector<hsize_t> shape;
  std::vector<double> values;
};

// One frame: its time and, per field of frame_fields.h, its values laid out as the field says
// (null where a field is absent from the layout, or zeros when the field allows).
struct H5Frame {
  double t = 0;
  const double* values[frame_field_count] = {};
  const double*& operator[](FrameField f) { return values[static_cast<int>(f)]; }
  const double* operator[](FrameField f) const { return values[static_cast<int>(f)]; }
};

class H5Frames {
 public:
  // A new file (replacing any of that name).
  H5Frames(const std::string& path, const ResultLayout& layout);
  // An existing file of a run being resumed: frames after the first `keep` are dropped from every
  // dataset of frames (those a killed run wrote after its checkpoint), and new frames follow them.
  // The frames kept must be those the checkpoint at time `resumed_at` counts: the last of them at
  // or before it and the next (a killed run's) after it; else InputError, nothing cut.
  H5Frames(const std::string& path, const ResultLayout& layout, int keep, double resumed_at);
  ~H5Frames();
  H5Frames(const H5Frames&) = delete;
  H5Frames& operator=(const H5Frames&) = delete;

  void attribute(const std::string& name, const std::string& value);
  void attribute(const std::string& name, double value);
  std::string text_attribute(const std::string& name) const;  // "" when absent
  void write_constant(const std::vector<double>& radius);     // radius and id
  // The walls' constant part (scenes with walls): the wall of each segment, the connectivity, the
  // names, and the segments themselves (4 S values) when no wall moves (null otherwise).
  void write_walls(const std::vector<int>& wall_of_segment, const std::vector<std::string>& names,
                   const double* fixed_segments);
  void append(const H5Frame& f);  // then a flush
  void write_table(const ResultTable& table);  // replaces a table of that name (a resumed run's)
  // Room for what closing writes (tables, frame views), taken before any of it is: a full disk
  // then fails before HDF5 writes, and the frames stay readable.
  void reserve_for_closing(const std::vector<ResultTable>& tables);
  // /frames/k/<name> for every frame k and dataset of frames but `time`: frame k as a dataset of its
  // own (a virtual one, no copy), which result.xdmf reads. At the end of a run: each frame once.
  void write_frame_views();
  int frames() const { return frames_; }
  // The frames of run `run_id` that the file at `path` holds, read only; -1 when it cannot be read
  // or is another run's.
  static int frames_of_run(const std::string& path, const std::string& run_id);
  // Every frame's values of a field the file holds, as written (row-major, F x ...).
  std::vector<double> read(FrameField f) const;
  std::vector<double> times() const { return read(FrameField::time); }
  void close();    // checked: the last writes may fail here
  void abandon();  // closes without checking (a run that failed: the file is removed)
  // After a write failed (a full disk): leaves the file as its last successful flush wrote it, as
  // a killed run leaves it, by dropping its handles unclosed: closing would write HDF5's cached
  // metadata, which on a full disk lands in part. The process is to end soon: the handles are not
  // reused, and kiln turns HDF5's exit handler off (h5_setup).
  void leave_as_flushed();

 private:
  void check_kept_frames(int keep, double resumed_at) const;
  struct Shape {
    const char* name = nullptr;
    const char* units = nullptr;
    int rank = 0;  // of one frame
    hsize_t dims[2] = {0, 0};
  };
  bool present(const FrameFieldInfo& f) const;
  Shape shape(const FrameFieldInfo& f) const;
  std::vector<double> read_rows(hid_t ds, const Shape& s, hsize_t rows) const;
  hid_t create(const Shape& s);
  hid_t open(const Shape& s, int keep);
  void drop_frame_views(int keep);  // those of the frames after `keep`
  void reserve_room(size_t bytes, const std::string& what);  // before HDF5 writes (output_h5.cpp)
  size_t frame_bytes() const;
  void extend_and_write(FrameField f, const double* data);
  void units(hid_t object, const char* units, const std::string& dataset);
  void write_array(const char* name, hid_t type, int rank, const hsize_t* dims, const void* data, const char* units);
  const double* as_written(const FrameFieldInfo& f, const double* values);  // (x, y, 0) triples, zeros
  std::string path_;
  ResultLayout layout_;
  hid_t file_ = -1;
  hid_t ds_[frame_field_count];  // -1: not in the file (set for every field by the constructors)
  int frames_ = 0;
  std::vector<double> triple_buffer_, zeros_;
};

}  // namespace kiln
