#include "signorini/core/interrupt.hpp"

#include <csignal>

namespace signorini {

namespace {
volatile std::sig_atomic_t g_signal = 0;

extern "C" void on_signal(int s) { g_signal = s; }
}  // namespace

void install_interrupt_handlers() {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
}

int interrupt_signal() { return g_signal; }

void set_interrupt(int signal) { g_signal = signal; }

}  // namespace signorini
