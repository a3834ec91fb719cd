#include "src/output/output_h5.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "src/base/error.h"
#include "src/base/h5_errors.h"
#include "src/base/text_format.h"

namespace kiln {

H5Frames::H5Frames(const std::string& path, const ResultLayout& layout) : path_(path), layout_(layout) {
  h5_setup();
  std::fill_n(ds_, frame_field_count, -1);
  file_ = h5_id(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), "create", path_);
  try {
    for (const FrameFieldInfo& f : frame_fields)
      if (present(f)) ds_[static_cast<int>(f.field)] = create(shape(f));
  } catch (...) {
    abandon();  // no destructor runs for an object whose constructor throws
    throw;
  }
  triple_buffer_.resize(3 * std::max(layout_.particles, layout_.walls));
  zeros_.assign(std::max({layout_.particles, layout_.walls, layout_.segments}), 0.0);  // a null field of any item
}

H5Frames::H5Frames(const std::string& path, const ResultLayout& layout, int keep, double resumed_at)
    : path_(path), layout_(layout) {
  h5_setup();
  std::fill_n(ds_, frame_field_count, -1);
  file_ = h5_id(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), "open (to resume)", path_);
  try {
    check_kept_frames(keep, resumed_at);
    for (const FrameFieldInfo& f : frame_fields)
      if (present(f)) ds_[static_cast<int>(f.field)] = open(shape(f), keep);
    drop_frame_views(keep);
    h5_check(H5Fflush(file_, H5F_SCOPE_GLOBAL), "write", path_);
  } catch (...) {
    abandon();
    throw;
  }
  frames_ = keep;
  triple_buffer_.resize(3 * std::max(layout_.particles, layout_.walls));
  zeros_.assign(std::max({layout_.particles, layout_.walls, layout_.segments}), 0.0);  // a null field of any item
}

H5Frames::~H5Frames() { abandon(); }

// A checkpoint of 3 frames at t = 0.4 s over a result of 41 (its checksums written afresh) was
// resumed, and frames 0.03 to 0.40 s were cut (issue 28's review): the count is checked against
// the frames' own times before anything is cut.
void H5Frames::check_kept_frames(int keep, double resumed_at) const {
  const hid_t ds = h5_id(H5Dopen2(file_, "time", H5P_DEFAULT), "open dataset 'time' in", path_);
  const hid_t space = H5Dget_space(ds);
  hsize_t stored = 0;
  const bool one_axis = space >= 0 && H5Sget_simple_extent_ndims(space) == 1 &&
                        H5Sget_simple_extent_dims(space, &stored, nullptr) == 1;
  if (space >= 0) H5Sclose(space);
  const hsize_t count = std::min<hsize_t>(stored, static_cast<hsize_t>(keep) + 1);
  std::vector<double> times;
  try {
    if (!one_axis) h5_check(-1, "read dataset 'time' of", path_);
    times = read_rows(ds, shape(frame_field(FrameField::time)), count);
  } catch (...) {
    H5Dclose(ds);
    throw;
  }
  H5Dclose(ds);
  if (count < static_cast<hsize_t>(keep))
    throw InputError(path_ + ": holds " + std::to_string(count) + " frames where the checkpoint counts " +
                     std::to_string(keep) + ": a result of another run, or frames lost");
  const bool last_before = keep == 0 || times[keep - 1] <= resumed_at;
  // A frame at the checkpoint's own time may follow it (a stop at a frame's time checkpoints first).
  const bool next_after = count <= static_cast<hsize_t>(keep) || times[keep] >= resumed_at;
  if (!last_before || !next_after)
    throw InputError(path_ + ": the checkpoint at t = " + format("%.9g", resumed_at) + " s counts " +
                     std::to_string(keep) + " frames, but this file's frame " + std::to_string(last_before ? keep : keep - 1) +
                     " is at t = " + format("%.9g", times[last_before ? keep : keep - 1]) +
                     " s: a checkpoint that does not match its frames (resuming it would drop finished frames)");
}

bool H5Frames::present(const FrameFieldInfo& f) const { return in_result(f, layout_); }

H5Frames::Shape H5Frames::shape(const FrameFieldInfo& f) const {
  const std::vector<size_t> dims = frame_dims(f, layout_);
  Shape s{f.name, f.units, static_cast<int>(dims.size()), {0, 0}};
  for (size_t k = 0; k < dims.size(); ++k) s.dims[k] = dims[k];
  return s;
}

