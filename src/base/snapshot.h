// A snapshot: named arrays of reals, integers and texts, written to and read from one HDF5 file
// (the checkpoint of a run, checkpoint.h5). Each part of a run saves what it needs to go on bit
// for bit (its state, not its configuration) under keys of its own, and reads them back, both
// through one list of its fields (SnapshotFields).
// The file: groups /real (float64 arrays), /integer (int64 arrays), /text (bytes), one dataset per key.
#pragma once
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "src/base/error.h"
#include "src/base/text_format.h"

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
  // One value: an array of another length is refused by name.
  double real(const std::string& key) const { return one(reals(key), key); }
  const std::vector<long long>& integers(const std::string& key) const;
  long long integer(const std::string& key) const { return one(integers(key), key); }
  // One whole number that a T holds, in [lo, hi] (a frame count is an int and not negative): a
  // stored int64 is narrowed only after this check, so a damaged count (1e15 frames) is refused by
  // name instead of wrapping to a negative one.
  template <class T>
  T integer_as(const std::string& key, T lo = std::numeric_limits<T>::min(), T hi = std::numeric_limits<T>::max()) const {
    return narrowed<T>(integer(key), key, lo, hi);
  }
  // A value stored under `key` as the T a reader keeps it in, checked as above.
  template <class T>
  T narrowed(long long v, const std::string& key, T lo = std::numeric_limits<T>::min(),
             T hi = std::numeric_limits<T>::max()) const {
    bool held;
    if constexpr (std::is_same_v<T, bool>)
      held = v == 0 || v == 1;
    else
      held = std::in_range<T>(v) && static_cast<T>(v) >= lo && static_cast<T>(v) <= hi;
    if (!held)
      throw layout_error(source_, "holds " + std::to_string(v) + " in '" + key + "' where a whole number in [" +
                                      std::to_string(lo) + ", " + std::to_string(hi) + "] belongs");
    return static_cast<T>(v);
  }
  template <class T>
  void get_integers(const std::string& key, std::vector<T>& out) const {
    const std::vector<long long>& v = integers(key);
    out.resize(v.size());
    for (size_t i = 0; i < v.size(); ++i)
      out[i] = narrowed<T>(v[i], key);
  }
  const std::string& text(const std::string& key) const;
  // The keys of the real arrays, in order.
  std::vector<std::string> real_keys() const {
    std::vector<std::string> keys;
    for (const auto& entry : reals_) keys.push_back(entry.first);
    return keys;
  }
  std::vector<std::string> integer_keys() const {
    std::vector<std::string> keys;
    for (const auto& entry : integers_) keys.push_back(entry.first);
    return keys;
  }
  std::vector<std::string> text_keys() const {
    std::vector<std::string> keys;
    for (const auto& entry : texts_) keys.push_back(entry.first);
    return keys;
  }
  bool has(const std::string& key) const {
    return reals_.count(key) || integers_.count(key) || texts_.count(key);
  }
  const std::string& source() const { return source_; }
  // A checkpoint whose fields are not this build's: `what` it lacks or holds, the file, the advice.
  static InputError layout_error(const std::string& source, const std::string& what);

  // Written under path + ".tmp" and renamed: a run killed while writing keeps its previous
  // checkpoint. Throws OutputError naming the file.
  void write(const std::string& path) const;
  // Throws InputError when the file is not a kiln snapshot, or when a dataset does not match the
  // checksum written with it (or is missing, or was added): nothing of a changed or damaged
  // checkpoint is used.
  static Snapshot read(const std::string& path);

 private:
  template <class V>
  typename V::value_type one(const V& v, const std::string& key) const {
    if (v.size() != 1)
      throw layout_error(source_, "holds " + std::to_string(v.size()) + " values in '" + key + "' where 1 belongs");
    return v[0];
  }
  void verify_checksums();
  std::string source_;  // the file it was read from, for messages
  std::map<std::string, std::vector<double>> reals_;
  std::map<std::string, std::vector<long long>> integers_;
  std::map<std::string, std::string> texts_;
};

// What a part of a run carries from step to step, listed once for both directions: a visit
// writes each field to a snapshot (saving) or reads it back (restoring). A part's
// `state(SnapshotFields&)` is its checkpoint.
class SnapshotFields {
 public:
  SnapshotFields(Snapshot& out, std::string prefix) : out_(&out), prefix_(std::move(prefix)) {}
  SnapshotFields(const Snapshot& in, std::string prefix) : in_(&in), prefix_(std::move(prefix)) {}
  bool saving() const { return out_ != nullptr; }
  std::string source() const { return in_ ? in_->source() : std::string(); }  // the file read, for messages
  // The same snapshot, keys under prefix + `more`.
  SnapshotFields within(const std::string& more) const {
    return out_ ? SnapshotFields(*out_, prefix_ + more) : SnapshotFields(*in_, prefix_ + more);
  }

