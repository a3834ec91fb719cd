// SIGINT and SIGTERM ask a run to stop where it is: the handler only records the signal, and the
// run, between two steps, writes its frame, its summary and a checkpoint, then exits 130 or 143.
// A second signal of either kind, a second or more after the first, ends the process at once (its
// default action), so a run that does not stop can still be killed; one within the second is the
// same request (GNU timeout signals the process, then its group).
#pragma once

namespace kiln {

// Installs the handlers (kiln run). Without them (studies, tests) the signals keep their defaults.
void catch_stop_signals();
// The signal received since, or 0.
int stop_signal();
// "SIGINT" or "SIGTERM".
const char* signal_name(int signal);

}  // namespace kiln
