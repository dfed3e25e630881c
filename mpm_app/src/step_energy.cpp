// The energy budget hung on the MPM step: see step_energy.hpp.
#include "step_energy.hpp"

#include "energies.hpp"

namespace mpmdem::mpm {

void StepEnergy::before_p2g(const Particles& p) {
  step_ = EnergyBudget{};
  // The points' velocities are the last G2P's unless points were removed or restored since.
  step_.W_transfer = E_k_points_ >= 0.0 ? E_k_points_ : kinetic_energy(p);
}

void StepEnergy::after_p2g(const Grid& grid) {
  step_.W_transfer -= grid_kinetic_energy(grid);
}

void StepEnergy::after_g2p(const Particles& p) {
  E_k_points_ = kinetic_energy(p);
  step_.W_transfer -= E_k_points_;
  step_.W_transfer_walls = -step_.W_bc;
  for (double w : wall_work_) step_.W_transfer_walls += w;  // point order
}

void StepEnergy::after_stress(const Particles& p) {
  budget_.W_int += 0.5 * (W_int_start_ + stress_work(p, true, work_terms_));
  budget_.W_damp += step_.W_damp;
  budget_.W_bc += step_.W_bc;
  budget_.W_transfer += step_.W_transfer;
  budget_.W_transfer_walls += step_.W_transfer_walls;
}

}  // namespace mpmdem::mpm
