#include "src/base/figure_script.h"

#include <cstdio>
#include <sstream>

#include "src/base/error.h"
#include "src/base/subprocess.h"

namespace kiln {

namespace {

constexpr const char* python = "/usr/bin/python3";

}  // namespace

void draw_figure(const std::string& script, const std::vector<std::string>& arguments, const std::string& figure) {
  std::vector<std::string> argv = {python, std::string(KILN_SCRIPTS_DIR) + "/" + script};
  argv.insert(argv.end(), arguments.begin(), arguments.end());
  const ProgramResult r = run_program(argv);
  // Its warnings are passed on as they are; of the rest, only the last line is kept (a traceback's
  // last line is the exception).
  std::istringstream lines(r.errors);
  std::string last;
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("warning: ", 0) == 0)
      std::fprintf(stderr, "%s\n", line.c_str());
    else if (line.find_first_not_of(" \t\r") != std::string::npos)
      last = line;
  }
  if (r.status == 0) return;
  const std::string said = last.rfind("error: ", 0) == 0 ? last.substr(7) : last;
  if (r.status == exit_bad_input || r.status == exit_output_failed || r.status == exit_internal)
    throw FigureError(r.status, said.empty() ? figure + " not written" : said);
  if (r.status < 0)
    throw FigureError(exit_output_failed, "cannot draw " + figure + ": " + (said.empty() ? python : said) +
                                              " (it needs Debian's /usr/bin/python3 with matplotlib: apt-get "
                                              "install python3-matplotlib)");
  throw FigureError(exit_internal, "cannot draw " + figure + ": " + script + " ended with status " +
                                       std::to_string(r.status) + (said.empty() ? "" : ": " + said) +
                                       " (a defect of kiln's figure scripts; please report it)");
}

}  // namespace kiln
