#include "src/base/text_format.h"

#include <cstdio>

namespace kiln {

std::string vformat(const char* format, va_list args) {
  va_list again;
  va_copy(again, args);
  const int n = std::vsnprintf(nullptr, 0, format, args);
  std::string s(n > 0 ? n : 0, '\0');
  std::vsnprintf(s.data(), s.size() + 1, format, again);
  va_end(again);
  return s;
}

std::string format(const char* format, ...) {
  va_list args;
  va_start(args, format);
  std::string s = vformat(format, args);
  va_end(args);
  return s;
}

std::string bounded(const std::string& message, size_t longest_word, size_t longest) {
  const size_t end_kept = longest_word / 3;
  std::string out;
  size_t i = 0;
  while (i < message.size()) {
    const bool space = message[i] == ' ' || message[i] == '\n';
    size_t j = i;
    while (j < message.size() && (message[j] == ' ' || message[j] == '\n') == space) ++j;
    if (!space && j - i > longest_word)
      out += message.substr(i, end_kept) + "[... " + std::to_string(j - i - 2 * end_kept) + " characters ...]" +
             message.substr(j - end_kept, end_kept);
    else
      out.append(message, i, j - i);
    i = j;
  }
  if (out.size() > longest) out = out.substr(0, longest) + "[... " + std::to_string(out.size() - longest) + " more characters]";
  return out;
}

}  // namespace kiln
