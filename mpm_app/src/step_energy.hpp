// The energy budget hung on the MPM step (energy_budget.hpp has the terms and their
// formulas): the solver calls one hook at each stage boundary, and StepEnergy measures the
// step's work terms there and adds them to the run's budget once the step has succeeded.
//
//   before_p2g(p)         W_transfer starts from the points' kinetic energy
//   after_p2g(grid)       ... less the grid's after P2G
//   before_grid_update    the damping force (W_damp) from the grid as P2G left it
//   before_bc(grid)       the node velocities before the walls and constraints
//   after_bc(grid, dt)    W_damp, W_bc; the grid's kinetic energy that G2P transfers back
//   g2p_walls()           what G2P needs to measure the walls' work per point
//   after_g2p(p)          W_transfer less the points' kinetic energy; W_transfer_walls
//   before_stress(p)      the stress work's first half (the stress before the update)
//   after_stress(p)       its second half; the step's terms join the run's budget
//
// Serial sums in node/point order: the figures do not depend on the thread count.
#pragma once

#include <vector>

#include "energy_budget.hpp"
#include "grid.hpp"
#include "particles.hpp"
#include "transfers.hpp"

namespace mpmdem::mpm {

class StepEnergy {
 public:
  // The run's budget so far (E_k0 and the work terms of the completed steps).
  const EnergyBudget& budget() const { return budget_; }
  void set_budget(const EnergyBudget& budget) { budget_ = budget; }
  void set_initial_kinetic_energy(double E_k0) { budget_.E_k0 = E_k0; }
  // The points changed outside a step (removed, restored after a failed step, a restart):
  // the next step measures their kinetic energy afresh.
  void points_changed() { E_k_points_ = -1.0; }

  void before_p2g(const Particles& p);
  void after_p2g(const Grid& grid);
  void before_grid_update(const Grid& grid, const Vec3& gravity, double damping) {
    grid_work_.before_update(grid, gravity, damping);
  }
  void before_bc(const Grid& grid) { grid_work_.before_bc(grid); }
  void after_bc(const Grid& grid, double dt) { grid_work_.after_bc(grid, dt, step_); }
  WallWork g2p_walls() { return {&grid_work_.v_free(), &wall_work_}; }
  void after_g2p(const Particles& p);
  void before_stress(const Particles& p) { W_int_start_ = stress_work(p, false, work_terms_); }
  void after_stress(const Particles& p);

 private:
  EnergyBudget budget_;  // the run's
  EnergyBudget step_;    // W_damp, W_bc, W_transfer(_walls) of the step being taken
  // Kinetic energy of the points after the last G2P, the start of the next step's W_transfer
  // (< 0: not known, after a restart, a restored step or removed points).
  double E_k_points_ = -1.0;
  double W_int_start_ = 0.0;
  GridWork grid_work_;
  std::vector<double> wall_work_;   // per point: the walls' work in G2P (W_transfer_walls)
  std::vector<double> work_terms_;  // stress_work()'s per-point terms
};

}  // namespace mpmdem::mpm
