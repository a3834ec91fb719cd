// printf into a std::string, for messages and tables of any length.
#pragma once
#include <cstdarg>
#include <string>

namespace kiln {

std::string format(const char* format, ...) __attribute__((format(printf, 1, 2)));
std::string vformat(const char* format, va_list args);

}  // namespace kiln
