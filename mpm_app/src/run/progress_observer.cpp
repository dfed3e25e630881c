#include "run/progress_observer.hpp"

namespace mpmdem::mpm {

void ProgressObserver::on_start(RunContext& run) {
  progress_.emplace(run.out, run.scene.output.progress_interval_s);
  progress_->start(run.solver.time());
}

void ProgressObserver::after_step(RunContext& run) {
  if (progress_->due()) progress_->update(state(run));
}

void ProgressObserver::on_end(RunContext& run) {
  progress_->print(state(run));
}

ProgressState ProgressObserver::state(const RunContext& run) {
  const Solver& s = run.solver;
  return {s.step_count(), s.time(),         run.end_time(),
          run.dt,         s.energies().E_k, s.initial_potential_energy()};
}

}  // namespace mpmdem::mpm