// The text attribute `units` of a dataset.
void H5Frames::units(hid_t object, const char* value, const std::string& dataset) {
  const hid_t type = H5Tcopy(H5T_C_S1);
  herr_t status = type < 0 ? -1 : H5Tset_size(type, std::char_traits<char>::length(value) + 1);
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attr = status < 0 || space < 0 ? -1 : H5Acreate2(object, "units", type, space, H5P_DEFAULT, H5P_DEFAULT);
  status = attr < 0 ? -1 : H5Awrite(attr, type, value);
  if (attr >= 0) H5Aclose(attr);
  if (space >= 0) H5Sclose(space);
  if (type >= 0) H5Tclose(type);
  h5_check(status, ("write the units of dataset '" + dataset + "' to").c_str(), path_);
}

// A dataset of frames: rank+1 dimensions, the first unlimited, one frame per chunk.
hid_t H5Frames::create(const Shape& s) {
  hsize_t dims[3] = {0, 0, 0}, maxdims[3] = {H5S_UNLIMITED, 0, 0}, chunk[3] = {1, 1, 1};
  for (int k = 0; k < s.rank; ++k) {
    dims[k + 1] = maxdims[k + 1] = s.dims[k];
    chunk[k + 1] = std::max<hsize_t>(s.dims[k], 1);
  }
  const hid_t space = h5_id(H5Screate_simple(s.rank + 1, dims, maxdims), "describe a dataset of", path_);
  const hid_t props = H5Pcreate(H5P_DATASET_CREATE);
  const herr_t chunked = props < 0 ? -1 : H5Pset_chunk(props, s.rank + 1, chunk);
  const hid_t ds = chunked < 0 ? -1 : H5Dcreate2(file_, s.name, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, props, H5P_DEFAULT);
  if (props >= 0) H5Pclose(props);
  H5Sclose(space);
  h5_id(ds, (std::string("create dataset '") + s.name + "' in").c_str(), path_);
  try {
    units(ds, s.units, s.name);
  } catch (...) {
    H5Dclose(ds);
    throw;
  }
  return ds;
}

// An existing dataset of frames, checked against this run's sizes, cut to `keep` frames.
hid_t H5Frames::open(const Shape& s, int keep) {
  const std::string name = s.name;
  const std::string what = "open dataset '" + name + "' in";
  if (H5Lexists(file_, s.name, H5P_DEFAULT) <= 0) {
    H5Eclear2(H5E_DEFAULT);
    throw InputError(path_ + " has no dataset '" + name +
                     "' of this run's frames (written by an older kiln, or a result of another run?)");
  }
  const hid_t ds = h5_id(H5Dopen2(file_, s.name, H5P_DEFAULT), what.c_str(), path_);
  const hid_t space = H5Dget_space(ds);
  hsize_t dims[3] = {0, 0, 0};
  const int found = space < 0 ? -1 : H5Sget_simple_extent_ndims(space);
  bool same = found == s.rank + 1 && H5Sget_simple_extent_dims(space, dims, nullptr) == found &&
              dims[0] >= static_cast<hsize_t>(keep);
  if (space >= 0) H5Sclose(space);
  for (int k = 0; same && k < s.rank; ++k) same = dims[k + 1] == s.dims[k];
  if (!same) {
    H5Dclose(ds);
    H5Eclear2(H5E_DEFAULT);
    throw InputError(path_ + ": dataset '" + name + "' does not hold the " + std::to_string(keep) +
                     " frames of this run that its checkpoint records (a result of another run, or of an "
                     "older kiln?)");
  }
  dims[0] = static_cast<hsize_t>(keep);
  try {
    h5_check(H5Dset_extent(ds, dims), "cut the frames after the checkpoint in", path_);
  } catch (...) {
    H5Dclose(ds);
    throw;
  }
  return ds;
}

