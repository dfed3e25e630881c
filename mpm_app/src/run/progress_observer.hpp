// The progress lines of a run (progress.hpp): at most one per output.progress_interval_s of
// wall time after a step, and one at the end.
#pragma once

#include <optional>

#include "progress.hpp"
#include "run/observer.hpp"

namespace mpmdem::mpm {

class ProgressObserver : public Observer {
 public:
  void on_start(RunContext& run) override;
  void after_step(RunContext& run) override;
  void on_end(RunContext& run) override;

 private:
  static ProgressState state(const RunContext& run);
  std::optional<Progress> progress_;
};

}  // namespace mpmdem::mpm
