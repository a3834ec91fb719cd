// kiln's figures (kiln plot's plots.png, a study's NAME.png) are drawn by Python scripts with
// Debian's /usr/bin/python3 and matplotlib: scripts/plot_case.py and scripts/plot_study.py. Both
// end the way scripts/kiln_figure.py makes them: exit 0 with the figure written, or one line on
// standard error and one of kiln's exit codes (README "Exit codes"): 2 bad input, 4 the figure could
// not be written (no room, no permission, matplotlib missing), 6 a defect of the script's. Here
// every command reads that outcome the same way. Issue 28's campaign: kiln order printed a Python
// traceback, blamed matplotlib and exited 0 when the disk was full or a fitted order was null.
#pragma once
#include <stdexcept>
#include <string>
#include <vector>

namespace kiln {

// A figure not drawn: what() is its one line (without "error: "), `status` kiln's exit code.
class FigureError : public std::runtime_error {
 public:
  FigureError(int exit_status, const std::string& message) : std::runtime_error(message), status(exit_status) {}
  int status;
};

// Runs scripts/`script` with `arguments` to draw `figure`, passing its warnings on to standard
// error. Throws FigureError when the figure was not drawn: with the script's own line, or for a
// script that could not start or ended otherwise (a signal, a traceback it let out) a line made
// here from the last line it wrote; never its traceback.
void draw_figure(const std::string& script, const std::vector<std::string>& arguments, const std::string& figure);

}  // namespace kiln
