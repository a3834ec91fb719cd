// Progress lines go to a terminal and nowhere else, and --quiet silences them all: standard error
// is pointed at a pseudo-terminal, which stands in for the user's.
#include <catch2/catch.hpp>
#include <fcntl.h>
#include <pty.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>

#include "src/base/progress.h"

using namespace kiln;

namespace {

// Standard error on a new pseudo-terminal until read_back, which returns what was written to it.
class StderrOnTerminal {
 public:
  StderrOnTerminal() {
    int terminal = -1;
    REQUIRE(openpty(&master_, &terminal, nullptr, nullptr, nullptr) == 0);
    saved_ = dup(STDERR_FILENO);
    dup2(terminal, STDERR_FILENO);
    close(terminal);
  }
  ~StderrOnTerminal() { restore(); }
  std::string read_back() {
    restore();
    fcntl(master_, F_SETFL, O_NONBLOCK);
    std::string text;
    char buffer[4096];
    for (ssize_t n; (n = read(master_, buffer, sizeof buffer)) > 0;) text.append(buffer, static_cast<size_t>(n));
    return text;
  }

 private:
  void restore() {
    if (saved_ < 0) return;
    dup2(saved_, STDERR_FILENO);
    close(saved_);
    saved_ = -1;
  }
  int master_ = -1, saved_ = -1;
};

}  // namespace

TEST_CASE("a stage that cannot report from inside shows what it does and the time elapsed on a terminal") {
  StderrOnTerminal terminal;
  {
    PhaseProgress progress("estimating the stability limit", false);
    progress.phase("the contacts at t = 0");
    std::this_thread::sleep_for(std::chrono::milliseconds(1300));  // two or three ticks of half a second
  }
  const std::string text = terminal.read_back();
  CHECK(text.find("estimating the stability limit: the contacts at t = 0, 1 s elapsed") != std::string::npos);
  REQUIRE(!text.empty());
  CHECK(text.back() == '\n');  // what is printed next starts on a line of its own
}

TEST_CASE("a stage shows nothing when asked to be quiet or shorter than half a second") {
  StderrOnTerminal terminal;
  {
    PhaseProgress quiet("a quiet stage", true);
    std::this_thread::sleep_for(std::chrono::milliseconds(700));
  }
  { PhaseProgress short_stage("a short stage", false); }
  CHECK(terminal.read_back().empty());
}

TEST_CASE("a process told to be quiet (--quiet) shows no progress line, a scene's checks included") {
  StderrOnTerminal terminal;
  silence_progress();
  {
    Progress counted("checking the start's overlaps", false);
    PhaseProgress stage("estimating the stability limit", false);
    std::this_thread::sleep_for(std::chrono::milliseconds(700));
    counted.update_items(1, 2, "discs");
  }
  CHECK(terminal.read_back().empty());
}