  void field(const std::string& key, double& v) {
    if (out_) out_->put(prefix_ + key, v);
    else v = in_->real(prefix_ + key);
  }
  void field(const std::string& key, std::vector<double>& v) {
    if (out_) out_->put(prefix_ + key, v);
    else v = in_->reals(prefix_ + key);
  }
  void field(const std::string& key, std::string& v) {
    if (out_) out_->put_text(prefix_ + key, v);
    else v = in_->text(prefix_ + key);
  }
  // A JSON document (statistics), as its text; one that does not parse is refused by name.
  void field(const std::string& key, nlohmann::json& v) {
    std::string text = out_ ? v.dump() : std::string();
    field(key, text);
    if (out_) return;
    v = nlohmann::json::parse(text, nullptr, false);
    if (v.is_discarded()) throw Snapshot::layout_error(in_->source(), "holds no JSON document in '" + prefix_ + key + "'");
  }
  void field(const std::string& key, bool& v) {
    long long i = v;
    integers(key, i);
    v = i != 0;
  }
  template <class T>
  void field(const std::string& key, T& v) requires std::is_integral_v<T> {
    integers(key, v);
  }
  template <class T>
  void field(const std::string& key, std::vector<T>& v) requires std::is_integral_v<T> {
    if (out_) out_->put_integers(prefix_ + key, v);
    else in_->get_integers(prefix_ + key, v);
  }
  // An array of a length the reader knows (one value per particle, per contact): read with any
  // other is refused by name, before anything indexes it.
  template <class T>
  void field(const std::string& key, std::vector<T>& v, std::initializer_list<size_t> lengths) {
    field(key, v);
    if (out_ || std::find(lengths.begin(), lengths.end(), v.size()) != lengths.end()) return;
    std::string allowed;
    for (size_t n : lengths) allowed += (allowed.empty() ? "" : " or ") + std::to_string(n);
    throw Snapshot::layout_error(in_->source(), "holds " + std::to_string(v.size()) + " values in '" + prefix_ + key +
                                                    "' where " + allowed + " belong");
  }
  // A real read into a T: a count kept among reals must be a whole number T holds (converting NaN
  // or 1e300 to an integer is undefined).
  template <class T>
  T real_as(double x, const std::string& key) const {
    if constexpr (std::is_integral_v<T>) {
      if (!(x >= static_cast<double>(std::numeric_limits<T>::min()) &&
            x < std::ldexp(1.0, std::numeric_limits<T>::digits) && x == std::floor(x)))
        throw Snapshot::layout_error(in_->source(), "holds " + format("%g", x) + " in '" + prefix_ + key +
                                                        "' where a whole number belongs");
    }
    return static_cast<T>(x);
  }
  // Several scalars in one array under one key, in this order.
  template <class... T>
  void reals(const std::string& key, T&... v) {
    if (out_) return out_->put(prefix_ + key, std::vector<double>{static_cast<double>(v)...});
    const std::vector<double>& got = sized(in_->reals(prefix_ + key), sizeof...(T), key);
    size_t k = 0;
    ((v = real_as<T>(got[k++], key)), ...);
  }
  template <class... T>
  void integers(const std::string& key, T&... v) {
    if (out_) return out_->put_integers(prefix_ + key, std::vector<long long>{static_cast<long long>(v)...});
    const std::vector<long long>& got = sized(in_->integers(prefix_ + key), sizeof...(T), key);
    size_t k = 0;
    ((v = in_->narrowed<T>(got[k++], prefix_ + key)), ...);
  }

 private:
  // A packed array of another length is another kiln's (or a damaged) checkpoint: refused by name.
  template <class V>
  const V& sized(const V& got, size_t n, const std::string& key) const {
    if (got.size() != n)
      throw Snapshot::layout_error(in_->source(), "holds " + std::to_string(got.size()) + " values in '" + prefix_ +
                                                      key + "' where " + std::to_string(n) + " belong");
    return got;
  }
  Snapshot* out_ = nullptr;
  const Snapshot* in_ = nullptr;
  std::string prefix_;
};

}  // namespace kiln
