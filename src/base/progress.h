// Progress of a long run on a terminal: one line rewritten at most twice a second, only when
// standard error is a terminal and --quiet was not given.
#pragma once
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

namespace kiln {

// Loading and checking fewer particles than this takes about a second: no line for them.
inline constexpr long progress_min_items = 1 << 17;

// --quiet: no progress line from anything in this process from now on (the command line's
// choice, which a scene's loading and checks deep below it must follow too).
void silence_progress();

class Progress {
 public:
  Progress(std::string label, bool quiet);
  ~Progress() { finish(); }  // an error thrown meanwhile starts on a line of its own
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  void update(double t, double t_end);           // a run: simulated time
  void update_runs(long done, long total);        // a study: finished simulations
  void update_items(long done, long total, const char* items);  // "done of total items"
  void next_stage() { start_ = std::chrono::steady_clock::now(); }  // times left from here on
  void finish();

 private:
  void show(double fraction, const std::string& what);
  std::string label_;
  bool enabled_;
  bool shown_ = false;
  std::chrono::steady_clock::time_point start_, last_;
};

// A stage that cannot report from inside (a library's tree built, an eigensolver): what is being
// done and the time elapsed, the line rewritten every half second by a thread of its own until
// the object is gone. Same conditions as Progress.
class PhaseProgress {
 public:
  PhaseProgress(std::string label, bool quiet);
  ~PhaseProgress();
  PhaseProgress(const PhaseProgress&) = delete;
  PhaseProgress& operator=(const PhaseProgress&) = delete;
  void phase(std::string what);

 private:
  void tick();
  std::string label_, what_;
  bool done_ = false, shown_ = false;
  std::chrono::steady_clock::time_point start_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::thread thread_;
};

}  // namespace kiln
