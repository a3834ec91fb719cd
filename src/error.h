// Errors a user can act on: every message names where the problem is (file, line, key).
#pragma once
#include <sstream>
#include <stdexcept>
#include <string>

namespace kiln {

struct Location {
  std::string file;  // scene file, or "--set" for a command-line override
  int line = 0;      // 1-based; 0 when unknown
  std::string key;   // dotted path of the offending key
};

inline std::string describe(const Location& at) {
  std::ostringstream s;
  s << at.file;
  if (at.line > 0) s << ':' << at.line;
  if (!at.key.empty()) s << ": key '" << at.key << "'";
  return s.str();
}

// A scene or argument that cannot be used. what() is the full message for the user.
class InputError : public std::runtime_error {
 public:
  InputError(const Location& at, const std::string& message)
      : std::runtime_error(describe(at) + ": " + message), location(at) {}
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
  Location location;
};

// A simulation that went unstable: the message says which check failed, when, and what dt to use.
class InstabilityError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace kiln
