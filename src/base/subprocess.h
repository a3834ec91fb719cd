// Running another program (ffmpeg, Debian's Python) without a shell: the arguments go as they are,
// so a path with spaces or quotes needs no quoting and cannot be read as a command.
#pragma once
#include <string>
#include <vector>

namespace kiln {

struct ProgramResult {
  int status = -1;     // its exit status, 128 + the signal that ended it, or -1: it could not start
  std::string errors;  // what it wrote to standard error
};
// Runs argv[0] (a path) with standard input from /dev/null, standard output discarded and
// standard error captured, and waits for it.
ProgramResult run_program(const std::vector<std::string>& argv);

// The path of the executable `name` in a directory of PATH (the standard /bin:/usr/bin when PATH is
// unset, as the shell does), or "" when there is none.
std::string find_program(const std::string& name);

}  // namespace kiln
