#include "run/checkpoints.hpp"

#include <exception>
#include <ostream>

#include "output/run_outputs.hpp"
#include "run_support.hpp"

namespace mpmdem::mpm {

void Checkpoints::restore(RunContext& run, const DriverState& d) {
  (void)run;
  newest_wall_s_ = d.wall_time_s;
}

void Checkpoints::on_start(RunContext& run) {
  const OutputParams& o = run.scene.output;
  schedule_.emplace(o.checkpoint_interval_steps, o.checkpoint_interval_s, run.wall_time());
}

bool Checkpoints::due(RunContext& run) const {
  return schedule_ && schedule_->due(run.solver.step_count(), run.wall_time());
}

void Checkpoints::write(RunContext& run) {
  Solver& solver = run.solver;
  require_finite(solver.particles(), solver.step_count());
  const double start = run.wall_time();
  const std::string dir = checkpoint_directory(run.dir, solver.step_count());
  const DriverState state = gather_();
  write_mpm_checkpoint(dir, solver.state(), state);
  solver.provider().checkpoint(dir + "/dem", solver.step_count());
  commit_checkpoint(run.dir, dir, run.scene.output.checkpoints_kept);
  newest_wall_s_ = state.wall_time_s;
  const double took = run.wall_time() - start;
  wall_s_ += took;
  ++written_;
  run.event() << "checkpoint " << dir << " (" << run_support::format_seconds(took) << " s)"
              << std::endl;
  schedule_->written(run.wall_time(), took);
}

std::string Checkpoints::write_fault(RunContext& run) {
  const std::string dir = fault_checkpoint_directory(run.dir, run.solver.step_count());
  try {
    write_mpm_checkpoint(dir, run.solver.state(), gather_());
    return dir;
  } catch (const std::exception& e) {
    run.err << "warning: writing the fault checkpoint " << dir << " failed: " << e.what()
            << std::endl;
    return "";
  }
}

void Checkpoints::add_figures(RunContext& run, RunSummary& summary) {
  (void)run;
  if (written_ == 0) return;  // this process's part of the run (a resumed one: since resuming)
  summary.analysis.emplace_back("checkpoints", static_cast<double>(written_));
  summary.analysis.emplace_back("checkpoint_wall_time_s", wall_s_);
}

}  // namespace mpmdem::mpm
