#include "output/checkpoint_schedule.hpp"

#include <algorithm>

namespace mpmdem::mpm {

CheckpointSchedule::CheckpointSchedule(std::int64_t every_steps, double interval_s, double now_s)
    : every_steps_(every_steps), interval_s_(interval_s), last_s_(now_s) {}

bool CheckpointSchedule::due(std::int64_t step, double now_s) const {
  if (every_steps_ > 0 && step % every_steps_ == 0) return true;
  return interval_s_ > 0.0 && now_s - last_s_ >= gap_s();
}

double CheckpointSchedule::gap_s() const {
  return std::max(interval_s_, (1.0 / kMaxCost - 1.0) * cost_s_);
}

}  // namespace mpmdem::mpm
