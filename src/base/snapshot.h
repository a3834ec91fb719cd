// A snapshot: named arrays of reals, integers and texts, written to and read from one HDF5 file
// (the checkpoint of a run, checkpoint.h5). Each part of a run saves what it needs to go on bit
// for bit (its state, not its configuration) under keys of its own, and reads them back.
// The file: groups /real (float64 arrays), /integer (int64 arrays), /text (bytes), one dataset per key.
#pragma once
#include <map>
#include <string>
#include <vector>

namespace kiln {

class Snapshot {
 public:
  void put(const std::string& key, double v) { reals_[key] = {v}; }
  void put(const std::string& key, const std::vector<double>& v) { reals_[key] = v; }
  void put_integer(const std::string& key, long long v) { integers_[key] = {v}; }
  template <class T>
  void put_integers(const std::string& key, const std::vector<T>& v) {
    integers_[key].assign(v.begin(), v.end());
  }
  void put_text(const std::string& key, const std::string& v) { texts_[key] = v; }

  // Each throws InputError naming the file and the key when the snapshot lacks it.
  const std::vector<double>& reals(const std::string& key) const;
  double real(const std::string& key) const { return reals(key).at(0); }
  const std::vector<long long>& integers(const std::string& key) const;
  long long integer(const std::string& key) const { return integers(key).at(0); }
  template <class T>
  void get_integers(const std::string& key, std::vector<T>& out) const {
    const std::vector<long long>& v = integers(key);
    out.assign(v.begin(), v.end());
  }
  const std::string& text(const std::string& key) const;
  bool has(const std::string& key) const {
    return reals_.count(key) || integers_.count(key) || texts_.count(key);
  }

  // Written under path + ".tmp" and renamed: a run killed while writing keeps its previous
  // checkpoint. Throws OutputError naming the file.
  void write(const std::string& path) const;
  // Throws InputError when the file is not a kiln snapshot.
  static Snapshot read(const std::string& path);

 private:
  std::string source_;  // the file it was read from, for messages
  std::map<std::string, std::vector<double>> reals_;
  std::map<std::string, std::vector<long long>> integers_;
  std::map<std::string, std::string> texts_;
};

}  // namespace kiln
