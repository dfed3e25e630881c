// The per-step outputs of a run (run_driver.cpp): energies.csv, timings.csv, the RVE cost
// logs and the VTK series, when each gets its next row or frame (output.energy_interval,
// output.interval), and when a checkpoint is due (output/checkpoint_schedule.hpp). The run
// driver steps the solver and calls after_step(); what is written when is decided here.
// The schedule is part of a checkpoint (save/resume), so a resumed run writes the same rows
// and frames as the uninterrupted one.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "output/checkpoint.hpp"
#include "output/checkpoint_schedule.hpp"
#include "output/energy_log.hpp"
#include "output/rve_cost_log.hpp"
#include "output/timing_log.hpp"
#include "output/vtk_writer.hpp"
#include "scene.hpp"
#include "solver.hpp"

namespace mpmdem::mpm {

class RunOutputs {
 public:
  RunOutputs(const Scene& scene, std::string dir);

  // A fresh run: new files, the energy row and the frame of t = 0.
  void start(const Solver& solver);
  // A resumed run: the files cut back to the checkpoint's step, the schedule from `d`.
  void resume(const Solver& solver, const DriverState& d);
  // From the first step on: checkpoints by step count and by wall time (now_s: wall clock).
  void start_checkpoints(double now_s);

  // After each step (dt: the step just taken): its timing row and RVE costs, then the energy
  // row and the frame when due.
  void after_step(Solver& solver, double dt);
  bool checkpoint_due(std::int64_t step, double now_s) const;
  void checkpoint_written(double now_s, double cost_s) { checkpoints_->written(now_s, cost_s); }

  void log_energy(const Solver& solver, double dt);
  void write_frame(const Solver& solver);
  bool frame_written_at(std::int64_t step) const { return last_frame_step_ == step; }
  // End of the run: the last energy row and frame, unless this step already has them.
  void final_rows(const Solver& solver, double dt);

  // The schedule into a checkpoint's state; flushes the buffered logs.
  void save(DriverState& d);
  // Flushes the logs; the per-phase time totals of timings.csv.
  std::vector<std::pair<std::string, double>> close();

 private:
  const Scene& scene_;
  std::string dir_;
  std::optional<EnergyLog> energy_;
  std::optional<TimingLog> timings_;
  std::optional<RveCostLog> rve_costs_;  // output.rve_costs, opened at the first step
  std::int64_t rve_costs_from_ = -1;     // a resumed run: the checkpoint's step
  std::vector<double> cost_s_;
  std::vector<int> cost_rank_;
  std::optional<VtkSeries> vtk_;
  std::optional<CheckpointSchedule> checkpoints_;
  double next_frame_ = 0.0;
  double next_energy_ = 0.0;
  std::int64_t last_energy_step_ = -1;
  std::int64_t last_frame_step_ = -1;
};

// Throws SimulationError naming the first non-finite value and the step: no state with one
// is written.
void require_finite(const Particles& p, std::int64_t step);

}  // namespace mpmdem::mpm
