// summary.json: the headline figures of a run (also of a failed or interrupted one).
//   status             "complete" | "failed" | "interrupted"
//   error              what stopped a failed run (absent otherwise)
//   scene, config_file, run_directory, model, program_version
//   wall_time_s, steps, n_material_points, removed_points, threads
//   step_wall_time_s   wall time inside the solver's steps only (no set-up, no output)
//   ns_per_point_step  step_wall_time_s / (steps * n_material_points) in ns
//   step_cpu_time_s    CPU time of all threads inside the steps (a busy machine inflates
//                      the wall time but not this)
//   time_s, end_time_s, dt_min_s, dt_max_s
//   mass_initial_kg, mass_final_kg, E_p0_J, E_p_J, E_k_J, E_d_J, E_d_over_E_p0
//   stop               {"reason": ..., <figures>}: why the time loop ended: "end_time"
//                      (solver.end_time), "duration" (column_collapse.duration_t_star),
//                      "at_rest" (column_collapse.at_rest), "max_steps", "interrupted", "failed";
//                      with column_collapse.at_rest also at_rest (1/0), time_s, step,
//                      time_over_t_star, quiet_since_t_star, kinetic_ratio, hold_t_star,
//                      min_t_star
//   energy_budget      the energy released since t = 0, released_J = E_p0 + E_k0 - E_p - E_k,
//                      split as in energy_budget.hpp: W_int_J (stress work: for RVEs the work
//                      the MPM did on them, for a local law the stored and plastic work),
//                      W_bc_J (walls and velocity constraints, e.g. the base), W_damp_J (local
//                      damping) and the residual E_err_J (transfers and time integration),
//                      E_err_J split into E_err_transfer_J (the kinetic energy the
//                      particle-grid transfers remove, W_transfer in energy_budget.hpp; of
//                      it E_err_transfer_walls_J at the walls, W_transfer_walls) and
//                      E_err_other_J (time integration, instabilities); each also as a
//                      share of released_J (*_share)
//   verification       {"kind": ..., <error figures of that kind>} (absent for kind none)
//   peer_fault         (a run that failed because DEM ranks died or stopped answering)
//                      {"kind": "died" | "no_reply", "step": the last step completed,
//                      "ranks": [...], "hosts": [...] (one per rank), "exact": whether
//                      those ranks are exactly the silent ones (false after a stall of a
//                      collective: every rank on another host is named), "checkpoint": the
//                      newest checkpoint complete on both sides ("" if none),
//                      "wall_time_at_checkpoint_s": the run's wall time when it was written}:
//                      what scripts/run --on-fault resume continues from (docs/cluster.md)
//   <analysis figures> top-level numbers of the scene's analysis (column_collapse: t_star_s,
//                      runout_m, ...; see analysis/column_collapse.hpp)
// Non-finite numbers are written as null (JSON has no NaN).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace mpmdem::mpm {

// The peer fault that ended a run (summary.json "peer_fault").
struct PeerFault {
  std::string kind;  // "died" (probed on mpm_app's host) | "no_reply" (a stall)
  std::int64_t step = 0;
  std::vector<int> ranks;
  std::vector<std::string> hosts;
  bool exact = false;
  std::string checkpoint;
  double wall_time_at_checkpoint_s = 0.0;
};

struct RunSummary {
  std::string status;
  std::string error;
  std::string scene;
  std::string config_file;
  std::string run_directory;
  std::string model;
  std::string program_version;
  double wall_time_s = 0.0;
  double step_wall_time_s = 0.0;
  double step_cpu_time_s = 0.0;
  std::int64_t steps = 0;
  std::int64_t resumed_from_step = -1;  // the checkpoint's step of a resumed run; -1: fresh
  std::int64_t steps_this_run = 0;      // steps this process ran (counted, not derived)
  std::size_t n_material_points = 0;
  std::size_t removed_points = 0;
  int threads = 1;
  double time_s = 0.0;
  double end_time_s = 0.0;
  double dt_min_s = 0.0;
  double dt_max_s = 0.0;
  double mass_initial_kg = 0.0;
  double mass_final_kg = 0.0;
  double mass_grid_kg = 0.0;  // the grid's mass after the last step's P2G (0: no step run)
  double E_p0_J = 0.0;
  double E_p_J = 0.0;
  double E_k_J = 0.0;
  double E_k0_J = 0.0;  // the energy budget's terms (energy_budget.hpp), since t = 0
  double W_int_J = 0.0;
  double W_damp_J = 0.0;
  double W_bc_J = 0.0;
  double W_transfer_J = 0.0;        // the part of E_err the transfers remove
  double W_transfer_walls_J = 0.0;  // the part of W_transfer_J at the walls
  // Figures of an analysis (e.g. column_collapse), written at the top level in this order.
  std::vector<std::pair<std::string, double>> analysis;
  std::string stop_reason;                                   // empty: no "stop" object
  std::vector<std::pair<std::string, double>> stop;          // its figures
  std::optional<PeerFault> peer_fault;                       // a failed run's, if a peer's
  std::string verification_kind;                             // empty: none
  std::vector<std::pair<std::string, double>> verification;  // figure name -> value
};

std::string to_json(const RunSummary& s);
// Writes dir/summary.json through a temporary file and a rename.
void write_summary(const std::string& path, const RunSummary& s);

}  // namespace mpmdem::mpm
