// printf into a std::string, for messages and tables of any length.
#pragma once
#include <cstdarg>
#include <string>

namespace kiln {

std::string format(const char* format, ...) __attribute__((format(printf, 1, 2)));
std::string vformat(const char* format, va_list args);

// A message as printed: every word (a run without spaces: a path, a value quoted back) longer than
// `longest_word` characters keeps its ends and says how much was left out, and the whole is cut
// at `longest` characters. A message quotes what it was given, and a 100 kB path or value must
// not become a 100 kB line (issue 28).
std::string bounded(const std::string& message, size_t longest_word = 240, size_t longest = 4000);

}  // namespace kiln
