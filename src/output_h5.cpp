#include "src/output_h5.h"

#include <stdexcept>

namespace kiln {

namespace {
void check(herr_t status, const char* what) {
  if (status < 0) throw std::runtime_error(std::string("HDF5 failed to ") + what);
}
}  // namespace

H5Frames::H5Frames(const std::string& path, int particles, bool thermal) : n_(particles) {
  file_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (file_ < 0) throw std::runtime_error("cannot create " + path);
  const hsize_t scalar[] = {1};
  const hsize_t pairs[] = {static_cast<hsize_t>(n_), 2};
  const hsize_t singles[] = {static_cast<hsize_t>(n_)};
  time_ = create("time", 0, scalar);
  position_ = create("position", 2, pairs);
  velocity_ = create("velocity", 2, pairs);
  angle_ = create("angle", 1, singles);
  omega_ = create("angular_velocity", 1, singles);
  if (thermal) temperature_ = create("temperature", 1, singles);
  pair_buffer_.resize(2 * n_);
  zeros_.assign(n_, 0.0);
}

H5Frames::~H5Frames() { close(); }

// A dataset of frames: rank+1 dimensions, the first unlimited, one frame per chunk.
hid_t H5Frames::create(const char* name, int rank, const hsize_t* frame_dims) {
  hsize_t dims[3] = {0, 0, 0}, maxdims[3] = {H5S_UNLIMITED, 0, 0}, chunk[3] = {1, 1, 1};
  for (int k = 0; k < rank; ++k) dims[k + 1] = maxdims[k + 1] = chunk[k + 1] = frame_dims[k];
  const hid_t space = H5Screate_simple(rank + 1, dims, maxdims);
  const hid_t props = H5Pcreate(H5P_DATASET_CREATE);
  check(H5Pset_chunk(props, rank + 1, chunk), "set a chunk size");
  const hid_t ds = H5Dcreate2(file_, name, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, props, H5P_DEFAULT);
  H5Pclose(props);
  H5Sclose(space);
  if (ds < 0) throw std::runtime_error(std::string("cannot create dataset ") + name);
  return ds;
}

void H5Frames::extend_and_write(hid_t ds, int rank, const hsize_t* frame_dims, const double* data) {
  hsize_t size[3] = {static_cast<hsize_t>(frames_ + 1), 0, 0}, start[3] = {static_cast<hsize_t>(frames_), 0, 0},
          count[3] = {1, 0, 0};
  for (int k = 0; k < rank; ++k) size[k + 1] = count[k + 1] = frame_dims[k];
  check(H5Dset_extent(ds, size), "extend a dataset");
  const hid_t file_space = H5Dget_space(ds);
  check(H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start, nullptr, count, nullptr), "select a frame");
  const hid_t mem_space = H5Screate_simple(rank + 1, count, nullptr);
  check(H5Dwrite(ds, H5T_NATIVE_DOUBLE, mem_space, file_space, H5P_DEFAULT, data), "write a frame");
  H5Sclose(mem_space);
  H5Sclose(file_space);
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
  ++frames_;
}

void H5Frames::write_constant(const std::vector<double>& radius) {
  const hsize_t dims[] = {static_cast<hsize_t>(n_)};
  const hid_t space = H5Screate_simple(1, dims, nullptr);
  const hid_t r = H5Dcreate2(file_, "radius", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  check(H5Dwrite(r, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, radius.data()), "write radius");
  H5Dclose(r);
  std::vector<long long> ids(n_);
  for (int i = 0; i < n_; ++i) ids[i] = i;
  const hid_t id = H5Dcreate2(file_, "id", H5T_NATIVE_LLONG, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  check(H5Dwrite(id, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, ids.data()), "write id");
  H5Dclose(id);
  H5Sclose(space);
}

void H5Frames::attribute(const std::string& name, const std::string& value) {
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, value.size() + 1);
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attr = H5Acreate2(file_, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
  check(H5Awrite(attr, type, value.c_str()), "write an attribute");
  H5Aclose(attr);
  H5Sclose(space);
  H5Tclose(type);
}

void H5Frames::attribute(const std::string& name, double value) {
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attr = H5Acreate2(file_, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT);
  check(H5Awrite(attr, H5T_NATIVE_DOUBLE, &value), "write an attribute");
  H5Aclose(attr);
  H5Sclose(space);
}

void H5Frames::close() {
  if (file_ < 0) return;
  for (hid_t ds : {time_, position_, velocity_, angle_, omega_, temperature_})
    if (ds >= 0) H5Dclose(ds);
  H5Fclose(file_);
  file_ = -1;
}

}  // namespace kiln
