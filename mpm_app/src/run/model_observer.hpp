// The constitutive model's part of the run: the number of RVE particles (which a resumed run
// takes from the checkpoint: the DEM servers do not report it again), and the model's
// counters in summary.json (remote: RVE spheres, DEM ranks, rebalances, evaluations, skips,
// no-contact updates; a local model: its own figures, constitutive/model_registry.hpp).
#pragma once

#include <cstdint>
#include <optional>

#include "run/observer.hpp"

namespace mpmdem::mpm {

class ModelObserver : public Observer {
 public:
  explicit ModelObserver(Solver& solver) : solver_(solver) {}

  void restore(RunContext& run, const DriverState& d) override;
  void save(DriverState& d) override;
  void add_figures(RunContext& run, RunSummary& summary) override;

  // The RVE particles of the run's DEM side (0 for a local model).
  std::int64_t rve_particles() const;

 private:
  Solver& solver_;
  std::optional<std::int64_t> resumed_rve_particles_;
};

}  // namespace mpmdem::mpm
