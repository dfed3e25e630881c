// Checkpoints of a run, so that `mpm_app SCENE --resume DIR` (scripts/run --resume RUN)
// continues it and ends in the same state as an uninterrupted run.
//
// Layout: RUN/checkpoints/step_<NNNNNNNNN>/
//   mpm.h5     the solver state (every particle field at full precision, provider slots,
//              time, step, time steps, E_p0, constraint flags) and the run driver's state
//              (next frame/energy times, VTK frame times, column-collapse stage and at-rest
//              timer, timing sums)
//   dem/       the DEM servers' RVE states (remote model: kCheckpoint; rank_<r>/...)
//   COMPLETE   written last, once both sides have saved: a checkpoint without it is ignored
// Only the newest `output.checkpoints_kept` complete checkpoints are kept.
// RUN/checkpoints/fault_step_<NNNNNNNNN>/mpm.h5: mpm_app's own state when a peer fault (a
// DEM rank died) ended the run after step N; never COMPLETE, never resumed from (docs/outputs.md).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "analysis/column_state.hpp"
#include "solver.hpp"

namespace mpmdem::mpm {

// What a run needs besides the solver to continue exactly: the run's own part (timing sums,
// wall time, time-step range, initial mass, provider state) and each observer's part
// (run/observer.hpp: Observer::save / restore). The file format is fixed here, so an
// observer's part is a field of this struct.
struct DriverState {
  // The outputs (output/run_outputs.hpp): their schedule.
  double next_frame = 0.0;
  double next_energy = 0.0;
  std::vector<double> frame_times;  // VTK frames written so far (frame_<k>.vtu)
  std::int64_t last_frame_step = -1;
  std::int64_t last_energy_step = -1;
  // The column collapse (run/column_observer.hpp): stage, snapshots, at-rest timer.
  ColumnState column;
  std::int64_t rve_particles = 0;  // the model (run/model_observer.hpp)
  // The run's own.
  double step_wall_time_s = 0.0, step_cpu_time_s = 0.0, wall_time_s = 0.0;
  double dt_min_s = 0.0, dt_max_s = 0.0, mass_initial_kg = 0.0;
  std::vector<double> provider_state;  // ConstitutiveProvider::save_state() (may be empty)
};

std::string checkpoint_directory(const std::string& run_dir, std::int64_t step);
std::string fault_checkpoint_directory(const std::string& run_dir, std::int64_t step);
// Writes dir/mpm.h5 (through a temporary name). Throws std::runtime_error.
void write_mpm_checkpoint(const std::string& dir, const SolverState& s, const DriverState& d);
// Marks dir complete (both sides saved) and removes all but the newest `keep` complete
// checkpoints (and any incomplete older ones) of the run.
void commit_checkpoint(const std::string& run_dir, const std::string& dir, int keep);
// The newest complete checkpoint of a run directory, or "" if there is none.
std::string latest_checkpoint(const std::string& run_dir);
// Reads dir/mpm.h5. Throws std::runtime_error naming the file if it is missing or broken.
void read_mpm_checkpoint(const std::string& dir, SolverState& s, DriverState& d);

}  // namespace mpmdem::mpm
