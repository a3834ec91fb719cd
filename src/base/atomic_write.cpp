// Files are written under a temporary name and renamed when complete: a reader never sees a
// half-written file under a final name.
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "src/base/error.h"
#include "src/base/atomic_write.h"

namespace kiln {

void write_file(const std::string& tmp, const std::string& text) {
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw OutputError("cannot create " + tmp + ": " + std::strerror(errno));
  const bool written = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  const int write_error = errno;
  // fclose flushes: on a full disk the error may only appear here.
  const bool closed = std::fclose(f) == 0;
  if (!written || !closed) {
    const int error = !written ? write_error : errno;
    std::remove(tmp.c_str());
    throw OutputError("cannot write " + tmp + ": " + std::strerror(error));
  }
}

void write_file_atomically(const std::string& path, const std::string& text) {
  write_file(path + ".tmp", text);
  publish(path + ".tmp", path);
}

void publish(const std::string& tmp, const std::string& path) {
  std::error_code error;
  std::filesystem::rename(tmp, path, error);
  if (error) {
    std::remove(tmp.c_str());
    throw OutputError("cannot rename " + tmp + " to " + path + ": " + error.message());
  }
}

void require_writable_directory(const std::string& dir, const std::string& option) {
  // Nothing is created here (a study that fails later writes nothing): the nearest part of the
  // path that exists must be a directory that takes a file.
  namespace fs = std::filesystem;
  std::error_code error;
  fs::path existing = fs::absolute(dir, error);
  while (!existing.empty() && !fs::exists(existing, error) && existing.has_parent_path() && existing != existing.parent_path())
    existing = existing.parent_path();
  std::string why;
  if (!fs::is_directory(existing, error)) {
    why = std::strerror(ENOTDIR);
  } else {
    const std::string probe = (existing / (".kiln-writable-" + std::to_string(::getpid()))).string();
    std::FILE* f = std::fopen(probe.c_str(), "w");
    if (!f) why = std::strerror(errno);
    else {
      std::fclose(f);
      std::remove(probe.c_str());
    }
  }
  if (!why.empty())
    throw InputError(option + " " + dir + ": cannot write there (" + why + "): give a directory you may write into");
}

}  // namespace kiln
