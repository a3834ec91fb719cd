#include "src/progress.h"

#include <unistd.h>

#include <cstdio>

namespace kiln {

Progress::Progress(std::string label, bool quiet)
    : label_(std::move(label)), enabled_(!quiet && isatty(STDERR_FILENO)) {
  start_ = last_ = std::chrono::steady_clock::now();
}

void Progress::update(double t, double t_end) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_ < std::chrono::milliseconds(500)) return;
  last_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double done = t / t_end;
  const double eta = done > 0 ? elapsed * (1 - done) / done : 0;
  std::fprintf(stderr, "\r%s: t = %.4g s of %.4g s (%3.0f%%), %.0f s elapsed, about %.0f s left   ", label_.c_str(), t,
               t_end, 100 * done, elapsed, eta);
  shown_ = true;
}

void Progress::finish() {
  if (shown_) std::fprintf(stderr, "\n");
  shown_ = false;
}

}  // namespace kiln
