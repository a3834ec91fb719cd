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

// A key path of up to 64 keys of 100 characters would make a message of kilobytes: a long one
// keeps its first 60 and last 100 characters (the innermost keys, which the line points at).
inline std::string shortened_key(const std::string& key) {
  constexpr size_t head = 60, tail = 100;
  if (key.size() <= head + tail + 5) return key;
  return key.substr(0, head) + " ... " + key.substr(key.size() - tail);
}

inline std::string describe(const Location& at) {
  std::ostringstream s;
  s << at.file;
  if (at.line > 0) s << ':' << at.line;
  if (!at.key.empty()) s << ": key '" << shortened_key(at.key) << "'";
  return s.str();
}

// A number for a message, in as few digits as the stream writes it (1e-07, 0.002).
inline std::string message_number(double v) {
  std::ostringstream s;
  s << v;
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

// An output that could not be written (a full disk, no permission): names the file and the cause.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A study in which every run failed: nothing to report (its files, showing the failures, are written).
class StudyError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The exit status of every kiln command (README "Exit codes"); main() maps each error to one.
enum ExitCode {
  exit_success = 0,
  exit_refused = 1,       // dt beyond the estimated stability limit or the step-count limit (--force runs it)
  exit_bad_input = 2,     // a scene, a checkpoint or an argument that cannot be used
  exit_unstable = 3,      // a run stopped by a stability check
  exit_output_failed = 4, // an output could not be written; nothing was published under a final name
  exit_study_failed = 5,  // a study in which every run failed: no figure to report
  exit_internal = 6,      // anything else: a defect of kiln's, please report it
  exit_sigint = 130,      // stopped by SIGINT (128 + 2): outputs and a checkpoint written where it stopped
  exit_sigterm = 143      // stopped by SIGTERM (128 + 15): likewise
};

// A simulation that went unstable: the message says which check failed, when, and what dt to use.
class InstabilityError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace kiln
