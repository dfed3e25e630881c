// Checkpoints of the run (output/checkpoint.hpp for the layout, output/checkpoint_schedule.hpp
// for when): after a step, once every observer has seen it, the run asks due() and, if so,
// write(): the checkpoint's state is gathered from the run and from every observer
// (Observer::save), mpm_app writes mpm.h5, the provider saves the DEM side (dem/), and the
// checkpoint is committed (COMPLETE). A peer fault gets mpm_app's own state only
// (write_fault). Its figures: the checkpoints this process wrote and their wall time.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "output/checkpoint_schedule.hpp"
#include "run/observer.hpp"

namespace mpmdem::mpm {

class Checkpoints : public Observer {
 public:
  // `gather` returns the run's state for a checkpoint: the run's own part and every
  // observer's (save()).
  explicit Checkpoints(std::function<DriverState()> gather) : gather_(std::move(gather)) {}

  void restore(RunContext& run, const DriverState& d) override;
  // Starts the schedule: from now on checkpoints by step count and by wall time.
  void on_start(RunContext& run) override;
  void add_figures(RunContext& run, RunSummary& summary) override;

  // Whether a checkpoint is due after the step just taken (reads the wall clock once).
  bool due(RunContext& run) const;
  // Both sides save; the checkpoint counts once both are done (COMPLETE).
  void write(RunContext& run);
  // A peer fault (a DEM rank died, an MPI failure): mpm_app saves its own state, without
  // COMPLETE (the DEM side is lost, --resume never picks it). Returns the directory, or ""
  // if it could not be written.
  std::string write_fault(RunContext& run);
  // The run's wall time when its newest checkpoint was written (also before a resume).
  double newest_wall_time_s() const { return newest_wall_s_; }

 private:
  std::function<DriverState()> gather_;
  std::optional<CheckpointSchedule> schedule_;
  double newest_wall_s_ = 0.0;  // the run's wall time at its newest checkpoint
  std::int64_t written_ = 0;    // checkpoints written by this process
  double wall_s_ = 0.0;         // their wall time, both sides
};

}  // namespace mpmdem::mpm
