#include "src/base/stop_signal.h"

#include <csignal>

namespace kiln {

namespace {
volatile std::sig_atomic_t received = 0;
extern "C" void record(int signal) {
  received = signal;
  std::signal(SIGINT, SIG_DFL);  // async-signal-safe: the next signal of either kind ends the process
  std::signal(SIGTERM, SIG_DFL);
}
}  // namespace

void catch_stop_signals() {
  struct sigaction action = {};
  action.sa_handler = record;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

int stop_signal() { return received; }
const char* signal_name(int signal) { return signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "a signal"; }

}  // namespace kiln
