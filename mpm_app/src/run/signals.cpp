#include "run/signals.hpp"

#include "run_driver.hpp"

namespace mpmdem::mpm {

namespace {

volatile std::sig_atomic_t g_stop = 0;

extern "C" void on_stop_signal(int sig) {
  if (g_stop) {  // second signal: stop at once
    std::signal(sig, SIG_DFL);
    std::raise(sig);
    return;
  }
  g_stop = 1;
}

}  // namespace

bool stop_requested() {
  return g_stop != 0;
}

void clear_stop_request() {
  g_stop = 0;
}

void request_stop() {
  g_stop = 1;
}

SignalGuard::SignalGuard(bool active) : active_(active) {
  if (!active_) return;
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, &old_int_);
  sigaction(SIGTERM, &sa, &old_term_);
}

SignalGuard::~SignalGuard() {
  if (!active_) return;
  sigaction(SIGINT, &old_int_, nullptr);
  sigaction(SIGTERM, &old_term_, nullptr);
}

}  // namespace mpmdem::mpm
