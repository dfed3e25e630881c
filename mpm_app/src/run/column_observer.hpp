// The granular column collapse on the time loop (analysis/column_collapse.hpp): the start of
// stage 2 and the at-rest detection as events, the snapshots at t_r + k t*
// (snapshots/<label>.h5 and a VTK frame), the end of the run once stage 2 is over, its
// monitor's state in checkpoints, and the column's figures and "stop" in summary.json.
#pragma once

#include "analysis/column_collapse.hpp"
#include "run/observer.hpp"

namespace mpmdem::mpm {

class ColumnCollapseObserver : public Observer {
 public:
  explicit ColumnCollapseObserver(const Scene& scene) : column_(scene) {}

  void restore(RunContext& run, const DriverState& d) override;
  void on_start(RunContext& run) override { observe(run); }
  void after_step(RunContext& run) override { observe(run); }
  bool ends_run(const RunContext& run) const override;
  double end_time() const override { return column_.end_time(); }
  void save(DriverState& d) override;
  void add_figures(RunContext& run, RunSummary& summary) override;

 private:
  void observe(RunContext& run);
  ColumnCollapseMonitor column_;
};

}  // namespace mpmdem::mpm