void H5Frames::extend_and_write(FrameField f, const double* data) {
  const Shape s = shape(frame_field(f));
  const hid_t ds = ds_[static_cast<int>(f)];
  hsize_t size[3] = {static_cast<hsize_t>(frames_ + 1), 0, 0}, start[3] = {static_cast<hsize_t>(frames_), 0, 0},
          count[3] = {1, 0, 0};
  for (int k = 0; k < s.rank; ++k) size[k + 1] = count[k + 1] = s.dims[k];
  const std::string what = "write frame " + std::to_string(frames_) + " of '" + s.name + "' to";
  h5_check(H5Dset_extent(ds, size), what.c_str(), path_);
  const hid_t file_space = h5_id(H5Dget_space(ds), what.c_str(), path_);
  const hid_t mem_space = H5Screate_simple(s.rank + 1, count, nullptr);
  herr_t status = mem_space < 0 ? -1 : H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start, nullptr, count, nullptr);
  if (status >= 0) status = H5Dwrite(ds, H5T_NATIVE_DOUBLE, mem_space, file_space, H5P_DEFAULT, data);
  if (mem_space >= 0) H5Sclose(mem_space);
  H5Sclose(file_space);
  h5_check(status, what.c_str(), path_);
}

// What the file holds of a frame's values: (x, y, 0) triples of two-component fields, zeros for
// a field the frame leaves null.
const double* H5Frames::as_written(const FrameFieldInfo& f, const double* values) {
  const int n = static_cast<int>(shape(f).dims[0]);
  if (!values && f.zeros_when_absent) return zeros_.data();
  if (!values) throw std::logic_error(std::string("a frame without its values of '") + f.name + "'");
  if (f.layout == FrameLayout::x_block_y_block) {
    for (int i = 0; i < n; ++i) {
      triple_buffer_[3 * i] = values[i];
      triple_buffer_[3 * i + 1] = values[n + i];
      triple_buffer_[3 * i + 2] = 0;
    }
    return triple_buffer_.data();
  }
  if (f.layout == FrameLayout::xy_pairs) {
    for (int i = 0; i < n; ++i) {
      triple_buffer_[3 * i] = values[2 * i];
      triple_buffer_[3 * i + 1] = values[2 * i + 1];
      triple_buffer_[3 * i + 2] = 0;
    }
    return triple_buffer_.data();
  }
  return values;
}

// Room on the disk is taken before HDF5 writes: a write or flush that meets a full disk writes
// HDF5's metadata in part (in place, where the file has room: the superblock's end of file beyond
// the file's end) and leaves a file no reader opens, so every finished frame was lost. Reserved
// first (posix_fallocate from HDF5's end of allocation, so the file runs at most that far ahead
// of its contents; HDF5 cuts it back when it closes), a full disk fails here, the file as its last
// flush left it.
void H5Frames::reserve_room(size_t bytes, const std::string& what) {
  haddr_t end = 0;
  h5_check(H5Fget_eoa(file_, &end), ("reserve room to " + what + " in").c_str(), path_);
  const int fd = ::open(path_.c_str(), O_WRONLY | O_CLOEXEC);
  const int error = fd < 0 ? errno : ::posix_fallocate(fd, static_cast<off_t>(end), static_cast<off_t>(bytes));
  if (fd >= 0) ::close(fd);
  if (error != 0) throw OutputError("cannot " + what + " to " + path_ + ": " + std::strerror(error));
}

size_t H5Frames::frame_bytes() const {
  size_t bytes = 0;
  for (const FrameFieldInfo& f : frame_fields) {
    if (ds_[static_cast<int>(f.field)] < 0) continue;
    size_t values = 1;
    const Shape s = shape(f);
    for (int k = 0; k < s.rank; ++k) values *= s.dims[k];
    bytes += values * sizeof(double);
  }
  return bytes;
}

// A frame: its values twice and 64 KiB for the chunk indexes and object headers it may add (one
// chunk per frame and dataset).
void H5Frames::append(const H5Frame& frame) {
  reserve_room(2 * frame_bytes() + 65536, "write frame " + std::to_string(frames_));
  for (const FrameFieldInfo& f : frame_fields) {
    if (ds_[static_cast<int>(f.field)] < 0) continue;
    const double* values = f.of == FrameOf::run ? &frame.t : frame[f.field];
    extend_and_write(f.field, as_written(f, values));
  }
  // Written through to the file now: HDF5 would otherwise hold the frame (and report a failed
  // write) until close, and a run killed before then would leave metadata that no reader opens.
  h5_check(H5Fflush(file_, H5F_SCOPE_GLOBAL), ("write frame " + std::to_string(frames_) + " to").c_str(), path_);
  ++frames_;
}

