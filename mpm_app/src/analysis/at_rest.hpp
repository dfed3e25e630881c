// The at-rest stop of a column collapse (column_collapse.at_rest): stage 2 ends once the
// deposit is at rest, i.e. E_k / E_p0 stayed below `kinetic_ratio` for `hold_time` of
// simulated time without a break, and not before `earliest_time`. E_p0 is the potential energy
// at the release measured from the base (the one Ed_over_Ep0_final divides by).
//
// The quiet window starts at the first step below the threshold and is reset by any step at or
// above it, so a transient dip (the column right after its release, a deposit that slows down
// and speeds up again) never stops the run unless it lasts the whole hold time. Times are
// measured from the release (stage-2 time); the caller converts from t*.
//
// State for checkpoints: the start of the current quiet window and the stop time; a resumed
// run restores both and stops at exactly the step the uninterrupted run stops at.
#pragma once

#include <optional>

namespace mpmdem::mpm {

class AtRestDetector {
 public:
  // kinetic_ratio > 0, hold_time >= 0, earliest_time >= 0 [s of stage 2].
  AtRestDetector(double kinetic_ratio, double hold_time, double earliest_time);

  // After each stage-2 step: the stage-2 time and E_k / E_p0 at it. Returns true once the
  // deposit is at rest (and from then on).
  bool update(double time, double ratio);

  bool at_rest() const { return at_rest_time_.has_value(); }
  // Stage-2 time at which the hold was complete.
  std::optional<double> at_rest_time() const { return at_rest_time_; }
  // Start of the current quiet window (E_k / E_p0 below the threshold since then).
  std::optional<double> quiet_since() const { return quiet_since_; }

  double kinetic_ratio() const { return kinetic_ratio_; }
  double hold_time() const { return hold_time_; }
  double earliest_time() const { return earliest_time_; }

  void restore(std::optional<double> quiet_since, std::optional<double> at_rest_time);

 private:
  double kinetic_ratio_;
  double hold_time_;
  double earliest_time_;
  std::optional<double> quiet_since_;
  std::optional<double> at_rest_time_;
};

}  // namespace mpmdem::mpm
