// Verification case bar_vibration (verification/bar_vibration.hpp): the bar's axial momentum
// after every step, and at the end of a complete run the period against 4 L / c in
// summary.json's "verification". A fault of the monitor is a warning, not a failed run: the
// figures are then absent.
#pragma once

#include <optional>

#include "run/observer.hpp"
#include "verification/bar_vibration.hpp"

namespace mpmdem::mpm {

class BarVibrationObserver : public Observer {
 public:
  void on_start(RunContext& run) override;
  void after_step(RunContext& run) override;
  void add_figures(RunContext& run, RunSummary& summary) override;

 private:
  std::optional<BarVibrationMonitor> bar_;
};

}  // namespace mpmdem::mpm
