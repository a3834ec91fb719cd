#include "src/output/result_reader.h"

#include "src/base/error.h"
#include "src/base/h5_errors.h"

namespace kiln {

namespace {

// An HDF5 identifier closed when it goes out of scope (whatever throws between).
struct Handle {
  hid_t id;
  herr_t (*close)(hid_t);
  ~Handle() {
    if (id >= 0) close(id);
  }
};

std::vector<Vec2> points(const std::vector<double>& triples) {
  std::vector<Vec2> p(triples.size() / 3);
  for (size_t i = 0; i < p.size(); ++i) p[i] = {triples[3 * i], triples[3 * i + 1]};
  return p;
}

void segments(const std::vector<double>& rows, std::vector<Vec2>& a, std::vector<Vec2>& b) {
  a.resize(rows.size() / 4);
  b.resize(rows.size() / 4);
  for (size_t s = 0; s < a.size(); ++s) {
    a[s] = {rows[4 * s], rows[4 * s + 1]};
    b[s] = {rows[4 * s + 2], rows[4 * s + 3]};
  }
}

}  // namespace

ResultReader::ResultReader(const std::string& path) : path_(path) {
  h5_setup();
  // The checks' messages say "cannot <do what> <file>": reading a result, that is bad input.
  try {
    file_ = h5_id(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "open", path_);
    times_ = values("time", -1);
    radius_ = values("radius", -1);
    thermal_ = H5Lexists(file_, "temperature", H5P_DEFAULT) > 0;
    if (H5Lexists(file_, "wall_segments", H5P_DEFAULT) > 0) {
      const Handle ds{h5_id(H5Dopen2(file_, "wall_segments", H5P_DEFAULT), "open 'wall_segments' of", path_), H5Dclose};
      const Handle space{h5_id(H5Dget_space(ds.id), "read 'wall_segments' of", path_), H5Sclose};
      walls_move_ = H5Sget_simple_extent_ndims(space.id) == 3;  // F x S x 4, else S x 4
      if (!walls_move_) fixed_segments_ = values("wall_segments", -1);
    }
  } catch (const OutputError& e) {
    if (file_ >= 0) H5Fclose(file_);
    throw InputError(e.what());
  }
}

ResultReader::~ResultReader() {
  if (file_ >= 0) H5Fclose(file_);
}

std::vector<double> ResultReader::values(const char* name, int frame) const {
  const std::string what = std::string("read dataset '") + name + "' of";
  const Handle ds{h5_id(H5Dopen2(file_, name, H5P_DEFAULT), what.c_str(), path_), H5Dclose};
  const Handle file_space{h5_id(H5Dget_space(ds.id), what.c_str(), path_), H5Sclose};
  hsize_t dims[3] = {0, 0, 0}, start[3] = {0, 0, 0};
  const int rank = H5Sget_simple_extent_ndims(file_space.id);
  if (rank < 1 || rank > 3) h5_check(-1, what.c_str(), path_);
  h5_check(H5Sget_simple_extent_dims(file_space.id, dims, nullptr), what.c_str(), path_);
  if (frame >= 0) {  // one slab of the first dimension
    start[0] = static_cast<hsize_t>(frame);
    dims[0] = 1;
    h5_check(H5Sselect_hyperslab(file_space.id, H5S_SELECT_SET, start, nullptr, dims, nullptr), what.c_str(), path_);
  }
  const Handle mem_space{h5_id(H5Screate_simple(rank, dims, nullptr), what.c_str(), path_), H5Sclose};
  std::vector<double> v(static_cast<size_t>(H5Sget_simple_extent_npoints(mem_space.id)));
  h5_check(H5Dread(ds.id, H5T_NATIVE_DOUBLE, mem_space.id, file_space.id, H5P_DEFAULT, v.data()), what.c_str(), path_);
  return v;
}

void ResultReader::read(int frame, Frame& f) const {
  try {
    f.position = points(values("position", frame));
    f.velocity = points(values("velocity", frame));
    if (thermal_) f.temperature = values("temperature", frame);
    segments(walls_move_ ? values("wall_segments", frame) : fixed_segments_, f.wall_a, f.wall_b);
  } catch (const OutputError& e) {
    throw InputError(std::string(e.what()) + " (frame " + std::to_string(frame) + ")");
  }
}

}  // namespace kiln
