#include "src/base/snapshot.h"

#include <hdf5.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <filesystem>

#include "src/base/error.h"
#include "src/base/h5_errors.h"

namespace kiln {

InputError Snapshot::layout_error(const std::string& source, const std::string& what) {
  return InputError((source.empty() ? "" : source + ": ") + "the checkpoint " + what +
                    ": it was written by a kiln whose state layout differs from this build's (a checkpoint "
                    "resumes only under the build that wrote it); rerun the scene from the start");
}

namespace {

template <class Map>
const typename Map::mapped_type& find(const Map& map, const std::string& key, const std::string& source) {
  const auto it = map.find(key);
  if (it == map.end())
    throw Snapshot::layout_error(source, "lacks '" + key + "'");
  return it->second;
}

void write_array(hid_t group, const std::string& key, hid_t type, const void* data, size_t n, const std::string& path) {
  const hsize_t dims[] = {static_cast<hsize_t>(n)};
  const hid_t space = H5Screate_simple(1, dims, nullptr);
  const hid_t ds = H5Dcreate2(group, key.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  herr_t status = ds < 0 ? -1 : n == 0 ? 0 : H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
  if (ds >= 0 && H5Dclose(ds) < 0) status = -1;
  H5Sclose(space);
  h5_check(status, ("write '" + key + "' to").c_str(), path);
}

// The checksum of a dataset: FNV-1a (64 bits) over its group, its key and its bytes. It proves
// what a checkpoint holds against damage and edits after it was written (four flipped bits, a
// coordinate times 1e200, a shortened array, another scene's text all resumed before).
uint64_t checksum(const char* group, const std::string& key, const void* data, size_t bytes) {
  uint64_t h = 1469598103934665603ull;
  auto mix = [&h](const unsigned char* p, size_t n) {
    for (size_t k = 0; k < n; ++k) h = (h ^ p[k]) * 1099511628211ull;
  };
  mix(reinterpret_cast<const unsigned char*>(group), std::strlen(group) + 1);
  mix(reinterpret_cast<const unsigned char*>(key.data()), key.size() + 1);
  mix(static_cast<const unsigned char*>(data), bytes);
  return h;
}

std::string checksum_hex(const char* group, const std::string& key, const void* data, size_t bytes) {
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(checksum(group, key, data, bytes)));
  return hex;
}

// The text dataset that holds every other dataset's checksum, a line "group<TAB>key<TAB>hex" each.
constexpr const char* checksums_key = "kiln.checksums";

// Calls read(name, dataset) for every dataset of a group.
template <class F>
void each_dataset(hid_t file, const char* group_name, const std::string& path, F read) {
  const hid_t group = h5_id(H5Gopen2(file, group_name, H5P_DEFAULT), "read the checkpoint", path);
  H5G_info_t info;
  h5_check(H5Gget_info(group, &info), "read the checkpoint", path);
  for (hsize_t k = 0; k < info.nlinks; ++k) {
    char name[1024];
    H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof name, H5P_DEFAULT);
    const std::string where = path + ": the checkpoint's '" + group_name + "/" + std::string(name).substr(0, 100) + "'";
    // What kiln never writes is bad input (exit 2), not an output failure: a group where a dataset
    // belongs, a dataset of another kind (variable-length strings), or one that declares more
    // values than it stores (a chunked 2^40-element dataset of 117 kB ended in bad_alloc).
    const hid_t object = H5Oopen(group, name, H5P_DEFAULT);
    const bool dataset = object >= 0 && H5Iget_type(object) == H5I_DATASET;
    if (object >= 0) H5Oclose(object);
    H5Eclear2(H5E_DEFAULT);
    if (!dataset) {
      H5Gclose(group);
      throw InputError(where + " is not a dataset");
    }
    const hid_t ds = h5_id(H5Dopen2(group, name, H5P_DEFAULT), "read the checkpoint", path);
    const hid_t type = H5Dget_type(ds);
    const H5T_class_t kind = H5Tget_class(type);
    const size_t bytes = std::strcmp(group_name, "text") == 0 ? 1 : 8;
    const bool fits = (std::strcmp(group_name, "real") == 0 ? kind == H5T_FLOAT : kind == H5T_INTEGER) &&
                      H5Tget_size(type) == bytes && !H5Tis_variable_str(type);
    H5Tclose(type);
    const hid_t space = H5Dget_space(ds);
    const hssize_t n = H5Sget_simple_extent_npoints(space);
    H5Sclose(space);
    const hsize_t stored = H5Dget_storage_size(ds);
    if (!fits || n < 0 || static_cast<hsize_t>(n) * bytes > stored) {
      H5Dclose(ds);
      H5Gclose(group);
      H5Eclear2(H5E_DEFAULT);
      throw InputError(where + (fits ? " declares " + std::to_string(n) + " values and stores " +
                                           std::to_string(stored) + " bytes"
                                     : " is not of the kind kiln writes there"));
    }
    read(std::string(name), ds, static_cast<size_t>(n));
    H5Dclose(ds);
  }
  H5Gclose(group);
}

}  // namespace

const std::vector<double>& Snapshot::reals(const std::string& key) const { return find(reals_, key, source_); }
const std::vector<long long>& Snapshot::integers(const std::string& key) const {
  return find(integers_, key, source_);
}
const std::string& Snapshot::text(const std::string& key) const { return find(texts_, key, source_); }

