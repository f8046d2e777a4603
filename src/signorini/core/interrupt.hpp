// SIGINT / SIGTERM during a run: the handler only records the signal; the analysis checks it
// between Newton iterations, stops there with the last converged increment as its state, and
// the results writer records `status: interrupted` (README, "Exit codes").
#pragma once

namespace signorini {

// Installs the handler for SIGINT and SIGTERM (the command line's `run` does this).
void install_interrupt_handlers();
// The signal received since the start (or the last set_interrupt(0)), 0 if none.
int interrupt_signal();
// As if `signal` had been received (tests), or 0 to forget a received one.
void set_interrupt(int signal);

}  // namespace signorini
