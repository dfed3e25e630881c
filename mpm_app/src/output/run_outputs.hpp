// The outputs of a run, an observer of its time loop (run/observer.hpp): energies.csv,
// timings.csv, the RVE cost logs and the VTK series, when each gets its next row or frame
// (output.energy_interval, output.interval; a frame also when another observer asks for
// one, RunContext::frame_wanted), and at the end the last row and frame and final_state.h5.
// The schedule is part of a checkpoint (save/restore), so a resumed run writes the same rows
// and frames as the uninterrupted one. Its figures: the per-phase time totals of timings.csv.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "output/checkpoint.hpp"
#include "output/energy_log.hpp"
#include "output/rve_cost_log.hpp"
#include "output/timing_log.hpp"
#include "output/vtk_writer.hpp"
#include "run/observer.hpp"
#include "scene.hpp"
#include "solver.hpp"

namespace mpmdem::mpm {

class RunOutputs : public Observer {
 public:
  RunOutputs(const Scene& scene, std::string dir);

  // A resumed run: the files cut back to the checkpoint's step, the schedule from `d`.
  void restore(RunContext& run, const DriverState& d) override;
  // A fresh run: new files, the energy row and the frame of t = 0.
  void on_start(RunContext& run) override;
  // After each step: its timing row and RVE costs, then the energy row and the frame when
  // due (or wanted).
  void after_step(RunContext& run) override;
  // End of the run: the last energy row and frame, unless this step already has them, and
  // final_state.h5 (output.hdf5).
  void on_end(RunContext& run) override;
  // The schedule into a checkpoint's state; flushes the buffered logs.
  void save(DriverState& d) override;
  // Flushes the logs; the per-phase time totals of timings.csv.
  void add_figures(RunContext& run, RunSummary& summary) override;

  void log_energy(const Solver& solver, double dt);
  void write_frame(const Solver& solver);
  bool frame_written_at(std::int64_t step) const { return last_frame_step_ == step; }

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
  double next_frame_ = 0.0;
  double next_energy_ = 0.0;
  std::int64_t last_energy_step_ = -1;
  std::int64_t last_frame_step_ = -1;
};

// Throws SimulationError naming the first non-finite value and the step: no state with one
// is written.
void require_finite(const Particles& p, std::int64_t step);

}  // namespace mpmdem::mpm
