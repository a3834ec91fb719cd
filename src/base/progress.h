// Progress of a long run on a terminal: one line rewritten at most twice a second, only when
// standard error is a terminal and --quiet was not given.
#pragma once
#include <chrono>
#include <string>

namespace kiln {

class Progress {
 public:
  Progress(std::string label, bool quiet);
  ~Progress() { finish(); }  // an error thrown meanwhile starts on a line of its own
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  void update(double t, double t_end);           // a run: simulated time
  void update_runs(long done, long total);        // a study: finished simulations
  void update_items(long done, long total, const char* items);  // "done of total items"
  void finish();

 private:
  void show(double fraction, const std::string& what);
  std::string label_;
  bool enabled_;
  bool shown_ = false;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace kiln
