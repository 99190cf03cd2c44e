#include "orchestrator/util/signals.hpp"

namespace demsa::util {

namespace {

// A signal handler can only reach a lock-free atomic of static storage.
volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void on_stop_signal(int signal) {
  g_stop_signal = signal;
  std::signal(signal, SIG_DFL);
}

}  // namespace

void StopFlag::install() {
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
}
bool StopFlag::raised() { return g_stop_signal != 0; }
int StopFlag::signal_number() { return static_cast<int>(g_stop_signal); }
void StopFlag::reset() { g_stop_signal = 0; }

}  // namespace demsa::util
