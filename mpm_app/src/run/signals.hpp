// The stop request of a run: SIGINT/SIGTERM (or request_stop(), run_driver.hpp) ask the run
// to stop after the current step (status "interrupted", run_status.hpp); a second signal
// stops the process at once.
#pragma once

#include <csignal>

namespace mpmdem::mpm {

bool stop_requested();
void clear_stop_request();

// SIGINT/SIGTERM ask the run to stop after the current step, for the guard's lifetime.
class SignalGuard {
 public:
  explicit SignalGuard(bool active);
  ~SignalGuard();
  SignalGuard(const SignalGuard&) = delete;
  SignalGuard& operator=(const SignalGuard&) = delete;

 private:
  bool active_;
  struct sigaction old_int_ {};
  struct sigaction old_term_ {};
};

}  // namespace mpmdem::mpm
