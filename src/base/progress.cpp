#include "src/base/progress.h"

#include <unistd.h>

#include <atomic>
#include <cstdio>

namespace kiln {

namespace {
std::atomic<bool> silenced{false};
bool shows(bool quiet) { return !quiet && !silenced && isatty(STDERR_FILENO); }
}  // namespace

void silence_progress() { silenced = true; }

Progress::Progress(std::string label, bool quiet) : label_(std::move(label)), enabled_(shows(quiet)) {
  start_ = last_ = std::chrono::steady_clock::now();
}

void Progress::update(double t, double t_end) {
  if (!enabled_) return;
  char what[96];
  std::snprintf(what, sizeof what, "t = %.4g s of %.4g s", t, t_end);
  show(t / t_end, what);
}

void Progress::update_runs(long done, long total) { update_items(done, total, "runs"); }

void Progress::update_items(long done, long total, const char* items) {
  if (!enabled_) return;
  show(static_cast<double>(done) / total, std::to_string(done) + " of " + std::to_string(total) + " " + items);
}

void Progress::show(double done, const std::string& what) {
  const auto now = std::chrono::steady_clock::now();
  if (now - last_ < std::chrono::milliseconds(500)) return;
  last_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  char left[48] = "";
  if (done > 0) std::snprintf(left, sizeof left, ", about %.0f s left", elapsed * (1 - done) / done);
  std::fprintf(stderr, "\r%s: %s (%3.0f%%), %.0f s elapsed%s   ", label_.c_str(), what.c_str(), 100 * done, elapsed,
               left);
  shown_ = true;
}

void Progress::finish() {
  if (shown_) std::fprintf(stderr, "\n");
  shown_ = false;
}

PhaseProgress::PhaseProgress(std::string label, bool quiet)
    : label_(std::move(label)), start_(std::chrono::steady_clock::now()) {
  if (shows(quiet)) thread_ = std::thread([this] { tick(); });
}

PhaseProgress::~PhaseProgress() {
  if (!thread_.joinable()) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    done_ = true;
  }
  wake_.notify_one();
  thread_.join();
  if (shown_) std::fprintf(stderr, "\n");  // an error thrown meanwhile starts on a line of its own
}

void PhaseProgress::phase(std::string what) {
  std::lock_guard<std::mutex> lock(mutex_);
  what_ = std::move(what);
}

void PhaseProgress::tick() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (!wake_.wait_for(lock, std::chrono::milliseconds(500), [this] { return done_; })) {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    std::fprintf(stderr, "\r%s: %s, %.0f s elapsed   ", label_.c_str(), what_.c_str(), elapsed);
    shown_ = true;
  }
}

}  // namespace kiln
