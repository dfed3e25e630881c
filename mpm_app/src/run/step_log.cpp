#include "run/step_log.hpp"

#include <ostream>
#include <string>

namespace mpmdem::mpm {

void StepLog::on_start(RunContext& run) {
  print_events(run);
}

void StepLog::after_step(RunContext& run) {
  const std::string line = dt_log_.line(run.dt, run.solver.step_count(), run.solver.time());
  if (!line.empty()) run.out << line << std::endl;
  print_events(run);
}

void StepLog::print_events(RunContext& run) {
  for (const std::string& e : run.solver.take_events()) run.event() << e << std::endl;
}

}  // namespace mpmdem::mpm
