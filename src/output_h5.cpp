#include "src/output_h5.h"

#include "src/error.h"
#include "src/h5_errors.h"

namespace kiln {

namespace {
const hsize_t scalar_frame[] = {1};
}  // namespace

H5Frames::H5Frames(const std::string& path, int particles, bool thermal) : path_(path), n_(particles) {
  h5_setup();
  file_ = h5_id(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), "create", path_);
  const hsize_t pairs[] = {static_cast<hsize_t>(n_), 2};
  const hsize_t singles[] = {static_cast<hsize_t>(n_)};
  time_ = create("time", 0, scalar_frame);
  position_ = create("position", 2, pairs);
  velocity_ = create("velocity", 2, pairs);
  angle_ = create("angle", 1, singles);
  omega_ = create("angular_velocity", 1, singles);
  if (thermal) temperature_ = create("temperature", 1, singles);
  pair_buffer_.resize(2 * n_);
  zeros_.assign(n_, 0.0);
}

H5Frames::H5Frames(const std::string& path, int particles, bool thermal, int keep) : path_(path), n_(particles) {
  h5_setup();
  file_ = h5_id(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), "open (to resume)", path_);
  const hsize_t pairs[] = {static_cast<hsize_t>(n_), 2};
  const hsize_t singles[] = {static_cast<hsize_t>(n_)};
  time_ = open("time", 0, scalar_frame, keep);
  position_ = open("position", 2, pairs, keep);
  velocity_ = open("velocity", 2, pairs, keep);
  angle_ = open("angle", 1, singles, keep);
  omega_ = open("angular_velocity", 1, singles, keep);
  if (thermal) temperature_ = open("temperature", 1, singles, keep);
  frames_ = keep;
  h5_check(H5Fflush(file_, H5F_SCOPE_GLOBAL), "write", path_);
  pair_buffer_.resize(2 * n_);
  zeros_.assign(n_, 0.0);
}

H5Frames::~H5Frames() { abandon(); }

// A dataset of frames: rank+1 dimensions, the first unlimited, one frame per chunk.
hid_t H5Frames::create(const char* name, int rank, const hsize_t* frame_dims) {
  hsize_t dims[3] = {0, 0, 0}, maxdims[3] = {H5S_UNLIMITED, 0, 0}, chunk[3] = {1, 1, 1};
  for (int k = 0; k < rank; ++k) dims[k + 1] = maxdims[k + 1] = chunk[k + 1] = frame_dims[k];
  const hid_t space = h5_id(H5Screate_simple(rank + 1, dims, maxdims), "describe a dataset of", path_);
  const hid_t props = H5Pcreate(H5P_DATASET_CREATE);
  const herr_t chunked = H5Pset_chunk(props, rank + 1, chunk);
  const hid_t ds = chunked < 0 ? -1 : H5Dcreate2(file_, name, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, props, H5P_DEFAULT);
  H5Pclose(props);
  H5Sclose(space);
  return h5_id(ds, (std::string("create dataset '") + name + "' in").c_str(), path_);
}

// An existing dataset of frames, checked against this run's particle count, cut to `keep` frames.
hid_t H5Frames::open(const char* name, int rank, const hsize_t* frame_dims, int keep) {
  const std::string what = std::string("open dataset '") + name + "' in";
  const hid_t ds = h5_id(H5Dopen2(file_, name, H5P_DEFAULT), what.c_str(), path_);
  const hid_t space = h5_id(H5Dget_space(ds), what.c_str(), path_);
  hsize_t dims[3] = {0, 0, 0};
  const int found = H5Sget_simple_extent_dims(space, dims, nullptr);
  H5Sclose(space);
  bool same = found == rank + 1 && dims[0] >= static_cast<hsize_t>(keep);
  for (int k = 0; same && k < rank; ++k) same = dims[k + 1] == frame_dims[k];
  if (!same) {
    H5Dclose(ds);
    throw InputError(path_ + ": dataset '" + name + "' does not hold the " + std::to_string(keep) +
                     " frames of this run that its checkpoint records (a result of another run?)");
  }
  dims[0] = static_cast<hsize_t>(keep);
  h5_check(H5Dset_extent(ds, dims), "cut the frames after the checkpoint in", path_);
  return ds;
}

