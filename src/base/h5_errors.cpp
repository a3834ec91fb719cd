#include "src/base/h5_errors.h"

#include <mutex>

#include "src/base/error.h"

namespace kiln {

void h5_setup() {
  static std::once_flag once;
  std::call_once(once, [] {
    H5dont_atexit();
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  });
}

namespace {

// The deepest entry of the error stack says what failed at the bottom; the outer ones only repeat
// which API call it was in. A failed system call's entry ("file write failed: time = ..., errno =
// 28, error message = 'No space left on device', buf = ...") is cut to the system's reason.
herr_t deepest(unsigned n, const H5E_error2_t* e, void* out) {
  if (n != 0 || !e->desc) return 0;
  std::string desc = e->desc;
  const std::string mark = "error message = '";
  const size_t at = desc.find(mark);
  if (at != std::string::npos) {
    const size_t from = at + mark.size();
    desc = desc.substr(0, desc.find(':')) + ": " + desc.substr(from, desc.find('\'', from) - from);
  }
  *static_cast<std::string*>(out) = desc.substr(0, desc.find('\n'));
  return 0;
}

[[noreturn]] void fail(const char* what, const std::string& file) {
  std::string reason;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, deepest, &reason);
  H5Eclear2(H5E_DEFAULT);
  std::string message = std::string("cannot ") + what + " " + file;
  if (!reason.empty()) message += ": " + reason;
  throw OutputError(message);
}
}  // namespace

herr_t h5_check(herr_t status, const char* what, const std::string& file) {
  if (status < 0) fail(what, file);
  return status;
}

hid_t h5_id(hid_t id, const char* what, const std::string& file) {
  if (id < 0) fail(what, file);
  return id;
}

}  // namespace kiln