void Snapshot::write(const std::string& path) const {
  h5_setup();
  const std::string tmp = path + ".tmp";
  const hid_t file = h5_id(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), "create", tmp);
  try {
    auto group = [&](const char* name) {
      return h5_id(H5Gcreate2(file, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), "write", tmp);
    };
    const hid_t real = group("real"), integer = group("integer"), text = group("text");
    std::string sums;
    auto sum = [&sums](const char* g, const std::string& key, const void* data, size_t bytes) {
      sums += std::string(g) + "\t" + key + "\t" + checksum_hex(g, key, data, bytes) + "\n";
    };
    for (const auto& [key, v] : reals_) {
      write_array(real, key, H5T_NATIVE_DOUBLE, v.data(), v.size(), tmp);
      sum("real", key, v.data(), v.size() * sizeof(double));
    }
    for (const auto& [key, v] : integers_) {
      write_array(integer, key, H5T_NATIVE_LLONG, v.data(), v.size(), tmp);
      sum("integer", key, v.data(), v.size() * sizeof(long long));
    }
    for (const auto& [key, v] : texts_) {
      write_array(text, key, H5T_NATIVE_UCHAR, v.data(), v.size(), tmp);
      sum("text", key, v.data(), v.size());
    }
    write_array(text, checksums_key, H5T_NATIVE_UCHAR, sums.data(), sums.size(), tmp);
    for (hid_t g : {real, integer, text}) h5_check(H5Gclose(g), "write", tmp);
    h5_check(H5Fclose(file), "finish writing", tmp);
  } catch (...) {
    H5Fclose(file);
    H5Eclear2(H5E_DEFAULT);
    std::remove(tmp.c_str());
    throw;
  }
  std::error_code error;
  std::filesystem::rename(tmp, path, error);
  if (error) throw OutputError("cannot rename " + tmp + " to " + path + ": " + error.message());
}

Snapshot Snapshot::read(const std::string& path) {
  h5_setup();
  Snapshot s;
  s.source_ = path;
  if (H5Fis_hdf5(path.c_str()) <= 0) {
    H5Eclear2(H5E_DEFAULT);
    throw InputError(path + ": not a kiln checkpoint (not an HDF5 file, or not readable)");
  }
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0 || H5Lexists(file, "real", H5P_DEFAULT) <= 0 || H5Lexists(file, "text", H5P_DEFAULT) <= 0 ||
      H5Lexists(file, "integer", H5P_DEFAULT) <= 0) {
    if (file >= 0) H5Fclose(file);
    H5Eclear2(H5E_DEFAULT);
    throw InputError(path + ": not a kiln checkpoint (no real, integer and text groups)");
  }
  each_dataset(file, "real", path, [&](const std::string& key, hid_t ds, size_t n) {
    std::vector<double>& v = s.reals_[key];
    v.resize(n);
    if (n) h5_check(H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), "read", path);
  });
  each_dataset(file, "integer", path, [&](const std::string& key, hid_t ds, size_t n) {
    std::vector<long long>& v = s.integers_[key];
    v.resize(n);
    if (n) h5_check(H5Dread(ds, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), "read", path);
  });
  each_dataset(file, "text", path, [&](const std::string& key, hid_t ds, size_t n) {
    std::string& v = s.texts_[key];
    v.resize(n);
    if (n) h5_check(H5Dread(ds, H5T_NATIVE_UCHAR, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), "read", path);
  });
  H5Fclose(file);
  s.verify_checksums();
  return s;
}

void Snapshot::verify_checksums() {
  const auto listed = texts_.find(checksums_key);
  if (listed == texts_.end())
    throw InputError(source_ + ": the checkpoint holds no checksums (a kiln before checksums wrote it, or it was "
                               "cut): it cannot prove what it holds; rerun the scene from the start");
  std::map<std::pair<std::string, std::string>, std::string> sums;
  std::istringstream lines(listed->second);
  for (std::string line; std::getline(lines, line);) {
    const size_t a = line.find('\t'), b = line.rfind('\t');
    if (a == std::string::npos || b == a) throw InputError(source_ + ": the checkpoint's checksums are damaged");
    sums[{line.substr(0, a), line.substr(a + 1, b - a - 1)}] = line.substr(b + 1);
  }
  texts_.erase(listed);
  auto check = [&](const char* g, const std::string& key, const void* data, size_t bytes) {
    const auto it = sums.find({g, key});
    if (it == sums.end() || it->second != checksum_hex(g, key, data, bytes))
      throw InputError(source_ + ": dataset '" + g + "/" + key.substr(0, 100) + "' " +
                       (it == sums.end() ? "is not one the checkpoint was written with"
                                         : "does not match its checksum") +
                       ": the checkpoint was changed or damaged after it was written; restart from an intact "
                       "checkpoint or rerun the scene");
    sums.erase(it);
  };
  for (const auto& [key, v] : reals_) check("real", key, v.data(), v.size() * sizeof(double));
  for (const auto& [key, v] : integers_) check("integer", key, v.data(), v.size() * sizeof(long long));
  for (const auto& [key, v] : texts_) check("text", key, v.data(), v.size());
  if (!sums.empty())
    throw InputError(source_ + ": dataset '" + sums.begin()->first.first + "/" + sums.begin()->first.second.substr(0, 100) +
                     "' is missing: the checkpoint was changed or damaged after it was written; restart from an "
                     "intact checkpoint or rerun the scene");
}

}  // namespace kiln