void H5Frames::extend_and_write(hid_t ds, int rank, const hsize_t* frame_dims, const double* data) {
  hsize_t size[3] = {static_cast<hsize_t>(frames_ + 1), 0, 0}, start[3] = {static_cast<hsize_t>(frames_), 0, 0},
          count[3] = {1, 0, 0};
  for (int k = 0; k < rank; ++k) size[k + 1] = count[k + 1] = frame_dims[k];
  h5_check(H5Dset_extent(ds, size), "extend a dataset of", path_);
  const hid_t file_space = h5_id(H5Dget_space(ds), "select a frame of", path_);
  const hid_t mem_space = H5Screate_simple(rank + 1, count, nullptr);
  herr_t status = H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start, nullptr, count, nullptr);
  if (status >= 0) status = H5Dwrite(ds, H5T_NATIVE_DOUBLE, mem_space, file_space, H5P_DEFAULT, data);
  H5Sclose(mem_space);
  H5Sclose(file_space);
  h5_check(status, ("write frame " + std::to_string(frames_) + " to").c_str(), path_);
}

void H5Frames::append(double t, const double* x, const double* y, const double* vx, const double* vy,
                      const double* angle, const double* omega, const double* temperature) {
  const hsize_t pairs[] = {static_cast<hsize_t>(n_), 2};
  const hsize_t singles[] = {static_cast<hsize_t>(n_)};
  extend_and_write(time_, 0, nullptr, &t);
  for (int i = 0; i < n_; ++i) {
    pair_buffer_[2 * i] = x[i];
    pair_buffer_[2 * i + 1] = y[i];
  }
  extend_and_write(position_, 2, pairs, pair_buffer_.data());
  for (int i = 0; i < n_; ++i) {
    pair_buffer_[2 * i] = vx[i];
    pair_buffer_[2 * i + 1] = vy[i];
  }
  extend_and_write(velocity_, 2, pairs, pair_buffer_.data());
  extend_and_write(angle_, 1, singles, angle ? angle : zeros_.data());
  extend_and_write(omega_, 1, singles, omega ? omega : zeros_.data());
  if (temperature_ >= 0) extend_and_write(temperature_, 1, singles, temperature);
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

std::vector<double> H5Frames::times() const {
  std::vector<double> t(frames_);
  if (frames_ == 0) return t;
  const hsize_t start[] = {0}, count[] = {static_cast<hsize_t>(frames_)};
  const hid_t file_space = h5_id(H5Dget_space(time_), "read the frame times of", path_);
  const hid_t mem_space = H5Screate_simple(1, count, nullptr);
  herr_t status = H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start, nullptr, count, nullptr);
  if (status >= 0) status = H5Dread(time_, H5T_NATIVE_DOUBLE, mem_space, file_space, H5P_DEFAULT, t.data());
  H5Sclose(mem_space);
  H5Sclose(file_space);
  h5_check(status, "read the frame times of", path_);
  return t;
}

void H5Frames::write_constant(const std::vector<double>& radius) {
  const hsize_t dims[] = {static_cast<hsize_t>(n_)};
  const hid_t space = h5_id(H5Screate_simple(1, dims, nullptr), "describe the radii in", path_);
  const hid_t r = H5Dcreate2(file_, "radius", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  herr_t status = r < 0 ? -1 : H5Dwrite(r, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, radius.data());
  if (r >= 0) H5Dclose(r);
  std::vector<long long> ids(n_);
  for (int i = 0; i < n_; ++i) ids[i] = i;
  const hid_t id = status < 0 ? -1 : H5Dcreate2(file_, "id", H5T_NATIVE_LLONG, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (id >= 0) status = H5Dwrite(id, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, ids.data());
  else status = -1;
  if (id >= 0) H5Dclose(id);
  H5Sclose(space);
  h5_check(status, "write the radii and ids to", path_);
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

void H5Frames::close() {
  if (file_ < 0) return;
  herr_t status = 0;
  for (hid_t* ds : {&time_, &position_, &velocity_, &angle_, &omega_, &temperature_}) {
    if (*ds >= 0 && H5Dclose(*ds) < 0) status = -1;
    *ds = -1;
  }
  if (H5Fclose(file_) < 0) status = -1;
  file_ = -1;
  h5_check(status, "finish writing", path_);
}

void H5Frames::abandon() {
  if (file_ < 0) return;
  for (hid_t* ds : {&time_, &position_, &velocity_, &angle_, &omega_, &temperature_}) {
    if (*ds >= 0) H5Dclose(*ds);
    *ds = -1;
  }
  H5Fclose(file_);
  file_ = -1;
  H5Eclear2(H5E_DEFAULT);
}

}  // namespace kiln
