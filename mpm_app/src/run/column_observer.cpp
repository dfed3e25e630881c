#include "run/column_observer.hpp"

#include <filesystem>
#include <ostream>
#include <string>

#include "output/hdf5_writer.hpp"
#include "output/run_outputs.hpp"

namespace mpmdem::mpm {

void ColumnCollapseObserver::restore(RunContext& run, const DriverState& d) {
  (void)run;
  column_.restore(d.column);
}

bool ColumnCollapseObserver::ends_run(const RunContext& run) const {
  return column_.done(run.solver.time());
}

void ColumnCollapseObserver::save(DriverState& d) {
  d.column = column_.state();
}

// Stage 2's start, the deposit at rest, the snapshots due at this time.
void ColumnCollapseObserver::observe(RunContext& run) {
  const Solver& solver = run.solver;
  const double t = solver.time();
  if (column_.observe(t, solver.boundary_conditions(), solver.particles())) {
    run.event() << "stage 2 (collapse) starts: stage 1 took " << t
                << " s; t* = " << column_.geometry().t_star
                << " s, the run ends at t = " << column_.end_time() << " s"
                << (column_.at_rest() ? " or earlier, once the deposit is at rest" : "")
                << std::endl;
  }
  if (column_.observe_rest(t, solver.particles())) {
    const AtRestDetector& r = *column_.at_rest();
    run.event() << "the deposit is at rest: E_k/E_p0 < " << r.kinetic_ratio()
                << " since t/t* = " << *r.quiet_since() / column_.geometry().t_star
                << "; stage 2 ends at t/t* = " << column_.time_over_t_star(t) << std::endl;
  }
  for (const std::string& label : column_.due_snapshots(t, 1e-6 * run.dt)) {
    require_finite(solver.particles(), solver.step_count());
    std::filesystem::create_directories(run.dir + "/snapshots");
    write_final_state(run.dir + "/snapshots/" + label + ".h5", solver.particles(),
                      {t, solver.step_count(), run.scene.name, run.scene.source_file});
    run.frame_wanted = true;  // the outputs write this step's frame (output/run_outputs.hpp)
    run.event() << "snapshot " << label << " (t/t* = " << column_.time_over_t_star(t) << ")"
                << std::endl;
  }
}

void ColumnCollapseObserver::add_figures(RunContext& run, RunSummary& summary) {
  const double t = run.solver.time();
  for (const auto& kv : column_.figures(t, run.solver.particles())) summary.analysis.push_back(kv);
  // A complete run that the column ended says why ("duration", "at_rest").
  const std::string why = column_.end_reason(t);
  if (!why.empty() && summary.stop_reason == "end_time") summary.stop_reason = why;
  summary.stop = column_.stop_figures(summary.time_s, summary.steps);
}

}  // namespace mpmdem::mpm