int H5Frames::frames_of_run(const std::string& path, const std::string& run_id) {
  h5_setup();
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  int frames = -1;
  if (file >= 0 && H5Aexists(file, "run_id") > 0) {
    const hid_t attr = H5Aopen(file, "run_id", H5P_DEFAULT);
    const hid_t type = H5Aget_type(attr);
    std::string id(H5Tget_size(type), '\0');
    const bool read = H5Aread(attr, type, id.data()) >= 0;
    H5Tclose(type);
    H5Aclose(attr);
    const hid_t ds = H5Dopen2(file, "time", H5P_DEFAULT);
    if (read && id.substr(0, id.find('\0')) == run_id && ds >= 0) {
      const hid_t space = H5Dget_space(ds);
      frames = static_cast<int>(H5Sget_simple_extent_npoints(space));
      H5Sclose(space);
    }
    if (ds >= 0) H5Dclose(ds);
  }
  if (file >= 0) H5Fclose(file);
  H5Eclear2(H5E_DEFAULT);
  return frames;
}

std::vector<double> H5Frames::read(FrameField field) const {
  const FrameFieldInfo& f = frame_field(field);
  const hid_t ds = ds_[static_cast<int>(field)];
  if (ds < 0) throw std::logic_error(std::string("read '") + f.name + "', which this result does not hold");
  return read_rows(ds, shape(f), static_cast<hsize_t>(frames_));
}

// The first `rows` frames of dataset `ds` of shape `s`, row-major.
std::vector<double> H5Frames::read_rows(hid_t ds, const Shape& s, hsize_t rows) const {
  const hsize_t start[3] = {0, 0, 0}, count[3] = {rows, s.dims[0], s.dims[1]};
  hsize_t values = count[0];
  for (int k = 0; k < s.rank; ++k) values *= count[k + 1];
  std::vector<double> v(values);
  if (values == 0) return v;
  const std::string what = std::string("read '") + s.name + "' of";
  const hid_t file_space = h5_id(H5Dget_space(ds), what.c_str(), path_);
  const hid_t mem_space = H5Screate_simple(s.rank + 1, count, nullptr);
  herr_t status = mem_space < 0 ? -1 : H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start, nullptr, count, nullptr);
  if (status >= 0) status = H5Dread(ds, H5T_NATIVE_DOUBLE, mem_space, file_space, H5P_DEFAULT, v.data());
  if (mem_space >= 0) H5Sclose(mem_space);
  H5Sclose(file_space);
  h5_check(status, what.c_str(), path_);
  return v;
}

