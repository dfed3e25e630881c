// When the run driver writes a checkpoint (output/checkpoint.hpp): after a step, if
//   - the step count is a multiple of output.checkpoint_interval_steps (> 0), or
//   - output.checkpoint_interval_s (> 0) of wall time have passed since the last checkpoint
//     (or since the run started or resumed), and at least (1/kMaxCost - 1) times the wall
//     time the last checkpoint took: time-triggered checkpoints then cost at most kMaxCost
//     (2 %) of the run's wall time, on any machine and under any load (the last cost
//     estimates the next one).
// Either trigger restarts the wall-time count, so the two combine as "whichever comes first".
// Only mpm_app reads the clock: it decides after step n and tells the DEM servers to save
// step n through the protocol (kCheckpoint), so both sides always checkpoint the same step
// even though the step a time trigger picks differs from run to run. A checkpoint changes
// no arithmetic of the run (tests CheckpointSchedule.*, checkpoint_time_*).
#pragma once

#include <cstdint>

namespace mpmdem::mpm {

class CheckpointSchedule {
 public:
  // every_steps <= 0 and interval_s <= 0 turn the respective trigger off. `now_s` is the
  // wall time (any monotonic origin) at which the run started or resumed.
  CheckpointSchedule(std::int64_t every_steps, double interval_s, double now_s);
  // Whether a checkpoint is due after step `step`, at wall time `now_s`.
  bool due(std::int64_t step, double now_s) const;
  // A checkpoint that took `cost_s` of wall time was written; the wall-time trigger counts
  // from `now_s` (the end of writing it).
  void written(double now_s, double cost_s) {
    last_s_ = now_s;
    cost_s_ = cost_s;
  }
  bool enabled() const { return every_steps_ > 0 || interval_s_ > 0.0; }
  // Wall time from the last checkpoint to the next time-triggered one.
  double gap_s() const;

  static constexpr double kMaxCost = 0.02;  // share of the wall time

 private:
  std::int64_t every_steps_;
  double interval_s_;
  double last_s_;
  double cost_s_ = 0.0;
};

}  // namespace mpmdem::mpm
