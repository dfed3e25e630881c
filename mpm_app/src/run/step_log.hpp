// The step log: the solver's events ("[step n, t=... s] <event>": a constraint released, ...)
// and the "time step: dt = ..." lines (progress.hpp, TimeStepLog) as they happen.
#pragma once

#include "progress.hpp"
#include "run/observer.hpp"

namespace mpmdem::mpm {

class StepLog : public Observer {
 public:
  void on_start(RunContext& run) override;
  void after_step(RunContext& run) override;

 private:
  static void print_events(RunContext& run);
  TimeStepLog dt_log_;
};

}  // namespace mpmdem::mpm
