// Wall time for what kiln reports of its own cost (a run's seconds, its estimate's, a benchmark's).
#pragma once
#include <chrono>

namespace kiln {

// Seconds of wall time since `start` (steady_clock: never set back while a run goes on).
inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace kiln