// A whole constant dataset with its units.
void H5Frames::write_array(const char* name, hid_t type, int rank, const hsize_t* dims, const void* data,
                           const char* unit) {
  const std::string what = std::string("write dataset '") + name + "' to";
  const hid_t space = h5_id(H5Screate_simple(rank, dims, nullptr), what.c_str(), path_);
  const hid_t ds = H5Dcreate2(file_, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  const herr_t status = ds < 0 ? -1 : H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
  H5Sclose(space);
  try {
    h5_check(status, what.c_str(), path_);
    units(ds, unit, name);
  } catch (...) {
    if (ds >= 0) H5Dclose(ds);
    throw;
  }
  h5_check(H5Dclose(ds), what.c_str(), path_);
}

void H5Frames::write_table(const ResultTable& table) {
  if (H5Lexists(file_, table.name.c_str(), H5P_DEFAULT) > 0)
    h5_check(H5Ldelete(file_, table.name.c_str(), H5P_DEFAULT), ("replace dataset '" + table.name + "' in").c_str(), path_);
  write_array(table.name.c_str(), H5T_NATIVE_DOUBLE, static_cast<int>(table.shape.size()), table.shape.data(),
              table.values.data(), table.units.c_str());
}

void H5Frames::write_constant(const std::vector<double>& radius) {
  const hsize_t dims[] = {static_cast<hsize_t>(layout_.particles)};
  write_array("radius", H5T_NATIVE_DOUBLE, 1, dims, radius.data(), "m");
  std::vector<long long> ids(layout_.particles);
  for (int i = 0; i < layout_.particles; ++i) ids[i] = i;
  write_array("id", H5T_NATIVE_LLONG, 1, dims, ids.data(), "1");
}

void H5Frames::write_walls(const std::vector<int>& wall_of_segment, const std::vector<std::string>& names,
                           const double* fixed_segments) {
  const int s = layout_.segments;
  const hsize_t per_segment[] = {static_cast<hsize_t>(s)};
  write_array("wall_of_segment", H5T_NATIVE_INT, 1, per_segment, wall_of_segment.data(), "1");
  std::vector<int> ends(2 * s);
  for (int k = 0; k < 2 * s; ++k) ends[k] = k;
  const hsize_t pairs[] = {static_cast<hsize_t>(s), 2};
  write_array("wall_connectivity", H5T_NATIVE_INT, 2, pairs, ends.data(), "1");
  if (fixed_segments) {
    const hsize_t rows[] = {static_cast<hsize_t>(s), 4};
    write_array("wall_segments", H5T_NATIVE_DOUBLE, 2, rows, fixed_segments, "m");
  }
  // The names as an array of variable-length UTF-8 strings: any text a scene gives stays whole.
  std::vector<const char*> text;
  for (const std::string& name : names) text.push_back(name.c_str());
  const hsize_t count[] = {text.size()};
  const hid_t type = H5Tcopy(H5T_C_S1);
  herr_t status = type < 0 ? -1 : H5Tset_size(type, H5T_VARIABLE);
  if (status >= 0) status = H5Tset_cset(type, H5T_CSET_UTF8);
  const hid_t space = H5Screate_simple(1, count, nullptr);
  const hid_t attr =
      status < 0 || space < 0 ? -1 : H5Acreate2(file_, "wall_names", type, space, H5P_DEFAULT, H5P_DEFAULT);
  status = attr < 0 ? -1 : H5Awrite(attr, type, text.data());
  if (attr >= 0) H5Aclose(attr);
  if (space >= 0) H5Sclose(space);
  if (type >= 0) H5Tclose(type);
  h5_check(status, "write attribute 'wall_names' to", path_);
}

void H5Frames::attribute(const std::string& name, const std::string& value) {
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, value.size() + 1);
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attr = H5Acreate2(file_, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
  const herr_t status = attr < 0 ? -1 : H5Awrite(attr, type, value.c_str());
  if (attr >= 0) H5Aclose(attr);
  H5Sclose(space);
  H5Tclose(type);
  h5_check(status, ("write attribute '" + name + "' to").c_str(), path_);
}

void H5Frames::attribute(const std::string& name, double value) {
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attr = H5Acreate2(file_, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT);
  const herr_t status = attr < 0 ? -1 : H5Awrite(attr, H5T_NATIVE_DOUBLE, &value);
  if (attr >= 0) H5Aclose(attr);
  H5Sclose(space);
  h5_check(status, ("write attribute '" + name + "' to").c_str(), path_);
}

std::string H5Frames::text_attribute(const std::string& name) const {
  if (H5Aexists(file_, name.c_str()) <= 0) return "";
  const hid_t attr = h5_id(H5Aopen(file_, name.c_str(), H5P_DEFAULT), "read an attribute of", path_);
  const hid_t type = H5Aget_type(attr);
  std::string value(H5Tget_size(type), '\0');
  const herr_t status = H5Aread(attr, type, value.data());
  H5Tclose(type);
  H5Aclose(attr);
  h5_check(status, "read an attribute of", path_);
  return value.substr(0, value.find('\0'));
}

namespace {
std::string frame_group(int k) { return "/frames/" + std::to_string(k); }
}  // namespace

void H5Frames::drop_frame_views(int keep) {
  if (H5Lexists(file_, "frames", H5P_DEFAULT) <= 0) return;
  for (int k = keep; H5Lexists(file_, frame_group(k).c_str(), H5P_DEFAULT) > 0; ++k)
    h5_check(H5Ldelete(file_, frame_group(k).c_str(), H5P_DEFAULT), "drop the frame views after the checkpoint in",
             path_);
}

// Frame k of a dataset of frames as a dataset of its own: a virtual dataset (HDF5 1.10) that maps
// the frame's slab of the source in this file ("."), so no value is stored twice.
// The views of every frame (measured on the drum and the heap: 552 to 558 bytes each, its group's
// share included), the tables, and 64 KiB, each counted about twice.
void H5Frames::reserve_for_closing(const std::vector<ResultTable>& tables) {
  size_t datasets = 0;
  for (hid_t ds : ds_) datasets += ds >= 0;
  size_t bytes = 65536 + 1024 * static_cast<size_t>(frames_) * datasets;
  for (const ResultTable& t : tables) bytes += 2 * t.values.size() * sizeof(double) + 4096;
  reserve_room(bytes, "write the tables and frame views");
}

void H5Frames::write_frame_views() {
  if (H5Lexists(file_, "frames", H5P_DEFAULT) <= 0) {
    const hid_t g = h5_id(H5Gcreate2(file_, "frames", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), "create group 'frames' in", path_);
    H5Gclose(g);
  }
  for (int k = 0; k < frames_; ++k) {
    const std::string group = frame_group(k);
    if (H5Lexists(file_, group.c_str(), H5P_DEFAULT) > 0) continue;  // a resumed run's earlier frames
    const std::string what = "write the views of frame " + std::to_string(k) + " to";
    const hid_t g = h5_id(H5Gcreate2(file_, group.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), what.c_str(), path_);
    herr_t status = 0;
    for (const FrameFieldInfo& f : frame_fields) {
      const hid_t source = ds_[static_cast<int>(f.field)];
      if (source < 0 || f.of == FrameOf::run || status < 0) continue;
      const Shape s = shape(f);
      const hsize_t start[3] = {static_cast<hsize_t>(k), 0, 0}, count[3] = {1, s.dims[0], s.dims[1]};
      const hid_t view_space = H5Screate_simple(s.rank, s.dims, nullptr);
      const hid_t source_space = H5Dget_space(source);
      const hid_t props = H5Pcreate(H5P_DATASET_CREATE);
      status = view_space < 0 || source_space < 0 || props < 0 ? -1 : H5Sselect_all(view_space);
      if (status >= 0) status = H5Sselect_hyperslab(source_space, H5S_SELECT_SET, start, nullptr, count, nullptr);
      if (status >= 0) status = H5Pset_virtual(props, view_space, ".", s.name, source_space);
      const hid_t view =
          status < 0 ? -1 : H5Dcreate2(g, s.name, H5T_NATIVE_DOUBLE, view_space, H5P_DEFAULT, props, H5P_DEFAULT);
      if (view < 0) status = -1;
      if (view >= 0) {
        try {
          units(view, s.units, group + "/" + s.name);
        } catch (...) {
          status = -1;
        }
        H5Dclose(view);
      }
      if (props >= 0) H5Pclose(props);
      if (source_space >= 0) H5Sclose(source_space);
      if (view_space >= 0) H5Sclose(view_space);
    }
    H5Gclose(g);
    h5_check(status, what.c_str(), path_);
  }
}

void H5Frames::close() {
  if (file_ < 0) return;
  herr_t status = 0;
  for (hid_t& ds : ds_) {
    if (ds >= 0 && H5Dclose(ds) < 0) status = -1;
    ds = -1;
  }
  if (H5Fclose(file_) < 0) status = -1;
  file_ = -1;
  h5_check(status, "finish writing", path_);
  // The room reserved ahead of HDF5 (reserve_room) is given back here: HDF5 does not cut the file
  // to its end of allocation when it closes, and a published result kept the last reservation as
  // zeros (issue 28's campaign: 80 kB of T3's 185 kB; 12.9 MB of 41.7 MB for 200,000 discs).
  const hid_t again = H5Fopen(path_.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  haddr_t end = 0;
  const bool known = again >= 0 && H5Fget_eoa(again, &end) >= 0 && end > 0;
  if (again >= 0) H5Fclose(again);
  H5Eclear2(H5E_DEFAULT);
  if (known && ::truncate(path_.c_str(), static_cast<off_t>(end)) != 0)
    throw OutputError("cannot give back the room reserved in " + path_ + ": " + std::strerror(errno));
}

void H5Frames::abandon() {
  if (file_ < 0) return;
  for (hid_t& ds : ds_) {
    if (ds >= 0) H5Dclose(ds);
    ds = -1;
  }
  H5Fclose(file_);
  file_ = -1;
  H5Eclear2(H5E_DEFAULT);
}

void H5Frames::leave_as_flushed() {
  if (file_ < 0) return;
  for (hid_t& ds : ds_) ds = -1;
  file_ = -1;
  H5Eclear2(H5E_DEFAULT);
}

}  // namespace kiln
