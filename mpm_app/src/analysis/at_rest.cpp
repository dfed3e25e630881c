#include "analysis/at_rest.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace mpmdem::mpm {

AtRestDetector::AtRestDetector(double kinetic_ratio, double hold_time, double earliest_time)
    : kinetic_ratio_(kinetic_ratio), hold_time_(hold_time), earliest_time_(earliest_time) {
  assert(kinetic_ratio > 0.0 && hold_time >= 0.0 && earliest_time >= 0.0);
}

bool AtRestDetector::update(double time, double ratio) {
  if (at_rest_time_) return true;
  // A non-finite ratio (no potential energy to compare with) is never "at rest".
  if (!(std::isfinite(ratio) && ratio < kinetic_ratio_)) {
    quiet_since_.reset();
    return false;
  }
  if (!quiet_since_) quiet_since_ = time;
  // The same relative tolerance as the stage-2 end (ColumnCollapseMonitor::done): a hold that
  // ends on a step boundary up to rounding counts as complete.
  const double eps = 1e-12 * std::max(1.0, std::abs(time));
  if (time >= earliest_time_ - eps && time - *quiet_since_ >= hold_time_ - eps) {
    at_rest_time_ = time;
  }
  return at_rest_time_.has_value();
}

void AtRestDetector::restore(std::optional<double> quiet_since,
                             std::optional<double> at_rest_time) {
  quiet_since_ = quiet_since;
  at_rest_time_ = at_rest_time;
}

}  // namespace mpmdem::mpm
