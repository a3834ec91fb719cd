// Files written whole or not at all: a reader never sees a half-written file under a final name.
#pragma once
#include <string>

namespace kiln {

// Writes `text` to path, every write checked: a full disk is an OutputError naming the file,
// and the partial file is removed.
void write_file(const std::string& path, const std::string& text);
// The same via path + ".tmp" and a rename, so no half-written file is left under `path`.
void write_file_atomically(const std::string& path, const std::string& text);
// Makes `dir` (and its parents) and checks that a file can be written there, before any work
// that ends in writing it: InputError naming the option and the reason (a study into a read-only
// directory ran all its runs, then exited 6).
void require_writable_directory(const std::string& dir, const std::string& option);
// Renames a finished temporary file to its final name (OutputError naming both on failure).
void publish(const std::string& tmp, const std::string& path);

}  // namespace kiln
