// The run is a time loop over observers (run_driver.cpp):
//
//   set up -> on_start -> for each step { solver.step(); after_step; checkpoint if due }
//          -> on_end -> summary.json (the run's figures, then add_figures of each)
//
// Everything a run does around the solver's steps is an observer with its own file: the
// step log (step_log.hpp), the outputs (output/run_outputs.hpp: energies, timings, RVE costs,
// VTK frames, final state), the checkpoints (checkpoints.hpp), the progress lines
// (progress_observer.hpp), the column collapse (column_observer.hpp) and each verification
// case (bar_vibration_observer.hpp, elastic_column_observer.hpp), and the constitutive
// model's counters (model_observer.hpp). The loop calls them in the order they were made
// (make_observers in run_driver.cpp) and never names a case. That order is also the order of
// their figures in summary.json; an observer that asks for a frame (frame_wanted) comes
// before the outputs. A checkpoint is written after every observer has seen the step.
//
// Each observer keeps its own part of a checkpoint (save() into, restore() from the
// checkpoint's DriverState, output/checkpoint.hpp) and adds its own figures to summary.json.
#pragma once

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "output/checkpoint.hpp"
#include "output/summary_json.hpp"
#include "run_status.hpp"
#include "scene.hpp"
#include "solver.hpp"

namespace mpmdem::mpm {

// What the observers see of a run. The run fills it; observers read the solver, never step it.
struct RunContext {
  const Scene& scene;
  const std::string& dir;  // the run directory
  Solver& solver;
  std::ostream& out;  // progress and events
  std::ostream& err;  // warnings
  // The run's wall time [s], also counting the time before a resume (RunOptions::clock).
  std::function<double()> wall_time;
  // The simulated time at which the run will end, as far as known now.
  std::function<double()> end_time;
  double dt = 0.0;  // the step just taken (0 before the first)
  RunStatus status = RunStatus::kComplete;
  bool resumed = false;       // the run continues from a checkpoint
  bool frame_wanted = false;  // an observer asks for a VTK frame of this step
  // Starts an event line: "[step <n>, t=<t> s] ".
  std::ostream& event() const;
};

class Observer {
 public:
  virtual ~Observer() = default;

  // A resumed run: its part of the checkpoint the run continues from (before on_start).
  virtual void restore(RunContext& run, const DriverState& d) {
    (void)run;
    (void)d;
  }
  // Before the first step this process runs (a fresh run: at t = 0).
  virtual void on_start(RunContext& run) { (void)run; }
  // After every step.
  virtual void after_step(RunContext& run) { (void)run; }
  // True if the run should end now (the column collapse's stage 2 is over).
  virtual bool ends_run(const RunContext& run) const {
    (void)run;
    return false;
  }
  // The simulated time at which it will end the run (infinity: it does not end it).
  virtual double end_time() const { return std::numeric_limits<double>::infinity(); }
  // After the last step of a run that did not fail: the last rows, frames and lines.
  virtual void on_end(RunContext& run) { (void)run; }
  // Its part of a checkpoint (and of a fault checkpoint).
  virtual void save(DriverState& d) { (void)d; }
  // Its figures for summary.json (also of a failed run); the observers add theirs in order.
  virtual void add_figures(RunContext& run, RunSummary& summary) {
    (void)run;
    (void)summary;
  }
};

using Observers = std::vector<std::unique_ptr<Observer>>;

}  // namespace mpmdem::mpm
